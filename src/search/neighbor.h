/* neighbor.h — Verlet lists of contact candidates with their contact history.
 *
 * Candidates are the particle pairs closer than `skin` surface to surface (found by the
 * linked cells, cells.h) and the particle-wall element pairs closer than `skin`. Each
 * candidate carries its contact history (contact_law.h), which survives rebuilds: it is
 * looked up by pair at each rebuild (sorted keys and binary search, no hashing). The
 * lists are valid while no particle has moved more than skin/2 since the build; the
 * caller checks that every step with esf_neighbor_check. Pairs are stored with a < b. */
#ifndef ESF_NEIGHBOR_H
#define ESF_NEIGHBOR_H

#include <stddef.h>
#include <stdint.h>

#include "bodies/particles.h"
#include "bodies/walls.h"
#include "contact/contact_law.h"
#include "search/cells.h"
#include "search/periodic.h"

/* A build's cost in screened candidates per particle (the adaptive skin), from timings
 * of both (docs/performance.md#lists-and-rebuilds). */
#define ESF_SKIN_BUILD_COST 100.0

/* A scene without a skin: ESF_SKIN_DEFAULT r_mean, the reference the adaptive skin's
 * range (1/8 to 2.5 of it) and its first value (ESF_SKIN_START of it, 0.1 r_mean) are
 * taken from (model/setup.c). It starts below the reference, since a first list at the
 * reference itself lasts long with several times the idle candidates
 * (docs/performance.md#lists-and-rebuilds). */
#define ESF_SKIN_DEFAULT 0.4
#define ESF_SKIN_START   0.25

/* Ledger scratch per contact (only allocated when the energy ledger is on):
 * [0] overlap (m), [1] normal dashpot force applied (N), [2..4] tangential dashpot force
 * on A (N), [5..7] total force on the particle (N, wall contacts). */
#define ESF_LED_STRIDE 8

typedef struct esf_candidates {
  size_t n, cap;
  uint32_t *a;            /* particle A */
  uint32_t *b;            /* particle B, or the wall element index */
  esf_contact_hist *h;    /* history */
  esf_contact_bond *bond; /* bond state, or NULL: the particle list of a scene with
                             bonds only (esf_neighbor.bonds) */
  esf_contact_roll
      *roll;        /* rolling resistance state, or NULL: scenes where some pair
                       has rolling or twisting friction only (esf_neighbor.rolling) */
  uint8_t *touch;   /* 1: touching at the last committed evaluation */
  double *led;      /* ESF_LED_STRIDE per contact, or NULL */
  double *vc0;      /* 3 per contact: relative contact velocity at the last commit
                       (the ODE methods' history carry), or NULL */
  double *wr0;      /* 3 per contact: relative spin wA - wB at the last commit (the
                       rolling state's carry; with carry and rolling only), or NULL */
  const double *xs; /* history as ODE state (dem_ode.h): 3 per contact, the live
                       tangential displacement, m; NULL otherwise (not owned) */
  double *xsdot;    /* its rate, m/s, written by evaluations when not NULL */
  int8_t *img;      /* 3 per candidate: the image of B (periodic.h), or NULL: the
                       particle list of a scene with periodic axes only */
  double plen[3];   /* with img: the periods, m (B's image is x_b + img plen) */
  /* with img and Lees-Edwards shear (per->le): the box, the flow offset now (set by
   * esf_neighbor_le_time), its multiple of L_f taken off at the build, the build's
   * time; m, m, s */
  const esf_periodic *per;
  double le_off, le_ref, le_tb;
} esf_candidates;

typedef struct esf_neighbor {
  double skin;       /* m */
  esf_candidates pp; /* particle-particle candidates */
  esf_candidates pw; /* particle-wall candidates */
  int ledger;        /* allocate ledger scratch */
  int carry;         /* keep vc0 (ODE methods set it before the first build) */
  int bonds;         /* keep pp.bond (model/setup.c sets it before the first build) */
  int rolling;       /* keep pp.roll and pw.roll (model/setup.c, likewise) */
  esf_cells *cells;
  esf_pairbuf buf;
  esf_pairbuf *wbuf;  /* the wall candidates' per-thread buffers, nwbuf of them */
  uint32_t *wscratch; /* and their wall index queries' scratch, nwbuf x wscratch_n */
  size_t nwbuf, wscratch_n;
  esf_wall_hit *wall_hits; /* scratch for the wall loop, pw.cap entries */
  double *wall_un;
  unsigned char *wall_keep;
  double *xref; /* positions at the last build, 3 * nref */
  size_t nref;
  long builds; /* rebuild count */
  /* Set by a step that drifted the particles and measured their displacement on the
   * way (fused/fused.c); the next esf_neighbor_check uses it instead of its own pass.
   * Cleared after every check (esf_sim_refresh). */
  int disp_valid;
  double max_disp2; /* largest squared displacement since the build, m^2 */
  int escaped;      /* with disp_valid: some particle left the domain */
  /* the scene's domain (particles leaving it are removed at the next build, which
   * esf_neighbor_check then asks for), or NULL, m */
  const double *dom_lo, *dom_hi;
  /* the periodic box (periodic.h), or NULL: no periodic axis; its image scratch */
  const esf_periodic *per;
  int8_t *pimg;
  size_t pimg_cap;
  double le_t; /* Lees-Edwards: the time of the next build (set by the caller), s */
  /* the wall element index (wall_index.h) */
  struct esf_wall_index *widx;
  int threads; /* threads for the build's per-particle passes (>= 1; set by the caller) */
  /* the adaptive skin (esf_neighbor_skin_tune): the range it moves in (both 0: fixed),
   * and the step of the last build (set by the caller after a build), m, m, steps */
  double skin_lo, skin_hi;
  long built_step;
  /* the build's storage: the old list's touching contacts copied aside (during a
   * build only), and the history transfer's scratch, kept between builds (ws_n
   * particle offsets, ws_m contact entries) */
  esf_candidates kept;
  size_t *ws_start, *ws_ostart, ws_n, ws_m;
  uint32_t *ws_ok;
} esf_neighbor;

int esf_neighbor_init(esf_neighbor *nb, double skin, int ledger, esf_error *err);
void esf_neighbor_release(esf_neighbor *nb);

/* Sets *rebuild when a particle moved more than skin/2 since the last build, or the
 * largest particle displacement plus wall_moved (how far a moving wall went, m) exceeds
 * skin/2, or a particle is outside the domain (or no build was made, or the count
 * changed). A non-finite position is an
 * ESF_ENUMERIC error naming the particle (by id). */
int esf_neighbor_check(const esf_neighbor *nb, const esf_particles *p, double wall_moved,
                       int *rebuild, esf_error *err);

/* The squared displacement past which esf_neighbor_check asks for a rebuild:
 * (skin/2)^2, m^2. */
double esf_neighbor_limit2(const esf_neighbor *nb);

/* Lets esf_neighbor_skin_tune move the skin within [lo, hi], m. */
void esf_neighbor_skin_range(esf_neighbor *nb, double lo, double hi);

/* The adaptive skin, for a rebuild at step `step` of the lists built at
 * nb->built_step for n particles (call it before removing or renumbering particles; it
 * does nothing with a fixed skin, a first build, or a changed count). Balances two costs
 * per particle and step that the skin trades: screening the candidates the skin adds
 * (those not touching: m_s per particle, proportional to the skin), and the build,
 * worth ESF_SKIN_BUILD_COST screened candidates per particle, amortised over the I
 * steps the lists lasted (proportional to the skin). Both go as s, their product m_s I
 * as s^2, and the balance m_s I = ESF_SKIN_BUILD_COST is met by s' = s sqrt(
 * ESF_SKIN_BUILD_COST / (m_s I)), taken within a factor 2 of s and within the range.
 * It depends on the state only (counts and steps), never on timings or threads, so runs
 * stay reproducible and thread-count independent. */
void esf_neighbor_skin_tune(esf_neighbor *nb, size_t n, long step);

/* The same from its counts: shell idle candidates (esf_neighbor_idle, over every
 * process of an MPI run) among n particles; the caller checks the conditions. */
void esf_neighbor_skin_tune_with(esf_neighbor *nb, size_t shell, size_t n, long step);

/* The particle candidates not touching at the last evaluation whose A is in [lo, hi). */
size_t esf_neighbor_idle(const esf_neighbor *nb, size_t lo, size_t hi);

/* Appends m touching contacts to the particle list (walls 0: pairs (a, b), turned
 * round when a > b) or the wall list (walls 1: particle a, element b) with their
 * histories, rolling and bond states (NULL: zero): an MPI run's migrating contacts
 * (par_cut.c), after esf_neighbor_remap and before the build that carries them. */
int esf_neighbor_inject(esf_neighbor *nb, int walls, size_t m, const uint32_t *a,
                        const uint32_t *b, const esf_contact_hist *h,
                        const esf_contact_roll *roll, const esf_contact_bond *bond,
                        esf_error *err);

/* Rebuilds both lists from the current positions, carrying the history of contacts
 * that were touching over to the new lists. */
int esf_neighbor_build(esf_neighbor *nb, const esf_particles *p, const esf_walls *w,
                       esf_error *err);

/* After particles were removed or reordered (remap: old index -> new index, SIZE_MAX
 * for removed; n_old entries), drops the candidates of removed particles and renumbers
 * the rest, turning pairs round where needed (a < b). The lists stay valid until the
 * next check, which asks for a build (xref is dropped); a reordering leaves them out of
 * (a, b) order, which only a build restores. */
void esf_neighbor_remap(esf_neighbor *nb, const size_t *remap, size_t n_old);

/* Makes room for npp particle-particle and npw particle-wall candidates (and the wall
 * loop's scratch); the lists' contents and counts are untouched. For checkpoint
 * restore, which then fills the lists. */
int esf_neighbor_reserve(esf_neighbor *nb, size_t npp, size_t npw, esf_error *err);

/* Candidate k's bond state, or NULL when c keeps none (the laws' `bond` argument). */
static inline const esf_contact_bond *esf_candidates_bond(const esf_candidates *c,
                                                          size_t k) {
  return c->bond ? &c->bond[k] : NULL;
}

/* Whether candidate k of c is bonded (Phi = 1; it is then touching). */
static inline int esf_candidates_bonded(const esf_candidates *c, size_t k) {
  const esf_contact_bond *b = esf_candidates_bond(c, k);
  return b && b->on;
}

/* The position of candidate k's B as the pair's geometry uses it: x_b itself, or its
 * periodic image (tmp filled) when the list has images. */
static inline const double *esf_candidates_xb(const esf_candidates *c, size_t k,
                                              const double *x, double tmp[3]) {
  const double *xb = x + 3 * (size_t)c->b[k];
  if (!c->img) return xb;
  esf_periodic_image(xb, c->img + 3 * k, c->plen, tmp);
  if (c->per && c->per->le) esf_periodic_le_image(c->per, c->img + 3 * k, c->le_off, tmp);
  return tmp;
}

/* The velocity of candidate k's B as the pair's kinematics use it: v_b, or with
 * Lees-Edwards shear its image's, v_b + m_g rate L_g along the flow axis (tmp filled). */
static inline const double *esf_candidates_vb(const esf_candidates *c, size_t k,
                                              const double *v, double tmp[3]) {
  const double *vb = v + 3 * (size_t)c->b[k];
  if (!c->img || !c->per || !c->per->le || !c->img[3 * k + c->per->grad]) return vb;
  for (int q = 0; q < 3; q++) tmp[q] = vb[q];
  tmp[c->per->flow] +=
      (double)c->img[3 * k + c->per->grad] * esf_periodic_le_speed(c->per);
  return tmp;
}

/* Lees-Edwards: the pair list's flow offset at time t (s); nothing without shear. */
static inline void esf_neighbor_le_time(esf_neighbor *nb, double t) {
  if (nb->per && nb->per->le)
    nb->pp.le_off = nb->per->rate * nb->per->len[nb->per->grad] * t - nb->pp.le_ref;
}

/* Number of contacts touching at the last committed evaluation. */
size_t esf_neighbor_touching(const esf_neighbor *nb);

#endif
