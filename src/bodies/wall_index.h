/* wall_index.h — spatial index of wall elements for the particle-wall candidate search.
 *
 * A wall group with many polygons (a mesh, a screw) gets a uniform grid of its elements'
 * bounding boxes, built once in the group's reference frame (the geometry as read,
 * esf_walls.e0 for moving walls): a query point is carried into that frame by the
 * inverse of the group's current rigid placement (displacement disp, rotation angle
 * about the motion's axis through its pivot, wall_motion.c), so a moving group is never
 * re-binned. Planes and small groups are not indexed and are always reported (the
 * caller tests them as before). A query reports every element whose bounding box
 * (reference frame) meets the cube of half-side r about the point: a superset of the
 * elements within distance r, each once. Queries share a scratch buffer: one thread. */
#ifndef ESF_WALL_INDEX_H
#define ESF_WALL_INDEX_H

#include <stddef.h>
#include <stdint.h>

#include "bodies/walls.h"

/* groups with fewer polygons than this are searched by brute force */
#define ESF_WALL_INDEX_MIN 32

typedef struct esf_wall_index esf_wall_index;

/* (Re)builds *idx when it is NULL or w's elements changed in number or storage. */
int esf_wall_index_sync(esf_wall_index **idx, const esf_walls *w, esf_error *err);

/* Entries of the scratch a query needs (the elements indexed, at least 1). */
size_t esf_wall_index_scratch(const esf_wall_index *idx);

/* Elements possibly within r of point x (w placed at its current time); *out points
 * into idx's storage or into the caller's scratch (esf_wall_index_scratch entries),
 * read only, valid until the next query with that scratch or the next sync. Queries
 * with separate scratch may run in parallel. */
void esf_wall_index_query(const esf_wall_index *idx, const esf_walls *w,
                          const double x[3], double r, uint32_t *scratch,
                          const uint32_t **out, size_t *n);

/* Number of indexed groups (for tests and logs). */
int esf_wall_index_grids(const esf_wall_index *idx);

void esf_wall_index_free(esf_wall_index **idx);

#endif
