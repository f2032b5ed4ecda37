/* fuzz_set.c — fuzzes `--set KEY=VALUE` overrides (esf_ydoc_override,
 * formats/yaml_tree.c) applied to a fixed valid scene, then the scene read, set up and
 * the integrator created as `esfera run SCENE --set ...` does (fuzz_sim.c).
 * How: each line of the input (up to 16; a NUL byte ends the input, as it would an
 * argument) is one override, applied in order until one fails, as esf_scene_load does.
 * The scene below has nodes of every kind the schema reads: two materials, explicit
 * particles, a CSV file, a lattice, a plane, a moving box, an STL mesh, a cylinder,
 * damping, events and a fluid.
 * What holds: a failed override leaves the tree exactly as it was (its documented
 * promise, checked by comparing a dump of the tree before and after); otherwise as
 * fuzz_scene.c: a status with a message, no crash, no undefined behaviour, no leak. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/yaml_tree.h"
#include "fuzz.h"

const char esf_fuzz_name[] = "set";

static const char scene[] =
    "name: fuzz_set\n"
    "gravity: [0, 0, -9.81]\n"
    "domain: {min: [-0.1, -0.1, -0.1], max: [0.2, 0.2, 0.3]}\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}\n"
    "  steel: {density: 7800, kn: 2.0e5, kt: 1.5e5, friction_angle: 20, cohesion: 0,\n"
    "          adhesion: {force: 0.5, epsilon: 0.5}}\n"
    "mixing: {kn: harmonic}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.005, position: [0.05, 0.05, 0.05]}\n"
    "  - {material: steel, radius: 0.004, position: [0.07, 0.05, 0.05],\n"
    "     velocity: [0, 0, -0.1], angular_velocity: [0, 1, 0]}\n"
    "  - {file: particles.csv, material: glass}\n"
    "  - generate: lattice\n"
    "    region: {min: [0, 0, 0.1], max: [0.04, 0.04, 0.14]}\n"
    "    radius: {uniform: [0.003, 0.004]}\n"
    "    material: {mix: {glass: 0.5, steel: 0.5}}\n"
    "    count: 8\n"
    "    seed: 2\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, -0.05], normal: [0, 0, 1]}, material: glass}\n"
    "  - box: {min: [-0.05, -0.05, -0.05], max: [0.15, 0.15, 0.25]}\n"
    "    open: [top]\n"
    "    material: steel\n"
    "    motion: {oscillate: {direction: [0, 0, 1], frequency: 20, amplitude: 0.001}}\n"
    "  - mesh: {file: tet.stl, scale: 0.01, translate: [0.1, 0.1, 0.1]}\n"
    "    material: glass\n"
    "  - cylinder: {base: [0.12, 0.0, 0.0], radius: 0.01, height: 0.02, segments: 8}\n"
    "    material: glass\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.2}\n"
    "damping: {global: {translation: 1.0}, local: {coefficient: 0.1}}\n"
    "contact: {tangential_frame: rotate}\n"
    "search: ~\n"
    "events:\n"
    "  - {at: 0.01, delete: {box: {min: [0.1, 0.1, 0.1], max: [0.2, 0.2, 0.2]}}}\n"
    "fluid:\n"
    "  porosity: 0.4\n"
    "  viscosity: 0.001\n"
    "  density: 1000\n"
    "  uniform: {velocity: [0, 0, 0.01], pressure_gradient: [0, 0, 0]}\n"
    "run: {duration: 0.01}\n"
    "output: {every: 0.005, energy_every: 0.001, contacts: true}\n";

/* The tree as text: kinds, texts, keys and paths (places are not compared). */
typedef struct dump {
  char *s;
  size_t n, cap;
} dump;

static void put(dump *d, const char *s) {
  size_t l = strlen(s) + 1;
  if (d->n + l > d->cap) {
    d->cap = 2 * (d->n + l);
    if (!(d->s = realloc(d->s, d->cap))) abort();
  }
  memcpy(d->s + d->n, s, l); /* NUL-separated */
  d->n += l;
}

static void dump_node(dump *d, const esf_ynode *n) {
  char h[64];
  snprintf(h, sizeof h, "%d %d %zu", (int)n->kind, n->quoted, n->n);
  put(d, h);
  put(d, n->path);
  if (n->text) put(d, n->text);
  for (size_t k = 0; (n->kind == ESF_YN_SEQ || n->kind == ESF_YN_MAP) && k < n->n; k++) {
    if (n->kind == ESF_YN_MAP) put(d, n->keys[k]);
    dump_node(d, n->items[k]);
  }
}

int esf_fuzz_one(const uint8_t *data, size_t size, esf_error *err) {
  char *text = malloc(size + 1);
  if (!text) abort();
  memcpy(text, data, size);
  text[size] = '\0';
  const char *path = ESF_FUZZ_DATA "/set.yaml";
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_parse_as(scene, sizeof scene - 1, path, &doc, err);
  if (rc) abort(); /* the fixed scene is valid */
  char *line = text;
  for (int k = 0; k < 16 && !rc && line < text + size; k++) {
    char *nl = strchr(line, '\n'), *next = nl ? nl + 1 : text + size;
    if (nl) *nl = '\0';
    dump before = {0}, after = {0};
    dump_node(&before, esf_ydoc_root(doc));
    rc = esf_ydoc_override(doc, line, err);
    if (rc) {
      dump_node(&after, esf_ydoc_root(doc));
      if (before.n != after.n || memcmp(before.s, after.s, before.n)) {
        fprintf(stderr, "fuzz_set: the failed override '%s' changed the tree\n", line);
        abort();
      }
    }
    free(before.s);
    free(after.s);
    line = next;
  }
  if (!rc) rc = esf_fuzz_scene(doc, path, err);
  esf_ydoc_free(&doc);
  free(text);
  return rc;
}
