/* scene_parts.h — the scene reader's own parts, for its files only: the particle and
 * wall lists (scene_particles.c, scene_walls.c, scene_meshes.c) and the helpers they
 * share (scene_util.c). The public entry points are scene.h's. */
#ifndef ESF_SCENE_PARTS_H
#define ESF_SCENE_PARTS_H

#include "bodies/fill.h"
#include "core/sim.h"
#include "formats/yaml_tree.h"

/* Parts (scene_particles.c, scene_walls.c). esf_scene_particles sets *entry (malloc'd,
 * the caller frees it) to the index in seq of the entry each particle came from. */
int esf_scene_particles(const esf_ynode *seq, const char *dir, esf_sim *s,
                        uint32_t **entry, esf_error *err);
/* A size distribution (`radius`: a number or {uniform | uniform_diameter | values,
 * fractions}; *buf owns the values) and a material mix (`material`: a name or
 * {mix: {name: fraction}}; *mats, *fr own its arrays), as generators and insert
 * entries give them (scene_particles.c). */
int esf_scene_size(const esf_ynode *r, esf_size_dist *sd, double **buf, esf_error *err);
int esf_scene_mix(const esf_ynode *mn, const esf_sim *s, esf_material_mix *mix,
                  int32_t **mats, double **fr, esf_error *err);
/* An entry {insert: {...}} of the particles list into s->insert (scene_insert.c). */
int esf_scene_insert(const esf_ynode *e, esf_sim *s, esf_error *err);
int esf_scene_walls(const esf_ynode *seq, const char *dir, esf_sim *s, esf_error *err);
/* A wall's `motion:` (scene_motion.c): one motion or a sequence into group. */
int esf_scene_motion(const esf_ynode *mo, esf_walls *w, int group, esf_error *err);
/* Mesh walls (scene_meshes.c): entry e's `mesh`, `cylinder` or `screw` into group. */
int esf_scene_wall_stl(const esf_ynode *e, const char *dir, esf_sim *s, int group,
                       int32_t mat, esf_error *err);
int esf_scene_wall_cylinder(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                            esf_error *err);
int esf_scene_wall_screw(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                         esf_error *err);

/* Initial overlaps (scene_overlap.c), after the particles (entry: as above) and
 * walls are read: a particle overlapping a wall at the start is an error unless
 * contact.allow_initial_overlap, and any overlap (wall or particle) beyond
 * contact.max_overlap of the radius is one always; the message names the particle,
 * the wall element or the other particle, the overlap and their scene entries. */
int esf_scene_check_overlaps(const esf_ynode *seq, const esf_ynode *walls,
                             const esf_sim *s, const uint32_t *entry, esf_error *err);

/* integrator.table (scene_butcher.c): the Butcher table of method erk into c->table,
 * checked; with no table, method erk is an error. in: the integrator mapping (method and
 * rtol read). */
/* domain.periodic (scene_domain.c): c->per and the removal box from the domain node. */
int esf_scene_periodic(const esf_ynode *dom, esf_config *c, esf_error *err);

int esf_scene_butcher(const esf_ynode *in, esf_config *c, esf_error *err);

/* output.walls and output.stress (scene_outputs.c) from the output mapping ou, after
 * energy_every was read (both need energy rows). */
int esf_scene_outputs(const esf_ynode *ou, esf_config *c, esf_error *err);

/* Helpers shared by the readers (scene_util.c). */
/* Re-raises err's message (set by a geometry builder) at node n's position. */
int esf_scene_fail_at(const esf_ynode *n, esf_error *err);
/* A unit vector from key `key` of map m: finite and non-zero, normalised. When not
 * required and the key is absent, u's value on entry (the default) is normalised. */
int esf_scene_unit_vector(const esf_ynode *m, const char *key, int required, double u[3],
                          esf_error *err);

#endif
