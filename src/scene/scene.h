/* scene.h — reading a YAML scene (docs/scene.md) into a simulation.
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

/* The material index named by a scalar node, or an error listing the materials
 * (scene_util.c; also read by `esfera generate`). */
int esf_scene_material(const esf_ynode *node, const esf_materials *m, int32_t *index,
                       esf_error *err);

#endif
