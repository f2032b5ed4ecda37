/* scene.h — reading a YAML scene (INTERFACE.md) into a simulation.
 *
 * Every key is checked against the schema: an unknown key, a wrong type or a missing
 * required key is an ESF_EINPUT error naming the file, line and column (or the --set
 * override that introduced it) and what was expected. */
#ifndef ESF_SCENE_H
#define ESF_SCENE_H

#include "core/sim.h"
#include "formats/yaml_tree.h"

/* Loads path, applies the overrides ("dotted.key=VALUE") in order, and fills s->cfg,
 * s->mats, s->p and s->walls (s must be zeroed). esf_sim_setup comes next. */
int esf_scene_load(const char *path, const char *const *overrides, int noverrides,
                   esf_sim *s, esf_error *err);

/* The same from an already parsed document (tests build scenes from strings). */
int esf_scene_read(esf_ydoc *doc, esf_sim *s, esf_error *err);

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

/* Helpers shared by the wall readers (scene_walls.c). */
/* Re-raises err's message (set by a geometry builder) at node n's position. */
int esf_scene_fail_at(const esf_ynode *n, esf_error *err);
/* A unit vector from key `key` of map m: finite and non-zero, normalised. When not
 * required and the key is absent, u's value on entry (the default) is normalised. */
int esf_scene_unit_vector(const esf_ynode *m, const char *key, int required, double u[3],
                          esf_error *err);

/* The material index named by a scalar node, or an error listing the materials. */
int esf_scene_material(const esf_ynode *node, const esf_materials *m, int32_t *index,
                       esf_error *err);

#endif
