/* test_yaml.c — the YAML tree: values read exactly, error places (file:line:col and
 * dotted path), unknown-key suggestions, overrides, file loading. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "formats/yaml_tree.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CHECK_MSG(err, expected)                                                         \
  CHECK(strcmp((err).msg, (expected)) == 0, "message\n  got      '%s'\n  expected '%s'", \
        (err).msg, (expected))
#define CHECK_PREFIX(err, prefix)                                                        \
  CHECK(strncmp((err).msg, (prefix), strlen(prefix)) == 0,                               \
        "message '%s' does not start with '%s'", (err).msg, (prefix))
#define CHECK_STR(a, b)                                                                  \
  CHECK((a) && strcmp((a), (b)) == 0, "got '%s', expected '%s'", (a) ? (a) : "(null)",   \
        (b))

static const char *scene = "# a scene\n"
                           "name: drop test\n"                       /* 2 */
                           "steps: 1000\n"                           /* 3 */
                           "gravity: [0, 0, -9.81]\n"                /* 4 */
                           "output: yes\n"                           /* 5 */
                           "materials:\n"                            /* 6 */
                           "  glass:\n"                              /* 7 */
                           "    density: 2500\n"                     /* 8 */
                           "    young: 6.3e10\n"                     /* 9 */
                           "    poisson: +0.25\n"                    /* 10 */
                           "    bad: abc\n"                          /* 11 */
                           "    quoted: \"3\"\n"                     /* 12 */
                           "    model: herz\n"                       /* 13 */
                           "particles:\n"                            /* 14 */
                           "  - {radius: 0.01, center: [0, 0, 1]}\n" /* 15 */
                           "  - radius: 1.0e-4\n"                    /* 16 */
                           "    center: [1, 2]\n"                    /* 17 */
                           "empty_a: ~\n"                            /* 18 */
                           "empty_b: null\n"                         /* 19 */
                           "empty_c:\n"                              /* 20 */
                           "text: |\n"                               /* 21 */
                           "  two\n"
                           "  lines\n";

static esf_ydoc *parse_ok(const char *text) {
  esf_ydoc *doc = NULL;
  esf_error err = {0};
  int st = esf_ydoc_parse(text, "s.yaml", &doc, &err);
  CHECK_OK(st, err);
  return doc;
}

static int parse_fails(const char *text, esf_error *err) {
  esf_ydoc *doc = NULL;
  int st = esf_ydoc_parse(text, "s.yaml", &doc, err);
  CHECK(doc == NULL, "a failed parse leaves no document");
  return st;
}

static void test_values(void) {
  esf_ydoc *doc = parse_ok(scene);
  esf_error err = {0};
  esf_ynode *root = esf_ydoc_root(doc);
  CHECK(root && root->kind == ESF_YN_MAP && root->n == 10, "root mapping of 10 keys");
  CHECK_STR(root->path, "");
  CHECK_STR(esf_ydoc_dir(doc), ".");
  const char *s = NULL;
  CHECK_OK(esf_yget_string(root, "name", 1, &s, &err), err);
  CHECK_STR(s, "drop test");
  long steps = 0;
  CHECK_OK(esf_yget_long(root, "steps", 1, &steps, &err), err);
  CHECK(steps == 1000, "steps %ld", steps);
  double g[3] = {0};
  CHECK_OK(esf_yget_doubles(root, "gravity", 1, g, 3, &err), err);
  CHECK(g[0] == 0 && g[1] == 0 && g[2] == -9.81, "gravity %g %g %g", g[0], g[1], g[2]);
  int b = -1;
  CHECK_OK(esf_yget_bool(root, "output", 1, &b, &err), err);
  CHECK(b == 1, "output yes");

  esf_ynode *glass = esf_ymap_get(esf_ymap_get(root, "materials"), "glass");
  CHECK(glass && glass->kind == ESF_YN_MAP, "glass is a mapping");
  CHECK(glass && glass->line == 8 && glass->col == 5, "glass at 8:5");
  CHECK_STR(glass->path, "materials.glass");
  double d = 0;
  CHECK_OK(esf_yget_double(glass, "density", 1, &d, &err), err);
  CHECK(d == 2500.0, "density %g", d);
  CHECK_OK(esf_yget_double(glass, "young", 1, &d, &err), err);
  CHECK(d == 6.3e10, "young %g", d);
  CHECK_OK(esf_yget_double(glass, "poisson", 1, &d, &err), err);
  CHECK(d == 0.25, "poisson %g", d);
  esf_ynode *density = esf_ymap_get(glass, "density");
  CHECK(density->kind == ESF_YN_SCALAR && !density->quoted, "plain scalar");
  CHECK(density->line == 8 && density->col == 14, "density at %d:%d", density->line,
        density->col);
  CHECK_STR(density->path, "materials.glass.density");
  CHECK(glass->key_line[0] == 8 && glass->key_col[0] == 5, "key place");

  /* optional keys keep the caller's default */
  d = 42;
  CHECK_OK(esf_yget_double(glass, "absent", 0, &d, &err), err);
  CHECK(d == 42, "default kept");
  CHECK(esf_ymap_get(glass, "absent") == NULL, "absent key");
  CHECK(esf_ymap_get(NULL, "x") == NULL, "NULL map");

  esf_ynode *parts = esf_ymap_get(root, "particles");
  CHECK(parts && parts->kind == ESF_YN_SEQ && parts->n == 2, "two particles");
  CHECK_STR(parts->items[1]->path, "particles.1");
  esf_ynode *r1 = esf_ymap_get(parts->items[1], "radius");
  CHECK_STR(r1->path, "particles.1.radius");
  CHECK(r1->line == 16 && r1->col == 13, "radius at %d:%d", r1->line, r1->col);
  CHECK_OK(esf_ynode_double(r1, &d, &err), err);
  CHECK(d == 1.0e-4, "radius %g", d);
  double c[3] = {0};
  CHECK_OK(esf_yget_doubles(parts->items[0], "center", 1, c, 3, &err), err);
  CHECK(c[0] == 0 && c[1] == 0 && c[2] == 1, "center");
  CHECK_STR(esf_ymap_get(parts->items[0], "center")->items[2]->path,
            "particles.0.center.2");

  CHECK(esf_ymap_get(root, "empty_a")->kind == ESF_YN_NULL, "~ is null");
  CHECK(esf_ymap_get(root, "empty_b")->kind == ESF_YN_NULL, "null is null");
  CHECK(esf_ymap_get(root, "empty_c")->kind == ESF_YN_NULL, "empty is null");
  CHECK(esf_ymap_get(root, "empty_c")->text == NULL, "null has no text");
  CHECK_OK(esf_yget_string(root, "text", 1, &s, &err), err);
  CHECK_STR(s, "two\nlines\n");

  char buf[64];
  CHECK_STR(esf_ynode_where(density, buf, sizeof buf), "s.yaml:8:14");

  static const char *const models[] = {"hooke", "hertz", NULL};
  int m = -1;
  CHECK(esf_yget_choice(glass, "model", 1, models, &m, &err) == ESF_EINPUT, "herz");
  CHECK_MSG(err, "s.yaml:13:12: materials.glass.model: expected one of: hooke, hertz; "
                 "got 'herz' (did you mean 'hertz'?)");
  CHECK(m == -1, "choice unchanged on error");
  esf_ydoc *d2 = parse_ok("model: hertz\n");
  CHECK_OK(esf_yget_choice(esf_ydoc_root(d2), "model", 1, models, &m, &err), err);
  CHECK(m == 1, "hertz is choice 1");
  esf_ydoc_free(&d2);
  CHECK(d2 == NULL, "free sets NULL");

  /* ---- errors at the node's place ---- */
  CHECK(esf_yget_double(glass, "bad", 1, &d, &err) == ESF_EINPUT, "abc");
  CHECK_MSG(err, "s.yaml:11:10: materials.glass.bad: expected a number, got 'abc'");
  CHECK(err.code == ESF_EINPUT, "code set");
  CHECK(esf_yget_double(glass, "quoted", 1, &d, &err) == ESF_EINPUT, "quoted");
  CHECK_MSG(err,
            "s.yaml:12:13: materials.glass.quoted: expected a number, got the string "
            "'3'");
  CHECK_OK(esf_yget_string(glass, "quoted", 1, &s, &err), err);
  CHECK_STR(s, "3");
  CHECK(esf_yget_double(glass, "density_x", 1, &d, &err) == ESF_EINPUT, "missing");
  CHECK_MSG(err, "s.yaml:8:5: materials.glass: missing key 'density_x'");
  CHECK(esf_yget_double(root, "nothing", 1, &d, &err) == ESF_EINPUT, "missing at top");
  CHECK_MSG(err, "s.yaml:2:1: missing key 'nothing'");
  CHECK(esf_yget_doubles(parts->items[1], "center", 1, c, 3, &err) == ESF_EINPUT,
        "2 of 3");
  CHECK_MSG(err,
            "s.yaml:17:13: particles.1.center: expected a sequence of 3 numbers, got "
            "2 items");
  CHECK(c[0] == 0 && c[1] == 0 && c[2] == 1, "vector unchanged on error");
  CHECK(esf_yget_doubles(root, "name", 1, c, 3, &err) == ESF_EINPUT, "not a seq");
  CHECK_MSG(err, "s.yaml:2:7: name: expected a sequence of 3 numbers, got 'drop test'");
  CHECK(esf_ynode_require_map(parts, &err) == ESF_EINPUT, "seq is no map");
  CHECK_MSG(err, "s.yaml:15:3: particles: expected a mapping, got a sequence");
  CHECK(esf_ynode_require_seq(glass, &err) == ESF_EINPUT, "map is no seq");
  CHECK_MSG(err, "s.yaml:8:5: materials.glass: expected a sequence, got a mapping");
  CHECK_OK(esf_ynode_require_seq(parts, &err), err);
  CHECK(esf_yget_string(root, "empty_a", 1, &s, &err) == ESF_EINPUT, "null string");
  CHECK_MSG(err, "s.yaml:18:10: empty_a: expected a string, got null");
  CHECK(esf_yget_bool(root, "steps", 1, &b, &err) == ESF_EINPUT, "1000 is no bool");
  CHECK_MSG(err, "s.yaml:3:8: steps: expected true or false, got '1000'");
  CHECK(esf_yget_long(glass, "bad", 1, &steps, &err) == ESF_EINPUT, "abc is no integer");
  CHECK_MSG(err, "s.yaml:11:10: materials.glass.bad: expected an integer, got 'abc'");
  esf_ydoc_free(&doc);
}

static void test_numbers(void) {
  static const struct {
    const char *text;
    double value;
  } good[] = {{"1e5", 1e5}, {"-2.5", -2.5},       {"1.0e-4", 1.0e-4},
              {"+3", 3.0},  {"10", 10.0},         {".5", 0.5},
              {"-0", -0.0}, {"6.02E23", 6.02e23}, {"1e-400", 0.0}};
  static const char *const bad[] = {"1.5x", "0x10", "1e",  "--1",
                                    "1,5",  "e5",   "1 2", "abc"};
  static const char *const infinite[] = {".inf",  "-.inf",  ".NaN",
                                         "1e999", "-1e999", "inf"};
  esf_error err = {0};
  char text[64], msg[256];
  for (size_t i = 0; i < sizeof good / sizeof *good; i++) {
    snprintf(text, sizeof text, "x: %s\n", good[i].text);
    esf_ydoc *doc = parse_ok(text);
    double d = -1;
    CHECK_OK(esf_yget_double(esf_ydoc_root(doc), "x", 1, &d, &err), err);
    CHECK(d == good[i].value, "%s read as %.17g", good[i].text, d);
    esf_ydoc_free(&doc);
  }
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    snprintf(text, sizeof text, "x: %s\n", bad[i]);
    esf_ydoc *doc = parse_ok(text);
    double d = -1;
    CHECK(esf_yget_double(esf_ydoc_root(doc), "x", 1, &d, &err) == ESF_EINPUT, "%s",
          bad[i]);
    snprintf(msg, sizeof msg, "s.yaml:1:4: x: expected a number, got '%s'", bad[i]);
    CHECK_MSG(err, msg);
    CHECK(d == -1, "unchanged");
    esf_ydoc_free(&doc);
  }
  for (size_t i = 0; i < sizeof infinite / sizeof *infinite; i++) {
    snprintf(text, sizeof text, "x: %s\n", infinite[i]);
    esf_ydoc *doc = parse_ok(text);
    double d = -1;
    CHECK(esf_yget_double(esf_ydoc_root(doc), "x", 1, &d, &err) == ESF_EINPUT, "%s",
          infinite[i]);
    snprintf(msg, sizeof msg, "s.yaml:1:4: x: expected a finite number, got '%s'",
             infinite[i]);
    CHECK_MSG(err, msg);
    esf_ydoc_free(&doc);
  }

  esf_ydoc *doc = parse_ok("a: 7\nb: -12\nc: 1e3\nd: 2.5\ne: 99999999999999999999\n"
                           "f: 2.0\ng: off\nh: TRUE\ni: 'yes'\nj: No\n");
  esf_ynode *root = esf_ydoc_root(doc);
  long l = 0;
  CHECK_OK(esf_yget_long(root, "a", 1, &l, &err), err);
  CHECK(l == 7, "a %ld", l);
  CHECK_OK(esf_yget_long(root, "b", 1, &l, &err), err);
  CHECK(l == -12, "b %ld", l);
  CHECK_OK(esf_yget_long(root, "c", 1, &l, &err), err);
  CHECK(l == 1000, "c %ld", l);
  CHECK_OK(esf_yget_long(root, "f", 1, &l, &err), err);
  CHECK(l == 2, "f %ld", l);
  CHECK(esf_yget_long(root, "d", 1, &l, &err) == ESF_EINPUT, "2.5 is not whole");
  CHECK_MSG(err, "s.yaml:4:4: d: expected a whole number, got '2.5'");
  CHECK(esf_yget_long(root, "e", 1, &l, &err) == ESF_EINPUT, "out of range");
  CHECK_PREFIX(err, "s.yaml:5:4: e: expected an integer from ");
  int b = -1;
  CHECK_OK(esf_yget_bool(root, "g", 1, &b, &err), err);
  CHECK(b == 0, "off");
  CHECK_OK(esf_yget_bool(root, "h", 1, &b, &err), err);
  CHECK(b == 1, "TRUE");
  CHECK_OK(esf_yget_bool(root, "j", 1, &b, &err), err);
  CHECK(b == 0, "No");
  CHECK(esf_yget_bool(root, "i", 1, &b, &err) == ESF_EINPUT, "quoted yes");
  CHECK_MSG(err, "s.yaml:9:4: i: expected true or false, got the string 'yes'");
  esf_ydoc_free(&doc);
}

static void test_keys(void) {
  esf_error err = {0};
  esf_ydoc *doc = parse_ok("materials:\n  glass:\n    densty: 1\n    young: 2\n"
                           "gravty: [0, 0, 0]\nzzz: 1\n");
  esf_ynode *root = esf_ydoc_root(doc);
  esf_ynode *glass = esf_ymap_get(esf_ymap_get(root, "materials"), "glass");
  static const char *const mat_keys[] = {"density", "young", "poisson", NULL};
  static const char *const top_keys[] = {"materials", "gravity", "particles", NULL};
  static const char *const top_no_g[] = {"materials", "particles", "steps", NULL};
  static const char *const none[] = {NULL};
  CHECK(esf_ymap_check_keys(glass, mat_keys, &err) == ESF_EINPUT, "densty");
  CHECK_MSG(
      err,
      "s.yaml:3:5: unknown key 'densty' in materials.glass (did you mean 'density'?)");
  CHECK(esf_ymap_check_keys(root, top_keys, &err) == ESF_EINPUT, "gravty");
  CHECK_MSG(err, "s.yaml:5:1: unknown key 'gravty' at the top level (did you mean "
                 "'gravity'?)");
  CHECK(esf_ymap_check_keys(root, top_no_g, &err) == ESF_EINPUT, "no suggestion");
  CHECK_MSG(err, "s.yaml:5:1: unknown key 'gravty' at the top level (expected one of: "
                 "materials, particles, steps)");
  CHECK(esf_ymap_check_keys(glass, none, &err) == ESF_EINPUT, "none allowed");
  CHECK_PREFIX(err, "s.yaml:3:5: unknown key 'densty' in materials.glass");
  CHECK_OK(esf_ymap_check_keys(NULL, mat_keys, &err), err);
  esf_ydoc_free(&doc);

  /* case-insensitive match and prefix suggestions */
  doc = parse_ok("Density: 1\n");
  CHECK(esf_ymap_check_keys(esf_ydoc_root(doc), mat_keys, &err) == ESF_EINPUT, "Density");
  CHECK_MSG(err, "s.yaml:1:1: unknown key 'Density' at the top level (did you mean "
                 "'density'?)");
  esf_ydoc_free(&doc);
  doc = parse_ok("pois: 1\n");
  CHECK(esf_ymap_check_keys(esf_ydoc_root(doc), mat_keys, &err) == ESF_EINPUT, "pois");
  CHECK_MSG(err, "s.yaml:1:1: unknown key 'pois' at the top level (did you mean "
                 "'poisson'?)");
  esf_ydoc_free(&doc);
  doc = parse_ok("{}");
  CHECK_OK(esf_ymap_check_keys(esf_ydoc_root(doc), mat_keys, &err), err);
  esf_ydoc_free(&doc);
}

static void test_syntax(void) {
  esf_error err = {0};
  CHECK(parse_fails("a: 1\nb:\n  c: 1\n  c: 2\n", &err) == ESF_EINPUT, "duplicate");
  CHECK_MSG(err, "s.yaml:4:3: b: duplicate key 'c' (first at line 3)");
  CHECK(parse_fails("a: 1\n b: 2\n", &err) == ESF_EINPUT, "bad indent");
  CHECK_MSG(err, "s.yaml:2:3: YAML syntax error: mapping values are not allowed in this "
                 "context");
  CHECK(parse_fails("ok: 1\n\tb: 2\n", &err) == ESF_EINPUT, "tab");
  CHECK_PREFIX(err, "s.yaml:2:1: YAML syntax error: ");
  CHECK(parse_fails("a: &x 1\nb: *x\n", &err) == ESF_EINPUT, "alias");
  CHECK_MSG(err, "s.yaml:2:4: b: aliases (*x) are not supported; write the value out");
  CHECK(parse_fails("b:\n  <<: {y: 2}\n", &err) == ESF_EINPUT, "merge key");
  CHECK_MSG(err, "s.yaml:2:3: b: merge keys ('<<') are not supported");
  CHECK(parse_fails("a: 1\n---\nb: 2\n", &err) == ESF_EINPUT, "two documents");
  CHECK_MSG(err, "s.yaml:2:1: only one YAML document is allowed per file");
  CHECK(parse_fails("[1, 2]: x\n", &err) == ESF_EINPUT, "collection key");
  CHECK_MSG(err, "s.yaml:1:1: mapping keys must be scalars");

  /* empty documents give an empty mapping */
  static const char *const empties[] = {"", "# nothing\n", "---\n", "~\n"};
  for (size_t i = 0; i < 4; i++) {
    esf_ydoc *doc = parse_ok(empties[i]);
    esf_ynode *root = esf_ydoc_root(doc);
    CHECK(root && root->kind == ESF_YN_MAP && root->n == 0, "empty doc %zu", i);
    esf_ydoc_free(&doc);
  }
}

static void test_overrides(void) {
  esf_error err = {0};
  esf_ydoc *doc =
      parse_ok("gravity: [0, 0, -9.81]\nmaterials:\n  glass:\n    density: 1\n"
               "particles:\n  - radius: 0.1\n  - radius: 0.3\nsolver: ~\n"
               "name: x\n");
  esf_ynode *root = esf_ydoc_root(doc);

  /* creating keys, with intermediate mappings */
  CHECK_OK(esf_ydoc_override(doc, "materials.steel.density=7800", &err), err);
  esf_ynode *steel = esf_ymap_get(esf_ymap_get(root, "materials"), "steel");
  CHECK(steel && steel->kind == ESF_YN_MAP && steel->line == 0, "steel created");
  CHECK_STR(steel->path, "materials.steel");
  CHECK_STR(steel->origin, "--set materials.steel.density=7800");
  double d = 0;
  CHECK_OK(esf_yget_double(steel, "density", 1, &d, &err), err);
  CHECK(d == 7800, "steel density %g", d);
  esf_ynode *sd = esf_ymap_get(steel, "density");
  CHECK_STR(sd->path, "materials.steel.density");
  CHECK(sd->line == 0 && sd->col == 0, "no place");
  CHECK_OK(esf_ydoc_override(doc, "output.every=5", &err), err);
  long every = 0;
  CHECK_OK(esf_yget_long(esf_ymap_get(root, "output"), "every", 1, &every, &err), err);
  CHECK(every == 5, "every %ld", every);

  /* replacing an existing value; the sequence with a flow sequence */
  CHECK_OK(esf_ydoc_override(doc, "materials.glass.density=2500", &err), err);
  esf_ynode *glass = esf_ymap_get(esf_ymap_get(root, "materials"), "glass");
  CHECK_OK(esf_yget_double(glass, "density", 1, &d, &err), err);
  CHECK(d == 2500, "glass density %g", d);
  CHECK(glass->n == 1, "replaced, not added");
  CHECK_OK(esf_ydoc_override(doc, "gravity=[1,2,3]", &err), err);
  double g[3] = {0};
  CHECK_OK(esf_yget_doubles(root, "gravity", 1, g, 3, &err), err);
  CHECK(g[0] == 1 && g[1] == 2 && g[2] == 3, "gravity %g %g %g", g[0], g[1], g[2]);
  esf_ynode *g2 = esf_ymap_get(root, "gravity")->items[2];
  CHECK_STR(g2->path, "gravity.2");
  CHECK_STR(g2->origin, "--set gravity=[1,2,3]");

  /* indexing a sequence */
  CHECK_OK(esf_ydoc_override(doc, "particles.1.radius=0.2", &err), err);
  esf_ynode *parts = esf_ymap_get(root, "particles");
  CHECK_OK(esf_yget_double(parts->items[1], "radius", 1, &d, &err), err);
  CHECK(d == 0.2, "radius %g", d);
  CHECK_OK(esf_yget_double(parts->items[0], "radius", 1, &d, &err), err);
  CHECK(d == 0.1, "other radius %g", d);
  CHECK_STR(esf_ymap_get(parts->items[1], "radius")->path, "particles.1.radius");
  CHECK_OK(esf_ydoc_override(doc, "particles.0={radius: 0.5, center: [0, 0, 1]}", &err),
           err);
  CHECK_STR(esf_ymap_get(parts->items[0], "center")->items[1]->path,
            "particles.0.center.1");

  /* a null becomes a mapping; an empty value is null; a string stays a string */
  CHECK_OK(esf_ydoc_override(doc, "solver.dt=1e-5", &err), err);
  CHECK_OK(esf_yget_double(esf_ymap_get(root, "solver"), "dt", 1, &d, &err), err);
  CHECK(d == 1e-5, "dt %g", d);
  CHECK_OK(esf_ydoc_override(doc, "name=", &err), err);
  CHECK(esf_ymap_get(root, "name")->kind == ESF_YN_NULL, "empty value is null");
  CHECK_OK(esf_ydoc_override(doc, "name='a=b'", &err), err);
  const char *s = NULL;
  CHECK_OK(esf_yget_string(root, "name", 1, &s, &err), err);
  CHECK_STR(s, "a=b");

  /* errors from nodes made by an override name the override */
  CHECK_OK(esf_ydoc_override(doc, "materials.glass.young=stiff", &err), err);
  CHECK(esf_yget_double(glass, "young", 1, &d, &err) == ESF_EINPUT, "stiff");
  CHECK_MSG(err, "--set materials.glass.young=stiff: materials.glass.young: expected a "
                 "number, got 'stiff'");
  static const char *const mat_keys[] = {"density", "young", NULL};
  CHECK_OK(esf_ydoc_override(doc, "materials.glass.densty=1", &err), err);
  CHECK(esf_ymap_check_keys(glass, mat_keys, &err) == ESF_EINPUT, "override key");
  CHECK_MSG(err,
            "--set materials.glass.densty=1: unknown key 'densty' in materials.glass "
            "(did you mean 'density'?)");
  char buf[128];
  CHECK_STR(esf_ynode_where(steel, buf, sizeof buf),
            "--set materials.steel.density=7800");

  /* override errors, which change nothing */
  size_t nroot = root->n;
  CHECK(esf_ydoc_override(doc, "gravity", &err) == ESF_EINPUT, "no =");
  CHECK_MSG(err, "--set gravity: expected KEY=VALUE");
  CHECK(esf_ydoc_override(doc, "=3", &err) == ESF_EINPUT, "empty key");
  CHECK_MSG(err, "--set =3: empty key before '='");
  CHECK(esf_ydoc_override(doc, "a..b=3", &err) == ESF_EINPUT, "empty component");
  CHECK_MSG(err, "--set a..b=3: empty component in key 'a..b'");
  CHECK(esf_ydoc_override(doc, "materials.glass.density.x=1", &err) == ESF_EINPUT,
        "scalar");
  CHECK_MSG(err,
            "--set materials.glass.density.x=1: cannot set materials.glass.density.x: "
            "materials.glass.density is a scalar");
  CHECK(esf_ydoc_override(doc, "particles.2.radius=1", &err) == ESF_EINPUT, "range");
  CHECK_MSG(err,
            "--set particles.2.radius=1: cannot set particles.2.radius: particles has "
            "2 items (index 2 is out of range)");
  CHECK(esf_ydoc_override(doc, "particles.first.radius=1", &err) == ESF_EINPUT, "word");
  CHECK_PREFIX(err, "--set particles.first.radius=1: cannot set particles.first.radius: "
                    "particles is a sequence");
  CHECK(esf_ydoc_override(doc, "newkey.x=[1, 2", &err) == ESF_EINPUT, "bad value");
  CHECK_PREFIX(err, "--set newkey.x=[1, 2: YAML syntax error in the value");
  CHECK(esf_ydoc_override(doc, "newkey.x={a: 1, a: 2}", &err) == ESF_EINPUT, "dup value");
  CHECK_MSG(err, "--set newkey.x={a: 1, a: 2}: newkey.x: duplicate key 'a'");
  CHECK(root->n == nroot && !esf_ymap_get(root, "newkey"),
        "failed overrides add nothing");
  esf_ydoc_free(&doc);
  esf_ydoc_free(&doc); /* a second free is harmless */
}

static void test_files(void) {
  esf_error err = {0};
  esf_ydoc *doc = NULL;
  CHECK(esf_ydoc_load("/nonexistent/dir/scene.yaml", &doc, &err) == ESF_EIO, "no file");
  CHECK_PREFIX(err, "/nonexistent/dir/scene.yaml: cannot open: ");
  CHECK(doc == NULL, "no doc");

  char name[] = "/tmp/esf_test_yaml_XXXXXX";
  int fd = mkstemp(name);
  CHECK(fd >= 0, "temporary file");
  if (fd < 0) return;
  FILE *f = fdopen(fd, "w");
  fputs("radius: 0.5\nbroken: [1,\n", f);
  fclose(f);
  char where[256];
  CHECK(esf_ydoc_load(name, &doc, &err) == ESF_EINPUT, "syntax error in file");
  snprintf(where, sizeof where, "%s:3:1: YAML syntax error: ", name);
  CHECK_PREFIX(err, where);

  f = fopen(name, "w");
  fputs("radius: 0.5\nname: abc\n", f);
  fclose(f);
  CHECK_OK(esf_ydoc_load(name, &doc, &err), err);
  CHECK_STR(esf_ydoc_dir(doc), "/tmp");
  double r = 0;
  CHECK_OK(esf_yget_double(esf_ydoc_root(doc), "radius", 1, &r, &err), err);
  CHECK(r == 0.5, "radius %g", r);
  CHECK(esf_yget_double(esf_ydoc_root(doc), "name", 1, &r, &err) == ESF_EINPUT, "abc");
  snprintf(where, sizeof where, "%s:2:7: name: expected a number, got 'abc'", name);
  CHECK_MSG(err, where);
  esf_ydoc_free(&doc);
  remove(name);
}

int main(void) {
  test_values();
  test_numbers();
  test_keys();
  test_syntax();
  test_overrides();
  test_files();
  return check_finish("test_yaml");
}
