/* scene_outputs.c — the output keys that ask for loads (docs/scene.md#output):
 * output.walls (bool: walls.csv, each wall's force and moment at every energy row) and
 * output.stress (a list of {region: {min, max}}: stress.csv, each region's average
 * stress at every energy row; output/wall_loads.h). Both are written at the energy
 * rows, or every output.stress_every seconds when given (> 0; a run without the ledger,
 * e.g. under Lees-Edwards shear), so output.energy_every: 0 with either and no
 * stress_every is an error at the key. Entry: the output mapping, energy_every read
 * (-1: not given); exit: c->out_walls, n_stress, stress_box, stress_every set. Units: m,
 * s. */
#include <math.h>

#include "scene/scene_parts.h"

int esf_scene_outputs(const esf_ynode *ou, esf_config *c, esf_error *err) {
  static const char *const skeys[] = {"region", NULL};
  static const char *const rkeys[] = {"min", "max", NULL};
  int rc = esf_yget_bool(ou, "walls", 0, &c->out_walls, err);
  const esf_ynode *st = esf_ymap_get(ou, "stress");
  c->n_stress = 0;
  if (!rc && st) {
    rc = esf_ynode_require_seq(st, err);
    if (!rc && st->n > ESF_STRESS_MAX)
      return esf_ynode_fail(st, err, "at most %d stress regions, got %zu", ESF_STRESS_MAX,
                            (size_t)st->n);
    for (size_t k = 0; !rc && k < (size_t)st->n; k++) {
      const esf_ynode *e = st->items[k], *r = NULL;
      double *b = c->stress_box[k];
      rc = esf_ynode_require_map(e, err);
      if (!rc) rc = esf_ymap_check_keys(e, skeys, err);
      if (!rc && !(r = esf_ymap_get(e, "region")))
        return esf_ynode_fail(e, err, "a stress region needs region: {min, max} (m)");
      if (!rc) rc = esf_ynode_require_map(r, err);
      if (!rc) rc = esf_ymap_check_keys(r, rkeys, err);
      if (!rc) rc = esf_yget_doubles(r, "min", 1, b, 3, err);
      if (!rc) rc = esf_yget_doubles(r, "max", 1, b + 3, 3, err);
      for (int q = 0; q < 3 && !rc; q++)
        if (!(b[q] < b[q + 3]))
          return esf_ynode_fail(r, err, "min must be below max in every direction");
    }
    c->n_stress = rc ? 0 : (int)st->n;
  }
  const esf_ynode *w = esf_ymap_get(ou, "walls"), *se = esf_ymap_get(ou, "stress_every");
  c->stress_every = 0;
  if (!rc && se) {
    rc = esf_ynode_double(se, &c->stress_every, err);
    if (!rc && !(c->stress_every > 0 && isfinite(c->stress_every)))
      return esf_ynode_fail(se, err, "must be a positive interval (s), got %g",
                            c->stress_every);
    if (!rc && !c->out_walls && !c->n_stress)
      return esf_ynode_fail(se, err, "needs output.stress or output.walls");
  }
  if (!rc && c->energy_every == 0 && !(c->stress_every > 0) &&
      (c->out_walls || c->n_stress))
    return esf_ynode_fail(c->out_walls ? w : st, err,
                          "written at the energy rows: needs output.energy_every > 0 "
                          "or output.stress_every");
  return rc;
}
