/* test_contact_lanes.c — the fused step's eight-lane batches (fused/pair_batch.c) give
 * the scalar contact law of the general path (contact/contact_linear.h, both built
 * from contact/law_body.h) bit for bit, pair by pair, with the kernels of every
 * instruction set this CPU runs (base, AVX2, AVX-512).
 *
 * 4000 random pairs of two materials (one with cohesion) in every state a batch meets:
 * new contacts (history not live) and old ones carrying a tangential displacement in a
 * tilted plane, sticking and sliding (history up to three times the Coulomb limit),
 * approaching and separating (dashpot cut to zero in tension), spheres apart (the
 * contact ends: its flag cleared, nothing else written) and overlaps past the limit
 * (reported, nothing committed). Each case runs with the seed's rotated frame and the
 * projected one, with restitution dashpots and Rayleigh ones, with one material
 * broadcast and with per-pair parameters; the pairs go through the batches in a
 * shuffled order and in batches of 1 to 8 lanes, and without rolling resistance, with
 * epsd and with cdt (states of the rolling and twisting springs up to three times
 * their limits, in a tilted plane; torques composed as model/forces.c does), for the
 * linear law and for the Hertz-Mindlin law (tsuji and constant dashpots; rolling's kn
 * then the normal tangent stiffness S_n at the overlap). Compared
 * with memcmp: the force on A, the torques on A and B, the committed history, rolling
 * state and touch flag, the failure and apart masks. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "contact/contact_hertz.h"
#include "contact/contact_linear.h"
#include "contact/contact_rolling.h"
#include "contact/lane_scalar.h"
#include "contact/material.h"
#include "fused/fused_impl.h"
#include "util/rng.h"
#include "util/vec3.h"

enum { NP = 4000 };

typedef struct cases {
  double y[9 * 2 * NP + 1]; /* x | v | w of 2 NP particles, one spare (pair_batch.h) */
  double radius[2 * NP], mass[2 * NP], inertia[2 * NP], sm[NP];
  int32_t material[2 * NP];
  uint32_t a[NP], b[NP];
  esf_contact_hist h[NP];
  esf_contact_roll roll[NP];
  uint8_t touch[NP];
} cases;

static double uni(esf_rng *r, double lo, double hi) {
  return lo + (hi - lo) * esf_rng_uniform(r);
}

/* Pair k: A at the origin-ish, B along a random direction at a gap or overlap of up to
 * 8% of the radii (the limit is 5%), velocities and spins of a rattling bed, a history
 * from zero to three times the Coulomb limit in a plane tilted a little from the
 * current one. */
static void make(cases *c, esf_rng *r) {
  const size_t n = 2 * NP;
  double *x = c->y, *v = c->y + 3 * n, *w = c->y + 6 * n;
  for (size_t k = 0; k < NP; k++) {
    const size_t ia = 2 * k, ib = 2 * k + 1;
    c->a[k] = (uint32_t)ia;
    c->b[k] = (uint32_t)ib;
    const double ra = uni(r, 1e-3, 3e-3), rb = uni(r, 1e-3, 3e-3);
    c->radius[ia] = ra;
    c->radius[ib] = rb;
    c->material[ia] = (int32_t)(k % 2);
    c->material[ib] = (int32_t)((k / 2) % 2);
    c->mass[ia] = 2500 * 4.18879 * ra * ra * ra;
    c->mass[ib] = 2500 * 4.18879 * rb * rb * rb;
    c->sm[k] = sqrt(c->mass[ia] * c->mass[ib] / (c->mass[ia] + c->mass[ib]));
    c->inertia[ia] = 0.4 * c->mass[ia] * ra * ra;
    c->inertia[ib] = 0.4 * c->mass[ib] * rb * rb;
    double u[3] = {uni(r, -1, 1), uni(r, -1, 1), uni(r, -1, 1)};
    v3_scale(u, 1.0 / v3_norm(u), u);
    /* overlap from -0.3 to 1.3 times the limit, 5% of the smaller radius */
    const double gap = -uni(r, -0.3, 1.3) * 0.05 * fmin(ra, rb);
    for (int q = 0; q < 3; q++) {
      x[3 * ia + q] = uni(r, -0.01, 0.01);
      x[3 * ib + q] = x[3 * ia + q] + (ra + rb + gap) * u[q];
      v[3 * ia + q] = uni(r, -0.2, 0.2);
      v[3 * ib + q] = uni(r, -0.2, 0.2);
      w[3 * ia + q] = uni(r, -50, 50);
      w[3 * ib + q] = uni(r, -50, 50);
    }
    double t[3] = {uni(r, -1, 1), uni(r, -1, 1), uni(r, -1, 1)}, hn[3];
    for (int q = 0; q < 3; q++) hn[q] = u[q] + 0.05 * t[q];
    v3_scale(hn, 1.0 / v3_norm(hn), hn);
    v3_axpy(t, -v3_dot(t, hn), hn); /* in the old plane */
    const double mag = uni(r, 0, 3) * 0.5 * fmax(-gap, 0) * 1e4 / 2857.0;
    v3_scale(c->h[k].xi, mag / fmax(v3_norm(t), 1e-300), t);
    v3_copy(c->h[k].n, hn);
    /* rolling state: up to three times mu_r R* kn un (mu_r 0.2, kn 1e4) */
    double s[3] = {uni(r, -1, 1), uni(r, -1, 1), uni(r, -1, 1)};
    v3_axpy(s, -v3_dot(s, hn), hn);
    const double lim = 0.2 * ra * rb / (ra + rb) * 1e4 * fmax(-gap, 0);
    v3_scale(c->roll[k].m, uni(r, 0, 3) * lim / fmax(v3_norm(s), 1e-300), s);
    c->roll[k].t = uni(r, -3, 3) * 0.5 * lim;
    c->touch[k] = (uint8_t)(esf_rng_uniform(r) < 0.75);
  }
  c->y[9 * n] = 0.0;
}

typedef struct result {
  double f[3], ta[3], tb[3];
  esf_contact_hist h;
  esf_contact_roll roll;
  uint8_t touch;
  int bad, apart;
  int sliding; /* the scalar law's report (not compared: the batch gives none) */
} result;

/* The general path's evaluation of pair k (model/forces.c's order of operations). */
static result scalar(const cases *c, const esf_materials *mt, double beta, int tframe,
                     double dt, double max_overlap, int roll, size_t k) {
  const size_t n = 2 * NP, ia = c->a[k], ib = c->b[k];
  const double *x = c->y, *v = c->y + 3 * n, *w = c->y + 6 * n;
  result r = {.touch = c->touch[k], .h = c->h[k], .roll = c->roll[k]};
  double d[3], d2, la, lb;
  const double ra = c->radius[ia], rb = c->radius[ib];
  if (!esf_law_pair_overlap_s(x + 3 * ia, x + 3 * ib, ra, rb, d, &d2)) {
    r.apart = 1;
    r.touch = 0;
    return r;
  }
  esf_contact_in in;
  esf_law_pair_kinematics_s(d, d2, ra, rb, v + 3 * ia, v + 3 * ib, w + 3 * ia, w + 3 * ib,
                            in.n, &in.un, &la, &lb, in.vc);
  if (in.un > max_overlap * fmin(ra, rb)) {
    r.bad = 1;
    return r;
  }
  in.spin_n = 0.5 * (v3_dot(w + 3 * ia, in.n) + v3_dot(w + 3 * ib, in.n));
  in.mstar = c->mass[ia] * c->mass[ib] / (c->mass[ia] + c->mass[ib]);
  in.rstar = ra * rb / (ra + rb);
  in.dt = dt;
  in.vinc = NULL;
  const esf_pair_params *pp = &mt->pair[c->material[ia] * mt->n + c->material[ib]];
  esf_contact_out out;
  if (mt->all_hertz)
    esf_contact_hertz_eval(pp, beta, tframe, &in, &c->h[k], !c->touch[k], &r.h, &out);
  else
    esf_contact_linear_eval(pp, beta, tframe, &in, &c->h[k], !c->touch[k], &r.h, &out);
  double m[3];
  v3_cross(m, in.n, out.ft);
  v3_copy(r.f, out.f);
  v3_scale(r.ta, la, m);
  v3_scale(r.tb, lb, m);
  if (roll) { /* model/forces.c's rolling(): M added to A's, subtracted from B's */
    double wrel[3], rs, ir, itw;
    v3_sub(wrel, w + 3 * ia, w + 3 * ib);
    esf_law_rolling_pair_s(ra, rb, c->mass[ia], c->mass[ib], c->inertia[ia],
                           c->inertia[ib], &rs, &ir, &itw);
    esf_law_rout_s o;
    esf_contact_rolling(pp, roll == 2 ? ESF_ROLL_CDT : ESF_ROLL_EPSD,
                        esf_contact_rolling_kn(pp, rs, in.un), 0, 0.0, rs, ir, itw,
                        out.fn, dt, in.n, wrel, NULL, &c->roll[k], c->touch[k], &o);
    for (int q = 0; q < 3; q++) {
      r.ta[q] += o.md[q] + o.ms[q];
      r.tb[q] -= o.md[q] + o.ms[q];
      r.roll.m[q] = o.hm[q];
    }
    r.roll.t = o.ht;
  }
  r.touch = 1;
  r.sliding = out.sliding;
  return r;
}

/* Every pair through the batches of one kernel set, in the order ord, nl lanes at a
 * time (cycling 1 .. 8); the results per pair. */
static void batched(const esf_fused_kernels *K, cases *c, const esf_materials *mt,
                    const esf_pair_params *one, double beta, int tframe, int cohesion,
                    double dt, double max_overlap, int roll, const uint32_t *ord,
                    result *res) {
  esf_contact_hist *h = malloc(NP * sizeof *h);
  esf_contact_roll *rl = malloc(NP * sizeof *rl);
  uint8_t *touch = malloc(NP);
  memcpy(h, c->h, NP * sizeof *h);
  memcpy(rl, c->roll, NP * sizeof *rl);
  memcpy(touch, c->touch, NP);
  const size_t n = 2 * NP;
  const esf_pair_batch_ctx ctx = {.x = c->y,
                                  .v = c->y + 3 * n,
                                  .w = c->y + 6 * n,
                                  .radius = c->radius,
                                  .material = c->material,
                                  .mt = mt,
                                  .one = one,
                                  .a = c->a,
                                  .b = c->b,
                                  .h = h,
                                  .touch = touch,
                                  .sm = c->sm,
                                  .beta = beta,
                                  .dt = dt,
                                  .max_overlap = max_overlap,
                                  .rotate = tframe == ESF_TFRAME_ROTATE,
                                  .cohesion = cohesion,
                                  .roll = roll ? rl : NULL,
                                  .mass = c->mass,
                                  .inertia = c->inertia,
                                  .roll_cdt = roll == 2,
                                  .hertz = mt->all_hertz,
                                  .hertz_cst = mt->hertz_constant};
  double out[ESF_BATCH][ESF_BATCH_OUT];
  for (size_t q0 = 0, nl = 1; q0 < NP; q0 += nl, nl = nl % ESF_BATCH + 1) {
    if (q0 + nl > NP) nl = NP - q0;
    unsigned apart = 0;
    const unsigned fail = K->batch(&ctx, ord + q0, (int)nl, out, NULL, &apart);
    for (size_t l = 0; l < nl; l++) {
      const size_t k = ord[q0 + l];
      result *r = &res[k];
      memset(r, 0, sizeof *r);
      r->bad = (int)(fail >> l & 1u);
      r->apart = (int)(apart >> l & 1u);
      if (!r->bad && !r->apart) {
        memcpy(r->f, out[l], sizeof r->f);
        memcpy(r->ta, out[l] + 4, sizeof r->ta);
        memcpy(r->tb, out[l] + 8, sizeof r->tb);
      }
    }
  }
  for (size_t k = 0; k < NP; k++) {
    res[k].h = h[k];
    res[k].roll = rl[k];
    res[k].touch = touch[k];
  }
  free(rl);
  free(h);
  free(touch);
}

/* The same bits: every field that both evaluations define. */
static int same(const result *a, const result *b) {
  if (a->bad != b->bad || a->apart != b->apart || a->touch != b->touch) return 0;
  if (a->bad) /* nothing committed */
    return memcmp(&a->h, &b->h, sizeof a->h) == 0 &&
           memcmp(&a->roll, &b->roll, sizeof a->roll) == 0;
  if (a->apart) return 1;
  return memcmp(a->f, b->f, sizeof a->f) == 0 &&
         memcmp(a->ta, b->ta, sizeof a->ta) == 0 &&
         memcmp(a->tb, b->tb, sizeof a->tb) == 0 &&
         memcmp(&a->h, &b->h, sizeof a->h) == 0 &&
         memcmp(&a->roll, &b->roll, sizeof a->roll) == 0;
}

int main(void) {
  static cases c;
  esf_rng rng;
  esf_rng_seed(&rng, 20261127);
  make(&c, &rng);
  esf_error err;
  esf_error_clear(&err);
  esf_materials mt = {0};
  esf_mixing_default(&mt.mixing);
  esf_material m0 = {.name = "plain",
                     .density = 2500,
                     .kn = 1e4,
                     .kt = 2857.0,
                     .restitution = 0.5,
                     .tangential_restitution = 0.7,
                     .friction = 0.5,
                     .tensile_limit = -1,
                     .rolling_friction = 0.2,
                     .rolling_damping = 0.3,
                     .twisting_friction = 0.1};
  esf_material m1 = m0;
  snprintf(m1.name, sizeof m1.name, "sticky");
  m1.kn = 2e4;
  m1.friction = 0.3;
  m1.cohesion = 0.05;
  m1.rolling_friction = 0.3; /* mixed: min */
  m1.rolling_damping = 0.5;
  int32_t idx;
  CHECK_OK(esf_materials_add(&mt, &m0, &idx, &err), err);
  CHECK_OK(esf_materials_add(&mt, &m1, &idx, &err), err);
  CHECK_OK(esf_materials_mix(&mt, &err), err);
  /* the same two materials as Hertz-Mindlin ones (contact_hertz.h), E chosen so that
     the tangent stiffnesses at these overlaps are near kt: the histories (forces now)
     scaled by kt stay near the Coulomb limit; with tsuji and with constant dashpots */
  esf_materials mth = {0}, mtc = {0};
  esf_mixing_default(&mth.mixing);
  esf_material h0 = m0, h1 = m1;
  h0.kn = h0.kt = h1.kn = h1.kt = 0;
  h0.youngs_modulus = 1e7;
  h0.poisson_ratio = 0.3;
  h1.youngs_modulus = 2.5e7;
  h1.poisson_ratio = 0.2;
  CHECK_OK(esf_materials_add(&mth, &h0, &idx, &err), err);
  CHECK_OK(esf_materials_add(&mth, &h1, &idx, &err), err);
  CHECK_OK(esf_materials_mix(&mth, &err), err);
  CHECK(mth.all_hertz && !mth.all_linear, "two Hertz materials: the Hertz law");
  esf_mixing_default(&mtc.mixing);
  CHECK_OK(esf_materials_add(&mtc, &h0, &idx, &err), err);
  CHECK_OK(esf_materials_add(&mtc, &h1, &idx, &err), err);
  mtc.hertz_constant = 1;
  mtc.impact_speed = 0.5;
  CHECK_OK(esf_materials_mix(&mtc, &err), err);
  static cases ch;
  memcpy(&ch, &c, sizeof c);
  for (size_t k = 0; k < NP; k++) {
    for (int q = 0; q < 3; q++) ch.h[k].xi[q] *= m0.kt;
    /* rolling states on the Hertz force's scale: kn 1e4 -> the secant hn sqrt(R* u) */
    const size_t ia = c.a[k], ib = c.b[k];
    const double ra = c.radius[ia], rb = c.radius[ib], rs = ra * rb / (ra + rb);
    double d[3];
    v3_sub(d, c.y + 3 * ib, c.y + 3 * ia);
    const double u = fmax(ra + rb - v3_norm(d), 0.0);
    const double sc =
        mth.pair[c.material[ia] * mth.n + c.material[ib]].hn * sqrt(rs * u) / m0.kn;
    v3_scale(ch.roll[k].m, sc, ch.roll[k].m);
    ch.roll[k].t *= sc;
  }
  /* the single-material runs use material 0 everywhere */
  cases *one_mat = malloc(sizeof *one_mat), *one_h = malloc(sizeof *one_h);
  memcpy(one_mat, &c, sizeof c);
  for (size_t i = 0; i < 2 * NP; i++) one_mat->material[i] = 0;
  memcpy(one_h, &ch, sizeof ch);
  for (size_t i = 0; i < 2 * NP; i++) one_h->material[i] = 0;

  uint32_t ord[NP];
  for (uint32_t k = 0; k < NP; k++) ord[k] = k;
  for (size_t k = NP - 1; k > 0; k--) { /* shuffled: lanes see every neighbour */
    const size_t j = (size_t)(esf_rng_uniform(&rng) * (double)(k + 1)) % (k + 1);
    const uint32_t t = ord[k];
    ord[k] = ord[j];
    ord[j] = t;
  }
  const char *isas[] = {"base", "avx2", "avx512"};
  static result ref[NP], got[NP];
  int compared = 0;
  long slides = 0, firsts = 0, aparts = 0, bads = 0, cut = 0;
  for (int q = 0; q < 3; q++) {
    esf_fused *f = NULL;
    if (esf_fused_create(&f, isas[q], &err) != ESF_OK) {
      printf("isa %s: not run here (%s)\n", isas[q], err.msg);
      esf_error_clear(&err);
      CHECK(q > 0, "the base kernels must run");
      continue;
    }
    compared++;
    const esf_fused_kernels *K = f->k;
    for (int law = 0; law < 3; law++)      /* linear, Hertz (tsuji), Hertz (constant) */
      for (int roll = 0; roll < 3; roll++) /* none, epsd, cdt */
        for (int tf = 0; tf < 2; tf++)
          for (int rayleigh = 0; rayleigh < 2; rayleigh++)
            for (int single = 0; single < 2; single++) {
              const esf_materials *ml = law == 0 ? &mt : law == 1 ? &mth : &mtc;
              cases *cs = law ? (single ? one_h : &ch) : (single ? one_mat : &c);
              const double beta = rayleigh ? 2e-4 : 0.0, dt = 2e-6, lim = 0.05;
              const int tframe = tf ? ESF_TFRAME_PROJECT : ESF_TFRAME_ROTATE;
              const esf_pair_params *one = single ? &ml->pair[0] : NULL;
              const int cohesion = !single; /* material 1 has cohesion */
              size_t diff = 0, first_diff = NP;
              for (size_t k = 0; k < NP; k++)
                ref[k] = scalar(cs, ml, beta, tframe, dt, lim, roll, k);
              batched(K, cs, ml, one, beta, tframe, cohesion, dt, lim, roll, ord, got);
              for (size_t k = 0; k < NP; k++)
                if (!same(&ref[k], &got[k])) {
                  diff++;
                  if (first_diff == NP) first_diff = k;
                }
              CHECK(diff == 0,
                    "%s law, %s, %s, %s frame, %s dashpots, %s: %zu of %d pairs differ "
                    "(first: pair %zu)",
                    law == 0   ? "linear"
                    : law == 1 ? "Hertz (tsuji)"
                               : "Hertz (constant)",
                    isas[q],
                    roll == 0   ? "no rolling"
                    : roll == 1 ? "epsd"
                                : "cdt",
                    tf ? "projected" : "rotated", rayleigh ? "Rayleigh" : "restitution",
                    single ? "one material" : "two materials", diff, NP, first_diff);
              if (q == 0 && roll == 0 && tf == 0 && rayleigh == 0 && single == 0 &&
                  law < 2)
                for (size_t k = 0; k < NP; k++) { /* what the cases cover */
                  aparts += ref[k].apart;
                  bads += ref[k].bad;
                  if (ref[k].apart || ref[k].bad) continue;
                  firsts += !c.touch[k];
                  cut += -v3_dot(ref[k].f, ref[k].h.n) == 0.0; /* fn */
                  slides += ref[k].sliding;
                }
            }
    esf_fused_free(&f);
  }
  printf(
      "pairs: %d; apart %ld, past the overlap limit %ld, new contacts %ld, normal force "
      "cut to zero %ld, sliding %ld\n",
      NP, aparts, bads, firsts, cut, slides);
  CHECK(aparts > 100 && bads > 100 && firsts > 100 && cut > 10 && slides > 50,
        "the cases cover every state (apart %ld, bad %ld, new %ld, cut %ld, sliding %ld)",
        aparts, bads, firsts, cut, slides);
  printf("kernels compared with the scalar law: %d instruction sets\n", compared);
  free(one_mat);
  free(one_h);
  esf_materials_release(&mt);
  esf_materials_release(&mth);
  esf_materials_release(&mtc);
  return check_finish("contact_lanes");
}
