/* wall_gen.h — wall meshes made here: a faceted cylinder and a screw (a shaft carrying
 * a helical flight, 004 §4.3), as polygons added to one wall group so that the group's
 * motion moves them all. Angles are measured in the plane normal to the axis from an
 * in-plane unit vector u (u = unit(axis x e), e the coordinate axis least aligned with
 * the axis; v = axis x u). */
#ifndef ESF_WALL_GEN_H
#define ESF_WALL_GEN_H

#include "bodies/walls.h"

typedef struct esf_cylinder_spec {
  double base[3]; /* centre of the bottom end, m */
  double axis[3]; /* unit axis, bottom -> top */
  double radius;  /* m (vertices lie on it; flats at radius cos(pi/segments)) */
  double height;  /* m */
  int segments;   /* facets around, >= 3 */
  int cap_bottom; /* close the bottom end (triangle fan) */
  int cap_top;    /* close the top end */
  int inward;     /* normals point toward the axis (a container) */
  int quads;      /* side facets as quadrilaterals (else two triangles each) */
} esf_cylinder_spec;

typedef struct esf_screw_spec {
  double base[3];          /* centre of the shaft's bottom end, m */
  double axis[3];          /* unit axis */
  double shaft_radius;     /* m */
  double radius;           /* flight's outer radius, m (> shaft_radius) */
  double pitch;            /* axial advance of the flight per turn, m; > 0 right-handed
                              about the axis, < 0 left-handed */
  double turns;            /* flight turns (> 0) */
  double start;            /* axial position of the flight's lower end above base, m */
  double length;           /* shaft length, m (>= start + turns |pitch|) */
  int segments;            /* facets per turn (flight and shaft), >= 3 */
  int radial;              /* rings across the flight's width, >= 1 */
  int quads;               /* shaft facets as quadrilaterals (the flight is always made of
                              triangles: a helicoid strip between two radial lines is
                              twisted, not planar) */
  int cap_bottom, cap_top; /* close the shaft's ends */
} esf_screw_spec;

/* Adds the cylinder's elements to w in group `group`. Errors: ESF_EINPUT for a bad
 * spec (non-positive sizes, fewer than 3 segments, zero axis). */
int esf_wall_gen_cylinder(const esf_cylinder_spec *c, int32_t material, int32_t group,
                          esf_walls *w, esf_error *err);

/* Adds the screw's elements (shaft, then flight) to w in group `group`. */
int esf_wall_gen_screw(const esf_screw_spec *c, int32_t material, int32_t group,
                       esf_walls *w, esf_error *err);

#endif
