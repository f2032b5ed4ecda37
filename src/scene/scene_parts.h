/* scene_parts.h — the scene reader's own parts, for its files only: the particle and
 * wall lists (scene_particles.c, scene_walls.c, scene_meshes.c) and the helpers they
 * share (scene_util.c). The public entry points are scene.h's. */
#ifndef ESF_SCENE_PARTS_H
#define ESF_SCENE_PARTS_H

#include "core/sim.h"
#include "formats/yaml_tree.h"

/* Parts (scene_particles.c, scene_walls.c). */
int esf_scene_particles(const esf_ynode *seq, const char *dir, esf_sim *s,
                        esf_error *err);
int esf_scene_walls(const esf_ynode *seq, const char *dir, esf_sim *s, esf_error *err);
/* Mesh walls (scene_meshes.c): entry e's `mesh`, `cylinder` or `screw` into group. */
int esf_scene_wall_stl(const esf_ynode *e, const char *dir, esf_sim *s, int group,
                       int32_t mat, esf_error *err);
int esf_scene_wall_cylinder(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                            esf_error *err);
int esf_scene_wall_screw(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                         esf_error *err);

/* Helpers shared by the readers (scene_util.c). */
/* Re-raises err's message (set by a geometry builder) at node n's position. */
int esf_scene_fail_at(const esf_ynode *n, esf_error *err);
/* A unit vector from key `key` of map m: finite and non-zero, normalised. When not
 * required and the key is absent, u's value on entry (the default) is normalised. */
int esf_scene_unit_vector(const esf_ynode *m, const char *key, int required, double u[3],
                          esf_error *err);

#endif
