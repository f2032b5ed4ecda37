/* rng.h — a small seeded random-number generator (xoshiro256**, seeded by splitmix64)
 * whose whole state is four words, so runs are reproducible and checkpointable. */
#ifndef ESF_RNG_H
#define ESF_RNG_H

#include <stdint.h>

typedef struct esf_rng {
  uint64_t s[4];
} esf_rng;

void esf_rng_seed(esf_rng *r, uint64_t seed);
uint64_t esf_rng_next(esf_rng *r);
/* Uniform in [0, 1). */
double esf_rng_uniform(esf_rng *r);

#endif
