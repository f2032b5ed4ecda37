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

#include <math.h>
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
  /* Lees-Edwards simple shear (domain.shear), or le = 0: the images across the
   * gradient faces are shifted along the flow axis by rate L_g t and move at rate L_g */
  int le, flow, grad; /* on; the flow and gradient axes */
  double rate;        /* shear rate, 1/s */
} esf_periodic;

/* Lees-Edwards: the flow offset of the image above the gradient faces at time t,
 * rate L_g t less the multiple `ref` of L_f below it (m; ref may be NULL). */
double esf_periodic_le_offset(const esf_periodic *pb, double t, double *ref);

/* Lees-Edwards: the images' speed along the flow axis, rate L_g (m/s). */
static inline double esf_periodic_le_speed(const esf_periodic *pb) {
  return pb->rate * pb->len[pb->grad];
}

/* Wraps the n positions x (3n) into [lo, lo + L) on the periodic axes; img (3n) counts
 * the periods each particle was moved by (x_unwrapped = x + img L). Exact in img; x
 * moves by a multiple of L (rounded once). Lees-Edwards (pb->le; v the velocities, t
 * the time): crossing the gradient faces m times (upward positive) moves x along the
 * flow axis by -m esf_periodic_le_offset(t) and v by -m rate L_g before the flow axis
 * is wrapped (the flow counter then counts the flow wraps only). Returns how many
 * particles moved. */
size_t esf_periodic_wrap(const esf_periodic *pb, size_t n, double *x, double *v, double t,
                         int32_t *img);

/* The largest cutoff 2 r_max + skin the periods allow: below min L / 2 over the
 * periodic axes (INFINITY when none). */
double esf_periodic_reach(const esf_periodic *pb);

/* The candidate pairs of the n particles (positions wrapped into the box) closer than
 * skin surface to surface through the periodic faces or inside the box, into out as
 * (a, b), a < b, sorted by (a, b), and their images into *img (3 per pair, grown as
 * *img_cap tracks). Method: every particle within 2 r_max + skin of a periodic face gets
 * image copies shifted by the periods (each combination of the faces it is near), the
 * cell search (cells.h) runs over particles and copies, and each particle-copy pair
 * becomes the pair with that image (a pair found from both sides once). Lees-Edwards:
 * a copy across the gradient faces (m_g) is shifted by m_g off along the flow axis
 * (off: esf_periodic_le_offset at the build), then by the flow period that takes it
 * back into the box, and gets flow copies near the flow faces from there. Fails with
 * ESF_EINPUT when 2 r_max + skin >= L / 2 on a periodic axis. */
int esf_periodic_pairs(const esf_periodic *pb, esf_cells *c, size_t n, const double *x,
                       const double *radius, double skin, double off, esf_pairbuf *out,
                       int8_t **img, size_t *img_cap, esf_error *err);

/* b's image position x_b + m L for pair image m (3 int8), the one expression every
 * periodic pair geometry uses (the general path, the fused batches' lanes, the
 * stability check, the contact network). */
static inline void esf_periodic_image(const double *xb, const int8_t *m,
                                      const double *len, double out[3]) {
  for (int q = 0; q < 3; q++) out[q] = xb[q] + (double)m[q] * len[q];
}

/* With Lees-Edwards: the flow offset of image m at offset off (m), added to the
 * flow component after esf_periodic_image's sum. */
static inline void esf_periodic_le_image(const esf_periodic *pb, const int8_t *m,
                                         double off, double out[3]) {
  out[pb->flow] += (double)m[pb->grad] * off;
}

/* The image of x nearest to ref (m), as the pair geometry places it: with Lees-Edwards
 * the gradient axis first, its image moving the flow coordinate by m_g off (off: the
 * list's offset, esf_candidates.le_off), then each other periodic axis. For a contact
 * point ref this is the partner's position on the contact's side (output/wall_loads.c's
 * branch vectors). */
static inline void esf_periodic_nearest(const esf_periodic *pb, double off,
                                        const double *ref, const double *x,
                                        double out[3]) {
  for (int q = 0; q < 3; q++) out[q] = x[q];
  if (pb->le) {
    const int g = pb->grad;
    const double m = -floor((out[g] - ref[g]) / pb->len[g] + 0.5);
    out[g] += m * pb->len[g];
    out[pb->flow] += m * off;
  }
  for (int q = 0; q < 3; q++)
    if (pb->on[q] && !(pb->le && q == pb->grad))
      out[q] += -floor((out[q] - ref[q]) / pb->len[q] + 0.5) * pb->len[q];
}

#endif
