/* particle_csv.c — reads particle definitions from a CSV file (particle_source.h).
 *
 * Format: the first line that is neither blank nor a comment ('#' after optional
 * whitespace) is the header; it names the columns, comma separated, in any order:
 * x, y, z, radius (m, required), vx, vy, vz (m/s), wx, wy, wz (rad/s) and material
 * (optional). Names are case-sensitive; whitespace around names and values is ignored;
 * no quoting. Every later non-blank, non-comment line is one particle with exactly as
 * many fields as the header. Numbers are parsed with strtod (the "C" locale, which
 * esfera never changes) and must be finite; radius must be > 0. A `material` field is
 * a name resolved by the caller's lookup callback; without that column every particle
 * gets default_material. Lines end in \n or \r\n and may be of any length (the line
 * buffer grows); a UTF-8 byte-order mark at the start is skipped.
 *
 * Errors: see esf_particles_read_csv. On entry `out` holds any number of definitions;
 * on success the file's particles are appended in file order; on failure `out` is
 * restored to its entry length. */
#include "scene/particle_source.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
  COL_X,
  COL_Y,
  COL_Z,
  COL_R,
  COL_VX,
  COL_VY,
  COL_VZ,
  COL_WX,
  COL_WY,
  COL_WZ,
  COL_MAT,
  NCOLS
};

static const char *const col_names[NCOLS] = {"x",  "y",  "z",  "radius", "vx",      "vy",
                                             "vz", "wx", "wy", "wz",     "material"};
static const char allowed_list[] = "x, y, z, radius, vx, vy, vz, wx, wy, wz, material";

/* A growable line buffer. */
typedef struct line_buf {
  char *s;
  size_t len, cap;
} line_buf;

/* Reads one line (without its \n or \r\n) into b. Returns 1 for a line, 0 at end of
 * file, or a negative status (ESF_ENOMEM; read errors are left to ferror). */
static int read_line(FILE *f, line_buf *b, esf_error *err) {
  b->len = 0;
  if (!b->s) {
    b->cap = 4096;
    b->s = malloc(b->cap);
    if (!b->s) return esf_fail(err, ESF_ENOMEM, "out of memory for a CSV line");
  }
  for (;;) {
    if (b->cap - b->len < 2) {
      size_t cap = 2 * b->cap;
      char *s = realloc(b->s, cap);
      if (!s) return esf_fail(err, ESF_ENOMEM, "out of memory for a CSV line");
      b->s = s;
      b->cap = cap;
    }
    size_t room = b->cap - b->len;
    if (room > INT_MAX) room = INT_MAX;
    if (!fgets(b->s + b->len, (int)room, f)) {
      if (b->len == 0) return 0;
      break; /* last line without a newline */
    }
    b->len += strlen(b->s + b->len);
    if (b->len > 0 && b->s[b->len - 1] == '\n') {
      b->s[--b->len] = '\0';
      break;
    }
    if (feof(f)) break;
  }
  if (b->len > 0 && b->s[b->len - 1] == '\r') b->s[--b->len] = '\0';
  return 1;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v'; }

/* Trims s in place (writes a terminator) and returns the start of the trimmed text. */
static char *trim(char *s, char *end) {
  while (s < end && is_space(*s)) s++;
  while (end > s && is_space(end[-1])) end--;
  *end = '\0';
  return s;
}

/* Skippable: blank (only whitespace) or a comment. */
static int skip_line(const char *s) {
  while (is_space(*s)) s++;
  return *s == '\0' || *s == '#';
}

/* Splits the line at commas into trimmed fields (in place). Returns the field count;
 * fields beyond max are counted but not stored. */
static size_t split(char *s, char **fields, size_t max) {
  size_t n = 0;
  for (;;) {
    char *comma = strchr(s, ',');
    char *end = comma ? comma : s + strlen(s);
    char *t = trim(s, end);
    if (n < max) fields[n] = t;
    n++;
    if (!comma) return n;
    s = comma + 1;
  }
}

/* Field storage that grows with the header's column count. */
typedef struct field_buf {
  char **f;
  size_t cap;
} field_buf;

static int count_commas(const char *s) {
  int n = 0;
  for (; *s; s++) n += *s == ',';
  return n;
}

static int fields_reserve(field_buf *fb, size_t n, esf_error *err) {
  if (n <= fb->cap) return ESF_OK;
  char **f = realloc(fb->f, n * sizeof *f);
  if (!f) return esf_fail(err, ESF_ENOMEM, "out of memory for CSV fields");
  fb->f = f;
  fb->cap = n;
  return ESF_OK;
}

/* Parses the header: map[c] = field index of column c, or -1. */
static int parse_header(const char *path, long lineno, char *line, field_buf *fb,
                        size_t *nfields, int map[NCOLS], esf_error *err) {
  int rc = fields_reserve(fb, (size_t)count_commas(line) + 1, err);
  if (rc) return rc;
  size_t n = split(line, fb->f, fb->cap);
  for (int c = 0; c < NCOLS; c++) map[c] = -1;
  for (size_t k = 0; k < n; k++) {
    const char *name = fb->f[k];
    if (!*name)
      return esf_fail(err, ESF_EINPUT, "%s:%ld:%zu: empty column name in the header",
                      path, lineno, k + 1);
    int c = 0;
    while (c < NCOLS && strcmp(name, col_names[c]) != 0) c++;
    if (c == NCOLS)
      return esf_fail(err, ESF_EINPUT, "%s:%ld:%zu: unknown column '%s' (allowed: %s)",
                      path, lineno, k + 1, name, allowed_list);
    if (map[c] >= 0)
      return esf_fail(err, ESF_EINPUT,
                      "%s:%ld:%zu: column '%s' appears twice (first as column %d)", path,
                      lineno, k + 1, name, map[c] + 1);
    map[c] = (int)k;
  }
  for (int c = COL_X; c <= COL_R; c++)
    if (map[c] < 0)
      return esf_fail(
          err, ESF_EINPUT,
          "%s:%ld: the header lacks the required column '%s' (required: x, y, "
          "z, radius)",
          path, lineno, col_names[c]);
  *nfields = n;
  return ESF_OK;
}

/* Parses a finite number from a trimmed field. */
static int parse_number(const char *path, long lineno, int col, const char *s, double *v,
                        esf_error *err) {
  char *end = NULL;
  double d = strtod(s, &end); /* overflow gives inf; underflow a tiny value, accepted */
  if (!*s || end == s || *end != '\0')
    return esf_fail(err, ESF_EINPUT, "%s:%ld:%d: expected a number, got '%s'", path,
                    lineno, col, s);
  if (!isfinite(d))
    return esf_fail(err, ESF_EINPUT, "%s:%ld:%d: expected a finite number, got '%s'",
                    path, lineno, col, s);
  *v = d;
  return ESF_OK;
}

/* Parses one data row into def. */
static int parse_row(const char *path, long lineno, char *line, field_buf *fb,
                     size_t nfields, const int map[NCOLS], int32_t default_material,
                     esf_material_lookup_fn lookup, void *lookup_ctx,
                     esf_particle_def *def, esf_error *err) {
  size_t n = split(line, fb->f, fb->cap);
  if (n != nfields)
    return esf_fail(err, ESF_EINPUT, "%s:%ld: expected %zu fields, got %zu", path, lineno,
                    nfields, n);
  memset(def, 0, sizeof *def);
  double *dst[COL_MAT] = {&def->x[0], &def->x[1], &def->x[2], &def->radius, &def->v[0],
                          &def->v[1], &def->v[2], &def->w[0], &def->w[1],   &def->w[2]};
  for (int c = 0; c < COL_MAT; c++) {
    if (map[c] < 0) continue;
    int rc = parse_number(path, lineno, map[c] + 1, fb->f[map[c]], dst[c], err);
    if (rc) return rc;
  }
  if (!(def->radius > 0.0))
    return esf_fail(err, ESF_EINPUT, "%s:%ld:%d: radius must be positive, got %s", path,
                    lineno, map[COL_R] + 1, fb->f[map[COL_R]]);
  def->material = default_material;
  if (map[COL_MAT] >= 0) {
    const char *name = fb->f[map[COL_MAT]];
    if (!*name)
      return esf_fail(err, ESF_EINPUT, "%s:%ld:%d: empty material name", path, lineno,
                      map[COL_MAT] + 1);
    int32_t index = -1;
    int rc = lookup(lookup_ctx, name, &index, err);
    if (rc) {
      if (err) esf_error_prefix(err, "%s:%ld:%d: ", path, lineno, map[COL_MAT] + 1);
      return rc;
    }
    def->material = index;
  }
  return ESF_OK;
}

/* Errors: ESF_EIO "cannot open 'PATH': reason" / "error reading 'PATH': reason";
 * ESF_EINPUT "PATH:LINE:COL: message" (COL = 1-based field number) or "PATH:LINE:
 * message" for whole-line problems, "PATH: no particles" for a file without data rows.
 * A material column with a NULL lookup, or no material column with default_material
 * < 0, is an ESF_EINPUT error at the header. */
int esf_particles_read_csv(const char *path, int32_t default_material,
                           esf_material_lookup_fn lookup, void *lookup_ctx,
                           esf_particle_defs *out, esf_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f) return esf_fail(err, ESF_EIO, "cannot open '%s': %s", path, strerror(errno));
  size_t n0 = out->n;
  line_buf lb = {0};
  field_buf fb = {0};
  int map[NCOLS];
  size_t nfields = 0;
  long lineno = 0;
  int have_header = 0, rc = ESF_OK;
  for (;;) {
    int got = read_line(f, &lb, err);
    if (got < 0) {
      rc = got;
      break;
    }
    if (got == 0) break;
    lineno++;
    char *line = lb.s;
    if (lineno == 1 && strncmp(line, "\xEF\xBB\xBF", 3) == 0) line += 3;
    if (skip_line(line)) continue;
    if (!have_header) {
      rc = parse_header(path, lineno, line, &fb, &nfields, map, err);
      if (rc) break;
      if (map[COL_MAT] >= 0 && !lookup) {
        rc = esf_fail(err, ESF_EINPUT,
                      "%s:%ld:%d: a material column needs a material table to look names "
                      "up in",
                      path, lineno, map[COL_MAT] + 1);
        break;
      }
      if (map[COL_MAT] < 0 && default_material < 0) {
        rc = esf_fail(err, ESF_EINPUT,
                      "%s:%ld: no material column and no material given for the file",
                      path, lineno);
        break;
      }
      have_header = 1;
      continue;
    }
    esf_particle_def def;
    rc = parse_row(path, lineno, line, &fb, nfields, map, default_material, lookup,
                   lookup_ctx, &def, err);
    if (rc) break;
    rc = esf_particle_defs_push(out, &def, err);
    if (rc) break;
  }
  if (rc == ESF_OK && ferror(f))
    rc = esf_fail(err, ESF_EIO, "error reading '%s': %s", path, strerror(errno));
  if (rc == ESF_OK && out->n == n0)
    rc = esf_fail(err, ESF_EINPUT,
                  have_header ? "%s: no particles (the file has a header but no rows)"
                              : "%s: no particles (the file is empty; expected a header "
                                "naming x, y, z, radius)",
                  path);
  fclose(f);
  free(lb.s);
  free(fb.f);
  if (rc) out->n = n0;
  return rc;
}
