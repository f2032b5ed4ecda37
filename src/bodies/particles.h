/* particles.h — particle data as a structure of arrays.
 *
 * The kinematic state lives in one block `y` of 9n doubles laid out as
 *   y = [ x (3n, m) | v (3n, m/s) | w (3n, rad/s) ]
 * so that an ODE integrator can wrap it as one vector without copying; x, v and w point
 * into it. Vectors are stored xyz-interleaved per particle (x[3i+k]). Per-particle
 * constants and accumulators are separate arrays. Capacity always equals n: the block
 * is reallocated when particles are added or removed (rare: scene set-up, particles
 * leaving the domain), so y stays contiguous. */
#ifndef ESF_PARTICLES_H
#define ESF_PARTICLES_H

#include <stddef.h>
#include <stdint.h>

#include "util/esf_error.h"

typedef struct esf_particles {
  size_t n;            /* particle count */
  double *y;           /* 9n: x | v | w, and one spare double (pair_batch.c) */
  double *x;           /* 3n positions, m (= y) */
  double *v;           /* 3n velocities, m/s (= y + 3n) */
  double *w;           /* 3n angular velocities, rad/s (= y + 6n) */
  double *f;           /* 3n force accumulator, N (NULL while released: core/sim.h) */
  double *t;           /* 3n torque accumulator, N m (likewise) */
  double *radius;      /* n, m */
  double *mass;        /* n, kg */
  double *inv_mass;    /* n, 1/kg */
  double *inertia;     /* n, kg m^2 (2/5 m r^2 spheres, 1/2 m r^2 disks) */
  double *inv_inertia; /* n, 1/(kg m^2) */
  int32_t *material;   /* n, index into the material table */
  int64_t *id;         /* n, stable identifier (the order particles were defined in) */
  int32_t *img;        /* 3n periodic image counters (the unwrapped position is x + img L,
                          search/periodic.h), or NULL: no periodic axis */
} esf_particles;

/* Mass (kg) and moment of inertia (kg m^2) of a sphere (dim 3: m = 4/3 pi r^3 rho,
 * I = 2/5 m r^2, 000 3-4..3-5) or a disk (dim 2: m = pi r^2 rho thickness,
 * I = 1/2 m r^2) of radius r (m) and density rho (kg/m^3). */
static inline void esf_particle_mass(int dim, double r, double rho, double thickness,
                                     double *m, double *inertia) {
  const double pi = 3.14159265358979323846;
  if (dim == 2) {
    *m = pi * r * r * thickness * rho;
    *inertia = 0.5 * *m * r * r;
  } else {
    *m = 4.0 / 3.0 * pi * r * r * r * rho;
    *inertia = 0.4 * *m * r * r;
  }
}

/* Grows p by k particles at the end, zeroed (the others keep their index). */
int esf_particles_append(esf_particles *p, size_t k, esf_error *err);

/* One particle's definition, as scene sources produce them. */
typedef struct esf_particle_def {
  double x[3], v[3], w[3]; /* m, m/s, rad/s */
  double radius;           /* m */
  int32_t material;        /* material index */
} esf_particle_def;

/* A growable list of definitions (scene reading collects into it). */
typedef struct esf_particle_defs {
  size_t n, cap;
  esf_particle_def *d;
} esf_particle_defs;

int esf_particle_defs_push(esf_particle_defs *defs, const esf_particle_def *def,
                           esf_error *err);
void esf_particle_defs_release(esf_particle_defs *defs);

/* Allocates storage for n particles (all arrays zeroed). */
int esf_particles_alloc(esf_particles *p, size_t n, esf_error *err);
void esf_particles_release(esf_particles *p);

/* Gives p zeroed image counters (p->img), if it has none. */
int esf_particles_images(esf_particles *p, esf_error *err);

/* Removes the particles with keep[i] == 0, preserving order; writes the old index ->
 * new index map into remap (SIZE_MAX for removed) when remap is not NULL. */
int esf_particles_compact(esf_particles *p, const unsigned char *keep, size_t *remap,
                          esf_error *err);

/* Reorders the particles: the new particle k is the old src[k] (src a permutation of
 * 0 .. n-1); the copy is shared among `threads` threads. */
int esf_particles_permute(esf_particles *p, const size_t *src, int threads,
                          esf_error *err);

#endif
