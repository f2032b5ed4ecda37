/* walls.h — the scene's walls: elements (planes, polygons; wall_geom.h) grouped into
 * walls (a plane, a polygon, a box, later meshes), each group with its rigid motion
 * state. The velocity of the wall material at a point enters the contact's relative
 * velocity, so moving walls need nothing else from the force loop. */
#ifndef ESF_WALLS_H
#define ESF_WALLS_H

#include <stddef.h>

#include "bodies/wall_geom.h"
#include "util/esf_error.h"

/* Prescribed rigid motions (wall_motion.c). */
enum {
  ESF_MOTION_NONE = 0,
  ESF_MOTION_TRANSLATE,
  ESF_MOTION_ROTATE,
  ESF_MOTION_OSCILLATE,
  ESF_MOTION_SERVO, /* velocity set by stress feedback each step (servo.h) */
  ESF_MOTION_TABLE  /* tabulated displacement, piecewise linear in time */
};

typedef struct esf_wall_motion {
  int kind;
  double vel[3];   /* translate: velocity, m/s */
  double axis[3];  /* rotate: unit axis (right hand) */
  double pivot[3]; /* rotate: a point of the axis at t = 0, m */
  double rate;     /* rotate: angular speed, rad/s */
  double dir[3];   /* oscillate: unit direction */
  double freq;     /* oscillate: Hz */
  double amp;      /* oscillate: m; displacement amp sin(2 pi freq t + phase) dir */
  double phase;    /* oscillate: rad */
  /* servo (servo.c): dir is the unit direction the wall moves to compress */
  double stress; /* servo: target compressive stress, Pa */
  double gain;   /* servo: m/(s Pa); 0: automatic, alpha A/(kn N_c dt) */
  double alpha;  /* servo: fraction of the stress error removed per step (auto gain) */
  double vmax;   /* servo: speed limit, m/s (0: set at set-up) */
  double area;   /* servo: loaded area, m^2 (0: from the elements) */
  double kn;     /* servo: largest wall-particle normal stiffness, N/m */
  double sigma;  /* servo: measured stress at the last committed evaluation, Pa */
  /* the time window of a prescribed motion (not servo): when timed, the motion sees
     tau = clamp(t, start, stop) - start and moves only for start <= t < stop */
  int timed;
  double start, stop; /* s (stop: INFINITY when not given) */
  /* table: nrow times (s, increasing, from start) and displacements (m, 3 a row);
     after the last row the wall moves on at `tail` (m/s; a velocity table's last) */
  int nrow;
  const double *row_t, *row_d; /* owned by the esf_walls (esf_walls_own) */
  double tail[3];
} esf_wall_motion;

typedef struct esf_wall_group {
  char label[32];              /* "plane", "box", "polygon" + index, for messages */
  int moving;                  /* 0: static (vel, omega zero) */
  double vel[3];               /* translational velocity, m/s */
  double omega[3];             /* angular velocity about `center`, rad/s */
  double center[3];            /* m */
  esf_wall_motion motion;      /* the first term (a rotation if any term rotates) */
  int nmore;                   /* further terms of a sequence, summed with the first */
  const esf_wall_motion *more; /* owned by the esf_walls (esf_walls_own) */
  int named;                   /* label is the scene's `name:` */
  int absent;                  /* removed by an event (or not yet added): no contacts */
  double disp[3];              /* displacement at the current time, m */
  double angle;                /* rotation angle at the current time, rad */
  double cos_a, sin_a;         /* its cosine and sine (esf_walls_set_time) */
  double reach; /* largest distance of its vertices from the rotation axis, m */
  double disp_mark[3], angle_mark; /* the same at the last candidate-list build */
} esf_wall_group;

typedef struct esf_walls {
  size_t n, cap;
  esf_wall_elem *e; /* the elements */
  int ngroups;
  esf_wall_group *g;
  int moving;         /* some group moves */
  esf_wall_elem *e0;  /* the elements at t = 0 (moving walls only), else NULL */
  double t;           /* time the elements are placed at, s */
  double *gforce;     /* 4 per group: spring force the group exerts on particles (N, xyz;
                         contact force less dashpots) and its touching contacts, summed at
                         each committed evaluation;
                         NULL unless a servo wall exists (servo.c) */
  double *gforce_blk; /* the same per block of ESF_LEDGER_BLOCK particles, 4 ngroups a
                         block, summed exactly into gforce (servo.c) */
  size_t gforce_nb;   /* blocks it has room for */
  void **own;         /* allocations the motions point into (tables, sequences) */
  int nown;
} esf_walls;

/* Adds a group; returns its index. */
int esf_walls_add_group(esf_walls *w, const char *label, int *group, esf_error *err);
/* Adds an element (copied; its group must exist). */
int esf_walls_add_elem(esf_walls *w, const esf_wall_elem *e, esf_error *err);
void esf_walls_release(esf_walls *w);
/* Makes w own a block from malloc (freed by esf_walls_release); on failure frees it. */
int esf_walls_own(esf_walls *w, void *block, esf_error *err);
/* The group named `name` (scene key `name:`), or -1. */
int esf_walls_find(const esf_walls *w, const char *name);

/* After the scene is read: keeps the reference geometry when a group moves and places
 * the walls at time t0. */
int esf_walls_freeze(esf_walls *w, double t0, esf_error *err);

/* Places every moving group at time t (elements, velocities); nothing when none moves
 * or t is the current time. */
void esf_walls_set_time(esf_walls *w, double t);

/* Upper bound of how far any wall point moved since the last esf_walls_mark, m. */
double esf_walls_moved(const esf_walls *w);

/* Records the current placement as the reference of esf_walls_moved. */
void esf_walls_mark(esf_walls *w);

/* Where a wall contact acts (docs/physics.md#contact-kinematics): the lever arm from
 * the particle's centre to the contact point, for a particle of radius r overlapping the
 * wall by un with its centre dist from the wall's nearest point (dist = r - un).
 * ESF_WALL_LEVER_SEED: rA - un/2, the point halfway through the overlap, as between two
 * particles (000 3-16); ESF_WALL_LEVER_SURFACE: dist, the wall's surface point. */
enum { ESF_WALL_LEVER_SEED = 0, ESF_WALL_LEVER_SURFACE = 1 };

static inline double esf_wall_lever(int rule, double r, double un, double dist) {
  return rule == ESF_WALL_LEVER_SURFACE ? dist : r - 0.5 * un;
}

/* The contact point of a wall contact: the nearest point q (surface rule), or
 * xa + la n (seed rule), with n the unit normal from the centre xa toward q. */
static inline void esf_wall_contact_point(int rule, const double xa[3], double la,
                                          const double n[3], const double q[3],
                                          double pc[3]) {
  for (int i = 0; i < 3; i++)
    pc[i] = rule == ESF_WALL_LEVER_SURFACE ? q[i] : xa[i] + la * n[i];
}

/* Velocity of wall group g's material at point q, m/s. */
static inline void esf_wall_point_velocity(const esf_wall_group *g, const double q[3],
                                           double v[3]) {
  double r0 = q[0] - g->center[0], r1 = q[1] - g->center[1], r2 = q[2] - g->center[2];
  v[0] = g->vel[0] + g->omega[1] * r2 - g->omega[2] * r1;
  v[1] = g->vel[1] + g->omega[2] * r0 - g->omega[0] * r2;
  v[2] = g->vel[2] + g->omega[0] * r1 - g->omega[1] * r0;
}

#endif
