/* threads.c — the threads a run may use (threads.h). */
#include "util/threads.h"

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
