/* test_sources.c — particle sources: the CSV reader (round trip of every column, \r\n,
 * comments, a byte-order mark, a line over 64 KiB, material names through a lookup, and
 * every error with its exact line and column), the random fill (no overlaps, inside the
 * region, reproducible per seed, size and material fractions within binomial 4-sigma
 * bounds, existing particles avoided, 2D, an overfull region, spec validation) and the
 * lattice (site counts, order and spacing, count limits, 2D). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "scene/particle_source.h"

static char tmpdir[256];
static char written[64][64]; /* names written into tmpdir, removed at the end */
static int nwritten = 0;

/* Writes content to tmpdir/name; returns the path in a static rotating buffer. */
static const char *write_file(const char *name, const char *content) {
  static char paths[4][512];
  static int k = 0;
  char *p = paths[k++ % 4];
  snprintf(p, 512, "%s/%s", tmpdir, name);
  if (nwritten < 64) snprintf(written[nwritten++], 64, "%s", name);
  FILE *f = fopen(p, "wb");
  if (!f) {
    CHECK(0, "cannot write %s", p);
    return p;
  }
  fputs(content, f);
  fclose(f);
  return p;
}

/* ---- CSV ------------------------------------------------------------------------- */

static const char *const materials[] = {"glass", "steel"};

static int lookup(void *ctx, const char *name, int32_t *index, esf_error *err) {
  int *calls = ctx;
  (*calls)++;
  for (int32_t k = 0; k < 2; k++)
    if (strcmp(name, materials[k]) == 0) {
      *index = k;
      return ESF_OK;
    }
  return esf_fail(err, ESF_EINPUT, "unknown material '%s'", name);
}

/* Reads content as name.csv and expects failure with code and the exact message
 * "PATH" + suffix. */
static void expect_error(const char *name, const char *content, int code,
                         const char *suffix) {
  const char *path = write_file(name, content);
  esf_particle_defs defs = {0};
  esf_particle_def keep = {{1, 2, 3}, {0}, {0}, 0.5, 0};
  esf_error err = {0};
  esf_particle_defs_push(&defs, &keep, &err);
  int calls = 0;
  int rc = esf_particles_read_csv(path, 0, lookup, &calls, &defs, &err);
  char want[ESF_ERROR_MSG_MAX];
  snprintf(want, sizeof want, "%s%s", path, suffix);
  CHECK(rc == code, "%s: status %d, expected %d (%s)", name, rc, code, err.msg);
  CHECK(err.code == code, "%s: err.code %d", name, err.code);
  CHECK(strcmp(err.msg, want) == 0, "%s: message\n  got  '%s'\n  want '%s'", name,
        err.msg, want);
  CHECK(defs.n == 1, "%s: the list must be restored to its entry length, has %zu", name,
        defs.n);
  esf_particle_defs_release(&defs);
}

static void test_csv_roundtrip(void) {
  /* every column, shuffled order, spaces, \r\n, comments, blank lines, a BOM */
  enum { N = 5 };
  double v[N][10];
  for (int i = 0; i < N; i++)
    for (int c = 0; c < 10; c++)
      v[i][c] = (c == 3 ? 0.001 : 1.0) * (i + 1) * (c + 0.1) / 7.0;
  v[2][0] = -1.25e-7; /* a negative and an exponent */
  char buf[8192];
  int len =
      snprintf(buf, sizeof buf,
               "\xEF\xBB\xBF# a packing\r\n\r\n  radius , z,y , x,vx,vy,vz,wx,wy,wz "
               "\r\n");
  for (int i = 0; i < N; i++) {
    len += snprintf(buf + len, sizeof buf - len,
                    "%.17g ,%.17g, %.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\r\n",
                    v[i][3], v[i][2], v[i][1], v[i][0], v[i][4], v[i][5], v[i][6],
                    v[i][7], v[i][8], v[i][9]);
    if (i == 1) len += snprintf(buf + len, sizeof buf - len, "   # comment\r\n  \t \r\n");
  }
  const char *path = write_file("roundtrip.csv", buf);
  esf_particle_defs defs = {0};
  esf_error err = {0};
  int rc = esf_particles_read_csv(path, 3, NULL, NULL, &defs, &err);
  CHECK_OK(rc, err);
  CHECK(defs.n == N, "read %zu particles, expected %d", defs.n, N);
  for (size_t i = 0; i < defs.n && i < N; i++) {
    const esf_particle_def *d = &defs.d[i];
    int same = d->x[0] == v[i][0] && d->x[1] == v[i][1] && d->x[2] == v[i][2] &&
               d->radius == v[i][3] && d->v[0] == v[i][4] && d->v[1] == v[i][5] &&
               d->v[2] == v[i][6] && d->w[0] == v[i][7] && d->w[1] == v[i][8] &&
               d->w[2] == v[i][9];
    CHECK(same, "particle %zu differs from what was written", i);
    CHECK(d->material == 3, "particle %zu: material %d, expected the default 3", i,
          (int)d->material);
  }
  /* appending: a second read adds after the first; no trailing newline; optional
   * columns default to zero */
  path = write_file("minimal.csv", "x,y,z,radius\n1,2,3,0.5");
  rc = esf_particles_read_csv(path, 0, NULL, NULL, &defs, &err);
  CHECK_OK(rc, err);
  CHECK(defs.n == N + 1, "append: %zu particles", defs.n);
  if (defs.n == N + 1) {
    const esf_particle_def *d = &defs.d[N];
    CHECK(d->x[0] == 1 && d->x[1] == 2 && d->x[2] == 3 && d->radius == 0.5,
          "minimal row misread");
    CHECK(d->v[0] == 0 && d->v[1] == 0 && d->v[2] == 0 && d->w[0] == 0 && d->w[1] == 0 &&
              d->w[2] == 0,
          "missing velocity columns must read as zero");
  }
  esf_particle_defs_release(&defs);
}

static void test_csv_materials(void) {
  const char *path = write_file("mat.csv", "x,y,z,radius,material\n"
                                           "0,0,0,1, steel\n"
                                           "1,0,0,1,glass\r\n"
                                           "2,0,0,1,steel\n");
  esf_particle_defs defs = {0};
  esf_error err = {0};
  int calls = 0;
  int rc = esf_particles_read_csv(path, -1, lookup, &calls, &defs, &err);
  CHECK_OK(rc, err);
  CHECK(defs.n == 3, "material file: %zu particles", defs.n);
  CHECK(calls == 3, "lookup called %d times", calls);
  if (defs.n == 3)
    CHECK(defs.d[0].material == 1 && defs.d[1].material == 0 && defs.d[2].material == 1,
          "materials %d %d %d, expected 1 0 1", (int)defs.d[0].material,
          (int)defs.d[1].material, (int)defs.d[2].material);
  esf_particle_defs_release(&defs);

  expect_error("badmat.csv", "x,y,z,radius,material\n0,0,0,1,glass\n\n1,0,0,1,wood\n",
               ESF_EINPUT, ":4:5: unknown material 'wood'");
  expect_error("emptymat.csv", "material,x,y,z,radius\n ,0,0,0,1\n", ESF_EINPUT,
               ":2:1: empty material name");

  /* a material column needs a lookup; no column needs a default */
  path = write_file("nolookup.csv", "x,y,z,radius,material\n0,0,0,1,glass\n");
  rc = esf_particles_read_csv(path, 0, NULL, NULL, &defs, &err);
  CHECK(rc == ESF_EINPUT && strstr(err.msg, ":1:5: a material column needs"),
        "material column without lookup: %d '%s'", rc, err.msg);
  path = write_file("nodefault.csv", "x,y,z,radius\n0,0,0,1\n");
  rc = esf_particles_read_csv(path, -1, lookup, &calls, &defs, &err);
  CHECK(rc == ESF_EINPUT && strstr(err.msg, ":1: no material column"),
        "no material column and no default: %d '%s'", rc, err.msg);
  CHECK(defs.n == 0, "nothing appended on failure");
  esf_particle_defs_release(&defs);
}

static void test_csv_errors(void) {
  expect_error("packing.csv",
               "x,y,z,radius\n0,0,0,0.001\n# comment\n\n1,1,1,0.001\n2,2,2,0.001\n"
               "3,3,3,-0.001\n",
               ESF_EINPUT, ":7:4: radius must be positive, got -0.001");
  expect_error("zero.csv", "radius,x,y,z\n0,1,1,1\n", ESF_EINPUT,
               ":2:1: radius must be positive, got 0");
  expect_error("abc.csv", "x,y,z,radius\n0,0,0,1\n1, abc ,0,1\n", ESF_EINPUT,
               ":3:2: expected a number, got 'abc'");
  expect_error("trail.csv", "x,y,z,radius\n0,0,0,1x\n", ESF_EINPUT,
               ":2:4: expected a number, got '1x'");
  expect_error("emptyfield.csv", "x,y,z,radius\n0,,0,1\n", ESF_EINPUT,
               ":2:2: expected a number, got ''");
  expect_error("inf.csv", "x,y,z,radius\n0,0,inf,1\n", ESF_EINPUT,
               ":2:3: expected a finite number, got 'inf'");
  expect_error("nan.csv", "x,y,z,radius\n0,0,0,nan\n", ESF_EINPUT,
               ":2:4: expected a finite number, got 'nan'");
  expect_error("huge.csv", "x,y,z,radius\n1e999,0,0,1\n", ESF_EINPUT,
               ":2:1: expected a finite number, got '1e999'");
  expect_error("fields.csv", "x,y,z,radius\n0,0,0,1\n\n# c\n1,1,1\n", ESF_EINPUT,
               ":5: expected 4 fields, got 3");
  expect_error("extra.csv", "x,y,z,radius\r\n0,0,0,1,\r\n", ESF_EINPUT,
               ":2: expected 4 fields, got 5");
  expect_error(
      "unknown.csv", "x,y,z,radius, foo\n0,0,0,1,2\n", ESF_EINPUT,
      ":1:5: unknown column 'foo' (allowed: x, y, z, radius, vx, vy, vz, wx, wy, "
      "wz, material)");
  expect_error("twice.csv", "x,y,z,radius,x\n", ESF_EINPUT,
               ":1:5: column 'x' appears twice (first as column 1)");
  expect_error("emptyname.csv", "x,,y,z,radius\n", ESF_EINPUT,
               ":1:2: empty column name in the header");
  expect_error(
      "missing.csv", "# hi\nx,y,radius\n0,0,1\n", ESF_EINPUT,
      ":2: the header lacks the required column 'z' (required: x, y, z, radius)");
  expect_error("empty.csv", "", ESF_EINPUT,
               ": no particles (the file is empty; expected a header naming x, y, z, "
               "radius)");
  expect_error("blank.csv", "\n  \r\n# only comments\n", ESF_EINPUT,
               ": no particles (the file is empty; expected a header naming x, y, z, "
               "radius)");
  expect_error("header.csv", "x,y,z,radius\r\n", ESF_EINPUT,
               ": no particles (the file has a header but no rows)");

  /* unreadable file */
  char path[600];
  snprintf(path, sizeof path, "%s/does-not-exist.csv", tmpdir);
  esf_particle_defs defs = {0};
  esf_error err = {0};
  int rc = esf_particles_read_csv(path, 0, NULL, NULL, &defs, &err);
  char want[700];
  snprintf(want, sizeof want, "cannot open '%s': No such file or directory", path);
  CHECK(rc == ESF_EIO && err.code == ESF_EIO, "missing file: status %d", rc);
  CHECK(strcmp(err.msg, want) == 0, "missing file: '%s'", err.msg);
  /* err may be NULL */
  rc = esf_particles_read_csv(path, 0, NULL, NULL, &defs, NULL);
  CHECK(rc == ESF_EIO, "missing file with NULL err: %d", rc);
  CHECK(defs.n == 0, "no particles on failure");
  esf_particle_defs_release(&defs);
}

static void test_csv_long_line(void) {
  /* a data line of > 64 KiB (padding is whitespace around values) and a header with
   * long padding too */
  size_t pad = 70000;
  char *buf = malloc(3 * pad + 200);
  size_t len = 0;
  memset(buf, ' ', pad);
  len += pad;
  len += (size_t)sprintf(buf + len, "x,y,z,radius\n");
  len += (size_t)sprintf(buf + len, "0.25,");
  memset(buf + len, ' ', pad);
  len += pad;
  len += (size_t)sprintf(buf + len, "0.5,\t-1.5,");
  memset(buf + len, ' ', pad);
  len += pad;
  len += (size_t)sprintf(buf + len, "0.125\n1,2,3,4\n");
  buf[len] = '\0';
  const char *path = write_file("long.csv", buf);
  free(buf);
  esf_particle_defs defs = {0};
  esf_error err = {0};
  int rc = esf_particles_read_csv(path, 0, NULL, NULL, &defs, &err);
  CHECK_OK(rc, err);
  CHECK(defs.n == 2, "long lines: %zu particles", defs.n);
  if (defs.n == 2) {
    CHECK(defs.d[0].x[0] == 0.25 && defs.d[0].x[1] == 0.5 && defs.d[0].x[2] == -1.5 &&
              defs.d[0].radius == 0.125,
          "long line misread");
    CHECK(defs.d[1].x[2] == 3 && defs.d[1].radius == 4,
          "line after the long one misread");
  }
  esf_particle_defs_release(&defs);
}

/* ---- random fill ------------------------------------------------------------------ */

static esf_fill_spec base_spec(void) {
  static const int32_t mats[2] = {4, 9};
  static const double fr[2] = {0.7, 0.3};
  esf_fill_spec s;
  memset(&s, 0, sizeof s);
  s.max[0] = 0.04;
  s.max[1] = 0.04;
  s.min[2] = 0.01;
  s.max[2] = 0.12;
  s.count = 300;
  s.size.kind = ESF_SIZE_UNIFORM;
  s.size.a = 0.0015;
  s.size.b = 0.0025;
  s.mix.n = 2;
  s.mix.material = mats;
  s.mix.fraction = fr;
  s.seed = 7;
  s.dim = 3;
  s.velocity[2] = -0.5;
  return s;
}

/* Every pair of [from, n) against [0, n): no overlap beyond rounding. */
static size_t count_overlaps(const esf_particle_defs *d, size_t from) {
  size_t bad = 0;
  for (size_t i = from; i < d->n; i++)
    for (size_t j = 0; j < i; j++) {
      const esf_particle_def *a = &d->d[i], *b = &d->d[j];
      double dx = a->x[0] - b->x[0], dy = a->x[1] - b->x[1], dz = a->x[2] - b->x[2];
      double dist = sqrt(dx * dx + dy * dy + dz * dz);
      if (dist < (a->radius + b->radius) * (1 - 1e-12)) bad++;
    }
  return bad;
}

static size_t count_outside(const esf_particle_defs *d, size_t from,
                            const esf_fill_spec *s) {
  size_t bad = 0;
  for (size_t i = from; i < d->n; i++)
    for (int k = 0; k < 3; k++) {
      if (s->dim == 2 && k == 1) continue;
      double x = d->d[i].x[k], r = d->d[i].radius;
      if (x - r < s->min[k] || x + r > s->max[k]) bad++;
    }
  return bad;
}

static void test_random_basic(void) {
  esf_fill_spec s = base_spec();
  esf_particle_defs a = {0}, b = {0}, c = {0};
  esf_error err = {0};
  int rc = esf_generate_random(&s, NULL, &a, &err);
  CHECK_OK(rc, err);
  CHECK(a.n == 300, "random fill: %zu particles, expected 300", a.n);
  CHECK(count_overlaps(&a, 0) == 0, "random fill: %zu overlapping pairs",
        count_overlaps(&a, 0));
  CHECK(count_outside(&a, 0, &s) == 0, "random fill: %zu particles outside",
        count_outside(&a, 0, &s));
  size_t badr = 0, badm = 0, badv = 0;
  for (size_t i = 0; i < a.n; i++) {
    const esf_particle_def *d = &a.d[i];
    badr += d->radius < 0.0015 || d->radius > 0.0025;
    badm += d->material != 4 && d->material != 9;
    badv += d->v[0] != 0 || d->v[1] != 0 || d->v[2] != -0.5 || d->w[0] != 0 ||
            d->w[1] != 0 || d->w[2] != 0;
    if (i > 0)
      CHECK(d->radius <= a.d[i - 1].radius, "not placed largest first at %zu", i);
  }
  CHECK(badr == 0, "%zu radii outside [a, b]", badr);
  CHECK(badm == 0, "%zu materials not from the mix", badm);
  CHECK(badv == 0, "%zu particles with wrong velocity or angular velocity", badv);

  rc = esf_generate_random(&s, NULL, &b, &err);
  CHECK_OK(rc, err);
  CHECK(b.n == a.n && memcmp(a.d, b.d, a.n * sizeof *a.d) == 0,
        "the same seed must give identical particles");
  s.seed = 8;
  rc = esf_generate_random(&s, NULL, &c, &err);
  CHECK_OK(rc, err);
  size_t same = 0;
  for (size_t i = 0; i < c.n && i < a.n; i++) same += a.d[i].x[0] == c.d[i].x[0];
  CHECK(c.n == a.n && same < 3, "another seed must differ (%zu equal x)", same);
  esf_particle_defs_release(&a);
  esf_particle_defs_release(&b);
  esf_particle_defs_release(&c);
}

/* |k - N p| <= 4 sqrt(N p (1 - p)) */
static void check_binomial(size_t k, size_t n, double p, const char *what) {
  double sd = sqrt((double)n * p * (1 - p));
  CHECK(fabs((double)k - (double)n * p) <= 4 * sd,
        "%s: %zu of %zu, expected %.1f +- %.1f", what, k, n, (double)n * p, 4 * sd);
}

static void test_random_fractions(void) {
  esf_fill_spec s = base_spec();
  s.count = 2000;
  s.max[0] = s.max[1] = 0.1;
  s.min[2] = 0.0;
  s.max[2] = 0.1;
  static const double values[3] = {0.001, 0.002, 0.003};
  static const double fracs[3] = {2, 5, 3}; /* normalised by the generator */
  s.size.kind = ESF_SIZE_DISCRETE;
  s.size.nvalues = 3;
  s.size.values = values;
  s.size.fractions = fracs;
  esf_particle_defs a = {0};
  esf_error err = {0};
  int rc = esf_generate_random(&s, NULL, &a, &err);
  CHECK_OK(rc, err);
  CHECK(a.n == 2000, "discrete fill: %zu particles", a.n);
  size_t nm = 0, nr[3] = {0, 0, 0}, other = 0;
  for (size_t i = 0; i < a.n; i++) {
    nm += a.d[i].material == 4;
    int found = 0;
    for (int k = 0; k < 3; k++)
      if (a.d[i].radius == values[k]) nr[k]++, found = 1;
    other += !found;
  }
  check_binomial(nm, a.n, 0.7, "material 4 of a 0.7/0.3 mix");
  CHECK(other == 0, "%zu radii not among the values", other);
  check_binomial(nr[0], a.n, 0.2, "radius 0.001 (fraction 0.2)");
  check_binomial(nr[1], a.n, 0.5, "radius 0.002 (fraction 0.5)");
  check_binomial(nr[2], a.n, 0.3, "radius 0.003 (fraction 0.3)");
  CHECK(count_overlaps(&a, 0) == 0, "discrete fill overlaps");
  CHECK(count_outside(&a, 0, &s) == 0, "discrete fill outside the region");

  /* a zero-fraction value is never drawn (and does not count as the largest radius) */
  static const double values2[2] = {0.001, 0.5};
  static const double fracs2[2] = {1, 0};
  s.size.nvalues = 2;
  s.size.values = values2;
  s.size.fractions = fracs2;
  s.count = 50;
  size_t n0 = a.n;
  rc = esf_generate_random(&s, NULL, &a, &err);
  CHECK_OK(rc, err);
  size_t big = 0;
  for (size_t i = n0; i < a.n; i++) big += a.d[i].radius != 0.001;
  CHECK(a.n == n0 + 50 && big == 0, "zero-fraction radius drawn %zu times", big);
  esf_particle_defs_release(&a);
}

static void test_random_existing_2d(void) {
  /* existing particles (one much larger than the fill's) are avoided; out == existing */
  esf_fill_spec s = base_spec();
  s.count = 200;
  esf_particle_defs d = {0};
  esf_error err = {0};
  esf_particle_def big = {{0.02, 0.02, 0.06}, {0}, {0}, 0.015, 0};
  esf_particle_def small = {{0.0, 0.0, 0.01}, {0}, {0}, 0.004, 0};
  esf_particle_def far = {{5, 5, 5}, {0}, {0}, 0.01, 0};
  esf_particle_defs_push(&d, &big, &err);
  esf_particle_defs_push(&d, &small, &err);
  esf_particle_defs_push(&d, &far, &err);
  int rc = esf_generate_random(&s, &d, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 203, "fill around existing: %zu", d.n);
  CHECK(count_overlaps(&d, 3) == 0, "fill overlaps existing or itself: %zu",
        count_overlaps(&d, 3));
  CHECK(count_outside(&d, 3, &s) == 0, "fill around existing: outside");
  esf_particle_defs_release(&d);

  /* 2D: y = 0, the region's y ignored */
  s = base_spec();
  s.dim = 2;
  s.min[1] = 5;
  s.max[1] = -5;
  s.count = 150;
  rc = esf_generate_random(&s, NULL, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 150, "2D fill: %zu", d.n);
  size_t bady = 0;
  for (size_t i = 0; i < d.n; i++) bady += d.d[i].x[1] != 0.0;
  CHECK(bady == 0, "2D fill: %zu particles with y != 0", bady);
  CHECK(count_overlaps(&d, 0) == 0, "2D fill overlaps");
  CHECK(count_outside(&d, 0, &s) == 0, "2D fill outside");
  esf_particle_defs_release(&d);
}

static void test_random_overfull(void) {
  esf_fill_spec s = base_spec();
  s.min[0] = s.min[1] = s.min[2] = 0;
  s.max[0] = s.max[1] = s.max[2] = 0.01;
  s.size.kind = ESF_SIZE_FIXED;
  s.size.a = 0.001;
  s.count = 1000;
  esf_particle_defs d = {0};
  esf_error err = {0};
  esf_particle_def one = {{9, 9, 9}, {0}, {0}, 1, 0};
  esf_particle_defs_push(&d, &one, &err);
  int rc = esf_generate_random(&s, NULL, &d, &err);
  CHECK(rc == ESF_EINPUT, "overfull: status %d", rc);
  CHECK(strncmp(err.msg, "could not place particle ", 25) == 0 &&
            strstr(err.msg, " of 1000 after 2000 attempts: the region is too full "
                            "(asked solid fraction 4.19;"),
        "overfull message: '%s'", err.msg);
  CHECK(d.n == 1, "overfull: list restored (%zu)", d.n);
  esf_particle_defs_release(&d);
}

static void expect_spec_error(const esf_fill_spec *s, int lattice, const char *part) {
  esf_particle_defs d = {0};
  esf_error err = {0};
  int rc = lattice ? esf_generate_lattice(s, &d, &err)
                   : esf_generate_random(s, NULL, &d, &err);
  CHECK(rc == ESF_EINPUT && strstr(err.msg, part), "expected '%s', got %d '%s'", part, rc,
        err.msg);
  CHECK(d.n == 0, "spec error: nothing appended");
  esf_particle_defs_release(&d);
}

static void test_spec_errors(void) {
  esf_fill_spec s = base_spec();
  s.max[1] = s.min[1];
  expect_spec_error(&s, 0, "region: min y (0) must be less than max y (0)");
  s = base_spec();
  s.size.a = 0;
  expect_spec_error(&s, 0, "0 < min <= max");
  s = base_spec();
  s.size.kind = ESF_SIZE_FIXED;
  s.size.a = -1;
  expect_spec_error(&s, 1, "radius must be positive");
  s = base_spec();
  s.size.b = 0.03;
  expect_spec_error(&s, 0,
                    "region is too small for a particle of radius 0.03: its extent "
                    "in x is 0.04 < 0.06");
  s = base_spec();
  static const double zero[2] = {0, 0}, neg[2] = {1, -1};
  s.mix.fraction = zero;
  expect_spec_error(&s, 0, "material fractions are all zero");
  s.mix.fraction = neg;
  expect_spec_error(&s, 0, "material fraction 2 must be a non-negative number");
  s = base_spec();
  s.count = 0;
  expect_spec_error(&s, 0, "count must be positive");
  s = base_spec();
  s.dim = 1;
  expect_spec_error(&s, 1, "dimension must be 2 or 3");
}

/* ---- lattice ---------------------------------------------------------------------- */

static void test_lattice(void) {
  esf_fill_spec s = base_spec();
  s.min[0] = s.min[1] = s.min[2] = 0;
  s.max[0] = s.max[1] = s.max[2] = 0.1;
  s.size.kind = ESF_SIZE_FIXED;
  s.size.a = 0.005;
  s.count = 0;
  esf_particle_defs d = {0};
  esf_error err = {0};
  int rc = esf_generate_lattice(&s, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 1000, "lattice spacing 2r: %zu sites, expected 1000", d.n);
  if (d.n == 1000) {
    CHECK_NEAR(d.d[0].x[0], 0.005, 1e-15, "first site x");
    CHECK_NEAR(d.d[0].x[2], 0.005, 1e-15, "first site z");
    CHECK_NEAR(d.d[1].x[0] - d.d[0].x[0], 0.01, 1e-15, "spacing along x");
    CHECK_NEAR(d.d[10].x[1] - d.d[0].x[1], 0.01, 1e-15, "spacing along y (x fastest)");
    CHECK_NEAR(d.d[100].x[2] - d.d[0].x[2], 0.01, 1e-15, "spacing along z");
    CHECK_NEAR(d.d[999].x[0], 0.095, 1e-15, "last site x");
    CHECK(count_outside(&d, 0, &s) == 0, "lattice outside the region");
    CHECK(count_overlaps(&d, 0) == 0, "lattice overlaps");
  }
  esf_particle_defs_release(&d);

  s.spacing = 0.02; /* floor((0.1 - 0.01) / 0.02) + 1 = 5 per axis */
  rc = esf_generate_lattice(&s, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 125, "lattice spacing 0.02: %zu sites, expected 125", d.n);
  if (d.n == 125) CHECK_NEAR(d.d[4].x[0], 0.085, 1e-15, "fifth site x");
  esf_particle_defs_release(&d);

  s.count = 7;
  rc = esf_generate_lattice(&s, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 7, "lattice count 7: %zu", d.n);
  if (d.n == 7) {
    CHECK_NEAR(d.d[6].x[0], 0.025, 1e-15, "7th site is the 2nd of the 2nd row: x");
    CHECK_NEAR(d.d[6].x[1], 0.025, 1e-15, "7th site y");
    CHECK(d.d[6].v[2] == -0.5 && d.d[6].material >= 4, "lattice velocity, material");
  }
  esf_particle_defs_release(&d);

  s.count = 126;
  expect_spec_error(&s, 1, "only 125 sites");
  s.count = 0;
  s.spacing = 0.009;
  expect_spec_error(&s, 1, "exceeds half the spacing");

  /* uniform radii: sites from r_max, radii within [a, b], reproducible */
  s.spacing = 0;
  s.size.kind = ESF_SIZE_UNIFORM;
  s.size.a = 0.002;
  s.size.b = 0.004;
  rc = esf_generate_lattice(&s, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 12 * 12 * 12, "lattice uniform: %zu sites", d.n);
  size_t badr = 0;
  for (size_t i = 0; i < d.n; i++) badr += d.d[i].radius < 0.002 || d.d[i].radius > 0.004;
  CHECK(badr == 0, "lattice radii outside [a, b]: %zu", badr);
  CHECK(count_outside(&d, 0, &s) == 0 && count_overlaps(&d, 0) == 0,
        "lattice uniform: outside or overlapping");
  esf_particle_defs_release(&d);

  /* 2D: x-z plane at y = 0 */
  s = base_spec();
  s.dim = 2;
  s.min[0] = s.min[2] = 0;
  s.max[0] = 0.1;
  s.max[2] = 0.05;
  s.size.kind = ESF_SIZE_FIXED;
  s.size.a = 0.005;
  s.count = 0;
  rc = esf_generate_lattice(&s, &d, &err);
  CHECK_OK(rc, err);
  CHECK(d.n == 50, "2D lattice: %zu sites, expected 50", d.n);
  size_t bady = 0;
  for (size_t i = 0; i < d.n; i++) bady += d.d[i].x[1] != 0.0;
  CHECK(bady == 0, "2D lattice: y != 0");
  if (d.n == 50) CHECK_NEAR(d.d[10].x[2] - d.d[0].x[2], 0.01, 1e-15, "2D lattice z step");
  esf_particle_defs_release(&d);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/esf_sources_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  test_csv_roundtrip();
  test_csv_materials();
  test_csv_errors();
  test_csv_long_line();
  test_random_basic();
  test_random_fractions();
  test_random_existing_2d();
  test_random_overfull();
  test_spec_errors();
  test_lattice();
  for (int k = 0; k < nwritten; k++) {
    char p[512];
    snprintf(p, sizeof p, "%s/%.63s", tmpdir, written[k]);
    unlink(p); /* names written twice fail the second time: fine */
  }
  if (rmdir(tmpdir) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return check_finish("test_sources");
}
