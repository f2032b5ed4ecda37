/* servo.h — servo-controlled walls: a wall group whose velocity is set after every
 * committed force evaluation by feedback on the stress it measures, so as to hold a
 * target confining stress on a face of a packing (seed 004 §4.4: 18 MPa held "by the
 * movement of the walls"). Leapfrog only. */
#ifndef ESF_SERVO_H
#define ESF_SERVO_H

#include "core/sim.h"

/* At set-up (after dt is chosen): the loaded area of each servo group (from its
 * polygons unless given), its wall-particle stiffness, the per-group force accumulator
 * s->walls.gforce. Refuses integrators other than the leapfrog, infinite planes
 * without an area, and 2D scenes without an area. Nothing when no wall is a servo. */
int esf_servo_setup(esf_sim *s, esf_error *err);

/* Room for the per-block accumulators of the current particles, zeroed when zero is 1
 * (the fused step zeroes each range's own). */
int esf_servo_blocks(esf_sim *s, int zero, esf_error *err);

/* The accumulator of particle i's contacts with group g: per block of particles, so
 * that the sums do not depend on how particles are shared among threads. */
static inline double *esf_servo_slot(esf_walls *w, size_t i, int g) {
  return w->gforce_blk + 4 * ((i / ESF_LEDGER_BLOCK) * (size_t)w->ngroups + (size_t)g);
}

/* After a committed evaluation filled the blocks of n particles: s->walls.gforce their
 * exact sum rounded once (the same bits in any order of the blocks), then
 * esf_servo_control. */
void esf_servo_update(esf_sim *s);
/* esf_servo_update's two halves, for sums spread over processes: adds the blocks to the
 * accumulators acc (4 a group: force xyz, contacts; merge those of all parts), and,
 * with s->walls.gforce set to the totals (acc's values), each servo group's measured
 * stress sigma = (F . dir)/A and velocity v = G (stress - sigma) dir limited to vmax. */
void esf_servo_block_sums(const esf_sim *s, esf_xsum *acc);
void esf_servo_control(esf_sim *s);

/* Adds one wall contact's spring force on the particle (the total less the dashpot
 * forces: the normal dashpot acts as -fd_n n on the particle, n toward the wall) to a
 * group's accumulator (4 doubles: force, contacts). */
static inline void esf_servo_add(double *acc, const esf_contact_out *o,
                                 const double n[3]) {
  for (int q = 0; q < 3; q++) acc[q] += o->f[q] + o->fd_n * n[q] - o->fd_t[q];
  acc[3] += 1.0;
}

/* Writes each servo wall's measured stress, target and speed to the run's log. */
void esf_servo_log_state(const esf_sim *s);

/* Area of a wall element projected on unit direction d (0 for a plane), m^2. */
double esf_wall_elem_area(const esf_wall_elem *e, const double d[3]);

#endif
