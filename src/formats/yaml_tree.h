/* yaml_tree.h — a YAML document as a small tree of nodes that remember where they came
 * from (file, line, column), with dotted-path overrides (`--set a.b.0.c=VALUE`) and the
 * typed accessors the scene reader uses. Every accessor reports errors through
 * esf_error with the node's place: "scene.yaml:12:5: materials.glass.density: expected
 * a number, got 'abc'". Nodes made by an override report "--set KEY=VALUE" instead.
 *
 * Ownership: an esf_ydoc owns all its nodes and strings; esf_ydoc_free releases them. */
#ifndef ESF_YAML_TREE_H
#define ESF_YAML_TREE_H

#include <stddef.h>

#include "util/esf_error.h"

typedef enum { ESF_YN_NULL, ESF_YN_SCALAR, ESF_YN_SEQ, ESF_YN_MAP } esf_ynode_kind;

typedef struct esf_ynode esf_ynode;
struct esf_ynode {
  esf_ynode_kind kind;
  char *text;         /* SCALAR: the scalar's text; NULL otherwise */
  int quoted;         /* SCALAR: written in quotes (then it is always a string) */
  const char *origin; /* the file name, or the override text "--set KEY=VALUE" */
  int line, col;      /* 1-based place in origin; 0 when origin is an override */
  char *path;         /* dotted path from the root, "materials.glass.density" ("" root) */
  size_t n;           /* SEQ: item count; MAP: key count */
  esf_ynode **items;  /* SEQ: the items; MAP: the values, items[k] for keys[k] */
  char **keys;        /* MAP: the keys, in document order */
  int *key_line;      /* MAP: place of each key (for unknown-key errors) */
  int *key_col;
};

typedef struct esf_ydoc esf_ydoc; /* opaque: owns the tree and its strings */

/* Reads and parses a YAML file. Syntax errors name file, line and column (ESF_EINPUT);
 * an unreadable file gives ESF_EIO. Duplicate keys in a mapping are errors. An empty
 * document gives an empty mapping as root. */
int esf_ydoc_load(const char *path, esf_ydoc **out, esf_error *err);

/* Parses YAML text; `name` stands in for the file name in messages. */
int esf_ydoc_parse(const char *text, const char *name, esf_ydoc **out, esf_error *err);

/* Parses len bytes of YAML text as if read from the file at path (messages name it;
 * relative paths resolve against its directory): a checkpoint's stored scene. */
int esf_ydoc_parse_as(const char *text, size_t len, const char *path, esf_ydoc **out,
                      esf_error *err);

/* The root node (a mapping for any valid scene). */
esf_ynode *esf_ydoc_root(esf_ydoc *doc);

/* The directory of the loaded file ("." for parsed text), for relative paths. */
const char *esf_ydoc_dir(const esf_ydoc *doc);

/* Applies one override "dotted.key=VALUE". VALUE is parsed as a YAML scalar or flow
 * collection ("[0,0,-9.81]", "{a: 1}"). Missing mapping keys along the path are created
 * (whether a key is allowed is the schema's business, checked later as for file keys);
 * a numeric component indexes a sequence and must exist. Replaces the node at the path.
 * Errors: no '=', empty key, indexing a scalar, index out of range, bad VALUE syntax. */
int esf_ydoc_override(esf_ydoc *doc, const char *assignment, esf_error *err);

void esf_ydoc_free(esf_ydoc **doc);

/* ---- reading the tree ------------------------------------------------------------ */

/* "file:line:col" or "--set KEY=VALUE" for a node, written into buf. Returns buf. */
const char *esf_ynode_where(const esf_ynode *node, char *buf, size_t len);

/* Fails with ESF_EINPUT and "WHERE: PATH: MESSAGE" for node; returns ESF_EINPUT. */
int esf_ynode_fail(const esf_ynode *node, esf_error *err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* The value under key in a mapping, or NULL when absent (or when map is NULL). */
esf_ynode *esf_ymap_get(const esf_ynode *map, const char *key);

/* Checks that every key of map is in `allowed` (NULL-terminated). An unknown key is an
 * ESF_EINPUT error at the key's place, naming the closest allowed key when one is near
 * ("did you mean 'density'?") and otherwise listing the allowed keys. A NULL map is ok.
 */
int esf_ymap_check_keys(const esf_ynode *map, const char *const *allowed, esf_error *err);

/* Requires node to be a mapping (or a sequence); error names what was expected. */
int esf_ynode_require_map(const esf_ynode *node, esf_error *err);
int esf_ynode_require_seq(const esf_ynode *node, esf_error *err);

/* Scalar conversions. Each fails with the node's place when the node is not a scalar of
 * that type: numbers accept YAML ints and floats (1, -2.5, 1.0e-4, 1e5, .inf is refused:
 * values must be finite); ints must be whole and in range; bools are true/false (also
 * yes/no/on/off); strings are any scalar. */
int esf_ynode_double(const esf_ynode *node, double *out, esf_error *err);
int esf_ynode_long(const esf_ynode *node, long *out, esf_error *err);
int esf_ynode_bool(const esf_ynode *node, int *out, esf_error *err);
int esf_ynode_string(const esf_ynode *node, const char **out, esf_error *err);
/* A sequence of exactly n numbers. */
int esf_ynode_doubles(const esf_ynode *node, double *out, size_t n, esf_error *err);

/* Keyed forms: when the key is absent, `required` decides between an error at the
 * mapping's place ("missing key 'density'") and leaving *out unchanged (the default
 * the caller set) with status ESF_OK. Return ESF_OK, or ESF_EINPUT. */
int esf_yget_double(const esf_ynode *map, const char *key, int required, double *out,
                    esf_error *err);
int esf_yget_long(const esf_ynode *map, const char *key, int required, long *out,
                  esf_error *err);
int esf_yget_bool(const esf_ynode *map, const char *key, int required, int *out,
                  esf_error *err);
int esf_yget_string(const esf_ynode *map, const char *key, int required, const char **out,
                    esf_error *err);
int esf_yget_doubles(const esf_ynode *map, const char *key, int required, double *out,
                     size_t n, esf_error *err);

/* Picks one of `names` (NULL-terminated) for a string value; error lists the choices. */
int esf_yget_choice(const esf_ynode *map, const char *key, int required,
                    const char *const *names, int *out, esf_error *err);

#endif
