/* material.h — materials and the contact parameters of every pair of materials.
 *
 * A material carries the per-surface properties of
 * docs/physics.md#material-parameters-and-mixing (stiffnesses, restitution, friction,
 * cohesion). The parameters of a contact between materials a and b (a particle-particle
 * or a particle-wall contact) are mixed from the two materials' by one rule per
 * property (esf_mixing), so that a pair of equal materials gets exactly the material's
 * own values under every rule. The mixed table is n x n, symmetric. */
#ifndef ESF_MATERIAL_H
#define ESF_MATERIAL_H

#include <stdint.h>

#include "util/esf_error.h"

#define ESF_NAME_MAX 64

typedef struct esf_material {
  char name[ESF_NAME_MAX];
  double density;                /* kg/m^3 (ignored for walls) */
  double kn;                     /* normal stiffness, N/m */
  double kt;                     /* tangential stiffness, N/m */
  double restitution;            /* normal restitution coefficient eta, (0, 1] */
  double tangential_restitution; /* eta_t for the tangential dashpot, (0, 1] */
  double friction;               /* Coulomb coefficient mu = tan(phi) */
  double cohesion;               /* c of the Mohr-Coulomb surface, N */
  double tensile_limit;          /* tension cut-off, N (>= 0); < 0: none given */
  double adhesion_force;         /* F of the adhesive law (004 2.23), N; 0: none */
  double adhesion_epsilon;       /* its epsilon, (0, 1) without 1/e */
  double adhesion_gap;           /* bond_gap: pairs this close at the start bond, m */
  double youngs_modulus;         /* E of the Hertz-Mindlin law, Pa; 0: linear (kn) */
  double poisson_ratio;          /* its nu, [0, 0.5) */
} esf_material;

/* Mixing rules. For equal values every rule returns that value. */
enum {
  ESF_MIX_HARMONIC = 0, /* 2ab/(a+b): series springs of two half-contacts of 2a and 2b */
  ESF_MIX_ARITHMETIC,   /* (a+b)/2 */
  ESF_MIX_GEOMETRIC,    /* sqrt(ab) */
  ESF_MIX_MIN,
  ESF_MIX_MAX,
  ESF_MIX_COUNT
};
extern const char *const esf_mix_names[]; /* "harmonic", ..., NULL */

/* One rule per mixed property. */
typedef struct esf_mixing {
  int kn, kt, restitution, tangential_restitution, friction, cohesion, tensile_limit;
  int adhesion_force, adhesion_epsilon, adhesion_gap; /* min, geometric, min */
} esf_mixing;

/* The defaults: kn, kt harmonic (001 3.45, series springs); restitution, tangential
 * restitution and friction min; cohesion and tensile limit min. */
void esf_mixing_default(esf_mixing *m);

double esf_mix(int rule, double a, double b);

/* The adhesive law's parameters for one pair
 * (docs/physics.md#adhesive-normal-law-and-bonds, contact_adhesive.c): overlaps u in m,
 * positive when interpenetrating. */
typedef struct esf_adhesion {
  double F, eps;    /* the inputs: largest tensile force (N) and epsilon */
  double delta;     /* m, 004 (2.23) */
  double alpha;     /* 1/m, 004 (2.24); alpha delta = -ln eps */
  double u_peak;    /* overlap of the largest tension F, ln(alpha delta)/alpha, m */
  double u_rupture; /* where a bond opens: 0 (eps < 1/e) or the negative root, m */
  double u_eq;      /* stable rest overlap of a bond: the positive root, or 0, m */
  double k_max;     /* largest |df/du| over u >= u_rupture, N/m */
  double gap;       /* bond_gap of the pair (bonds.h), m */
} esf_adhesion;

struct esf_contact_law;

/* The mixed parameters of one material pair. */
typedef struct esf_pair_params {
  const struct esf_contact_law *law; /* linear, or adhesive when both materials are */
  double kn, kt;                     /* N/m */
  double gamma_n, gamma_t;           /* damping ratios from restitution, 004 (2.28) */
  double cn_factor;                  /* c_n = cn_factor * sqrt(m*), N s/m / sqrt(kg) */
  double ct_factor;                  /* c_t = ct_factor * sqrt(m*) */
  double mu;                         /* friction coefficient */
  double cohesion;                   /* N */
  double tensile_limit; /* N, >= 0: the shear strength vanishes when f_n < -limit */
  esf_adhesion adh;     /* the adhesive law's parameters (law = adhesive only) */
  /* Hertz-Mindlin (law = hertz; kn = kt = 0 then; docs/physics.md#hertz-mindlin-law):
     cn_factor, ct_factor are 2 gamma sqrt(1.5 hn) and 2 gamma_t sqrt(ht) (tsuji: c =
     factor sqrt(m*) a^(1/2)), or the constant dashpots' 2 gamma sqrt(S(u_ref)) */
  double estar, gstar; /* effective moduli E*, G*, Pa */
  double hn, ht;       /* (4/3) E* and 8 G*, Pa */
  int hertz_constant;  /* the constant dashpots (contact.hertz_damping: constant) */
  double v_imp;        /* their impact speed (esf_materials.impact_speed), m/s */
} esf_pair_params;

typedef struct esf_materials {
  int n;
  esf_material *m;
  esf_pair_params *pair; /* n*n, pair[a*n + b] */
  esf_mixing mixing;
  double rayleigh_beta; /* > 0: contact dashpots c = beta k (001 3.47) replace the
                           restitution-derived ones */
  /* summaries of the pair table, for the fused step's choices (fused/fused.c) */
  int hertz_constant;  /* contact.hertz_damping: constant (1) or tsuji (0) */
  double impact_speed; /* integrator.impact_speed, m/s (the constant dashpots' u_ref) */
  int all_linear;      /* every pair uses the linear law (esf_materials_mix) */
  int all_hertz;       /* every pair uses the Hertz-Mindlin law (esf_materials_mix) */
  int any_cohesion;    /* some pair has cohesion != 0 (esf_materials_mix) */
  int particles_fused; /* every pair of two materials that particles use has a law the
                          fused step computes (ESF_LAW_FUSED; esf_bonds_setup sets it) */
} esf_materials;

/* gamma = -ln(eta) / sqrt(pi^2 + ln^2 eta), 004 (2.28); 0 for eta = 1. */
double esf_restitution_gamma(double eta);

/* The Hertz-Mindlin law's damping ratio gamma for restitution eta (hertz_map.c): the
 * exact inverse of the restitution of the damped Hertz oscillator with the no-tension
 * cut, m u'' = -k u^(3/2) - 2 gamma sqrt(m (3/2) k u^(1/2)) u' (force >= 0), which does
 * not depend on the impact speed; 0 for eta >= 1. */
double esf_hertz_gamma(double eta);
/* The restitution of that oscillator for damping ratio gamma (>= 0). */
double esf_hertz_restitution(double gamma);
/* As esf_hertz_gamma for cst = 0; cst = 1: for the constant dashpot 2 gamma sqrt(m*
 * S_n(u_p)), u_p the undamped peak overlap at the impact speed (exact at that speed). */
double esf_hertz_gamma_form(double eta, int cst);

/* Adds a material (copied); returns its index in *index. Error on a duplicate name. */
int esf_materials_add(esf_materials *t, const esf_material *m, int32_t *index,
                      esf_error *err);
/* Index of a material by name, or -1. */
int32_t esf_materials_find(const esf_materials *t, const char *name);
/* Builds the pair table from the materials and the mixing rules. */
int esf_materials_mix(esf_materials *t, esf_error *err);
void esf_materials_release(esf_materials *t);

#endif
