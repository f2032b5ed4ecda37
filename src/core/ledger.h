/* ledger.h — the energy ledger (docs/output.md#energycsv;
 * docs/physics.md#energy-ledger).
 *
 * Stored energies are measured from the state; dissipation and wall work are tallied
 * every step along each path. The balance residual
 *   total_error = (kinetic + gravity + elastic) - e0 - work_walls - work_fluid
 *                 + dissipated + removed
 * is zero for an exact integration; what is left is the integrator's energy error. */
#ifndef ESF_LEDGER_H
#define ESF_LEDGER_H

#include <stdio.h>

typedef struct esf_ledger {
  int on;
  double kin_t, kin_r; /* kinetic, translational and rotational, J */
  double pot_g;        /* gravitational potential, -m g.x, J */
  double el_n, el_t;   /* elastic, normal and tangential springs, J */
  double d_normal;     /* normal dashpots, J (cumulative) */
  double d_tangential; /* tangential dashpots, J */
  double d_friction;   /* Coulomb slip, J */
  double d_global;     /* global viscous damping, J */
  double d_local;      /* local non-viscous damping, J */
  double w_walls;      /* work done by walls on the particles, J */
  double e_removed;    /* energy carried away by particles leaving the domain or
                          deleted by events (with their contacts' elastic energy), J */
  double d_bonds;      /* energy bonds held when they ruptured (adhesive law), J */
  double w_fluid;      /* work done by the fluid force on the particles (drag.c), J */
  double e0;           /* stored energy at the start, J */
  int started;         /* e0 set */
} esf_ledger;

double esf_ledger_stored(const esf_ledger *l);
double esf_ledger_dissipated(const esf_ledger *l);
double esf_ledger_total_error(const esf_ledger *l);

/* The columns of an energy row (energy.csv and /energy in frames.h5), in order. */
enum { ESF_LEDGER_NCOLS = 20 };
extern const char *const esf_ledger_columns[ESF_LEDGER_NCOLS];
enum { ESF_LEDGER_ALPHA = 17 }; /* the column of alpha_global */

/* One row's values at time t (s) with global damping alpha (1/s), in column order. */
void esf_ledger_values(double t, const esf_ledger *l, double alpha,
                       double row[ESF_LEDGER_NCOLS]);

/* energy.csv: header, and one row. */
void esf_ledger_header(FILE *f);
void esf_ledger_row(FILE *f, double t, const esf_ledger *l, double alpha);

/* Instantaneous energy rates and stored energies at an evaluation's state, for
 * integrators that integrate the ledger as quadratures (set s->tally to collect;
 * model/forces.c fills it). */
typedef struct esf_force_tally {
  double p_normal;     /* power dissipated by normal dashpots, W */
  double p_tangential; /* power dissipated by tangential dashpots, W */
  double p_walls;      /* power delivered by walls to the particles, W */
  double e_el_n;       /* elastic energy (1/2) kn u^2, J */
  double e_el_t;       /* elastic energy (1/2) kt |xi|^2, J */
  double slip;         /* Coulomb slip work of this evaluation (committing), J */
  double p_spring_t;   /* power into the tangential springs as applied (Coulomb cap
                          included), W; history as ODE state only */
  double p_fluid;      /* power delivered by the fluid force (drag.c), W */
} esf_force_tally;

#endif
