/* stability.c — the live stability check (stability.h; docs/physics.md#live-stability-
 * check).
 *
 * The leapfrog's dashpots see v_{n-1/2} and its global damping is centred, so for the
 * linearised contact network x_{n+1} - 2 x_n + x_{n-1} + dt B (x_n - x_{n-1})
 * + dt^2 A x_n = 0 (mass-scaled, centred damping dropped). Its discrete energy
 * d^T (I - dt B/2 - dt^2 A/4) d + (dt^2/4) s^T A s (d = x_{n+1} - x_n, s = x_{n+1} +
 * x_n) never grows, and is positive definite exactly when lambda_max(dt^2 A + 2 dt B)
 * < 4: for a single mode this is dt < (2/omega)(sqrt(1 + xi^2) - xi) (001 3.66).
 * lambda_max: Lanczos on the operator applied contact by contact (no matrix; threaded,
 * the same bits on any thread count), a deterministic start vector, the tridiagonal's
 * top Ritz value every 4 steps, stopped when its residual bound is below 1e-3 of it.
 * Springs: the linear law's kn and sticking kt (an adhesive pair's largest bonded
 * tangent stiffness; Hertz-Mindlin's S_n = 2 E* a, S_t = 8 G* a at the current overlap,
 * a = sqrt(R* u)), dashpots as the law has them, lever arms to the contact point, as
 * `esfera modes` assembles them densely (app/modes.c); the turning normal's geometric
 * stiffness is neglected. Touching: overlap > 0, or bonded; a contact at its Coulomb
 * cap (or frictionless) has no tangential spring or dashpot. Rolling resistance (epsd):
 * its rotational springs and dashpots (esf_stab_roll_apply), elastic also at the limit.
 * Units: SI. Entry: a set-up sim with its candidate lists built; nothing is changed. */
#include "model/stability.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bodies/wall_geom.h"
#include "contact/contact_rolling.h"
#include "contact/lane_scalar.h"
#include "model/forces.h"
#include "util/clock.h"
#include "util/threads.h"
#include "util/vec3.h"

#define LZ_MAX   120  /* Lanczos steps at most */
#define LZ_EVERY 4    /* steps between tridiagonal solves */
#define LZ_TOL   1e-3 /* residual bound / Ritz value to stop */

static inline void springs(const esf_pair_params *pp, double beta, double mstar,
                           double rstar, double un, double kc[4]) {
  if (pp->law == &esf_contact_hertz) { /* tangent stiffnesses at un (contact_hertz.h) */
    double ks, qa, sm = sqrt(mstar);
    esf_law_hertz_springs_s(pp->hn, pp->ht, rstar, fmax(un, 0.0), &ks, &kc[0], &kc[1],
                            &qa);
    if (pp->hertz_constant) qa = esf_law_hertz_qref_s(pp->estar, sm, rstar, pp->v_imp);
    esf_law_hertz_dashpots_s(beta, pp->cn_factor, pp->ct_factor, sm, qa, kc[0], kc[1],
                             &kc[2], &kc[3]);
    return;
  }
  double kn = pp->law->flags & ESF_LAW_TENSION ? pp->adh.k_max : pp->kn;
  kc[0] = kn;
  kc[1] = pp->kt;
  kc[2] = beta > 0 ? beta * pp->kn : pp->cn_factor * sqrt(mstar); /* as the laws */
  kc[3] = beta > 0 ? beta * pp->kt : pp->ct_factor * sqrt(mstar);
}

void esf_stab_springs(const esf_pair_params *pp, double beta, double mstar, double rstar,
                      double un, double kc[4]) {
  springs(pp, beta, mstar, rstar, un, kc);
}

/* Pair candidate k's centre-to-centre vector d (A to B or its image) and d[3] its
 * square; 1 when it touches (overlap, or a bond). Without branches on the outcome. */
static inline int pair_near(const esf_sim *s, size_t k, double d[4]) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  uint32_t a = c->a[k], b = c->b[k];
  double rs = p->radius[a] + p->radius[b], xb[3];
  v3_sub(d, esf_candidates_xb(c, k, p->x, xb), p->x + 3 * a);
  d[3] = v3_norm2(d);
  return (d[3] < rs * rs) | (c->bond && esf_candidates_bonded(c, k) && c->touch[k]);
}

/* A touching pair's unit normal n and lever arms from pair_near's d; 0 when the
 * centres coincide. */
static inline int pair_finish(const esf_sim *s, size_t k, const double d[4], double n[3],
                              double *la, double *lb) {
  const esf_particles *p = &s->p;
  uint32_t a = s->nb.pp.a[k], b = s->nb.pp.b[k];
  double rs = p->radius[a] + p->radius[b], dist = sqrt(d[3]), un = rs - dist;
  if (!(dist > 0)) return 0;
  v3_scale(n, 1.0 / dist, d);
  *la = p->radius[a] - 0.5 * un;
  *lb = p->radius[b] - 0.5 * un;
  return 1;
}

/* The tangential terms of a linear-law contact (law_body.h): none when its cap
 * coh + mu fn is zero or less (frictionless); at the cap at its last commit (kt |xi|
 * there, with the elastic normal force kn u) sliding, the unit slip direction in *t
 * (xi brought into the current tangent plane). slip: whether it slides when known (an
 * earlier call's c->slip for the same state), -1 when not. */
static inline void tangential(const esf_pair_params *pp, const esf_contact_hist *h,
                              int live, double un, const double n[3], int slip,
                              esf_stab_contact *c) {
  c->slip = 0;
  if (pp->law->flags & ESF_LAW_TENSION) return;
  const int hz = pp->law == &esf_contact_hertz; /* fel (2/3) S_n u; xi the force */
  double tau = pp->cohesion + pp->mu * (hz ? c->kc[0] / 1.5 : pp->kn) * un;
  if (tau <= 0) {
    c->kc[1] = c->kc[3] = 0.0;
    return;
  }
  if (slip == 0) return;
  double xi = slip > 0 ? 0.0 : live ? v3_norm(h->xi) : 0.0;
  if (slip < 0 && !((hz ? 1.0 : pp->kt) * xi >= (1 - 1e-9) * tau)) return;
  double s = v3_dot(h->xi, n), t[3], m;
  for (int q = 0; q < 3; q++) t[q] = h->xi[q] - s * n[q];
  m = v3_norm(t);
  if (!(m > 0)) return;
  v3_scale(c->t, 1.0 / m, t);
  c->slip = 1;
}

/* The rolling resistance's springs and dashpots of a contact (esf_law_rolling_par with
 * R* and the inertias of esf_law_rolling_pair; a wall, b < 0: rA, IA + mA rA^2, IA as
 * forces.c; kn at overlap un: esf_contact_rolling_kn), epsd only: cdt's constant
 * torque has no stiffness. */
static inline void roll_springs(const esf_sim *s, const esf_pair_params *par, size_t a,
                                long b, double un, esf_stab_contact *c) {
  const esf_particles *p = &s->p;
  c->roll = s->mats.any_rolling && s->mats.rolling_model == ESF_ROLL_EPSD;
  if (!c->roll) return;
  double rs, ir, itw, ra = p->radius[a], ia = p->inertia[a];
  if (b >= 0)
    esf_law_rolling_pair_s(ra, p->radius[b], p->mass[a], p->mass[b], ia, p->inertia[b],
                           &rs, &ir, &itw);
  else
    rs = ra, ir = ia + p->mass[a] * ra * ra, itw = ia;
  esf_law_rpar_s P;
  esf_law_rolling_par_s(esf_contact_rolling_kn(par, rs, un), par->mu_r, par->mu_tw,
                        par->eta_r, rs, ir, itw, 1.0, 0, &P);
  c->kr[0] = P.kr;
  c->kr[1] = P.ktw;
  c->kr[2] = P.cr;
  c->kr[3] = P.ctw;
}

/* Touching pair candidate k (pair_near's d) as the check sees it in *c; 0 when its
 * centres coincide. */
static inline int pair_contact_at(const esf_sim *s, size_t k, const double d[4], int slip,
                                  esf_stab_contact *c) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  const esf_candidates *pp = &s->nb.pp;
  if (!pair_finish(s, k, d, c->n, &c->la, &c->lb)) return 0;
  c->a = pp->a[k];
  c->b = pp->b[k];
  const esf_pair_params *par = &mt->pair[p->material[c->a] * mt->n + p->material[c->b]];
  const double ra = p->radius[c->a], rb = p->radius[c->b];
  const double u = ra - c->la + rb - c->lb;
  springs(par, s->beta, p->mass[c->a] * p->mass[c->b] / (p->mass[c->a] + p->mass[c->b]),
          ra * rb / (ra + rb), u, c->kc);
  tangential(par, &pp->h[k], slip < 0 && pp->touch[k], u, c->n, slip, c);
  roll_springs(s, par, c->a, c->b, u, c);
  return 1;
}

/* Pair candidate k as the check sees it in *c; 0 when it does not touch. */
static inline int pair_contact(const esf_sim *s, size_t k, esf_stab_contact *c) {
  double d[4];
  return pair_near(s, k, d) && pair_contact_at(s, k, d, -1, c);
}

/* The wall contacts of particle pw->a[k0] (its candidates k0 .. the returned end) that
 * carry force (forces.c's choice among hits on shared mesh edges and vertices): fn on
 * each, their count added to *cnt. */
static inline size_t wall_contacts(const esf_sim *s, size_t k0, esf_stab_visit fn,
                                   void *ctx, size_t *cnt) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  const esf_candidates *pw = &s->nb.pw;
  enum { MAXH = 32 };
  esf_wall_hit hits[MAXH];
  double un[MAXH];
  uint32_t elem[MAXH];
  size_t kk[MAXH], k1;
  unsigned char keep[MAXH];
  esf_stab_contact c;
  const uint32_t a = pw->a[k0];
  size_t m = 0;
  for (k1 = k0; k1 < pw->n && pw->a[k1] == a; k1++) {
    esf_wall_hit h;
    esf_wall_nearest(&s->walls.e[pw->b[k1]], p->x + 3 * (size_t)a, &h);
    if (!(h.dist < p->radius[a]) || m == MAXH) continue; /* beyond MAXH: ignored */
    hits[m] = h;
    un[m] = p->radius[a] - h.dist;
    elem[m] = pw->b[k1];
    kk[m++] = k1;
  }
  if (m == 0) return k1;
  esf_forces_select_wall_hits(&s->walls, elem, hits, un, m, p->radius[a], keep);
  for (size_t j = 0; j < m; j++) {
    if (!keep[j]) continue;
    c.a = a;
    c.b = -1;
    v3_copy(c.n, hits[j].n);
    c.la = esf_wall_lever(s->cfg.wall_lever, p->radius[a], un[j], hits[j].dist);
    c.lb = 0.0;
    const esf_pair_params *par =
        &mt->pair[p->material[a] * mt->n + s->walls.e[elem[j]].material];
    springs(par, s->beta, p->mass[a], p->radius[a], un[j], c.kc);
    tangential(par, &pw->h[kk[j]], pw->touch[kk[j]], un[j], c.n, -1, &c);
    roll_springs(s, par, a, -1, un[j], &c);
    fn(&c, ctx);
    ++*cnt;
  }
  return k1;
}

size_t esf_stab_contacts(const esf_sim *s, esf_stab_visit fn, void *ctx) {
  const esf_candidates *pp = &s->nb.pp, *pw = &s->nb.pw;
  esf_stab_contact c;
  size_t cnt = 0;
  for (size_t k = 0; k < pp->n; k++)
    if (pair_contact(s, k, &c)) fn(&c, ctx), cnt++;
  for (size_t k0 = 0; k0 < pw->n;) k0 = wall_contacts(s, k0, fn, ctx, &cnt);
  return cnt;
}

/* The operator: y += (sum over touching contacts G^T (ck S_K + cc S_C) G) x on 6
 * coordinates per particle, each contact's geometry and springs recomputed from the
 * state at each application; a byte per pair candidate, set once per estimate, says
 * which touch and which slide (the idle ones and the sticking ones' histories are not
 * read). Lanczos runs on M^{-1} K' in the M inner product (the spectrum of
 * M^{-1/2} K' M^{-1/2}, without scaled copies); weights() gives M's diagonal, 0 on
 * frozen coordinates (2D: y and the rotations about x and z), and its inverse.
 * Order: the particles in blocks of BLOCK, fixed whatever the thread count. With the
 * lists sorted by A with B >= A (a build leaves them so), each particle's row receives
 * its terms in list order when the blocks are passed in order, and is final once its
 * block is: M^{-1} and the block's share of the inner product are applied there. With
 * threads, each takes a range of whole blocks, first adding B's side of the touching
 * pairs that enter its rows from earlier ranges (gathered once, in list order; computed
 * twice), then its blocks with both sides of the pairs inside it and A's side of those
 * leaving it: every row gets the serial pass's sums. Inner products are summed by
 * coordinate within a block, then block by block: the same bits on any thread count. */
#define BLOCK 1024

typedef struct op {
  esf_sim *s;
  double ck, cc; /* weights of the springs and the dashpots */
  const double *x;
  double *y;
  size_t contacts;
  int nth;             /* threads */
  size_t nblk;         /* blocks of BLOCK particles */
  double *part;        /* a block's partial sum (nblk) */
  size_t *cnt;         /* a block's contacts (nblk) */
  size_t *poff, *woff; /* a block's first pair and wall candidate (nblk + 1); poff NULL:
                          lists not sorted, whole passes */
  uint8_t *flag;       /* per pair candidate: 1 touching, 2 sliding (or NULL) */
  size_t nr, *rb;      /* threads: nr ranges, range r's blocks rb[r] .. rb[r + 1] */
  size_t *inoff, *in;  /* the touching pairs entering range r: in[inoff[r] ..] */
} op;

static const int free2[6] = {1, 0, 1, 0, 1, 0};

static inline double minv(const esf_sim *s, size_t i, int j) {
  if (s->cfg.dim != 3 && !free2[j]) return 0.0;
  return j < 3 ? s->p.inv_mass[i] : s->p.inv_inertia[i];
}

/* M's diagonal on particle i's coordinates (0 on frozen ones), and its inverse */
static inline void weights(const esf_sim *s, size_t i, double m[6], double mi[6]) {
  for (int j = 0; j < 6; j++) {
    mi[j] = minv(s, i, j);
    m[j] = !(mi[j] > 0) ? 0.0 : j < 3 ? s->p.mass[i] : s->p.inertia[i];
  }
}

/* contact c's terms into its bodies' rows in `which` (1: A's, 2: B's, 3: both) */
static inline void apply_c(const op *o, const esf_stab_contact *c, int which) {
  double sink[6] = {0};
  const int wall = c->b < 0;
  const double *xb = wall ? NULL : o->x + 6 * (size_t)c->b;
  double *ya = which & 1 ? o->y + 6 * c->a : sink;
  double *yb = wall ? NULL : which & 2 ? o->y + 6 * (size_t)c->b : sink;
  esf_stab_contact_apply(
      c->n, c->slip ? c->t : NULL, c->la, c->lb, o->ck * c->kc[0] + o->cc * c->kc[2],
      o->ck * c->kc[1] + o->cc * c->kc[3], o->x + 6 * c->a, xb, ya, yb);
  if (c->roll)
    esf_stab_roll_apply(c->n, o->ck * c->kr[0] + o->cc * c->kr[2],
                        o->ck * c->kr[1] + o->cc * c->kr[3], o->x + 6 * c->a, xb, ya, yb);
}

static void apply_wall(const esf_stab_contact *c, void *ctx) { apply_c(ctx, c, 1); }

/* pairs k0..k1 (both sides when B < hi, A's alone otherwise), then walls w0..w1;
 * returns the contacts. By chunks of candidates: the touching ones' contacts first,
 * then their terms, so that their square roots and divisions overlap. */
static size_t range_pass(op *o, size_t k0, size_t k1, size_t w0, size_t w1, size_t hi) {
  enum { CHUNK = 32 };
  esf_stab_contact c[CHUNK];
  size_t cnt = 0;
  for (size_t k = k0; k < k1; k += CHUNK) {
    size_t m = 0, t = 0, e = k + CHUNK < k1 ? k + CHUNK : k1, idx[CHUNK];
    double d[CHUNK][4];
    const uint8_t *f = o->flag;
    if (f) { /* the touching ones, their sliding known */
      for (size_t q = k; q < e; q++) idx[t] = q, t += f[q] & 1u;
      for (size_t j = 0; j < t; j++) {
        pair_near(o->s, idx[j], d[j]);
        m += (size_t)pair_contact_at(o->s, idx[j], d[j], f[idx[j]] >> 1, c + m);
      }
    } else {
      for (size_t q = k; q < e; q++) idx[t] = q, t += (size_t)pair_near(o->s, q, d[t]);
      for (size_t j = 0; j < t; j++)
        m += (size_t)pair_contact_at(o->s, idx[j], d[j], -1, c + m);
    }
    for (size_t j = 0; j < m; j++) apply_c(o, c + j, (size_t)c[j].b < hi ? 3 : 1);
    cnt += m;
  }
  for (size_t k = w0; k < w1;) k = wall_contacts(o->s, k, apply_wall, o, &cnt);
  return cnt;
}

/* y += K' x (the contacts in list order, serial) */
static void op_apply(op *o, const double *x, double *y) {
  o->x = x;
  o->y = y;
  o->contacts = range_pass(o, 0, o->s->nb.pp.n, 0, o->s->nb.pw.n, SIZE_MAX);
}

enum { V_START, V_DIV, V_ADD, V_SCALE, V_MINV_DOT, V_RES_DOT, V_STEP, V_DOT };

/* a loop over particles i0..i1 with their weights m, mi and rows x (of u), z (of v) */
#define EACH(body)                                                                       \
  for (size_t i = i0; i < i1; i++) {                                                     \
    double *x = u + 6 * i, *z = v ? v + 6 * i : NULL;                                    \
    (void)z;                                                                             \
    weights(s, i, m, mi);                                                                \
    for (int j = 0; j < 6; j++) {                                                        \
      body;                                                                              \
    }                                                                                    \
  }                                                                                      \
  break

/* One vector operation on particles i0..i1 (u, v: its operands, c its scalar); their
 * share of the M inner product it ends with, summed by coordinate. */
static double vec_rows(const esf_sim *s, int kind, double c, double c2, double *u,
                       double *v, size_t i0, size_t i1) {
  double r[6] = {0}, m[6], mi[6];
  switch (kind) {
  case V_START: /* a hash of the coordinate's index on the free coordinates */
    EACH(uint64_t h =
             (uint64_t)(6 * i + j) * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
         h ^= h >> 31; h *= 0xBF58476D1CE4E5B9ull; h ^= h >> 29;
         x[j] = mi[j] > 0 ? (double)(h >> 11) * 0x1p-53 - 0.5 : 0.0;
         r[j] += m[j] * x[j] * x[j]);
  case V_DIV:
    EACH(x[j] = c > 0 ? x[j] / c : 0.0);
  case V_ADD:
    EACH(x[j] += c * z[j]);
  case V_SCALE:
    EACH(x[j] *= c * m[j]);
  case V_MINV_DOT:
    EACH(x[j] *= mi[j]; r[j] += m[j] * x[j] * z[j]);
  case V_RES_DOT:
    EACH(double t = x[j] - c * z[j]; r[j] += m[j] * t * t);
  case V_STEP: /* v' = (u - alpha v) / b, u' = -b M v */
    EACH(double t = x[j] - c2 * z[j]; x[j] = t / c; z[j] *= -c * m[j]);
  default:
    EACH(r[j] += m[j] * x[j] * z[j]);
  }
  return ((((r[0] + r[1]) + r[2]) + r[3]) + r[4]) + r[5];
}
#undef EACH

static inline size_t block_end(const op *o, size_t B) {
  return (B + 1) * BLOCK < o->s->p.n ? (B + 1) * BLOCK : o->s->p.n;
}

/* Blocks B0..B1 (a pair's both sides when B < hi, A's alone otherwise), each block's
 * rows finished (y = M^{-1} y, and its share of y.x) once passed. */
static void blocks_pass(op *o, size_t B0, size_t B1, size_t hi) {
  for (size_t B = B0; B < B1; B++) {
    o->cnt[B] = range_pass(o, o->poff[B], o->poff[B + 1], o->woff[B], o->woff[B + 1], hi);
    o->part[B] = vec_rows(o->s, V_MINV_DOT, 0, 0, o->y, (double *)o->x, B * BLOCK,
                          block_end(o, B));
  }
}

/* range r of the threaded pass: B's side of the pairs entering its rows from earlier
 * ranges, then its blocks */
static void range_task(op *o, size_t r) {
  esf_stab_contact c;
  double d[4];
  for (size_t j = o->inoff[r]; j < o->inoff[r + 1]; j++) {
    size_t k = o->in[j];
    pair_near(o->s, k, d);
    if (pair_contact_at(o->s, k, d, o->flag[k] >> 1, &c)) apply_c(o, &c, 2);
  }
  size_t B1 = o->rb[r + 1];
  blocks_pass(o, o->rb[r], B1, B1 > 0 ? block_end(o, B1 - 1) : 0);
}

/* The blocks' first candidates of a list sorted by A (0: not sorted) */
static int offsets(const esf_candidates *c, size_t nblk, size_t *off) {
  for (size_t k = 1; k < c->n; k++)
    if (c->a[k] < c->a[k - 1]) return 0;
  for (size_t B = 0, k = 0; B <= nblk; B++) {
    while (k < c->n && c->a[k] < B * BLOCK) k++;
    off[B] = k;
  }
  return 1;
}

/* The plan: the blocks' candidates when the lists are sorted by A with B >= A
 * (o->poff); with threads, one range of whole blocks a thread (even in pair
 * candidates) and the touching pairs entering each range from earlier ones (o->in).
 * Without it, the whole passes (the same bits). */
static void op_plan(op *o) {
  const esf_candidates *pp = &o->s->nb.pp;
  size_t nb = o->nblk, nr = (size_t)o->nth < nb ? (size_t)o->nth : nb, *in = NULL;
  esf_stab_contact c;
  if ((o->flag = malloc(pp->n ? pp->n : 1)))
    for (size_t k = 0; k < pp->n; k++)
      o->flag[k] = pair_contact(o->s, k, &c) ? (uint8_t)(1 | c.slip << 1) : 0;
  size_t *off = malloc((3 * nb + 2 * nr + 4) * sizeof *off);
  if (!o->flag || !off || !offsets(pp, nb, off) ||
      !offsets(&o->s->nb.pw, nb, off + nb + 1)) {
    free(off);
    return;
  }
  for (size_t k = 0; k < pp->n; k++)
    if (pp->b[k] < pp->a[k]) {
      free(off);
      return;
    }
  o->poff = off, o->woff = off + nb + 1;
  if (nr < 2) return;
  size_t *rb = off + 2 * nb + 2, *inoff = rb + nr + 1, *rof = inoff + nr + 1, tot = 0;
  for (size_t r = 0, B = 0; r <= nr; r++) { /* range r: blocks rb[r] .. rb[r + 1] */
    while (B < nb && o->poff[B] < pp->n * r / nr) B++;
    rb[r] = r == nr ? nb : B;
  }
  for (size_t r = 0; r < nr; r++)
    for (size_t B = rb[r]; B < rb[r + 1]; B++) rof[B] = r;
  memset(inoff, 0, (nr + 1) * sizeof *inoff);
  for (size_t k = 0; k < pp->n; k++) {
    size_t rt = rof[pp->b[k] / BLOCK];
    if (rt != rof[pp->a[k] / BLOCK] && (o->flag[k] & 1u)) inoff[rt + 1]++, tot++;
  }
  for (size_t r = 0; r < nr; r++) inoff[r + 1] += inoff[r];
  if (!(in = malloc((tot ? tot : 1) * sizeof *in))) return; /* serial */
  size_t *fill = o->cnt;                                    /* the ranges' next entries */
  memcpy(fill, inoff, nr * sizeof *fill);
  for (size_t k = 0; k < pp->n; k++) {
    size_t rt = rof[pp->b[k] / BLOCK];
    if (rt != rof[pp->a[k] / BLOCK] && (o->flag[k] & 1u)) in[fill[rt]++] = k;
  }
  o->nr = nr, o->rb = rb, o->inoff = inoff, o->in = in;
}

/* Top eigenpair of the m x m tridiagonal (al, be): its value, and s (m) */
static int tridiag_top(const double *al, const double *be, int m, double *theta,
                       double *s) {
  gsl_matrix *T = gsl_matrix_calloc((size_t)m, (size_t)m);
  gsl_matrix *V = gsl_matrix_alloc((size_t)m, (size_t)m);
  gsl_vector *e = gsl_vector_alloc((size_t)m);
  gsl_eigen_symmv_workspace *w = gsl_eigen_symmv_alloc((size_t)m);
  int ok = T && V && e && w;
  if (ok) {
    for (int j = 0; j < m; j++) {
      gsl_matrix_set(T, (size_t)j, (size_t)j, al[j]);
      if (j + 1 < m) {
        gsl_matrix_set(T, (size_t)j, (size_t)j + 1, be[j + 1]);
        gsl_matrix_set(T, (size_t)j + 1, (size_t)j, be[j + 1]);
      }
    }
    gsl_eigen_symmv(T, e, V, w);
    size_t top = gsl_vector_max_index(e);
    *theta = gsl_vector_get(e, top);
    for (int j = 0; j < m; j++) s[j] = gsl_matrix_get(V, (size_t)j, top);
  }
  if (w) gsl_eigen_symmv_free(w);
  gsl_vector_free(e);
  gsl_matrix_free(V);
  gsl_matrix_free(T);
  return ok ? ESF_OK : ESF_ENOMEM;
}

/* Thread t of T: vector operation `kind` on the blocks of its ranges (all blocks
 * without a threaded plan), their shares of its inner product in part (or not kept) */
static void own_vec(const op *o, int t, int T, int kind, double c, double c2, double *u,
                    double *v, double *part) {
  const size_t nr = o->in ? o->nr : 1;
  for (size_t r = (size_t)t; r < nr; r += (size_t)T) {
    const size_t B1 = o->in ? o->rb[r + 1] : o->nblk;
    for (size_t B = o->in ? o->rb[r] : 0; B < B1; B++) {
      double q = vec_rows(o->s, kind, c, c2, u, v, B * BLOCK, block_end(o, B));
      if (part) part[B] = q;
    }
  }
}

/* Thread t of T: y = M^{-1} (y + K' x) on the rows of its ranges, the blocks' shares
 * of y.x in o->part and their contacts in o->cnt */
static void own_op(op *o, int t, int T) {
  if (!o->poff) { /* lists not sorted (one thread): the whole pass, then the rows */
    memset(o->cnt, 0, o->nblk * sizeof *o->cnt);
    o->cnt[0] = range_pass(o, 0, o->s->nb.pp.n, 0, o->s->nb.pw.n, SIZE_MAX);
    own_vec(o, 0, 1, V_MINV_DOT, 0, 0, o->y, (double *)o->x, o->part);
  } else if (!o->in)
    blocks_pass(o, 0, o->nblk, SIZE_MAX);
  else
    for (size_t r = (size_t)t; r < o->nr; r += (size_t)T) range_task(o, r);
}

static double sum_parts(const op *o, const double *part) {
  double r = 0;
  for (size_t B = 0; B < o->nblk; B++) r += part[B];
  return r;
}

/* One Lanczos pass's state, shared by its threads */
typedef struct lz {
  op *o;
  double *u, *v, *y, *al, *be, *s, *theta, *part2;
  int *m, mm, second, stop, rc;
  _Atomic long bar; /* arrivals at the barriers (only grows) */
} lz;

/* the T threads' e-th barrier */
static void sync_all(lz *L, long e, int T) {
  if (T < 2) return;
  atomic_fetch_add_explicit(&L->bar, 1, memory_order_acq_rel);
  esf_threads_wait(&L->bar, e * T);
}

/* Lanczos with two vectors (Paige's form: u <- A v - beta u, alpha = u.v, u -= alpha
 * v, then the two swap roles) by thread t of T, each on its ranges' rows, meeting at
 * the inner products and before each operator (which reads other ranges' rows); the
 * inner products are the blocks' shares summed in block order by every thread, so all
 * see the same values, and thread 0 keeps the tridiagonal. Second pass (y): sums the
 * Ritz vector y = sum s_j v_j of the first pass's m steps. */
static void lz_thread(lz *L, int t, int T) {
  op o = *L->o; /* this thread's x, y */
  double *u = L->u, *v = L->v, *pa = o.part, *pb = L->part2;
  long e = 0;
  own_vec(&o, t, T, V_START, 0, 0, v, NULL, pa);
  sync_all(L, ++e, T);
  own_vec(&o, t, T, V_DIV, sqrt(sum_parts(&o, pa)), 0, v, NULL, NULL); /* unit in M */
  own_vec(&o, t, T, V_SCALE, -L->be[0], 0, u, NULL, NULL); /* later V_STEP's */
  sync_all(L, ++e, T);
  for (int j = 0; j < L->mm; j++) {
    if (L->y) own_vec(&o, t, T, V_ADD, L->s[j], 0, L->y, v, NULL);
    if (L->second && j + 1 == L->mm) break;
    /* u = M^{-1} (K' v - beta_j M u): the contacts add into M times the old term */
    o.x = v, o.y = u;
    own_op(&o, t, T);
    sync_all(L, ++e, T);
    const double a = L->second ? L->al[j] : sum_parts(&o, pa); /* u.v */
    if (t == 0) {
      L->o->contacts = 0;
      for (size_t B = 0; B < o.nblk; B++) L->o->contacts += o.cnt[B];
    }
    double b = L->be[j + 1]; /* b = |u - alpha v| (V_STEP stores u - alpha v) */
    if (!L->second) {
      own_vec(&o, t, T, V_RES_DOT, a, 0, u, v, pb);
      sync_all(L, ++e, T);
      b = sqrt(sum_parts(&o, pb));
      int last = j + 1 == L->mm || !(b > 1e-14 * fabs(a));
      if (t == 0) L->al[j] = a, L->be[j + 1] = b;
      if (last || (j + 1) % LZ_EVERY == 0) {
        if (t == 0) {
          L->rc = tridiag_top(L->al, L->be, j + 1, L->theta, L->s);
          if (!L->rc) *L->m = j + 1;
          L->stop = L->rc || last || b * fabs(L->s[j]) <= LZ_TOL * fabs(*L->theta);
        }
        sync_all(L, ++e, T);
        if (L->stop) return;
      }
    }
    if (!(b > 0)) break;
    own_vec(&o, t, T, V_STEP, b, a, u, v, NULL); /* (u, v) <- (-b M v, (u - a v) / b) */
    double *w = u;
    u = v, v = w;
    sync_all(L, ++e, T);
  }
}

/* One Lanczos pass (the second with y), threaded by the plan's ranges */
static int lanczos(op *o, double *u, double *v, size_t nd, double *al, double *be, int *m,
                   double *theta, double *s, double *y) {
  lz L = {.o = o, .u = u, .v = v, .y = y, .al = al, .be = be, .s = s};
  L.theta = theta, L.part2 = o->part + o->nblk, L.m = m;
  L.mm = y ? *m : LZ_MAX, L.second = y != NULL, L.stop = L.rc = 0;
  atomic_init(&L.bar, 0);
  memset(u, 0, nd * sizeof *u);
  if (y) memset(y, 0, nd * sizeof *y);
  if (!y) be[0] = 0;
  const int T = o->in ? (int)o->nr : 1;
#pragma omp parallel num_threads(T) if (T > 1)
  {
#ifdef _OPENMP
    lz_thread(&L, omp_get_thread_num(), omp_get_num_threads());
#else
    lz_thread(&L, 0, 1);
#endif
  }
  return L.rc;
}

/* The energy y.G^T S G.y of each contact in the mode y; the largest names the mode. */
typedef struct share {
  const double *y;
  double best;
  size_t a;
  long b;
} share;

static void share_one(const esf_stab_contact *c, void *ctx) {
  share *h = ctx;
  const int wall = c->b < 0;
  double ya[6] = {0}, yb[6] = {0}, e = 0;
  const double *xa = h->y + 6 * c->a, *xb = wall ? NULL : h->y + 6 * (size_t)c->b;
  esf_stab_contact_apply(c->n, c->slip ? c->t : NULL, c->la, c->lb, c->kc[0], c->kc[1],
                         xa, xb, ya, wall ? NULL : yb);
  if (c->roll)
    esf_stab_roll_apply(c->n, c->kr[0], c->kr[1], xa, xb, ya, wall ? NULL : yb);
  for (int j = 0; j < 6; j++) e += xa[j] * ya[j] + (wall ? 0.0 : xb[j] * yb[j]);
  if (e > h->best) h->best = e, h->a = c->a, h->b = c->b;
}

/* The top mode of the Ritz vector y (unit in M): frequency, damping ratio, the step at
 * which it reaches 4 with the local damping factor fl, and the contact that stores most
 * of its energy; w is scratch. */
static void top_mode(op *o, const double *y, double *w, size_t nd, double fl,
                     esf_stability *out) {
  const esf_sim *s = o->s;
  o->ck = 1, o->cc = 0; /* a = y.K.y, b = y.C.y */
  memset(w, 0, nd * sizeof *w);
  op_apply(o, y, w);
  double a = 0, b = 0;
  for (size_t q = 0; q < nd; q++) a += y[q] * w[q];
  o->ck = 0, o->cc = 1;
  memset(w, 0, nd * sizeof *w);
  op_apply(o, y, w);
  for (size_t q = 0; q < nd; q++) b += y[q] * w[q];
  out->omega = a > 0 ? sqrt(a) : 0.0;
  out->xi = a > 0 ? b / (2 * out->omega) : 0.0;
  /* fl (dt^2 a + 2 dt b) = 4 */
  out->dt_limit = a > 0 ? (-b + sqrt(b * b + 4 * a / fl)) / a : INFINITY;
  share h = {.y = y, .best = -1};
  esf_stab_contacts(s, share_one, &h);
  if (h.best >= 0) {
    out->id = s->p.id[h.a];
    out->other = h.b >= 0 ? s->p.id[h.b] : -1;
  }
}

int esf_stability_estimate(esf_sim *s, double dt, int with_mode, esf_stability *out,
                           esf_error *err) {
  size_t nd = 6 * s->p.n;
  *out = (esf_stability){.id = -1, .other = -2, .dt_limit = INFINITY};
  if (nd == 0) return ESF_OK;
  /* two vectors, a third for the top mode's second pass (48 bytes a particle each) */
  const size_t nblk = (s->p.n + BLOCK - 1) / BLOCK;
  double *buf = malloc((with_mode ? 3 : 2) * nd * sizeof *buf);
  double *al = malloc((2 * (LZ_MAX + 2) + LZ_MAX + 2 * nblk) * sizeof *al);
  size_t *cnt = malloc(nblk * sizeof *cnt);
  if (!buf || !al || !cnt) {
    free(buf), free(al), free(cnt);
    return esf_fail(err, ESF_ENOMEM, "stability check: out of memory for %zu particles",
                    s->p.n);
  }
  double *be = al + LZ_MAX + 2, *sv = be + LZ_MAX + 2, *u = buf, *v = buf + nd;
  const double fl = s->local ? 1.0 + s->cfg.local_coef : 1.0;
  op o = {.s = s,
          .ck = fl * dt * dt,
          .cc = fl * 2.0 * dt,
          .nth = s->cfg.threads > 1 ? s->cfg.threads : 1,
          .nblk = nblk,
          .part = sv + LZ_MAX,
          .cnt = cnt};
  op_plan(&o);
  int m = 0;
  double theta = 0;
  int rc = lanczos(&o, u, v, nd, al, be, &m, &theta, sv, NULL);
  out->lambda = theta > 0 ? theta : 0.0;
  out->iters = m;
  out->contacts = o.contacts;
  if (!rc && with_mode && o.contacts > 0 && m > 0) {
    double *y = buf + 2 * nd;
    rc = lanczos(&o, u, v, nd, al, be, &m, &theta, sv, y); /* regenerates the v_j */
    own_vec(&o, 0, 1, V_DOT, 0, 0, y, y, o.part);
    double ny = sqrt(sum_parts(&o, o.part));
    if (ny > 0) own_vec(&o, 0, 1, V_DIV, ny, 0, y, NULL, NULL);
    if (!rc) top_mode(&o, y, u, nd, fl, out);
  }
  free(o.poff);
  free(o.in);
  free(o.flag);
  free(cnt);
  free(buf);
  free(al);
  return rc;
}

int esf_stability_limit(esf_sim *s, double *dt_limit, esf_stability *top,
                        esf_error *err) {
  double dt = s->dt > 0 ? s->dt : 1.0;
  *dt_limit = INFINITY;
  for (int it = 0; it < 30; it++) {
    int rc = esf_stability_estimate(s, dt, 1, top, err);
    if (rc) return rc;
    if (!isfinite(top->dt_limit)) return ESF_OK;
    double prev = dt;
    dt = top->dt_limit;
    if (fabs(dt - prev) <= 1e-6 * dt) break;
  }
  *dt_limit = dt;
  return ESF_OK;
}
