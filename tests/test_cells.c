/* test_cells.c — the linked-cell search must find exactly the pairs brute force finds,
 * with one grid and with size classes (every set is run in each mode): random
 * polydisperse sets (radius ratios 1:1 to 1:10, bimodal, 1:100; one class empty, a
 * class of one), dense and sparse, particles on cell
 * boundaries and on the bounding box's faces, flat (2D, 1D) sets, a particle far away
 * (grid cap), n = 0, 1, 2, the strict cutoff, and non-finite positions. The one grid
 * swept by 2 and 3 threads finds one thread's pairs in one thread's order. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "search/cells.h"
#include "util/rng.h"

static int cmp_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return x < y ? -1 : x > y;
}

/* The pairs as sorted (min, max) keys; checks i != j and indices < n. */
static uint64_t *sorted_keys(const esf_pairbuf *b, size_t n, const char *what) {
  uint64_t *k = malloc((b->n ? b->n : 1) * sizeof *k);
  int bad = 0;
  for (size_t p = 0; p < b->n; p++) {
    uint32_t i = b->i[p], j = b->j[p];
    if (i == j || i >= n || j >= n) bad++;
    uint32_t lo = i < j ? i : j, hi = i < j ? j : i;
    k[p] = (uint64_t)lo << 32 | hi;
  }
  CHECK(bad == 0, "%s: %d pairs with i == j or an index out of range", what, bad);
  qsort(k, b->n, sizeof *k, cmp_u64);
  return k;
}

/* The search modes every set is run in: the automatic choice, one grid forced, size
 * classes forced (factor 2, and a fine factor 1.3 that makes up to 8 classes). */
static const struct {
  esf_cells_mode mode;
  double factor;
  const char *name;
} modes[] = {{ESF_CELLS_AUTO, 0, "auto"},
             {ESF_CELLS_ONE_GRID, 0, "one grid"},
             {ESF_CELLS_CLASSES, 2.0, "classes f = 2"},
             {ESF_CELLS_CLASSES, 1.3, "classes f = 1.3"}};
enum { NMODES = sizeof modes / sizeof modes[0] };

/* Runs the cell search (on a shared, reused grid) in every mode and brute force, and
 * compares the sets of pairs. */
static void compare(esf_cells *cells, size_t n, const double *x, const double *r,
                    double skin, const char *what) {
  esf_pairbuf a = {0}, b = {0};
  esf_error err = {0};
  int rc = esf_pairs_brute(n, x, r, skin, &b, &err);
  CHECK_OK(rc, err);
  uint64_t *kb = sorted_keys(&b, n, what);
  for (int m = 0; m < NMODES; m++) {
    rc = esf_cells_tune(cells, modes[m].mode, modes[m].factor, &err);
    CHECK_OK(rc, err);
    rc = esf_cells_pairs(cells, n, x, r, skin, &a, &err);
    CHECK_OK(rc, err);
    uint64_t *ka = sorted_keys(&a, n, what);
    size_t dup = 0;
    for (size_t p = 1; p < a.n; p++) dup += ka[p] == ka[p - 1];
    CHECK(dup == 0, "%s (%s): %zu duplicate pairs", what, modes[m].name, dup);
    int same = a.n == b.n && (a.n == 0 || memcmp(ka, kb, a.n * sizeof *ka) == 0);
    CHECK(same, "%s (%s): cells found %zu pairs, brute force %zu", what, modes[m].name,
          a.n, b.n);
    free(ka);
  }
  /* the one grid swept by 2 and 3 threads in slabs: the same pairs in the same order
     as one thread (the slabs' buffers are appended in layer order) */
  CHECK_OK(esf_cells_tune(cells, ESF_CELLS_ONE_GRID, 0, &err), err);
  CHECK_OK(esf_cells_pairs(cells, n, x, r, skin, &a, &err), err);
  for (int T = 2; T <= 3; T++) {
    esf_pairbuf t = {0};
    esf_cells_threads(cells, T);
    CHECK_OK(esf_cells_pairs(cells, n, x, r, skin, &t, &err), err);
    int same = t.n == a.n && (a.n == 0 || (memcmp(t.i, a.i, a.n * sizeof *a.i) == 0 &&
                                           memcmp(t.j, a.j, a.n * sizeof *a.j) == 0));
    CHECK(same, "%s (one grid, %d threads): %zu pairs, not one thread's %zu in order",
          what, T, t.n, a.n);
    esf_pairbuf_release(&t);
  }
  esf_cells_threads(cells, 1);
  CHECK_OK(esf_cells_tune(cells, ESF_CELLS_AUTO, 0, &err), err);
  free(kb);
  esf_pairbuf_release(&a);
  esf_pairbuf_release(&b);
}

static double uni(esf_rng *g, double a, double b) {
  return a + (b - a) * esf_rng_uniform(g);
}

/* n particles uniform in a box of edge L (dims with flat[d] set to 0), radii in
 * [rmin, ratio rmin]. */
static void random_set(esf_rng *g, size_t n, double L, const int flat[3], double rmin,
                       double ratio, double *x, double *r) {
  for (size_t i = 0; i < n; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = flat[d] ? 0 : uni(g, 0, L);
    r[i] = uni(g, rmin, ratio * rmin);
  }
}

int main(void) {
  esf_cells *cells = NULL;
  esf_error err = {0};
  CHECK_OK(esf_cells_create(&cells, &err), err);
  esf_rng g;
  esf_rng_seed(&g, 20240611);
  const size_t NMAX = 4000;
  double *x = malloc(3 * NMAX * sizeof *x), *r = malloc(NMAX * sizeof *r);
  static const int none[3] = {0, 0, 0}, flat_y[3] = {0, 1, 0}, flat_yz[3] = {0, 1, 1};

  /* n = 0, 1: no pairs, no error (x, r may be NULL for n = 0) */
  {
    esf_pairbuf b = {0};
    CHECK_OK(esf_cells_pairs(cells, 0, NULL, NULL, 0.1, &b, &err), err);
    CHECK(b.n == 0, "n = 0: %zu pairs", b.n);
    CHECK_OK(esf_pairs_brute(0, NULL, NULL, 0.1, &b, &err), err);
    CHECK(b.n == 0, "n = 0 brute: %zu pairs", b.n);
    double x1[3] = {1, 2, 3}, r1[1] = {0.5};
    CHECK_OK(esf_cells_pairs(cells, 1, x1, r1, 0.1, &b, &err), err);
    CHECK(b.n == 0, "n = 1: %zu pairs", b.n);
    esf_pairbuf_release(&b);
    CHECK(b.i == NULL && b.j == NULL && b.cap == 0, "release clears the buffer");
  }

  /* n = 2: the cutoff is strict; cut = 0.5 + 0.25 + 0.25 = 1 exactly */
  {
    double r2[2] = {0.5, 0.25};
    double at[6] = {0, 0, 0, 1, 0, 0}, in[6] = {0, 0, 0, 0.999, 0, 0};
    double diag[6] = {0, 0, 0, 0.5, 0.5, 0.5}; /* |d| = 0.866 */
    esf_pairbuf b = {0};
    CHECK_OK(esf_cells_pairs(cells, 2, at, r2, 0.25, &b, &err), err);
    CHECK(b.n == 0, "n = 2 at exactly the cutoff: %zu pairs", b.n);
    CHECK_OK(esf_cells_pairs(cells, 2, in, r2, 0.25, &b, &err), err);
    CHECK(b.n == 1 && b.i[0] == 0 && b.j[0] == 1, "n = 2 inside the cutoff: %zu pairs",
          b.n);
    CHECK_OK(esf_cells_pairs(cells, 2, diag, r2, 0.25, &b, &err), err);
    CHECK(b.n == 1, "n = 2 on a diagonal: %zu pairs", b.n);
    /* zero radii and zero skin: nothing can be closer than 0 */
    double r0[2] = {0, 0}, same[6] = {1, 1, 1, 1, 1, 1};
    CHECK_OK(esf_cells_pairs(cells, 2, same, r0, 0, &b, &err), err);
    CHECK(b.n == 0, "zero cutoff: %zu pairs", b.n);
    esf_pairbuf_release(&b);
    compare(cells, 2, at, r2, 0.25, "n = 2 at the cutoff");
    compare(cells, 2, in, r2, 0.25, "n = 2 inside");
    compare(cells, 2, same, r2, -0.5, "n = 2 coincident, negative skin");
  }

  /* random polydisperse sets: dense and sparse, radius ratios 1 to 5, several skins */
  {
    static const struct {
      size_t n;
      double L, rmin, ratio, skin;
      const char *what;
    } cases[] = {
        {50, 1.0, 0.02, 1.0, 0.01, "small monodisperse"},
        {500, 1.0, 0.03, 5.0, 0.005, "polydisperse 1:5, dense"},
        {2000, 1.0, 0.01, 5.0, 0.002, "polydisperse 1:5, medium"},
        {3000, 10.0, 0.01, 3.0, 0.0, "sparse, zero skin"},
        {3000, 1.0, 0.02, 2.0, 0.01, "very dense (many per cell)"},
        {1000, 1.0, 0.001, 5.0, 0.05, "skin larger than the particles"},
        {800, 1.0, 0.05, 5.0, -0.02, "negative skin (overlaps only)"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
      random_set(&g, cases[c].n, cases[c].L, none, cases[c].rmin, cases[c].ratio, x, r);
      compare(cells, cases[c].n, x, r, cases[c].skin, cases[c].what);
    }
  }

  /* polydisperse sets for the size classes: ratios 1:1 to 1:10, dense and sparse,
     3D and flat 2D; a bimodal set; pairs in the set must never depend on the mode */
  {
    static const double ratios[] = {1.0, 3.0, 5.0, 10.0};
    static const struct {
      size_t n;
      double L, rmin, skin;
      const char *what;
    } dens[] = {{3000, 1.0, 0.012, 0.004, "dense"}, {2000, 4.0, 0.01, 0.002, "sparse"}};
    char what[96];
    for (size_t q = 0; q < sizeof ratios / sizeof ratios[0]; q++)
      for (size_t e = 0; e < 2; e++)
        for (int flat = 0; flat < 2; flat++) {
          /* dense: the largest spheres fill about 1/3 of the box in 3D; the radii are
             scaled so a ratio does not change the packing much */
          double rmin = dens[e].rmin * 3.0 / (1.0 + ratios[q]);
          random_set(&g, dens[e].n, dens[e].L, flat ? flat_y : none, rmin, ratios[q], x,
                     r);
          snprintf(what, sizeof what, "ratio 1:%g, %s, %s", ratios[q], dens[e].what,
                   flat ? "2D y = 0" : "3D");
          compare(cells, dens[e].n, x, r, dens[e].skin, what);
        }
    /* bimodal 1:5 (two sizes only), dense */
    for (size_t i = 0; i < 3000; i++) {
      for (int d = 0; d < 3; d++) x[3 * i + d] = uni(&g, 0, 1);
      r[i] = (i % 4) ? 0.006 : 0.03;
    }
    compare(cells, 3000, x, r, 0.003, "bimodal 1:5, dense");
    /* the automatic choice: one grid for a monodisperse set, classes for a bimodal 1:5
       set with equal volumes of both sizes (about 125 small per large: a cell of the
       single grid holds dozens of small ones) */
    for (size_t i = 0; i < 3000; i++) {
      r[i] = i % 126 ? 0.004 : 0.02;
      for (int d = 0; d < 3; d++) x[3 * i + d] = uni(&g, 0, 0.15); /* solid fr. 0.5 */
    }
    CHECK_OK(esf_cells_tune(cells, ESF_CELLS_AUTO, 0, &err), err);
    esf_pairbuf b = {0};
    CHECK_OK(esf_cells_pairs(cells, 3000, x, r, 0.002, &b, &err), err);
    CHECK(esf_cells_nclasses(cells) >= 2, "auto, bimodal 1:5 equal volumes: %d grids",
          esf_cells_nclasses(cells));
    compare(cells, 3000, x, r, 0.002, "bimodal 1:5, equal volumes");
    for (size_t i = 0; i < 3000; i++) r[i] = 0.01;
    CHECK_OK(esf_cells_pairs(cells, 3000, x, r, 0.002, &b, &err), err);
    CHECK(esf_cells_nclasses(cells) == 1, "auto, monodisperse: %d grids",
          esf_cells_nclasses(cells));
    esf_pairbuf_release(&b);
    /* the small class only in one corner, the large ones elsewhere (class boxes apart) */
    for (size_t i = 0; i < 2000; i++) {
      int small = i % 2;
      for (int d = 0; d < 3; d++)
        x[3 * i + d] = small ? uni(&g, 0, 0.3) : uni(&g, 0.2, 1);
      r[i] = small ? uni(&g, 0.003, 0.006) : uni(&g, 0.02, 0.04);
    }
    compare(cells, 2000, x, r, 0.002, "classes in different boxes");
  }

  /* edge cases of the classes */
  {
    /* a huge ratio 1:100: many classes, the largest few */
    for (size_t i = 0; i < 3000; i++) {
      for (int d = 0; d < 3; d++) x[3 * i + d] = uni(&g, 0, 1);
      r[i] = i % 100 ? uni(&g, 0.001, 0.003) : uni(&g, 0.05, 0.1);
    }
    compare(cells, 3000, x, r, 0.001, "ratio 1:100, few large");
    for (size_t i = 0; i < 3000; i++) r[i] = uni(&g, 0.001, 0.1);
    compare(cells, 3000, x, r, 0.001, "ratio 1:100, uniform radii");
    /* one large particle among many small ones (a class of one), and one small one
       among many large ones */
    for (size_t i = 0; i < 2000; i++) r[i] = uni(&g, 0.004, 0.006);
    r[1234] = 0.3;
    compare(cells, 2000, x, r, 0.002, "one large particle");
    for (size_t i = 0; i < 2000; i++) r[i] = uni(&g, 0.02, 0.03);
    r[77] = 0.001;
    compare(cells, 2000, x, r, 0.002, "one small particle");
    /* all in one class (monodisperse with classes forced: the others are empty) */
    for (size_t i = 0; i < 2000; i++) r[i] = 0.01;
    compare(cells, 2000, x, r, 0.002, "monodisperse, one class");
    /* zero radii: the smallest 2 r + skin is the skin alone */
    for (size_t i = 0; i < 2000; i++) r[i] = i % 3 ? 0.0 : 0.02;
    compare(cells, 2000, x, r, 0.004, "zero radii and 1:11 with the skin");
    /* negative skin: the small ones have 2 r + skin <= 0 and pair only with large ones */
    for (size_t i = 0; i < 2000; i++) r[i] = i % 3 ? uni(&g, 0.001, 0.004) : 0.05;
    compare(cells, 2000, x, r, -0.01, "negative skin, small ones below the cutoff");
    /* 2 r + skin <= 0 for every particle: no pair at all */
    compare(cells, 2000, x, r, -0.2, "negative skin larger than every diameter");
  }

  /* particles exactly on cell boundaries: positions multiples of the nominal cell edge
     2 r_max + skin, and of half of it; pairs at exactly the cutoff are excluded */
  {
    const double rmax = 0.125, skin = 0.25, h = 2 * rmax + skin; /* 0.5, exact */
    size_t n = 0;
    for (int i = 0; i < 8; i++)
      for (int j = 0; j < 8; j++)
        for (int k = 0; k < 8; k++, n++) {
          x[3 * n] = i * h;
          x[3 * n + 1] = j * h;
          x[3 * n + 2] = k * h;
          r[n] = (n % 3) ? rmax : rmax / 5;
        }
    compare(cells, n, x, r, skin, "lattice at the cell edge");
    for (size_t i = 0; i < 3 * n; i++) x[i] *= 0.5;
    compare(cells, n, x, r, skin, "lattice at half the cell edge");
    for (size_t i = 0; i < n; i++) r[i] = rmax; /* all at exactly the cutoff on axes */
    for (size_t i = 0; i < 3 * n; i++) x[i] *= 2;
    compare(cells, n, x, r, skin, "monodisperse lattice at the cutoff");
    /* random radii, positions snapped to multiples of the edge with small offsets */
    for (size_t i = 0; i < n; i++) {
      r[i] = uni(&g, rmax / 5, rmax);
      for (int d = 0; d < 3; d++) {
        double m = floor(uni(&g, 0, 6)) * h;
        x[3 * i + d] = m + ((esf_rng_next(&g) & 3) == 0 ? uni(&g, -1e-9, 1e-9) : 0);
      }
    }
    compare(cells, n, x, r, skin, "snapped to cell boundaries");
  }

  /* particles on the bounding box's faces and corners */
  {
    size_t n = 1500;
    for (size_t i = 0; i < n; i++) {
      for (int d = 0; d < 3; d++) x[3 * i + d] = uni(&g, 0, 2);
      int face = (int)(esf_rng_next(&g) % 7);
      if (face < 6) x[3 * i + face / 2] = (face & 1) ? 2.0 : 0.0;
      r[i] = uni(&g, 0.01, 0.05);
    }
    for (int c = 0; c < 8; c++)
      for (int d = 0; d < 3; d++) x[3 * c + d] = (c >> d) & 1 ? 2.0 : 0.0;
    compare(cells, n, x, r, 0.01, "on the bounding box's faces");
  }

  /* flat sets: 2D (all y = 0) and 1D (all y = z = 0) */
  random_set(&g, 2000, 1.0, flat_y, 0.005, 5.0, x, r);
  compare(cells, 2000, x, r, 0.002, "2D set, y = 0");
  random_set(&g, 2000, 20.0, flat_yz, 0.005, 5.0, x, r);
  compare(cells, 2000, x, r, 0.002, "1D set, y = z = 0");
  random_set(&g, 300, 1.0, flat_y, 0.01, 5.0, x, r);
  for (size_t i = 0; i < 300; i++) x[3 * i + 1] = 7.25; /* flat, off the origin */
  compare(cells, 300, x, r, 0.01, "2D set, y = 7.25");

  /* a particle very far away: the grid is capped, the result unchanged */
  {
    size_t n = 2000;
    random_set(&g, n, 1.0, none, 0.005, 5.0, x, r);
    x[3 * 17] = 1e6;
    x[3 * 17 + 1] = -2e6;
    x[3 * 17 + 2] = 5e5;
    compare(cells, n, x, r, 0.002, "one particle 1e6 m away");
    x[3 * 17 + 1] = 0.5;
    x[3 * 17 + 2] = 0.5;
    x[3 * 17] = 1e12; /* far along x only */
    compare(cells, n, x, r, 0.002, "one particle 1e12 m away along x");
    x[3 * 17] = -1e300;
    compare(cells, n, x, r, 0.002, "one particle 1e300 m away");
    /* two tight clusters far apart with near pairs in both */
    for (size_t i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) x[3 * i + d] = uni(&g, 0, 0.3) + (i & 1 ? 1e4 : 0);
    compare(cells, n, x, r, 0.002, "two clusters 1e4 m apart");
  }

  /* reuse with a smaller, then a larger set on the same grid storage */
  random_set(&g, 10, 0.1, none, 0.01, 2.0, x, r);
  compare(cells, 10, x, r, 0.01, "reuse, n = 10");
  random_set(&g, NMAX, 1.5, none, 0.005, 5.0, x, r);
  compare(cells, NMAX, x, r, 0.003, "reuse, n = 4000");

  /* non-finite positions */
  {
    esf_pairbuf b = {0};
    random_set(&g, 20, 1.0, none, 0.05, 2.0, x, r);
    x[3 * 7 + 1] = NAN;
    int rc = esf_cells_pairs(cells, 20, x, r, 0.01, &b, &err);
    CHECK(rc == ESF_ENUMERIC, "NaN position: status %d", rc);
    CHECK(strstr(err.msg, "particle 7 has a non-finite position") != NULL, "message: %s",
          err.msg);
    CHECK(b.n == 0, "no pairs on error");
    x[3 * 7 + 1] = 0.5;
    x[3 * 19 + 2] = -INFINITY;
    rc = esf_pairs_brute(20, x, r, 0.01, &b, &err);
    CHECK(rc == ESF_ENUMERIC && strstr(err.msg, "particle 19") != NULL,
          "infinite position, brute force: status %d, %s", rc, err.msg);
    x[3 * 19 + 2] = 0.5;
    rc = esf_cells_tune(cells, (esf_cells_mode)7, 2.0, &err);
    CHECK(rc == ESF_EINPUT, "tuning: unknown mode: status %d", rc);
    rc = esf_cells_tune(cells, ESF_CELLS_CLASSES, 1.0, &err);
    CHECK(rc == ESF_EINPUT, "tuning: factor 1: status %d", rc);
    rc = esf_cells_pairs(cells, 20, x, r, NAN, &b, &err);
    CHECK(rc == ESF_EINPUT, "non-finite skin: status %d", rc);
    r[3] = -1;
    rc = esf_cells_pairs(cells, 20, x, r, 0.01, &b, &err);
    CHECK(rc == ESF_EINPUT, "negative radius: status %d", rc);
    esf_pairbuf_release(&b);
  }

  /* the pair buffer grows geometrically and keeps what it holds */
  {
    esf_pairbuf b = {0};
    int ok = 1;
    for (uint32_t k = 0; k < 100000 && ok; k++)
      ok = esf_pairbuf_push(&b, k, k + 1, &err) == 0;
    CHECK(ok && b.n == 100000 && b.cap >= b.n && b.cap < 4 * b.n, "push: n %zu cap %zu",
          b.n, b.cap);
    CHECK(b.i[99999] == 99999 && b.j[0] == 1, "push keeps the pairs");
    esf_pairbuf_release(&b);
  }

  esf_cells_free(&cells);
  CHECK(cells == NULL, "free sets NULL");
  esf_cells_free(&cells); /* freeing NULL is a no-op */
  free(x);
  free(r);
  return check_finish("test_cells");
}
