/* periodic.h — periodic boundaries: the box, the wrap of positions into it with
 * per-particle image counters, and the candidate search across the box's periodic faces
 * (docs/physics.md#periodic-boundaries).
 *
 * A candidate pair (a, b) across a periodic face carries its image: three integers
 * m in {-1, 0, 1}, and the pair's geometry uses b's image x_b + m L (L the box's
 * periods, 0 on an axis that is not periodic). With every period L > 2 (2 r_max + skin)
 * at most one image of b is within reach of a (the minimum-image convention), so the
 * key (a, b) stays unique and the contact history is carried by it as without
 * periodic axes. */
#ifndef ESF_PERIODIC_H
#define ESF_PERIODIC_H

#include <stddef.h>
#include <stdint.h>

#include "search/cells.h"
#include "search/pairbuf.h"
#include "util/esf_error.h"

typedef struct esf_periodic {
  int any;       /* some axis is periodic */
  int on[3];     /* axis k is periodic */
  double lo[3];  /* the box's lower corner, m */
  double len[3]; /* the period along each periodic axis (0 on the others), m */
} esf_periodic;

/* Wraps the n positions x (3n) into [lo, lo + L) on the periodic axes; img (3n) counts
 * the periods each particle was moved by (x_unwrapped = x + img L). Exact in img; x
 * moves by a multiple of L (rounded once). Returns how many particles moved. */
size_t esf_periodic_wrap(const esf_periodic *pb, size_t n, double *x, int32_t *img);

/* The largest cutoff 2 r_max + skin the periods allow: below min L / 2 over the
 * periodic axes (INFINITY when none). */
double esf_periodic_reach(const esf_periodic *pb);

/* The candidate pairs of the n particles (positions wrapped into the box) closer than
 * skin surface to surface through the periodic faces or inside the box, into out as
 * (a, b), a < b, sorted by (a, b), and their images into *img (3 per pair, grown as
 * *img_cap tracks). Method: every particle within 2 r_max + skin of a periodic face gets
 * image copies shifted by the periods (each combination of the faces it is near), the
 * cell search (cells.h) runs over particles and copies, and each particle-copy pair
 * becomes the pair with that image (a pair found from both sides once). Fails with
 * ESF_EINPUT when 2 r_max + skin >= L / 2 on a periodic axis. */
int esf_periodic_pairs(const esf_periodic *pb, esf_cells *c, size_t n, const double *x,
                       const double *radius, double skin, esf_pairbuf *out, int8_t **img,
                       size_t *img_cap, esf_error *err);

/* b's image position x_b + m L for pair image m (3 int8), the one expression every
 * periodic pair geometry uses (the general path, the fused batches' lanes, the
 * stability check, the contact network). */
static inline void esf_periodic_image(const double *xb, const int8_t *m,
                                      const double *len, double out[3]) {
  for (int q = 0; q < 3; q++) out[q] = xb[q] + (double)m[q] * len[q];
}

#endif
