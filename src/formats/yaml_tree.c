/* yaml_tree.c — libyaml's event stream turned into a tree of esf_ynode that remember
 * their place (file, line, column); dotted-path overrides; typed accessors that fail with
 * that place.
 *
 * Conventions: every allocation of a document lives in its arena (a chain of malloc'd
 * blocks released together by esf_ydoc_free), so a node replaced by an override stays
 * valid until the document is freed. Node arrays grow by doubling through the arena; the
 * capacity is implied by n (4, 8, 16, ...). Lines and columns are 1-based; line 0 marks a
 * node made by an override, whose origin is "--set KEY=VALUE". Plain `~`, `null` and
 * empty scalars are ESF_YN_NULL, and a null node reads as an empty mapping in lookups.
 * Aliases and merge keys are refused, anchors are ignored. A failed load frees
 * everything; a failed override leaves the tree as it was. */
#include "formats/yaml_tree.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

enum { MAX_DEPTH = 200, GOT_MAX = 80, LIST_MAX = 1024 };

typedef union block {
  union block *next;
  max_align_t align;
} block;

struct esf_ydoc {
  block *blocks; /* the arena: everything below points into it */
  esf_ynode *root;
  const char *dir;
};

/* ---- arena and node building ----------------------------------------------------- */

static void *arena_alloc(esf_ydoc *doc, size_t size) {
  if (size > SIZE_MAX - sizeof(block)) return NULL;
  block *b = calloc(1, sizeof(block) + size);
  if (!b) return NULL;
  b->next = doc->blocks;
  doc->blocks = b;
  return b + 1;
}

static char *arena_strndup(esf_ydoc *doc, const char *s, size_t len) {
  char *p = arena_alloc(doc, len + 1);
  if (p) memcpy(p, s, len);
  return p;
}

static char *join_path(esf_ydoc *doc, const char *parent, const char *comp) {
  size_t a = strlen(parent), b = strlen(comp);
  char *p = arena_alloc(doc, a + b + 2);
  if (!p) return NULL;
  if (a) {
    memcpy(p, parent, a);
    p[a++] = '.';
  }
  memcpy(p + a, comp, b + 1);
  return p;
}

static esf_ynode *new_node(esf_ydoc *doc, esf_ynode_kind kind, const char *origin,
                           int line, int col, char *path) {
  esf_ynode *n = arena_alloc(doc, sizeof *n);
  if (n)
    *n = (esf_ynode){
        .kind = kind, .origin = origin, .line = line, .col = col, .path = path};
  return n;
}

/* arr with room for element n: a bigger arena copy when n has reached the capacity. */
static void *room(esf_ydoc *doc, void *arr, size_t n, size_t elem) {
  if (n != 0 && (n < 4 || (n & (n - 1)) != 0)) return arr;
  size_t cap = n ? 2 * n : 4;
  if (cap > SIZE_MAX / elem) return NULL;
  void *p = arena_alloc(doc, cap * elem);
  if (p && n) memcpy(p, arr, n * elem);
  return p;
}

static int seq_append(esf_ydoc *doc, esf_ynode *seq, esf_ynode *item) {
  esf_ynode **items = room(doc, seq->items, seq->n, sizeof *items);
  if (!items) return ESF_ENOMEM;
  seq->items = items;
  seq->items[seq->n++] = item;
  return ESF_OK;
}

static int map_append(esf_ydoc *doc, esf_ynode *map, char *key, int line, int col,
                      esf_ynode *value) {
  esf_ynode **items = room(doc, map->items, map->n, sizeof *items);
  char **keys = room(doc, map->keys, map->n, sizeof *keys);
  int *kl = room(doc, map->key_line, map->n, sizeof *kl);
  int *kc = room(doc, map->key_col, map->n, sizeof *kc);
  if (!items || !keys || !kl || !kc) return ESF_ENOMEM;
  map->items = items, map->keys = keys, map->key_line = kl, map->key_col = kc;
  items[map->n] = value, keys[map->n] = key, kl[map->n] = line, kc[map->n] = col;
  map->n++;
  return ESF_OK;
}

/* ---- messages -------------------------------------------------------------------- */

static int nomem(esf_error *err) {
  return esf_fail(err, ESF_ENOMEM, "out of memory while reading YAML");
}

static const char *where(const char *origin, int line, int col, char *buf, size_t len) {
  if (line > 0)
    snprintf(buf, len, "%s:%d:%d", origin, line, col);
  else
    snprintf(buf, len, "%s", origin);
  return buf;
}

static int vfail_at(esf_error *err, const char *origin, int line, int col,
                    const char *path, const char *fmt, va_list ap) {
  char place[512], msg[ESF_ERROR_MSG_MAX];
  vsnprintf(msg, sizeof msg, fmt, ap);
  where(origin, line, col, place, sizeof place);
  if (path && path[0]) return esf_fail(err, ESF_EINPUT, "%s: %s: %s", place, path, msg);
  return esf_fail(err, ESF_EINPUT, "%s: %s", place, msg);
}

__attribute__((format(printf, 6, 7))) static int fail_at(esf_error *err,
                                                         const char *origin, int line,
                                                         int col, const char *path,
                                                         const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int st = vfail_at(err, origin, line, col, path, fmt, ap);
  va_end(ap);
  return st;
}

/* What a node is, for "expected X, got ...": 'abc', the string '3', null, a mapping. */
static const char *got(const esf_ynode *node, char *buf, size_t len) {
  if (node->kind != ESF_YN_SCALAR)
    return node->kind == ESF_YN_NULL  ? "null"
           : node->kind == ESF_YN_SEQ ? "a sequence"
                                      : "a mapping";
  int cut = strlen(node->text) > 40;
  snprintf(buf, len, "%s'%.40s%s'", node->quoted ? "the string " : "", node->text,
           cut ? "..." : "");
  return buf;
}

static void append(char *buf, size_t size, size_t *used, const char *s) {
  if (*used >= size) return;
  int w = snprintf(buf + *used, size - *used, "%s", s);
  if (w > 0) *used += (size_t)w;
}

/* "a, b, c" */
static const char *list_names(const char *const *names, char *buf, size_t size) {
  size_t used = 0;
  buf[0] = '\0';
  for (size_t i = 0; names[i]; i++) {
    if (i) append(buf, size, &used, ", ");
    append(buf, size, &used, names[i]);
  }
  return buf;
}

static int ci_equal(const char *a, const char *b) {
  for (; *a && *b; a++, b++)
    if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
  return *a == *b;
}

static int ci_prefix(const char *pre, const char *s) {
  for (; *pre; pre++, s++)
    if (tolower((unsigned char)*pre) != tolower((unsigned char)*s)) return 0;
  return 1;
}

/* Levenshtein distance ignoring case; 99 for names too long to bother with. */
static int distance(const char *a, const char *b) {
  size_t la = strlen(a), lb = strlen(b);
  if (la > 63 || lb > 63) return 99;
  int row[64];
  for (size_t j = 0; j <= lb; j++) row[j] = (int)j;
  for (size_t i = 1; i <= la; i++) {
    int diag = row[0];
    row[0] = (int)i;
    for (size_t j = 1; j <= lb; j++) {
      int up = row[j];
      int cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
      int best = diag + cost;
      if (up + 1 < best) best = up + 1;
      if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
      row[j] = best;
      diag = up;
    }
  }
  return row[lb];
}

/* The name a misspelt word most likely meant: same letters in another case, then the
 * nearest within 2 edits, then one being a prefix of the other; NULL when none. */
static const char *closest(const char *word, const char *const *names) {
  for (size_t i = 0; names[i]; i++)
    if (ci_equal(word, names[i])) return names[i];
  const char *best = NULL;
  int bestd = 3;
  for (size_t i = 0; names[i]; i++) {
    int d = distance(word, names[i]);
    if (d < bestd && d < (int)strlen(names[i])) best = names[i], bestd = d;
  }
  if (best) return best;
  for (size_t i = 0; names[i]; i++) {
    size_t lw = strlen(word), ln = strlen(names[i]);
    if ((lw >= 3 && ci_prefix(word, names[i])) || (ln >= 3 && ci_prefix(names[i], word)))
      return names[i];
  }
  return NULL;
}

/* ---- parsing --------------------------------------------------------------------- */

typedef struct {
  esf_ydoc *doc;
  yaml_parser_t parser;
  const char *origin; /* file name, or "--set KEY=VALUE" */
  int is_override;    /* nodes get line 0; syntax errors name a column of VALUE */
  const unsigned char *text;
  size_t len;
  esf_error *err;
} reader;

static int mark_line(const reader *r, yaml_mark_t m) {
  return r->is_override ? 0 : m.line < INT_MAX ? (int)m.line + 1 : INT_MAX;
}
static int mark_col(const reader *r, yaml_mark_t m) {
  return r->is_override ? 0 : m.column < INT_MAX ? (int)m.column + 1 : INT_MAX;
}

static int syntax_error(reader *r) {
  yaml_parser_t *p = &r->parser;
  if (p->error == YAML_MEMORY_ERROR) return nomem(r->err);
  size_t line = p->problem_mark.line, col = p->problem_mark.column;
  if (p->error == YAML_READER_ERROR) { /* the reader gives a byte offset only */
    line = col = 0;
    for (size_t i = 0; i < p->problem_offset && i < r->len; i++) {
      if (r->text[i] == '\n')
        line++, col = 0;
      else
        col++;
    }
  }
  const char *problem = p->problem ? p->problem : "unknown error";
  if (r->is_override)
    return esf_fail(r->err, ESF_EINPUT,
                    "%s: YAML syntax error in the value (column %zu): %s", r->origin,
                    col + 1, problem);
  return esf_fail(r->err, ESF_EINPUT, "%s:%zu:%zu: YAML syntax error: %s", r->origin,
                  line + 1, col + 1, problem);
}

static int next_event(reader *r, yaml_event_t *ev) {
  return yaml_parser_parse(&r->parser, ev) ? ESF_OK : syntax_error(r);
}

static int is_null_text(const char *s) {
  return !*s || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") ||
         !strcmp(s, "NULL");
}

static int parse_node(reader *r, yaml_event_t *ev, char *path, int depth,
                      esf_ynode **out);

static int parse_seq(reader *r, esf_ynode *seq, int depth) {
  for (size_t i = 0;; i++) {
    yaml_event_t ev;
    int st = next_event(r, &ev);
    if (st) return st;
    if (ev.type == YAML_SEQUENCE_END_EVENT) {
      yaml_event_delete(&ev);
      return ESF_OK;
    }
    char idx[32];
    snprintf(idx, sizeof idx, "%zu", i);
    char *path = join_path(r->doc, seq->path, idx);
    esf_ynode *item;
    if (!path) {
      yaml_event_delete(&ev);
      return nomem(r->err);
    }
    if ((st = parse_node(r, &ev, path, depth + 1, &item))) return st;
    if (seq_append(r->doc, seq, item)) return nomem(r->err);
  }
}

static int parse_map(reader *r, esf_ynode *map, int depth) {
  for (;;) {
    yaml_event_t ev;
    int st = next_event(r, &ev);
    if (st) return st;
    if (ev.type == YAML_MAPPING_END_EVENT) {
      yaml_event_delete(&ev);
      return ESF_OK;
    }
    int kl = mark_line(r, ev.start_mark), kc = mark_col(r, ev.start_mark);
    if (ev.type != YAML_SCALAR_EVENT) {
      yaml_event_delete(&ev);
      return fail_at(r->err, r->origin, kl, kc, map->path,
                     "mapping keys must be scalars");
    }
    int plain = ev.data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
    char *key =
        arena_strndup(r->doc, (const char *)ev.data.scalar.value, ev.data.scalar.length);
    yaml_event_delete(&ev);
    if (!key) return nomem(r->err);
    if (plain && !strcmp(key, "<<"))
      return fail_at(r->err, r->origin, kl, kc, map->path,
                     "merge keys ('<<') are not supported");
    for (size_t k = 0; k < map->n; k++) {
      if (strcmp(map->keys[k], key)) continue;
      if (map->key_line[k] > 0)
        return fail_at(r->err, r->origin, kl, kc, map->path,
                       "duplicate key '%s' (first at line %d)", key, map->key_line[k]);
      return fail_at(r->err, r->origin, kl, kc, map->path, "duplicate key '%s'", key);
    }
    char *path = join_path(r->doc, map->path, key);
    if (!path) return nomem(r->err);
    esf_ynode *value;
    if ((st = next_event(r, &ev))) return st;
    if ((st = parse_node(r, &ev, path, depth + 1, &value))) return st;
    if (map_append(r->doc, map, key, kl, kc, value)) return nomem(r->err);
  }
}

/* Builds the node that starts with *ev (deleting it) and everything nested in it. */
static int parse_node(reader *r, yaml_event_t *ev, char *path, int depth,
                      esf_ynode **out) {
  int line = mark_line(r, ev->start_mark), col = mark_col(r, ev->start_mark);
  yaml_event_type_t type = ev->type;
  esf_ynode *node = NULL;
  int st = ESF_OK;
  *out = NULL;
  if (depth > MAX_DEPTH) {
    st = fail_at(r->err, r->origin, line, col, path, "nested more than %d levels deep",
                 MAX_DEPTH);
  } else if (type == YAML_ALIAS_EVENT) {
    st = fail_at(r->err, r->origin, line, col, path,
                 "aliases (*%s) are not supported; write the value out",
                 (const char *)ev->data.alias.anchor);
  } else if (type == YAML_SCALAR_EVENT) {
    const char *tag = (const char *)ev->data.scalar.tag;
    int quoted = ev->data.scalar.style != YAML_PLAIN_SCALAR_STYLE ||
                 (tag && !strcmp(tag, YAML_STR_TAG));
    const char *text = (const char *)ev->data.scalar.value;
    if (!quoted && !tag && is_null_text(text)) {
      node = new_node(r->doc, ESF_YN_NULL, r->origin, line, col, path);
    } else {
      node = new_node(r->doc, ESF_YN_SCALAR, r->origin, line, col, path);
      if (node) node->quoted = quoted;
      if (node) node->text = arena_strndup(r->doc, text, ev->data.scalar.length);
      if (node && !node->text) node = NULL;
    }
    if (!node) st = nomem(r->err);
  } else if (type == YAML_SEQUENCE_START_EVENT || type == YAML_MAPPING_START_EVENT) {
    int seq = type == YAML_SEQUENCE_START_EVENT;
    node = new_node(r->doc, seq ? ESF_YN_SEQ : ESF_YN_MAP, r->origin, line, col, path);
    st = node ? ESF_OK : nomem(r->err);
  } else {
    st = esf_fail(r->err, ESF_EINTERNAL, "%s: unexpected YAML event %d", r->origin,
                  (int)type);
  }
  yaml_event_delete(ev);
  if (!st && type == YAML_SEQUENCE_START_EVENT) st = parse_seq(r, node, depth);
  if (!st && type == YAML_MAPPING_START_EVENT) st = parse_map(r, node, depth);
  if (!st) *out = node;
  return st;
}

/* Parses one YAML document from text; *out is NULL for an empty stream. */
static int read_yaml(esf_ydoc *doc, const char *origin, int is_override, const char *text,
                     size_t len, char *root_path, esf_ynode **out, esf_error *err) {
  reader r = {.doc = doc,
              .origin = origin,
              .is_override = is_override,
              .text = (const unsigned char *)text,
              .len = len,
              .err = err};
  yaml_event_t ev;
  int st;
  *out = NULL;
  if (!yaml_parser_initialize(&r.parser)) return nomem(err);
  yaml_parser_set_input_string(&r.parser, r.text, len);
  if ((st = next_event(&r, &ev))) goto done; /* stream start */
  yaml_event_delete(&ev);
  if ((st = next_event(&r, &ev))) goto done; /* document start, or the end */
  if (ev.type == YAML_STREAM_END_EVENT) {
    yaml_event_delete(&ev);
    goto done;
  }
  yaml_event_delete(&ev);
  if ((st = next_event(&r, &ev))) goto done;
  if ((st = parse_node(&r, &ev, root_path, 0, out))) goto done;
  if ((st = next_event(&r, &ev))) goto done; /* document end */
  yaml_event_delete(&ev);
  if ((st = next_event(&r, &ev))) goto done;
  if (ev.type != YAML_STREAM_END_EVENT) {
    if (is_override)
      st = esf_fail(err, ESF_EINPUT, "%s: the value holds more than one YAML document",
                    origin);
    else
      st = fail_at(err, origin, mark_line(&r, ev.start_mark), mark_col(&r, ev.start_mark),
                   "", "only one YAML document is allowed per file");
  }
  yaml_event_delete(&ev);
done:
  yaml_parser_delete(&r.parser);
  if (st) *out = NULL;
  return st;
}

static int parse_text(const char *text, size_t len, const char *name, size_t dirlen,
                      esf_ydoc **out, esf_error *err) {
  esf_ydoc *doc = calloc(1, sizeof *doc);
  *out = NULL;
  if (!doc) return nomem(err);
  char *origin = arena_strndup(doc, name, strlen(name));
  char *dir = dirlen ? arena_strndup(doc, name, dirlen) : arena_strndup(doc, ".", 1);
  char *root_path = arena_strndup(doc, "", 0);
  int st = origin && dir && root_path ? ESF_OK : nomem(err);
  if (!st) st = read_yaml(doc, origin, 0, text, len, root_path, &doc->root, err);
  if (!st && !doc->root) doc->root = new_node(doc, ESF_YN_MAP, origin, 1, 1, root_path);
  if (!st && !doc->root) st = nomem(err);
  if (st) {
    esf_ydoc_free(&doc);
    return st;
  }
  if (doc->root->kind == ESF_YN_NULL) doc->root->kind = ESF_YN_MAP; /* "---" alone */
  doc->dir = dir;
  *out = doc;
  return ESF_OK;
}

int esf_ydoc_parse(const char *text, const char *name, esf_ydoc **out, esf_error *err) {
  return parse_text(text, strlen(text), name ? name : "<string>", 0, out, err);
}

int esf_ydoc_load(const char *path, esf_ydoc **out, esf_error *err) {
  *out = NULL;
  FILE *f = fopen(path, "rb");
  if (!f) return esf_fail(err, ESF_EIO, "%s: cannot open: %s", path, strerror(errno));
  char *buf = NULL;
  size_t len = 0, cap = 0, got_n;
  do {
    if (len == cap) {
      char *nb = cap > SIZE_MAX / 2 ? NULL : realloc(buf, cap ? 2 * cap : 4096);
      if (!nb) {
        free(buf);
        fclose(f);
        return nomem(err);
      }
      buf = nb;
      cap = cap ? 2 * cap : 4096;
    }
    got_n = fread(buf + len, 1, cap - len, f);
    len += got_n;
  } while (got_n > 0);
  int bad = ferror(f), e = errno;
  fclose(f);
  if (bad) {
    free(buf);
    return esf_fail(err, ESF_EIO, "%s: cannot read: %s", path, strerror(e));
  }
  int st = esf_ydoc_parse_as(buf, len, path, out, err);
  free(buf);
  return st;
}

int esf_ydoc_parse_as(const char *text, size_t len, const char *path, esf_ydoc **out,
                      esf_error *err) {
  *out = NULL;
  const char *slash = strrchr(path, '/');
  size_t dirlen = !slash ? 0 : slash == path ? 1 : (size_t)(slash - path);
  return parse_text(text, len, path, dirlen, out, err);
}

esf_ynode *esf_ydoc_root(esf_ydoc *doc) { return doc ? doc->root : NULL; }

const char *esf_ydoc_dir(const esf_ydoc *doc) { return doc ? doc->dir : "."; }

void esf_ydoc_free(esf_ydoc **doc) {
  if (!doc || !*doc) return;
  for (block *b = (*doc)->blocks, *next; b; b = next) {
    next = b->next;
    free(b);
  }
  free(*doc);
  *doc = NULL;
}

/* ---- overrides ------------------------------------------------------------------- */

static int is_index(const char *s, size_t *out) {
  size_t v = 0;
  if (!*s) return 0;
  for (; *s; s++) {
    if (!isdigit((unsigned char)*s)) return 0;
    size_t d = (size_t)(*s - '0');
    v = v > (SIZE_MAX - d) / 10 ? SIZE_MAX : v * 10 + d;
  }
  *out = v;
  return 1;
}

static const char *path_name(const char *path) {
  return path[0] ? path : "the top level";
}

/* Follows comps from the root. With value NULL it only checks the way and finds the
 * target's path (so that a failing override changes nothing); with a value it also
 * creates the missing mappings and puts value in place. */
static int walk(esf_ydoc *doc, char **comps, size_t ncomp, const char *key,
                const char *origin, esf_ynode *value, char **target, esf_error *err) {
  esf_ynode *cur = doc->root;
  char *path = cur->path;
  int beyond = 0; /* dry run past the existing tree: the rest would be created */
  for (size_t i = 0; i < ncomp; i++) {
    int last = i + 1 == ncomp;
    const char *c = comps[i];
    if (!beyond && cur->kind == ESF_YN_SCALAR)
      return esf_fail(err, ESF_EINPUT, "%s: cannot set %s: %s is a scalar", origin, key,
                      path_name(cur->path));
    if (!beyond && cur->kind == ESF_YN_NULL) {
      if (value)
        *cur = (esf_ynode){.kind = ESF_YN_MAP, .origin = origin, .path = cur->path};
      else
        beyond = 1;
    }
    if (!beyond && cur->kind == ESF_YN_SEQ) {
      size_t idx;
      if (!is_index(c, &idx))
        return esf_fail(err, ESF_EINPUT,
                        "%s: cannot set %s: %s is a sequence (index it "
                        "with an item number)",
                        origin, key, path_name(cur->path));
      if (idx >= cur->n)
        return esf_fail(err, ESF_EINPUT,
                        "%s: cannot set %s: %s has %zu item%s (index %s is out of range)",
                        origin, key, path_name(cur->path), cur->n, cur->n == 1 ? "" : "s",
                        c);
      path = cur->items[idx]->path;
      if (last && value)
        cur->items[idx] = value;
      else
        cur = cur->items[idx];
      continue;
    }
    esf_ynode *found = beyond ? NULL : esf_ymap_get(cur, c);
    if (found) {
      path = found->path;
      size_t k = 0;
      while (cur->items[k] != found) k++;
      if (last && value)
        cur->items[k] = value;
      else
        cur = found;
      continue;
    }
    if (!(path = join_path(doc, path, c))) return nomem(err);
    if (!value) {
      beyond = 1;
      continue;
    }
    esf_ynode *child = last ? value : new_node(doc, ESF_YN_MAP, origin, 0, 0, path);
    if (!child || map_append(doc, cur, comps[i], 0, 0, child)) return nomem(err);
    cur = child;
  }
  *target = path;
  return ESF_OK;
}

int esf_ydoc_override(esf_ydoc *doc, const char *assignment, esf_error *err) {
  size_t alen = strlen(assignment);
  char *origin = arena_alloc(doc, alen + 7);
  if (!origin) return nomem(err);
  memcpy(origin, "--set ", 6);
  memcpy(origin + 6, assignment, alen);
  const char *value_text = strchr(origin + 6, '=');
  if (!value_text) return esf_fail(err, ESF_EINPUT, "%s: expected KEY=VALUE", origin);
  /* the key, trimmed, split at '.' into components (arena strings: they become keys) */
  const char *kb = origin + 6, *ke = value_text++;
  while (kb < ke && isspace((unsigned char)*kb)) kb++;
  while (ke > kb && isspace((unsigned char)ke[-1])) ke--;
  if (kb == ke) return esf_fail(err, ESF_EINPUT, "%s: empty key before '='", origin);
  char *key = arena_strndup(doc, kb, (size_t)(ke - kb));
  char *split = arena_strndup(doc, kb, (size_t)(ke - kb));
  size_t ncomp = 1;
  for (const char *p = kb; p < ke; p++) ncomp += *p == '.';
  char **comps = arena_alloc(doc, ncomp * sizeof *comps);
  if (!key || !split || !comps) return nomem(err);
  for (size_t i = 0; i < ncomp; i++) {
    comps[i] = split;
    split += strcspn(split, ".");
    if (*split) *split++ = '\0';
    if (!comps[i][0])
      return esf_fail(err, ESF_EINPUT, "%s: empty component in key '%s'", origin, key);
  }
  char *target;
  int st = walk(doc, comps, ncomp, key, origin, NULL, &target, err);
  if (st) return st;
  esf_ynode *value;
  st = read_yaml(doc, origin, 1, value_text, strlen(value_text), target, &value, err);
  if (st) return st;
  if (!value && !(value = new_node(doc, ESF_YN_NULL, origin, 0, 0, target)))
    return nomem(err);
  return walk(doc, comps, ncomp, key, origin, value, &target, err);
}

/* ---- reading the tree ------------------------------------------------------------ */

const char *esf_ynode_where(const esf_ynode *node, char *buf, size_t len) {
  return where(node->origin, node->line, node->col, buf, len);
}

int esf_ynode_fail(const esf_ynode *node, esf_error *err, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int st = node ? vfail_at(err, node->origin, node->line, node->col, node->path, fmt, ap)
                : esf_failv(err, ESF_EINPUT, fmt, ap);
  va_end(ap);
  return st;
}

esf_ynode *esf_ymap_get(const esf_ynode *map, const char *key) {
  if (!map || map->kind != ESF_YN_MAP || !key) return NULL;
  for (size_t k = 0; k < map->n; k++)
    if (!strcmp(map->keys[k], key)) return map->items[k];
  return NULL;
}

int esf_ymap_check_keys(const esf_ynode *map, const char *const *allowed,
                        esf_error *err) {
  if (!map || map->kind != ESF_YN_MAP) return ESF_OK;
  for (size_t k = 0; k < map->n; k++) {
    const char *key = map->keys[k];
    size_t i = 0;
    while (allowed[i] && strcmp(allowed[i], key)) i++;
    if (allowed[i]) continue;
    /* a key added by an override has no place of its own: its value's origin tells */
    int line = map->key_line[k], col = map->key_col[k];
    const char *origin = line > 0 ? map->origin : map->items[k]->origin;
    char in[600], hint[LIST_MAX + 32], list[LIST_MAX];
    const char *near = closest(key, allowed);
    snprintf(in, sizeof in, map->path[0] ? "in %.580s" : "at the top level", map->path);
    if (near)
      snprintf(hint, sizeof hint, "did you mean '%s'?", near);
    else if (!allowed[0])
      snprintf(hint, sizeof hint, "no keys are allowed here");
    else
      snprintf(hint, sizeof hint, "expected one of: %s",
               list_names(allowed, list, sizeof list));
    return fail_at(err, origin, line, col, "", "unknown key '%s' %s (%s)", key, in, hint);
  }
  return ESF_OK;
}

int esf_ynode_require_map(const esf_ynode *node, esf_error *err) {
  char g[GOT_MAX];
  if (node->kind == ESF_YN_MAP) return ESF_OK;
  return esf_ynode_fail(node, err, "expected a mapping, got %s", got(node, g, sizeof g));
}

int esf_ynode_require_seq(const esf_ynode *node, esf_error *err) {
  char g[GOT_MAX];
  if (node->kind == ESF_YN_SEQ) return ESF_OK;
  return esf_ynode_fail(node, err, "expected a sequence, got %s", got(node, g, sizeof g));
}

/* 0: a finite number; 1: not a number; 2: a number that is not finite. */
static int parse_number(const char *s, double *out) {
  const char *body = s + (*s == '+' || *s == '-');
  if (ci_equal(body, ".inf") || ci_equal(body, ".nan") || ci_equal(body, "inf") ||
      ci_equal(body, "nan") || ci_equal(body, "infinity"))
    return 2;
  int digits = 0;
  for (const char *p = s; *p; p++) {
    if (isdigit((unsigned char)*p))
      digits = 1;
    else if (!strchr("+-.eE", *p))
      return 1; /* no hex, no "inf" spelt by strtod */
  }
  if (!digits) return 1;
  char *end;
  double d = strtod(s, &end);
  if (end == s || *end) return 1;
  if (!isfinite(d)) return 2;
  *out = d;
  return 0;
}

static int plain_scalar(const esf_ynode *node) {
  return node->kind == ESF_YN_SCALAR && !node->quoted;
}

int esf_ynode_double(const esf_ynode *node, double *out, esf_error *err) {
  char g[GOT_MAX];
  double d;
  int r = plain_scalar(node) ? parse_number(node->text, &d) : 1;
  if (r == 2)
    return esf_ynode_fail(node, err, "expected a finite number, got %s",
                          got(node, g, sizeof g));
  if (r)
    return esf_ynode_fail(node, err, "expected a number, got %s", got(node, g, sizeof g));
  *out = d;
  return ESF_OK;
}

int esf_ynode_long(const esf_ynode *node, long *out, esf_error *err) {
  char g[GOT_MAX];
  double d;
  if (!plain_scalar(node) || parse_number(node->text, &d))
    return esf_ynode_fail(node, err, "expected an integer, got %s",
                          got(node, g, sizeof g));
  const char *s = node->text + (node->text[0] == '+' || node->text[0] == '-');
  int digits_only = s[strspn(s, "0123456789")] == '\0'; /* then read exactly */
  if (!digits_only && d != floor(d))
    return esf_ynode_fail(node, err, "expected a whole number, got %s",
                          got(node, g, sizeof g));
  errno = 0;
  long v = digits_only ? strtol(node->text, NULL, 10) : 0;
  if (digits_only ? errno == ERANGE : !(d >= (double)LONG_MIN && d < -(double)LONG_MIN))
    return esf_ynode_fail(node, err, "expected an integer from %ld to %ld, got %s",
                          LONG_MIN, LONG_MAX, got(node, g, sizeof g));
  *out = digits_only ? v : (long)d;
  return ESF_OK;
}

int esf_ynode_bool(const esf_ynode *node, int *out, esf_error *err) {
  static const char *const yes[] = {"true", "yes", "on"};
  static const char *const no[] = {"false", "no", "off"};
  char g[GOT_MAX];
  for (int i = 0; plain_scalar(node) && i < 3; i++) {
    if (ci_equal(node->text, yes[i])) return *out = 1, ESF_OK;
    if (ci_equal(node->text, no[i])) return *out = 0, ESF_OK;
  }
  return esf_ynode_fail(node, err, "expected true or false, got %s",
                        got(node, g, sizeof g));
}

int esf_ynode_string(const esf_ynode *node, const char **out, esf_error *err) {
  char g[GOT_MAX];
  if (node->kind != ESF_YN_SCALAR)
    return esf_ynode_fail(node, err, "expected a string, got %s", got(node, g, sizeof g));
  *out = node->text;
  return ESF_OK;
}

int esf_ynode_doubles(const esf_ynode *node, double *out, size_t n, esf_error *err) {
  char g[GOT_MAX];
  const char *s = n == 1 ? "" : "s";
  if (node->kind != ESF_YN_SEQ)
    return esf_ynode_fail(node, err, "expected a sequence of %zu number%s, got %s", n, s,
                          got(node, g, sizeof g));
  if (node->n != n)
    return esf_ynode_fail(node, err,
                          "expected a sequence of %zu number%s, got %zu item%s", n, s,
                          node->n, node->n == 1 ? "" : "s");
  double d;
  for (size_t i = 0; i < n; i++) { /* check all before writing any */
    int st = esf_ynode_double(node->items[i], &d, err);
    if (st) return st;
  }
  for (size_t i = 0; i < n; i++) esf_ynode_double(node->items[i], &out[i], err);
  return ESF_OK;
}

/* The value under key, NULL when absent and not required. A null map reads as empty. */
static int keyed(const esf_ynode *map, const char *key, int required,
                 const esf_ynode **val, esf_error *err) {
  *val = NULL;
  if (map && map->kind != ESF_YN_MAP && map->kind != ESF_YN_NULL)
    return esf_ynode_require_map(map, err);
  *val = esf_ymap_get(map, key);
  if (*val || !required) return ESF_OK;
  return esf_ynode_fail(map, err, "missing key '%s'", key);
}

int esf_yget_double(const esf_ynode *map, const char *key, int required, double *out,
                    esf_error *err) {
  const esf_ynode *v;
  int st = keyed(map, key, required, &v, err);
  return st || !v ? st : esf_ynode_double(v, out, err);
}

int esf_yget_long(const esf_ynode *map, const char *key, int required, long *out,
                  esf_error *err) {
  const esf_ynode *v;
  int st = keyed(map, key, required, &v, err);
  return st || !v ? st : esf_ynode_long(v, out, err);
}

int esf_yget_bool(const esf_ynode *map, const char *key, int required, int *out,
                  esf_error *err) {
  const esf_ynode *v;
  int st = keyed(map, key, required, &v, err);
  return st || !v ? st : esf_ynode_bool(v, out, err);
}

int esf_yget_string(const esf_ynode *map, const char *key, int required, const char **out,
                    esf_error *err) {
  const esf_ynode *v;
  int st = keyed(map, key, required, &v, err);
  return st || !v ? st : esf_ynode_string(v, out, err);
}

int esf_yget_doubles(const esf_ynode *map, const char *key, int required, double *out,
                     size_t n, esf_error *err) {
  const esf_ynode *v;
  int st = keyed(map, key, required, &v, err);
  return st || !v ? st : esf_ynode_doubles(v, out, n, err);
}

int esf_yget_choice(const esf_ynode *map, const char *key, int required,
                    const char *const *names, int *out, esf_error *err) {
  const esf_ynode *v;
  char list[LIST_MAX], g[GOT_MAX], hint[GOT_MAX + 32] = "";
  int st = keyed(map, key, required, &v, err);
  if (st || !v) return st;
  for (int i = 0; v->kind == ESF_YN_SCALAR && names[i]; i++)
    if (!strcmp(names[i], v->text)) return *out = i, ESF_OK;
  const char *near = v->kind == ESF_YN_SCALAR ? closest(v->text, names) : NULL;
  if (near) snprintf(hint, sizeof hint, " (did you mean '%s'?)", near);
  return esf_ynode_fail(v, err, "expected one of: %s; got %s%s",
                        list_names(names, list, sizeof list), got(v, g, sizeof g), hint);
}
