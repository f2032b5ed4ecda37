/* bonds.h — the bond rule Phi of the adhesive law
 * (docs/physics.md#adhesive-normal-law-and-bonds; 004 2.25).
 *
 * Bonds are the contacts that exist at the start of the analysis between particles of
 * an adhesive material pair (both materials have `adhesion`). "Exist" is defined with
 * the pair's law (contact_adhesive.c) and its bond_gap (materials' adhesion.bond_gap,
 * mixed by min), u0 the initial overlap (> 0 interpenetrating):
 *   bond_gap = 0 (default, the seed's rule): u0 >= u_rupture, i.e. touching or
 *     overlapping, or (eps > 1/e) within the law's tensile range of gaps; no offset;
 *   bond_gap = G > 0 (packings that are not exactly touching): u0 >= -G, and
 *     each such bond is set at rest: the law sees u = un + s with the offset
 *     s = max(0, u_eq - u0) (u_eq the law's rest overlap), so the bond starts at its
 *     equilibrium instead of being pulled shut or torn at once.
 * Wall contacts never bond. A bond breaks when u < u_rupture and never heals; the pair's
 * later contacts follow the linear law. The bond state lives beside each particle
 * contact's history (esf_contact_bond, in nb.pp.bond, which only scenes with bonds
 * keep), and travels with it through list rebuilds as long as the pair
 * stays a candidate: a bond reaches a gap of at most s - u_rupture <= G + u_eq -
 * u_rupture before it breaks, and the skin must exceed that (esf_bonds_setup). */
#ifndef ESF_BONDS_H
#define ESF_BONDS_H

#include "util/esf_error.h"

struct esf_sim;

typedef struct esf_bonds {
  int on;       /* some particle material pair in the scene is adhesive */
  int pending;  /* bonds are formed at the first list build (esf_sim_refresh) */
  long formed;  /* bonds at the start */
  long broken;  /* bonds ruptured so far */
  double reach; /* the largest gap a bond can open to before rupture, m */
} esf_bonds;

/* After the pair table is mixed and the skin chosen: finds whether any adhesive pair is
 * used by particles and the bond reach; an automatic skin (skin_auto) is raised to 1.25
 * reach, a given one not above the reach is an ESF_EINPUT error. */
int esf_bonds_setup(struct esf_sim *s, int skin_auto, esf_error *err);

/* Forms the bonds from the freshly built candidate list (once; clears pending). */
int esf_bonds_form(struct esf_sim *s, esf_error *err);

/* Bonds still intact (scans the candidate list; an MPI run's processes all call it). */
long esf_bonds_alive(const struct esf_sim *s);

/* Bonds ruptured so far over every process (bonds.broken counts a process's own). */
long esf_bonds_broken(const struct esf_sim *s);

#endif
