/* contact_law.h — the contact-law strategy table.
 *
 * A contact law turns the kinematics of one contact (normal, overlap, relative velocity
 * at the contact point) and its history (the tangential elastic displacement and the
 * normal it was last expressed in) into the contact force. Both time integrators call
 * the same law: the leapfrog commits the updated history every step; a Runge-Kutta
 * stage evaluates it without committing (history frozen), and so on.
 *
 * Conventions (docs/physics.md#contact-kinematics): n is the unit normal from A's
 * centre toward B (or toward the wall point); un > 0 is the overlap; vc is the velocity
 * of B's contact point minus A's; forces returned are those acting ON A (B receives the
 * opposite). */
#ifndef ESF_CONTACT_LAW_H
#define ESF_CONTACT_LAW_H

#include <math.h>
#include <stdint.h>

#include "contact/material.h"

/* The kinematics of one contact at the evaluation instant. */
typedef struct esf_contact_in {
  double n[3];   /* unit normal A -> B */
  double un;     /* overlap, m (> 0 when touching) */
  double vc[3];  /* relative velocity of the contact point, B minus A, m/s */
  double spin_n; /* (w_A + w_B).n / 2, rad/s: the contact plane's spin about n (3-18) */
  double mstar;  /* reduced mass, kg (the particle's mass against a wall) */
  double rstar;  /* reduced radius rA rB / (rA + rB), m (rA against a wall) */
  double dt;     /* time over which the tangential increment integrates, s */
  const double *vinc; /* NULL, or the relative velocity to integrate the increment with
                         over dt (its tangential part is taken), m/s */
} esf_contact_in;

/* The history one contact carries between steps (48 bytes, no padding: checkpoints
 * store it raw). */
typedef struct esf_contact_hist {
  double xi[3]; /* tangential elastic displacement, m (force on A = kt xi); Hertz-
                   Mindlin: the elastic tangential force on A itself, N */
  double n[3];  /* the normal xi was last expressed in */
} esf_contact_hist;

/* The bond state of one contact (Phi of 004 2.25; bonds.h): set only at the start of
 * the analysis, cleared for good when the bond ruptures; zero for every other contact.
 * Kept beside the history only by scenes with bonds (esf_candidates.bond), so that the
 * others neither store nor stream it (16 bytes a candidate). */
typedef struct esf_contact_bond {
  double s;      /* offset added to the overlap for the bonded law, m (bond_gap) */
  int32_t on;    /* 1: bonded (Phi = 1) */
  int32_t spare; /* zero: no padding bytes in the record (checkpoints store it raw) */
} esf_contact_bond;

/* What the law returns. */
typedef struct esf_contact_out {
  double f[3];      /* total force on A, N */
  double ft[3];     /* its tangential part, N (the torque arm acts on this) */
  double fn;        /* normal force magnitude, N (> 0 compressive) */
  double fd_n;      /* the normal dashpot's share of fn actually applied, N */
  double fel;       /* the normal spring's force (> 0 repulsive), N */
  double fd_t[3];   /* the tangential dashpot force on A actually applied, N */
  double slip_work; /* friction work of this evaluation (force x slip), J */
  double e_el_n;    /* elastic energy in the normal spring, J */
  double e_el_t;    /* elastic energy in the tangential spring, J */
  double w_st;      /* Hertz: energy given by the tangential stiffness's change, J */
  int touching;     /* 0: no force (separated); history is reset */
  int sliding;      /* 1: the Coulomb cap was active */
  int broke;        /* 1: a bond ruptured in this evaluation (Phi 1 -> 0) */
  double e_break;   /* the energy the bond held when it ruptured, J (broke = 1) */
} esf_contact_out;

/* How the stored tangential displacement follows a turning contact plane. */
enum {
  ESF_TFRAME_ROTATE = 0, /* the seed's two small rotations, 000 (3-17)-(3-18) */
  ESF_TFRAME_PROJECT = 1 /* project on the new plane, rescale to keep |xi| */
};

enum {
  ESF_LAW_HISTORY = 1u << 0, /* carries tangential history */
  ESF_LAW_TENSION = 1u << 1, /* may pull (adhesive) */
  ESF_LAW_FUSED = 1u << 2 /* the fused step's batches compute it (fused/pair_batch.c) */
};

typedef struct esf_contact_law {
  const char *name;
  unsigned flags;
  /* Evaluates the law. hist is read; when hist_out is not NULL the updated history is
   * written there (it may alias hist). `first` marks a contact that was not touching
   * at the last commit: its history starts from zero. bond is the contact's bond
   * state, or NULL (no bond); the law never writes it: a rupture sets out->broke, and
   * the caller that commits clears the bond state. */
  void (*eval)(const esf_pair_params *pp, double beta, int tframe,
               const esf_contact_in *in, const esf_contact_hist *hist,
               const esf_contact_bond *bond, int first, esf_contact_hist *hist_out,
               esf_contact_out *out);
  /* Elastic energy of the normal spring at overlap un for a touching contact with
   * bond state bond (or NULL) and reduced radius rstar (m), J; *fel receives the elastic
   * normal force (> 0 repulsive), N. */
  double (*energy_n)(const esf_pair_params *pp, const esf_contact_bond *bond, double un,
                     double rstar, double *fel);
} esf_contact_law;

/* The tangential spring's force on A of a history record xi: kt xi, or xi itself for
 * the Hertz-Mindlin law (its record is the force), N. */
static inline void esf_contact_ket(const esf_pair_params *pp, const double xi[3],
                                   double ket[3]) {
  for (int q = 0; q < 3; q++) ket[q] = pp->ht > 0 ? xi[q] : pp->kt * xi[q];
}

/* Elastic energy of the tangential spring of a touching contact with history xi at
 * overlap un, reduced radius rstar: (1/2) kt |xi|^2, or for the Hertz-Mindlin law (xi
 * the force) |xi|^2 / (2 S_t), S_t = 8 G* sqrt(R* un), J. */
static inline double esf_contact_energy_t(const esf_pair_params *pp, const double xi[3],
                                          double un, double rstar) {
  const double x2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  if (pp->ht > 0) {
    const double st = un > 0 ? pp->ht * sqrt(rstar * un) : 0.0;
    return st > 0 ? 0.5 * x2 / st : 0.0;
  }
  return 0.5 * pp->kt * x2;
}

extern const esf_contact_law esf_contact_linear;
/* docs/physics.md#hertz-mindlin-law */
extern const esf_contact_law esf_contact_hertz;
/* docs/physics.md#adhesive-normal-law-and-bonds, 004 2.22-2.25 */
extern const esf_contact_law esf_contact_adhesive;

/* The tangential part shared by the laws and the force assembly: contact_tangential.h
 * (esf_contact_tangential, esf_contact_finish). */

/* The adhesive law's parameters from the user's F, epsilon and kn (contact_adhesive.c):
 * fills *a, or returns ESF_EINPUT with a message in err for epsilon outside (0, 1),
 * too close to 1/e, or F < 0. F = 0 gives delta = 0 (the linear law). */
int esf_adhesion_derive(double F, double eps, double kn, esf_adhesion *a, esf_error *err);

/* The bonded law's elastic normal force k_n [u + delta expm1(-alpha u)] (> 0
 * repulsive; 2.22 with the sign flipped) and its energy W(u) = integral_0^u of it. */
double esf_adhesion_force(double kn, const esf_adhesion *a, double u);
double esf_adhesion_energy(double kn, const esf_adhesion *a, double u);

#endif
