/* scene_loads.h — scene keys of the loads (scene_loads.c, loads/): servo wall
 * motion, `events:` (deleting particles in a region at a time) and `fluid:` (one-way
 * fluid force). */
#ifndef ESF_SCENE_LOADS_H
#define ESF_SCENE_LOADS_H

#include "core/sim.h"
#include "formats/yaml_tree.h"

/* motion: {servo: {...}} of one wall (node: the servo mapping). */
int esf_scene_servo(const esf_ynode *node, esf_wall_motion *m, esf_error *err);

/* The top-level `events:` and `fluid:` keys (absent: nothing). */
int esf_scene_loads(const esf_ynode *root, esf_sim *s, esf_error *err);

#endif
