/* walls.h — the scene's walls: elements (planes, polygons; wall_geom.h) grouped into
 * walls (a plane, a polygon, a box, later meshes), each group with its rigid motion
 * state. The velocity of the wall material at a point enters the contact's relative
 * velocity, so moving walls need nothing else from the force loop. */
#ifndef ESF_WALLS_H
#define ESF_WALLS_H

#include <stddef.h>

#include "esf_error.h"
#include "wall_geom.h"

typedef struct esf_wall_group {
  char label[32];   /* "plane", "box", "polygon" + index, for messages */
  int moving;       /* 0: static (vel, omega zero) */
  double vel[3];    /* translational velocity, m/s */
  double omega[3];  /* angular velocity about `center`, rad/s */
  double center[3]; /* m */
} esf_wall_group;

typedef struct esf_walls {
  size_t n, cap;
  esf_wall_elem *e; /* the elements */
  int ngroups;
  esf_wall_group *g;
} esf_walls;

/* Adds a group; returns its index. */
int esf_walls_add_group(esf_walls *w, const char *label, int *group, esf_error *err);
/* Adds an element (copied; its group must exist). */
int esf_walls_add_elem(esf_walls *w, const esf_wall_elem *e, esf_error *err);
void esf_walls_release(esf_walls *w);

/* Velocity of wall group g's material at point q, m/s. */
static inline void esf_wall_point_velocity(const esf_wall_group *g, const double q[3],
                                           double v[3]) {
  double r0 = q[0] - g->center[0], r1 = q[1] - g->center[1], r2 = q[2] - g->center[2];
  v[0] = g->vel[0] + g->omega[1] * r2 - g->omega[2] * r1;
  v[1] = g->vel[1] + g->omega[2] * r0 - g->omega[0] * r2;
  v[2] = g->vel[2] + g->omega[0] * r1 - g->omega[1] * r0;
}

#endif
