/* wall_mesh.h — the walls as a triangle mesh, for output (frames.h5, frames.xdmf).
 *
 * Every element gives its own points (no sharing between elements): a polygon of nv
 * vertices gives those nv points and the fan triangles (0,1,2), (0,2,3), wound so that
 * the right-hand normal is the element's normal. An infinite plane is drawn as a
 * square patch of 4 points and 2 triangles, wound the same way: centred on the
 * projection onto the plane of the centre of a box (the particles' bounding box, see
 * esf_wall_mesh_build), with side = the box's diagonal, so the patch covers the box's
 * whole shadow on the plane. Each triangle carries its element's group and material.
 * Moving walls (walls.h) are drawn where their motion puts them at the time asked for,
 * from a private copy: the walls handed in are not changed. */
#ifndef ESF_WALL_MESH_H
#define ESF_WALL_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "bodies/walls.h"
#include "util/esf_error.h"

typedef struct esf_wall_mesh {
  size_t np;         /* points */
  size_t nt;         /* triangles */
  double *points;    /* 3 np, m */
  int32_t *tri;      /* 3 nt point indices (from 0) */
  int32_t *group;    /* nt: the wall group of each triangle */
  int32_t *material; /* nt: its material index */
  size_t cap_p, cap_t;
  esf_wall_elem *scratch_e; /* moving walls: elements placed at the mesh's time */
  esf_wall_group *scratch_g;
  size_t cap_se;
  int cap_sg;
} esf_wall_mesh;

/* Fills m (reusing its storage) with the mesh of walls at time t (s). box_lo,
 * box_hi: the box that sizes plane patches, usually the particles' bounding box; when
 * NULL (or empty) the finite elements' box is used, and without those a 1 m square
 * about each plane's point. */
int esf_wall_mesh_build(const esf_walls *walls, double t, const double *box_lo,
                        const double *box_hi, esf_wall_mesh *m, esf_error *err);

void esf_wall_mesh_release(esf_wall_mesh *m);

#endif
