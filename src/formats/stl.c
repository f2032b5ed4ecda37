/* stl.c — STL reader (stl.h): binary when the size is 84 + 50 N for the header's N,
 * else ASCII.
 *
 * Binary layout: 80-byte header, uint32 N (little endian), then N records of 50 bytes:
 * normal (3 float32, ignored), three vertices (9 float32), a uint16 attribute count
 * (ignored). ASCII: `solid [name]`, then per triangle `facet normal nx ny nz`,
 * `outer loop`, three `vertex x y z`, `endloop`, `endfacet`, closed by `endsolid
 * [name]`; several solids may follow each other. Keywords are case-insensitive; the
 * stated normals are ignored (the element's normal comes from its vertex order).
 * Triangle check: coordinates finite; the longest edge L > 0; 2 area / L^2 (the height
 * over the longest edge, relative) above ESF_STL_SLIVER. Coordinates stay in the file's
 * units (the scene scales them). Entry: any file; exit: *out holds every triangle, or
 * nothing and an error naming file and line (ASCII) or triangle index (binary). */
#include "formats/stl.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "util/atomic_file.h"
#include "util/vec3.h"

int esf_stl_check_triangle(const double v[3][3], esf_error *err) {
  for (int k = 0; k < 3; k++)
    for (int q = 0; q < 3; q++)
      if (!isfinite(v[k][q]))
        return esf_fail(err, ESF_EINPUT,
                        "vertex %d has a non-finite coordinate (%g, %g, %g)", k + 1,
                        v[k][0], v[k][1], v[k][2]);
  /* the edges scaled by a power of two (exact) so that the largest component is in
     [0.5, 1): squares and products neither overflow nor underflow */
  double l2 = 0, e[3][3], c[3], m = 0;
  for (int k = 0; k < 3; k++) {
    v3_sub(e[k], v[(k + 1) % 3], v[k]);
    for (int q = 0; q < 3; q++) m = fmax(m, fabs(e[k][q]));
  }
  if (!isfinite(m))
    return esf_fail(err, ESF_EINPUT,
                    "vertices too far apart: an edge of (%g, %g, %g), (%g, %g, %g), "
                    "(%g, %g, %g) is longer than the largest number",
                    v[0][0], v[0][1], v[0][2], v[1][0], v[1][1], v[1][2], v[2][0],
                    v[2][1], v[2][2]);
  if (!(m > 0))
    return esf_fail(err, ESF_EINPUT,
                    "degenerate triangle (its three vertices coincide at "
                    "(%g, %g, %g))",
                    v[0][0], v[0][1], v[0][2]);
  int ex;
  frexp(m, &ex);
  for (int k = 0; k < 3; k++) {
    v3_scale(e[k], ldexp(1.0, -ex), e[k]);
    if (v3_norm2(e[k]) > l2) l2 = v3_norm2(e[k]);
  }
  v3_cross(c, e[0], e[2]); /* (v1 - v0) x (v0 - v2) = (v1 - v0) x -(v2 - v0) */
  double rel = v3_norm(c) / l2;
  if (!(rel > ESF_STL_SLIVER))
    return esf_fail(
        err, ESF_EINPUT,
        "degenerate triangle (zero or near-zero area: height / longest edge = "
        "%.3g, at most %g; vertices (%g, %g, %g), (%g, %g, %g), (%g, %g, %g))",
        rel, ESF_STL_SLIVER, v[0][0], v[0][1], v[0][2], v[1][0], v[1][1], v[1][2],
        v[2][0], v[2][1], v[2][2]);
  return ESF_OK;
}

void esf_stl_release(esf_stl *s) {
  free(s->v);
  free(s->line);
  memset(s, 0, sizeof *s);
}

static int grow(esf_stl *s, size_t *cap, esf_error *err) {
  if (s->n < *cap) return ESF_OK;
  size_t nc = *cap ? 2 * *cap : 64;
  double(*v)[3][3] = realloc(s->v, nc * sizeof *v);
  if (v) s->v = v;
  long *l = v ? realloc(s->line, nc * sizeof *l) : NULL;
  if (!l) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu STL triangles", nc);
  s->line = l;
  *cap = nc;
  return ESF_OK;
}

static int read_binary(const unsigned char *b, const char *path, esf_stl *s,
                       esf_error *err) {
  size_t n =
      (size_t)b[80] | (size_t)b[81] << 8 | (size_t)b[82] << 16 | (size_t)b[83] << 24;
  s->binary = 1;
  s->v = malloc((n ? n : 1) * sizeof *s->v);
  s->line = calloc(n ? n : 1, sizeof *s->line);
  if (!s->v || !s->line)
    return esf_fail(err, ESF_ENOMEM, "out of memory for %zu STL triangles", n);
  for (size_t t = 0; t < n; t++) {
    const unsigned char *r = b + 84 + 50 * t + 12;
    for (int k = 0; k < 9; k++) {
      uint32_t u = (uint32_t)r[4 * k] | (uint32_t)r[4 * k + 1] << 8 |
                   (uint32_t)r[4 * k + 2] << 16 | (uint32_t)r[4 * k + 3] << 24;
      float f;
      memcpy(&f, &u, sizeof f);
      s->v[t][k / 3][k % 3] = f;
    }
    s->n = t + 1;
    int rc = esf_stl_check_triangle((const double(*)[3])s->v[t], err);
    if (rc)
      return esf_error_prefix(
          err, "%s: binary STL triangle %zu (of %zu, byte offset %zu): ", path, t + 1, n,
          84 + 50 * t);
  }
  return ESF_OK;
}

/* ASCII tokenizer over a NUL-terminated buffer */
typedef struct lexer {
  const char *p;
  long line;
  char tok[64];
} lexer;

static int next(lexer *lx) {
  while (*lx->p && isspace((unsigned char)*lx->p)) {
    if (*lx->p == '\n') lx->line++;
    lx->p++;
  }
  size_t k = 0;
  while (*lx->p && !isspace((unsigned char)*lx->p)) {
    if (k + 1 < sizeof lx->tok) lx->tok[k++] = *lx->p;
    lx->p++;
  }
  lx->tok[k] = 0;
  return k > 0;
}

static void skip_line(lexer *lx) {
  while (*lx->p && *lx->p != '\n') lx->p++;
}

static int expect(lexer *lx, const char *word, const char *path, esf_error *err) {
  if (next(lx) && strcasecmp(lx->tok, word) == 0) return ESF_OK;
  return esf_fail(err, ESF_EINPUT, "%s:%ld: ASCII STL: expected '%s', got '%s'", path,
                  lx->line, word, lx->tok[0] ? lx->tok : "end of file");
}

static int number(lexer *lx, double *x, const char *path, esf_error *err) {
  char *end = NULL;
  if (next(lx)) {
    errno = 0;
    *x = strtod(lx->tok, &end);
    if (end != lx->tok && *end == 0) return ESF_OK;
  }
  return esf_fail(err, ESF_EINPUT, "%s:%ld: ASCII STL: expected a number, got '%s'", path,
                  lx->line, lx->tok[0] ? lx->tok : "end of file");
}

static int read_ascii(const char *text, const char *path, const char *hint, esf_stl *s,
                      esf_error *err) {
  lexer lx = {text, 1, ""};
  size_t cap = 0;
  int rc = expect(&lx, "solid", path, err), solids = 0;
  while (!rc) {
    solids++;
    skip_line(&lx); /* the solid's name */
    for (;;) {
      if (!next(&lx)) {
        return esf_fail(err, ESF_EINPUT,
                        "%s:%ld: ASCII STL: end of file inside solid %d "
                        "(no 'endsolid')%s",
                        path, lx.line, solids, hint);
      }
      if (strcasecmp(lx.tok, "endsolid") == 0) break;
      if (strcasecmp(lx.tok, "facet") != 0)
        return esf_fail(err, ESF_EINPUT,
                        "%s:%ld: ASCII STL: expected 'facet' or "
                        "'endsolid', got '%s'%s",
                        path, lx.line, lx.tok, hint);
      long line = lx.line;
      double nrm[3], v[3][3];
      rc = expect(&lx, "normal", path, err);
      for (int q = 0; q < 3 && !rc; q++) rc = number(&lx, &nrm[q], path, err);
      if (!rc) rc = expect(&lx, "outer", path, err);
      if (!rc) rc = expect(&lx, "loop", path, err);
      for (int k = 0; k < 3 && !rc; k++) {
        rc = expect(&lx, "vertex", path, err);
        for (int q = 0; q < 3 && !rc; q++) rc = number(&lx, &v[k][q], path, err);
      }
      if (!rc && (!next(&lx) || strcasecmp(lx.tok, "endloop") != 0))
        return esf_fail(err, ESF_EINPUT,
                        "%s:%ld: ASCII STL: expected 'endloop' after "
                        "three vertices, got '%s' (a facet has exactly 3 vertices)",
                        path, lx.line, lx.tok[0] ? lx.tok : "end of file");
      if (!rc) rc = expect(&lx, "endfacet", path, err);
      if (rc) return rc;
      rc = grow(s, &cap, err);
      if (rc) return rc;
      memcpy(s->v[s->n], v, sizeof v);
      s->line[s->n] = line;
      s->n++;
      rc = esf_stl_check_triangle((const double(*)[3])v, err);
      if (rc)
        return esf_error_prefix(err, "%s:%ld: ASCII STL facet %zu: ", path, line, s->n);
    }
    skip_line(&lx); /* endsolid's name */
    if (!next(&lx)) return ESF_OK;
    if (strcasecmp(lx.tok, "solid") != 0)
      return esf_fail(err, ESF_EINPUT,
                      "%s:%ld: ASCII STL: expected 'solid' or end of "
                      "file after 'endsolid', got '%s'",
                      path, lx.line, lx.tok);
  }
  return rc;
}

int esf_stl_read(const char *path, esf_stl *out, esf_error *err) {
  memset(out, 0, sizeof *out);
  char *buf = NULL;
  size_t nb = 0;
  esf_error rerr = {0};
  int rrc = esf_read_file(path, &buf, &nb, &rerr);
  if (rrc) return esf_fail(err, rrc, "%s: cannot open STL file (%s)", path, rerr.msg);
  unsigned char *b = (unsigned char *)buf; /* NUL-terminated past nb */
  size_t hn = 0;
  if (nb >= 84)
    hn = (size_t)b[80] | (size_t)b[81] << 8 | (size_t)b[82] << 16 | (size_t)b[83] << 24;
  int rc;
  const char *s = (const char *)b;
  while (*s && isspace((unsigned char)*s)) s++;
  int solid = strncasecmp(s, "solid", 5) == 0;
  if (nb >= 84 && nb == 84 + 50 * hn) {
    rc = read_binary(b, path, out, err);
  } else if (solid && memchr(b, 0, nb) == NULL) {
    char hint[160] = "";
    if (nb >= 84)
      snprintf(hint, sizeof hint,
               " (read as ASCII; as binary its %zu bytes would not match "
               "the 84 + 50 x %zu = %zu its header announces)",
               nb, hn, 84 + 50 * hn);
    rc = read_ascii(s, path, hint, out, err);
  } else if (nb >= 84) {
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: binary STL of %zu bytes, but its header announces "
                  "%zu triangles = %zu bytes: truncated or a wrong triangle count",
                  path, nb, hn, 84 + 50 * hn);
  } else {
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: not an STL file (%zu bytes: neither ASCII "
                  "'solid ...' nor a binary STL of at least 84 bytes)",
                  path, nb);
  }
  free(b);
  if (rc) esf_stl_release(out);
  return rc;
}
