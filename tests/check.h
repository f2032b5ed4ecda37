/* check.h — the test harness: CHECK-style assertions that count and report, and a
 * closing line. Each test program returns non-zero when any check failed. */
#ifndef ESF_CHECK_H
#define ESF_CHECK_H

#include <math.h>
#include <stdio.h>

static int check_failures_ = 0;
static int check_count_ = 0;

#define CHECK(cond, ...)                                                                 \
  do {                                                                                   \
    check_count_++;                                                                      \
    if (!(cond)) {                                                                       \
      check_failures_++;                                                                 \
      fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);           \
      fprintf(stderr, __VA_ARGS__);                                                      \
      fputc('\n', stderr);                                                               \
    }                                                                                    \
  } while (0)

/* |a - b| <= tol, with both values printed on failure */
#define CHECK_NEAR(a, b, tol, what)                                                      \
  do {                                                                                   \
    double ca_ = (a), cb_ = (b), ct_ = (tol);                                            \
    CHECK(fabs(ca_ - cb_) <= ct_, "%s: got %.10g, expected %.10g (tol %.3g)", what, ca_, \
          cb_, ct_);                                                                     \
  } while (0)

#define CHECK_OK(status, err) CHECK((status) == 0, "status %d: %s", (status), (err).msg)

static inline int check_finish(const char *name) {
  printf("%s: %d checks, %d failed\n", name, check_count_, check_failures_);
  return check_failures_ ? 1 : 0;
}

#endif
