/* clock.h — wall time for the run's timings (monotonic, seconds). */
#ifndef ESF_CLOCK_H
#define ESF_CLOCK_H

#include <time.h>

static inline double esf_now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
