/* ledger.h — the energy ledger (docs/output.md#energycsv;
 * docs/physics.md#energy-ledger).
 *
 * Stored energies are measured from the state; dissipation and wall work are tallied
 * every step along each path. The balance residual
 *   total_error = (kinetic + gravity + elastic) - e0 - work_walls - work_fluid
 *                 - work_tangential_stiffness + dissipated + removed - inserted
 * is zero for an exact integration; what is left is the integrator's energy error. */
#ifndef ESF_LEDGER_H
#define ESF_LEDGER_H

#include <stddef.h>
#include <stdio.h>

#include "util/vec4.h"
#include "util/xsum.h"

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
  double el_r;         /* elastic, rolling and twisting springs, J */
  double d_rolling;    /* rolling and twisting resistance: dashpots, plastic rolling,
                          the constant torques' work, J (cumulative) */
  double w_stiff;      /* energy the Hertz-Mindlin tangential springs gained as their
                          stiffness changed under a carried force, J (cumulative) */
  double e_inserted;   /* energy brought in by particles inserted during the run
                          (kinetic and gravitational, loads/insert.c), J */
  double e0;           /* stored energy at the start, J */
  int started;         /* e0 set */
} esf_ledger;

double esf_ledger_stored(const esf_ledger *l);
double esf_ledger_dissipated(const esf_ledger *l);
double esf_ledger_total_error(const esf_ledger *l);

/* The columns of an energy row (energy.csv and /energy in frames.h5), in order. */
enum { ESF_LEDGER_NCOLS = 24 };
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
  double p_rolling;    /* power dissipated by the rolling resistance's dashpots and
                          constant torques, W */
  double e_el_r;       /* elastic energy of the rolling and twisting springs, J */
  double slip_r;       /* their plastic work in this evaluation (committing), J */
  double p_stiff;      /* rate of the Hertz tangential springs' energy from their
                          stiffness's change at a fixed force, W */
} esf_force_tally;

/* The leapfrog's ledger, summed the same way on the general path and the fused step,
 * on any thread count (docs/physics.md#energy-ledger).
 *
 * Per step, every contact adds to per-particle rows (ESF_LR doubles a particle, rows of
 * four, in the order the particle receives its forces): the forces and torques of its
 * normal dashpot, tangential dashpot, normal spring and tangential spring, and in the
 * fourth lane of its first particle's rows (A: the pair's lower index, or the particle
 * of a wall contact) its scalars: slip work, a ruptured bond's energy, the Hertz
 * springs' stiffness change, the wall's work rate, the springs' energies. A contact's
 * dissipation over the step is then the power of its dashpots at the mid-step
 * velocities, and its spring's energy in the leapfrog's measure
 * W(u_n) + (1/2) f . (u_{n+1} - u_n) uses the new velocities: both sums over particles
 * of rows . velocities (esf_ledger_particle); a wall contact adds its wall's side (the
 * prescribed wall velocity) as scalars. Particles are summed in blocks of
 * ESF_LEDGER_BLOCK (channels ESF_LB_*), and the blocks exactly (esf_ledger_step,
 * util/xsum.h): the fused step's ranges hold whole blocks, and the blocks' totals do
 * not depend on their order, so no sum depends on how whole blocks are shared among
 * threads or processes.
 *
 * The first ESF_LR_DISS doubles (and the rolling resistance's ESF_LR_RD) hold what the
 * cumulative terms need (dissipation, slip, bonds, wall work, stiffness changes); the
 * rest only the stored energies (springs). A step whose stored energies nobody reads
 * may leave the latter out (esf_ledger_kick.light: the fused step's steps of a call
 * but its last, docs/performance.md#light-steps-issue-26): the cumulative terms are
 * the same bits either way. */
#define ESF_LR           40 /* ledger rows per particle with rolling resistance */
#define ESF_LR_PLAIN     32 /* without: the rolling rows (ESF_LR_RD, _RE) are absent */
#define ESF_LR_DISS      16 /* the rows of the cumulative terms: DN, W, DT, MDT */
#define ESF_LR_DISS_N    4  /* DN alone (ESF_LEDGER_NO_T and ESF_LEDGER_NO_W) */
#define ESF_LEDGER_BLOCK 64 /* particles per block of the ledger's sums */
enum {                      /* row offsets (xyz, then the scalar lane) */
       ESF_LR_DN = 0,       /* normal dashpot force | slip work (J) */
       ESF_LR_W = 4,    /* a moving wall's side of the dashpots' power: normal -fd vw.n,
                           tangential fdt.vw (W) | rolling md.omega (W) | wall work rate
                           F.v_wall (W) */
       ESF_LR_DT = 8,   /* tangential dashpot force | energy of ruptured bonds (J) */
       ESF_LR_MDT = 12, /* tangential dashpot torque | the energy a Hertz tangential
                           spring gained from its stiffness's change (J) */
       ESF_LR_EN = 16,  /* normal spring force | its energy W (J) */
       ESF_LR_ET = 20,  /* tangential spring force | the tangential spring's energy */
       ESF_LR_MET = 24, /* tangential spring torque | -0 */
       ESF_LR_RD = 32,  /* rolling resistance's dissipative torque | its plastic work */
       ESF_LR_RE = 36   /* rolling resistance's spring torque | the springs' energy */
};
#define ESF_LR_BOND  (ESF_LR_DT + 3)  /* lane: ruptured bonds' energy (J) */
#define ESF_LR_STIFF (ESF_LR_MDT + 3) /* lane: Hertz stiffness change (J) */
#define ESF_LR_WWORK (ESF_LR_W + 3)   /* lane: the walls' work rate (W) */
/* A particle's rows: esf_ledger_lr(roll) doubles, roll 1 when the scene has rolling
 * resistance (the rows of a scene without it hold no rolling rows: it neither stores
 * nor streams them). */
static inline size_t esf_ledger_lr(int roll) { return roll ? ESF_LR : ESF_LR_PLAIN; }
/* A pair contact's rows of one particle, as the fused step's batches and slots write a
 * side: ESF_LR_PAIR doubles, the rows DN, DT, MDT, EN, ET, MET (side row j at 4 j),
 * then with rolling resistance RD and RE (ESF_LR_PAIR_ROLL in all); side row j goes
 * to esf_ledger_side_pos(j) of the particle's rows (esf_ledger_side_add). */
#define ESF_LR_PAIR      24
#define ESF_LR_PAIR_ROLL 32
#define ESF_LS_BOND      7 /* a side's lane of ESF_LR_BOND */
static inline int esf_ledger_side_pos(int j) {
  return j == 0  ? ESF_LR_DN
         : j < 3 ? ESF_LR_DT + 4 * (j - 1)
         : j < 6 ? ESF_LR_EN + 4 * (j - 3)
                 : ESF_LR_RD + 4 * (j - 6);
}
/* The rows a step of the fused step writes and reads (esf_ledger_side_add, the
 * batches' esf_pair_batch_ctx, esf_ledger_kick): */
enum {
  ESF_LEDGER_LIGHT = 1,  /* the cumulative terms' rows only: DN, W, DT, MDT, RD (a step
                            whose stored energies nobody reads) */
  ESF_LEDGER_NO_T = 2,   /* not DT, MDT: no tangential dashpot, bond or Hertz spring in
                            the scene (their rows and lanes would stay +0) */
  ESF_LEDGER_ROLL = 4,   /* the rolling resistance's rows */
  ESF_LEDGER_NO_W = 8,   /* not W: static walls (their side of every term +0) */
  ESF_LEDGER_ZEROED = 16 /* the rows are zero already (the fused step's pair pass) */
};

/* Adds a pair side's rows s (ESF_LR_PAIR doubles, then with ESF_LEDGER_ROLL the two
 * rolling rows) to a particle's rows r, those that the flags set in `set` ask for;
 * four at a time, in order. */
static inline void esf_ledger_side_add(double *r, const double *s, unsigned set) {
  const int light = set & ESF_LEDGER_LIGHT, t = !(set & ESF_LEDGER_NO_T);
  const int roll = set & ESF_LEDGER_ROLL;
  for (int j = 0; j < (roll ? 8 : 6); j++)
    if ((j != 1 && j != 2) || t)
      if (!light || j < 3 || j == 6) v4_acc(r + esf_ledger_side_pos(j), s + 4 * j);
}
enum {            /* channels of a block's sums */
       ESF_LB_KT, /* kinetic, translational, at v_{n+1/2}, J */
       ESF_LB_KR, /* kinetic, rotational */
       ESF_LB_PE, /* gravity at (x_n + x_{n+1})/2 */
       ESF_LB_KO, /* kinetic at v_{n-1/2} (the start's stored energy) */
       ESF_LB_PO, /* gravity at x_n - v_{n-1/2} dt/2 */
       ESF_LB_DG, /* global damping over the step */
       ESF_LB_DL, /* local damping */
       ESF_LB_DN, /* normal dashpots */
       ESF_LB_DT, /* tangential dashpots */
       ESF_LB_EN, /* normal springs, J (stored) */
       ESF_LB_ET, /* tangential springs */
       ESF_LB_SL, /* Coulomb slip */
       ESF_LB_WW, /* work of the walls */
       ESF_LB_BD, /* ruptured bonds */
       ESF_LB_WF, /* work of the fluid force */
       ESF_LB_SW, /* Hertz tangential springs' stiffness change */
       ESF_LB_ER, /* rolling and twisting springs, J (stored) */
       ESF_LB_DR, /* rolling resistance's dissipation */
       ESF_LB_N = 18
};

/* The torque directions of the tangential dashpot and spring forces on A: n x fdt,
 * n x ket (the torques are these times the lever arms). */
static inline void esf_ledger_torques(const double n[3], const double fdt[3],
                                      const double ket[3], double md[3], double me[3]) {
  md[0] = n[1] * fdt[2] - n[2] * fdt[1];
  md[1] = n[2] * fdt[0] - n[0] * fdt[2];
  md[2] = n[0] * fdt[1] - n[1] * fdt[0];
  me[0] = n[1] * ket[2] - n[2] * ket[1];
  me[1] = n[2] * ket[0] - n[0] * ket[2];
  me[2] = n[0] * ket[1] - n[1] * ket[0];
}

/* Adds one touching pair contact to the rows of A (ra) and B (rb): n, lever arms la,
 * lb, the normal dashpot fd and spring fel (N, compressive positive), the tangential
 * dashpot fdt and spring ket forces on A (N), the slip work and the springs' energies
 * (J). */
static inline void esf_ledger_pair_rows(double *ra, double *rb, const double n[3],
                                        double la, double lb, double fd, double fel,
                                        const double fdt[3], const double ket[3],
                                        double slip, double e_n, double e_t) {
  double md[3], me[3], x;
  esf_ledger_torques(n, fdt, ket, md, me);
  for (int q = 0; q < 3; q++) {
    x = -fd * n[q];
    ra[ESF_LR_DN + q] += x;
    rb[ESF_LR_DN + q] -= x;
    x = -fel * n[q];
    ra[ESF_LR_EN + q] += x;
    rb[ESF_LR_EN + q] -= x;
    ra[ESF_LR_DT + q] += fdt[q];
    rb[ESF_LR_DT + q] -= fdt[q];
    ra[ESF_LR_MDT + q] += la * md[q];
    rb[ESF_LR_MDT + q] += lb * md[q];
    ra[ESF_LR_ET + q] += ket[q];
    rb[ESF_LR_ET + q] -= ket[q];
    ra[ESF_LR_MET + q] += la * me[q];
    rb[ESF_LR_MET + q] += lb * me[q];
  }
  ra[ESF_LR_DN + 3] += slip;
  ra[ESF_LR_EN + 3] += e_n;
  ra[ESF_LR_ET + 3] += e_t;
}

/* Adds one touching wall contact of a particle to its rows r: as a pair's A side
 * (esf_ledger_pair_rows), with the wall's side at its point velocity vw: the contact
 * force f's work rate f . vw, the dashpots' power on the wall, and the springs'
 * extrapolation -(dt/2) fel vw.n and (dt/2) ket.vw folded into their energies.
 * The rows esf_ledger_side_add's `set` asks for (not ESF_LEDGER_ROLL's). */
static inline void esf_ledger_wall_rows_set(double *r, const double n[3], double la,
                                            double fd, double fel, const double fdt[3],
                                            const double ket[3], double slip, double e_n,
                                            double e_t, const double f[3],
                                            const double vw[3], double dt, unsigned set) {
  double md[3], me[3], x;
  esf_ledger_torques(n, fdt, ket, md, me);
  for (int q = 0; q < 3; q++) {
    x = -fd * n[q];
    r[ESF_LR_DN + q] += x;
  }
  if (!(set & ESF_LEDGER_NO_T))
    for (int q = 0; q < 3; q++) {
      r[ESF_LR_DT + q] += fdt[q];
      r[ESF_LR_MDT + q] += la * md[q];
    }
  const double vwn = vw[0] * n[0] + vw[1] * n[1] + vw[2] * n[2];
  r[ESF_LR_DN + 3] += slip;
  if (!(set & ESF_LEDGER_NO_W)) {
    r[ESF_LR_WWORK] += f[0] * vw[0] + f[1] * vw[1] + f[2] * vw[2];
    r[ESF_LR_W] += -fd * vwn;
    r[ESF_LR_W + 1] += fdt[0] * vw[0] + fdt[1] * vw[1] + fdt[2] * vw[2];
  }
  if (set & ESF_LEDGER_LIGHT) return;
  for (int q = 0; q < 3; q++) {
    x = -fel * n[q];
    r[ESF_LR_EN + q] += x;
    r[ESF_LR_ET + q] += ket[q];
    r[ESF_LR_MET + q] += la * me[q];
  }
  const double kv = ket[0] * vw[0] + ket[1] * vw[1] + ket[2] * vw[2];
  r[ESF_LR_EN + 3] += e_n - 0.5 * dt * fel * vwn;
  r[ESF_LR_ET + 3] += e_t + 0.5 * dt * kv;
}
static inline void esf_ledger_wall_rows(double *r, const double n[3], double la,
                                        double fd, double fel, const double fdt[3],
                                        const double ket[3], double slip, double e_n,
                                        double e_t, const double f[3], const double vw[3],
                                        double dt) {
  esf_ledger_wall_rows_set(r, n, la, fd, fel, fdt, ket, slip, e_n, e_t, f, vw, dt, 0);
}

/* Adds one touching contact's rolling resistance (contact_rolling.h) to the rows of A
 * (ra) and B (rb, or NULL for a wall, whose angular velocity is om): the dissipative
 * torque md and the springs' torque ms on A (B gets the opposite), the plastic work and
 * the springs' energy (J). A wall's side, as for the tangential spring and dashpot:
 * the dissipative torque's power md.om, the springs' extrapolation (dt/2) ms.om, and the
 * wall's work rate (md + ms).om. */
static inline void esf_ledger_roll_rows(double *ra, double *rb, const double md[3],
                                        const double ms[3], double slip, double e,
                                        const double *om, double dt) {
  for (int q = 0; q < 3; q++) {
    ra[ESF_LR_RD + q] += md[q];
    ra[ESF_LR_RE + q] += ms[q];
    if (rb) {
      rb[ESF_LR_RD + q] -= md[q];
      rb[ESF_LR_RE + q] -= ms[q];
    }
  }
  ra[ESF_LR_RD + 3] += slip;
  ra[ESF_LR_RE + 3] += e;
  if (om) {
    double pd = 0, ps = 0;
    for (int q = 0; q < 3; q++) {
      pd += md[q] * om[q];
      ps += ms[q] * om[q];
    }
    ra[ESF_LR_W + 2] += pd;
    ra[ESF_LR_RE + 3] += 0.5 * dt * ps;
    ra[ESF_LR_WWORK] += pd + ps;
  }
}

/* One particle's kick in the ledger's blocks (esf_ledger_kick_particle): the step, the
 * damping coefficients, gravity, and which rows the step has. */
typedef struct esf_ledger_kick {
  double dt, alpha_r, alpha_t; /* s, 1/s */
  const double *g;             /* gravity, m/s^2 */
  int roll;                    /* the rows carry rolling resistance (ESF_LR_RD, _RE) */
  int light;                   /* 1: the cumulative channels only (ESF_LEDGER_LIGHT) */
  int no_t;                    /* 1: rows DT, MDT absent (ESF_LEDGER_NO_T) */
  int no_w;                    /* 1: row W absent (ESF_LEDGER_NO_W) */
} esf_ledger_kick;

/* The terms of a particle's dashpots over the step, (F . vbar - P_wall) dt, from its
 * rows r and mid-step velocities vb, wb: normal (rows DN, W), tangential (DT, MDT, W;
 * without them, no_t, the wall's side alone: the same bits as rows of +0). */
static inline double esf_ledger_dn_term(const double *r, const double vb[3], double dt,
                                        int no_w) {
  const double *dn = r + ESF_LR_DN;
  double pdn = 0;
  for (int q = 0; q < 3; q++) pdn += dn[q] * vb[q];
  return (pdn - (no_w ? 0.0 : r[ESF_LR_W])) * dt;
}
static inline double esf_ledger_dt_term(const double *r, const double vb[3],
                                        const double wb[3], double dt, int no_t,
                                        int no_w) {
  const double *dtg = r + ESF_LR_DT, *mdt = r + ESF_LR_MDT;
  double pdt = 0;
  if (!no_t)
    for (int q = 0; q < 3; q++) pdt += dtg[q] * vb[q] + mdt[q] * wb[q];
  return (pdt - (no_w ? 0.0 : r[ESF_LR_W + 1])) * dt;
}

/* The rows of a step's particle i: rows r (ESF_LR), velocities and spins before (vo,
 * wo: v_{n-1/2}) and after the kick (vn, wn), mid-step vb, wb. Adds to its block's
 * channels blk the dashpots' dissipation -(F . vbar + M . wbar) dt and the scalars
 * (slip, wall work, bonds, stiffness changes), and unless k->light the springs'
 * energies less (1/2) (F . v_{n+1/2} + M . w_{n+1/2}) dt; with roll, the rolling
 * resistance's rows likewise. Each channel's operations are the same whether light or
 * not. */
static inline void esf_ledger_particle(const esf_ledger_kick *k, const double *r,
                                       const double vn[3], const double wn[3],
                                       const double vb[3], const double wb[3],
                                       double *blk) {
  const double dt = k->dt;
  blk[ESF_LB_DN] -= esf_ledger_dn_term(r, vb, dt, k->no_w);
  blk[ESF_LB_DT] -= esf_ledger_dt_term(r, vb, wb, dt, k->no_t, k->no_w);
  blk[ESF_LB_SL] += r[ESF_LR_DN + 3];
  if (!k->no_w) blk[ESF_LB_WW] += r[ESF_LR_WWORK] * dt; /* else +0 */
  if (!k->no_t) {                                       /* else +0, which adds nothing */
    blk[ESF_LB_BD] += r[ESF_LR_BOND];
    blk[ESF_LB_SW] += r[ESF_LR_STIFF];
  }
  if (!k->light) {
    const double *en = r + ESF_LR_EN, *et = r + ESF_LR_ET, *met = r + ESF_LR_MET;
    double pen = 0, pet = 0;
    for (int q = 0; q < 3; q++) {
      pen += en[q] * vn[q];
      pet += et[q] * vn[q] + met[q] * wn[q];
    }
    blk[ESF_LB_EN] += en[3] - 0.5 * pen * dt;
    blk[ESF_LB_ET] += et[3] - 0.5 * pet * dt;
  }
  if (!k->roll) return; /* no rolling resistance: its rows are zero */
  const double *rd = r + ESF_LR_RD, *re = r + ESF_LR_RE; /* rolling (zero without) */
  double pdr = 0;
  for (int q = 0; q < 3; q++) pdr += rd[q] * wb[q];
  blk[ESF_LB_DR] += rd[3] - (pdr - (k->no_w ? 0.0 : r[ESF_LR_W + 2])) * dt;
  if (k->light) return;
  double per = 0;
  for (int q = 0; q < 3; q++) per += re[q] * wn[q];
  blk[ESF_LB_ER] += re[3] - 0.5 * per * dt;
}

/* Global damping's work over the step, (alpha_r m |vbar|^2 + alpha_t I |wbar|^2) dt. */
static inline double esf_ledger_dg_term(const esf_ledger_kick *k, double m, double I,
                                        double vb2, double wb2) {
  return (k->alpha_r * m * vb2 + k->alpha_t * I * wb2) * k->dt;
}

/* One particle's kick in the ledger's blocks: its kinetic energies at v_{n+1/2} (v, w)
 * and v_{n-1/2} (v0, w0), gravity at x_n +- (dt/2) v (x: x_n), global damping
 * alpha_r m |vbar|^2 + alpha_t I |wbar|^2 and local damping -(fl . vbar + ml . wbar)
 * over dt (fl, ml: the local damping force and moment, or NULL), the fluid force's work
 * ff . vbar dt (ff or NULL), and its ledger rows (r or NULL: esf_ledger_particle).
 * k->light: the cumulative channels only (no kinetic, gravitational or elastic
 * energies: a step whose stored energies nobody reads; the rows' stored part unread). */
static inline void esf_ledger_kick_particle(const esf_ledger_kick *k, double m, double I,
                                            const double x[3], const double v0[3],
                                            const double v[3], const double w0[3],
                                            const double w[3], const double *fl,
                                            const double *ml, const double *ff,
                                            const double *r, double *blk) {
  double vb[3], wb[3], vb2 = 0, wb2 = 0;
  for (int q = 0; q < 3; q++) {
    vb[q] = 0.5 * (v0[q] + v[q]);
    wb[q] = 0.5 * (w0[q] + w[q]);
    vb2 += vb[q] * vb[q];
    wb2 += wb[q] * wb[q];
  }
  if (!k->light) {
    const double h = 0.5 * k->dt;
    double g0 = 0, g1 = 0, vo2 = 0, wo2 = 0, v2 = 0, w2 = 0;
    for (int q = 0; q < 3; q++) {
      g0 += k->g[q] * (x[q] - h * v0[q]);
      g1 += k->g[q] * (x[q] + h * v[q]);
      vo2 += v0[q] * v0[q];
      wo2 += w0[q] * w0[q];
      v2 += v[q] * v[q];
      w2 += w[q] * w[q];
    }
    blk[ESF_LB_KO] += 0.5 * m * vo2 + 0.5 * I * wo2;
    blk[ESF_LB_KT] += 0.5 * m * v2;
    blk[ESF_LB_KR] += 0.5 * I * w2;
    blk[ESF_LB_PO] -= m * g0;
    blk[ESF_LB_PE] -= m * g1;
  }
  blk[ESF_LB_DG] += esf_ledger_dg_term(k, m, I, vb2, wb2);
  if (fl)
    blk[ESF_LB_DL] -= (fl[0] * vb[0] + fl[1] * vb[1] + fl[2] * vb[2] + ml[0] * wb[0] +
                       ml[1] * wb[1] + ml[2] * wb[2]) *
                      k->dt;
  if (ff) blk[ESF_LB_WF] += (ff[0] * vb[0] + ff[1] * vb[1] + ff[2] * vb[2]) * k->dt;
  if (r) esf_ledger_particle(k, r, v, w, vb, wb, blk);
}

/* Sums the nb blocks' channels (ESF_LB_N each) exactly, rounds each total once, and
 * books the step (esf_ledger_step_sums): the same bits in any order of the blocks. */
void esf_ledger_step(esf_ledger *l, const double *blocks, size_t nb);
/* The two halves of esf_ledger_step, for sums spread over processes: adds the nb
 * blocks' channels to the accumulators acc (one a channel; merge those of all parts,
 * esf_xsum_merge or a limb-wise integer sum), then books the totals t (acc's values):
 * stored energies set, dissipation and work added; the first booked step also sets e0. */
void esf_ledger_block_sums(const double *blocks, size_t nb, esf_xsum acc[ESF_LB_N]);
void esf_ledger_step_sums(esf_ledger *l, const double t[ESF_LB_N]);

#endif
