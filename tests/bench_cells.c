/* bench_cells.c — times the contact-candidate search (esf_cells_pairs) with one grid and
 * with size classes, on random polydisperse sets and on packings read from CSV files.
 * A benchmark, not a test: it prints figures and asserts nothing about speed; it does
 * check that every mode finds the same number of pairs (exit status 1 when one does not).
 *
 * usage: bench_cells [-n N] [-r REPS] [-p PHI] [FILE.csv ...]
 *   without files: N spheres (default 20000), radii in [r, q r] uniform by number,
 *   uniform by volume (number density ~ r^-3), bimodal with 1 in 5 large, bimodal with
 *   equal volumes of both sizes (for several q), positions
 *   uniform in a cube sized for a nominal solid fraction PHI (default 0.55, overlaps
 *   allowed), skin 0.4 × the mean radius (esfera's default);
 *   FILE.csv: a header naming x, y, z, radius (other columns ignored), same skin rule.
 * Each figure is the median of REPS (default 21) searches on a reused grid, in ms of
 * the thread's CPU time (the machine may be shared: wall time would count waiting). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "search/cells.h"
#include "util/rng.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_d(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

static const struct {
  esf_cells_mode mode;
  double factor;
  const char *name;
} modes[] = {{ESF_CELLS_ONE_GRID, 0, "one grid"},
             {ESF_CELLS_CLASSES, 2.0, "classes f=2"},
             {ESF_CELLS_CLASSES, 1.5, "classes f=1.5"},
             {ESF_CELLS_CLASSES, 3.0, "classes f=3"},
             {ESF_CELLS_AUTO, 0, "auto"}};
enum { NMODES = sizeof modes / sizeof modes[0] };

/* Returns the number of modes whose pair count differs from the first mode's. */
static int run(const char *what, size_t n, const double *x, const double *r, int reps) {
  double rmin = INFINITY, rmax = 0, rsum = 0;
  for (size_t i = 0; i < n; i++) {
    rsum += r[i];
    if (r[i] < rmin) rmin = r[i];
    if (r[i] > rmax) rmax = r[i];
  }
  double skin = 0.4 * rsum / (double)n;
  esf_cells *c = NULL;
  esf_error err = {0};
  esf_pairbuf b = {0};
  double *t = malloc((size_t)reps * sizeof *t), t0 = 0, tmin0 = 0;
  size_t np0 = 0;
  int differ = 0;
  printf("%-28s n=%zu r=[%.3g, %.3g] skin=%.3g S=%.2f\n", what, n, rmin, rmax, skin,
         (2 * rmax + skin) / (2 * rmin + skin));
  for (int m = 0; m < NMODES; m++) {
    if (esf_cells_create(&c, &err) ||
        esf_cells_tune(c, modes[m].mode, modes[m].factor, &err))
      goto fail;
    for (int k = -1; k < reps; k++) { /* k = -1: warm-up, sizes the storage */
      double a = now();
      if (esf_cells_pairs(c, n, x, r, skin, &b, &err)) goto fail;
      if (k >= 0) t[k] = now() - a;
    }
    qsort(t, (size_t)reps, sizeof *t, cmp_d);
    double med = t[reps / 2];
    if (m == 0) {
      t0 = med;
      tmin0 = t[0];
      np0 = b.n;
    }
    printf("  %-14s %9.3f ms (min %8.3f)  pairs %zu%s  x%.2f (min x%.2f)  grids %d  "
           "%.1f B/particle\n",
           modes[m].name, 1e3 * med, 1e3 * t[0], b.n, b.n == np0 ? "" : " DIFFER",
           t0 / med, tmin0 / t[0], esf_cells_nclasses(c),
           (double)esf_cells_bytes(c) / (double)n);
    differ += b.n != np0;
    esf_cells_free(&c);
  }
  free(t);
  esf_pairbuf_release(&b);
  return differ;
fail:
  fprintf(stderr, "bench_cells: %s\n", err.msg);
  exit(1);
}

/* Reads x, y, z, radius from a CSV file with a header. Returns the count. */
static size_t read_csv(const char *path, double **x, double **r) {
  FILE *f = fopen(path, "r");
  if (!f) {
    perror(path);
    exit(1);
  }
  char line[4096];
  int col[4] = {-1, -1, -1, -1}, ncol = 0;
  static const char *names[4] = {"x", "y", "z", "radius"};
  if (!fgets(line, sizeof line, f)) exit(1);
  for (char *tok = strtok(line, ",\r\n"); tok; tok = strtok(NULL, ",\r\n"), ncol++) {
    while (*tok == ' ') tok++;
    for (int k = 0; k < 4; k++)
      if (strcmp(tok, names[k]) == 0) col[k] = ncol;
  }
  size_t n = 0, cap = 1024;
  *x = malloc(3 * cap * sizeof **x);
  *r = malloc(cap * sizeof **r);
  while (fgets(line, sizeof line, f)) {
    if (n == cap) {
      cap *= 2;
      *x = realloc(*x, 3 * cap * sizeof **x);
      *r = realloc(*r, cap * sizeof **r);
    }
    double v[64];
    int k = 0;
    for (char *tok = strtok(line, ",\r\n"); tok && k < 64; tok = strtok(NULL, ",\r\n"))
      v[k++] = strtod(tok, NULL);
    if (k == 0) continue;
    for (int d = 0; d < 3; d++) (*x)[3 * n + d] = v[col[d]];
    (*r)[n] = v[col[3]];
    n++;
  }
  fclose(f);
  return n;
}

/* Exit status: 1 when some mode's pair count differed. */
static int report(int differ) {
  if (differ)
    fprintf(stderr, "bench_cells: %d pair counts DIFFER between modes\n", differ);
  return differ ? 1 : 0;
}

int main(int argc, char **argv) {
  size_t n = 20000;
  int reps = 21, a = 1;
  double phi = 0.55;
  for (; a < argc && argv[a][0] == '-'; a += 2) {
    if (a + 1 >= argc) return 2;
    if (strcmp(argv[a], "-n") == 0)
      n = (size_t)atol(argv[a + 1]);
    else if (strcmp(argv[a], "-r") == 0)
      reps = atoi(argv[a + 1]);
    else if (strcmp(argv[a], "-p") == 0)
      phi = atof(argv[a + 1]);
    else
      return 2;
  }
  if (reps < 1) reps = 1;
  int differ = 0;
  if (a < argc) {
    for (; a < argc; a++) {
      double *x, *r;
      size_t m = read_csv(argv[a], &x, &r);
      differ += run(argv[a], m, x, r, reps);
      free(x);
      free(r);
    }
    return report(differ);
  }
  double *x = malloc(3 * n * sizeof *x), *r = malloc(n * sizeof *r);
  esf_rng g;
  static const struct {
    char kind; /* n: uniform by number, v: by volume, b: bimodal 1 in 5 large,
                  e: bimodal, equal volumes of both sizes */
    double q;
  } sets[] = {{'n', 1},   {'n', 1.5}, {'n', 2},   {'n', 3}, {'n', 5}, {'n', 10},
              {'v', 1.5}, {'v', 2},   {'v', 2.5}, {'v', 3}, {'v', 5}, {'v', 10},
              {'b', 5},   {'e', 2},   {'e', 3},   {'e', 5}, {'e', 10}};
  for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
    esf_rng_seed(&g, 42 + k);
    const double r0 = 1e-3, q = sets[k].q;
    const size_t nlarge = (size_t)((double)n / (1 + q * q * q)); /* 'e' */
    double vol = 0;
    for (size_t i = 0; i < n; i++) {
      double u = esf_rng_uniform(&g);
      switch (sets[k].kind) {
      case 'n':
        r[i] = r0 * (1 + (q - 1) * u);
        break;
      case 'v':
        r[i] = r0 / sqrt(1 - u * (1 - 1 / (q * q)));
        break; /* pdf ~ r^-3 */
      case 'b':
        r[i] = i % 5 ? r0 : q * r0;
        break;
      default:
        r[i] = i < nlarge ? q * r0 : r0;
        break;
      }
      vol += 4.0 / 3.0 * M_PI * r[i] * r[i] * r[i];
    }
    double L = cbrt(vol / phi);
    for (size_t i = 0; i < 3 * n; i++) x[i] = L * esf_rng_uniform(&g);
    char what[64];
    static const char *kname[] = {"uniform by number", "uniform by volume",
                                  "bimodal, 1/5 large", "bimodal, equal volumes"};
    const char *kn = kname[sets[k].kind == 'n'   ? 0
                           : sets[k].kind == 'v' ? 1
                           : sets[k].kind == 'b' ? 2
                                                 : 3];
    snprintf(what, sizeof what, "%s 1:%g", kn, q);
    differ += run(what, n, x, r, reps);
  }
  free(x);
  free(r);
  return report(differ);
}
