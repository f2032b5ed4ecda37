/* threads.c — the threads a run may use, and a thread's wait for a flag (threads.h). */
#include "util/threads.h"

#include <sched.h>
#include <stdatomic.h>

#ifdef _OPENMP
#include <omp.h>
#endif

int esf_threads_available(void) {
#ifdef _OPENMP
  const int n = omp_get_max_threads();
  return n > 0 ? n : 1;
#else
  return 1;
#endif
}

/* A spinning thread's hint to the core (x86 pause: fewer wasted issue slots, and no
 * memory-order flush when the flag changes). */
static inline void cpu_relax(void) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

/* Spins before a waiting thread yields its core: a wait between two steps is a few
 * microseconds, and a yield is a system call of about one (yielding sooner spent time
 * in the kernel's scheduler:
 * docs/performance.md#bursts-threads-that-do-not-meet-between-steps). */
#define SPIN 4096

double esf_threads_wait(_Atomic long *flag, long e) {
  if (atomic_load_explicit(flag, memory_order_acquire) >= e) return 0.0;
#ifdef _OPENMP
  const double t0 = omp_get_wtime();
#endif
  for (unsigned spin = 0; atomic_load_explicit(flag, memory_order_acquire) < e; spin++)
    if (spin < SPIN)
      cpu_relax();
    else
      sched_yield(); /* more threads than cores */
#ifdef _OPENMP
  return omp_get_wtime() - t0;
#else
  return 0.0;
#endif
}
