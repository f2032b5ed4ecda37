/* clang_compat.h — forced into every file of the fuzz build (-include, meson.build):
 * GCC's two-vector __builtin_shuffle (a, b, mask), which src/fused/pair_batch.c uses
 * with constant masks and clang does not know, as a lane-by-lane statement expression:
 * lane k is a[m[k]] for m[k] < n, else b[m[k] - n], n the lane count. Slower than the
 * real shuffle, the same values. Remove it once pair_batch.c writes those shuffles as
 * __builtin_shufflevector (a, b, i0, i1, ...), which GCC and clang both know. */
#if defined(__clang__) && !defined(__builtin_shuffle)
#define __builtin_shuffle(a, b, m)                                                       \
  __extension__({                                                                        \
    __typeof__((a) + (a)) a_ = (a), b_ = (b), r_; /* unqualified */                      \
    __typeof__(m) m_ = (m);                                                              \
    const int n_ = (int)(sizeof r_ / sizeof r_[0]);                                      \
    for (int k_ = 0; k_ < n_; k_++) r_[k_] = m_[k_] < n_ ? a_[m_[k_]] : b_[m_[k_] - n_]; \
    r_;                                                                                  \
  })
#endif
