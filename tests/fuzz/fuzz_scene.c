/* fuzz_scene.c — fuzzes the scene reader with whole YAML scenes: the YAML tree
 * (formats/yaml_tree.c), the schema (scene/), the particle sources, walls, meshes and
 * loads it reads, then set-up and the integrator's creation, as `esfera run SCENE`
 * does before its first step (fuzz_sim.c).
 * How: the input is parsed as the text of ESF_FUZZ_DATA/scene.yaml (esf_ydoc_parse_as,
 * what esf_scene_load does after reading the file), so that relative files resolve in
 * tests/fuzz/data (particles.csv, tet.stl). Inputs naming /dev, /proc or /sys are
 * skipped: a scene may name any file, and a device can be endless.
 * What holds: ESF_OK, or an error with a message (ESF_EINPUT and ESF_EIO for bad input;
 * ESF_ENOMEM when the scene asks for more than the harness's allocation limit,
 * fuzz_main.c); no crash, no undefined behaviour, no leak, on any bytes. */
#include <string.h>

#include "formats/yaml_tree.h"
#include "fuzz.h"

const char esf_fuzz_name[] = "scene";

static int names_device(const uint8_t *d, size_t n) {
  static const char *const dirs[] = {"/dev", "/proc", "/sys"};
  for (int k = 0; k < 3; k++) {
    size_t l = strlen(dirs[k]);
    for (size_t i = 0; i + l <= n; i++)
      if (!memcmp(d + i, dirs[k], l)) return 1;
  }
  return 0;
}

int esf_fuzz_one(const uint8_t *data, size_t size, esf_error *err) {
  if (names_device(data, size)) return ESF_OK;
  const char *path = ESF_FUZZ_DATA "/scene.yaml";
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_parse_as((const char *)data, size, path, &doc, err);
  if (!rc) rc = esf_fuzz_scene(doc, path, err);
  esf_ydoc_free(&doc);
  return rc;
}
