/* test_api.c — the public C API (esfera.h) as a user's program sees it: this test
 * includes esfera.h alone and links the shared library, whose exports are that API.
 * Checks: versions; errors located (file:line:column) with their codes, a failed
 * handle refusing calls; the ODE view of scenes/head_on.yaml: y0's layout against the
 * state arrays, rhs against the linear spring-dashpot's force kn u + cn du/dt (mixing of
 * equal materials gives each its own k; cn = 2 gamma sqrt(m* kn), gamma = -ln e /
 * sqrt(pi^2 + ln^2 e), docs/physics.md) and against the library's own force array, a
 * recoverable rhs failure, commit (time, steps, order); step with the leapfrog (k
 * steps of dt), the ledger closing, the two uses refusing each other; independent
 * handles. Argument: the source root. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "esfera.h"

static const double PI = 3.14159265358979323846;

static int located(const char *msg, const char *file) {
  const char *p = strstr(msg, file);
  int line = 0, col = 0;
  return p && sscanf(p + strlen(file), ":%d:%d:", &line, &col) == 2 && line > 0 &&
         col > 0;
}

static void errors(const char *head_on) {
  /* a scene with a misspelt key, in a file of its own */
  char path[] = "/tmp/esf_api_XXXXXX";
  int fd = mkstemp(path);
  CHECK(fd >= 0, "mkstemp");
  FILE *f = fdopen(fd, "w");
  fputs("name: bad\nmaterials:\n  glass: {densty: 2500, kn: 1.0e5}\n", f);
  fclose(f);
  esf_handle *h = NULL;
  int rc = esf_handle_open(&h, path, NULL, 0);
  CHECK(rc == ESF_EINPUT && h != NULL, "bad scene: status %d", rc);
  CHECK(located(esf_handle_message(h), path) && strstr(esf_handle_message(h), "densty"),
        "located message: %s", esf_handle_message(h));
  CHECK(esf_handle_status(h) == ESF_EINPUT, "status kept");
  CHECK(esf_handle_step(h, 1) == ESF_EINPUT && esf_handle_ode_size(h) == 0,
        "a failed handle refuses calls");
  size_t len = 1;
  CHECK(esf_handle_array(h, ESF_ARRAY_POSITION, &len) == NULL && len == 0, "no arrays");
  esf_handle_close(&h);
  CHECK(h == NULL, "close sets NULL");
  esf_handle_close(&h); /* again: a no-op */
  esf_handle_close(NULL);
  unlink(path);

  rc = esf_handle_open(&h, "/nonexistent/scene.yaml", NULL, 0);
  CHECK(rc < 0 && strstr(esf_handle_message(h), "/nonexistent/scene.yaml"),
        "missing file: %d %s", rc, esf_handle_message(h));
  esf_handle_close(&h);

  const char *bad[] = {"integrator.method=euler"};
  rc = esf_handle_open(&h, head_on, bad, 1);
  CHECK(rc == ESF_EINPUT && strstr(esf_handle_message(h), "unknown method 'euler'"),
        "unknown method: %s", esf_handle_message(h));
  esf_handle_close(&h);

  const char *off[] = {"output.energy_every=0"};
  rc = esf_handle_open(&h, head_on, off, 1);
  CHECK(rc == ESF_OK, "ledger off opens: %s", esf_handle_message(h));
  CHECK(esf_handle_step(h, 1) == ESF_OK, "steps");
  double row[ESF_ENERGY_COLUMNS];
  CHECK(esf_handle_energies(h, row) == ESF_EINPUT &&
            strstr(esf_handle_message(h), "output.energy_every"),
        "ledger off: %s", esf_handle_message(h));
  CHECK(esf_handle_step(h, 1) == ESF_OK, "not failed by a refused call");
  esf_handle_close(&h);
}

static void ode_view(const char *head_on) {
  esf_handle *h = NULL;
  int rc = esf_handle_open(&h, head_on, NULL, 0);
  CHECK(rc == ESF_OK, "open: %s", esf_handle_message(h));
  double row[ESF_ENERGY_COLUMNS];
  CHECK(esf_handle_energies(h, row) == ESF_EINPUT, "no ledger before the first call");
  size_t n = esf_handle_count(h), m = esf_handle_ode_size(h), nall = 0;
  while (esf_ode_quadrature((int)nall)) nall++;
  const size_t nq = esf_handle_ode_nq(h);
  CHECK(nall >= 9 && !strcmp(esf_ode_quadrature(7), "work_tangential_stiffness") &&
            !strcmp(esf_ode_quadrature(8), "dissipated_rolling"),
        "%zu quadratures named", nall);
  CHECK(nq == 8, "without rolling resistance: %zu quadratures in y", nq);
  CHECK(n == 2 && m == 9 * n + nq, "layout n %zu m %zu", n, m);
  { /* with rolling friction: the rolling quadrature too */
    const char *roll[] = {"materials.glass.rolling_friction=0.1"};
    esf_handle *hr = NULL;
    CHECK(esf_handle_open(&hr, head_on, roll, 1) == ESF_OK, "rolling: %s",
          esf_handle_message(hr));
    CHECK(esf_handle_ode_nq(hr) == 9 && esf_handle_ode_size(hr) == 9 * n + 9,
          "rolling: nq %zu, y of %zu", esf_handle_ode_nq(hr), esf_handle_ode_size(hr));
    esf_handle_close(&hr);
  }
  double *y = calloc(m, sizeof *y), *dy = calloc(m, sizeof *dy);
  CHECK(esf_handle_y0(h, y) == ESF_OK, "y0");
  size_t len = 0;
  const double *x = esf_handle_array(h, ESF_ARRAY_POSITION, &len);
  const double *v = esf_handle_array(h, ESF_ARRAY_VELOCITY, &len);
  CHECK(len == 3 * n && memcmp(x, y, 3 * n * sizeof *y) == 0 &&
            memcmp(v, y + 3 * n, 3 * n * sizeof *y) == 0,
        "y0 holds x, v");
  const double *mass = esf_handle_array(h, ESF_ARRAY_MASS, &len);
  double r = 0.005, m1 = 2500 * 4.0 / 3.0 * PI * r * r * r, kn = 1e5;
  CHECK(len == n && fabs(mass[0] / m1 - 1) < 1e-14, "mass %.17g %.17g", mass[0], m1);

  /* overlap u = 2 mm, approaching at 0.2 m/s */
  y[0] = -0.004, y[3] = 0.004, y[3 * n] = 0.1, y[3 * n + 3] = -0.1;
  CHECK(esf_handle_rhs(h, 0.0, y, dy) == ESF_OK, "rhs: %s", esf_handle_message(h));
  double le = log(0.5), gam = -le / sqrt(PI * PI + le * le);
  double cn = 2 * gam * sqrt(m1 / 2 * kn), fx = kn * 0.002 + cn * 0.2;
  CHECK_NEAR(dy[3 * n] * m1, -fx, 1e-12 * fx, "rhs: force on sphere 1");
  CHECK_NEAR(dy[3 * n + 3] * m1, fx, 1e-12 * fx, "rhs: force on sphere 2");
  CHECK(dy[0] == 0.1 && dy[3] == -0.1, "dx/dt = v");
  CHECK(dy[9 * n] > 0 && fabs(dy[9 * n] / (cn * 0.04) - 1) < 1e-12,
        "dashpot power %.10g, expected cn du^2 %.10g", dy[9 * n], cn * 0.04);
  const double *f = esf_handle_array(h, ESF_ARRAY_FORCE, &len);
  CHECK(f[0] == dy[3 * n] * mass[0] || fabs(f[0] / (dy[3 * n] * mass[0]) - 1) < 1e-15,
        "rhs = the library's force / m: %.17g %.17g", f[0], dy[3 * n] * mass[0]);

  /* a failure inside f (overlap beyond the limit) is recoverable */
  double *bad = malloc(m * sizeof *bad);
  memcpy(bad, y, m * sizeof *y);
  bad[0] = -0.001, bad[3] = 0.001;
  rc = esf_handle_rhs(h, 0.0, bad, dy);
  CHECK(rc == ESF_ENUMERIC && strstr(esf_handle_message(h), "overlap"), "overlap: %d %s",
        rc, esf_handle_message(h));
  CHECK(esf_handle_rhs(h, 0.0, y, dy) == ESF_OK, "rhs again after a failure");
  free(bad);

  /* commits: time, steps, order */
  CHECK(esf_handle_y0(h, y) == ESF_OK, "y0");
  CHECK(esf_handle_commit(h, 1e-6, y) == ESF_OK, "commit: %s", esf_handle_message(h));
  CHECK(esf_handle_time(h) == 1e-6 && esf_handle_steps(h) == 1, "commit advances");
  CHECK(esf_handle_commit(h, 0.5e-6, y) == ESF_EINPUT, "commit back in time refused");
  CHECK(esf_handle_energies(h, row) == ESF_OK && row[0] == 1e-6, "ledger at the commit");
  CHECK(esf_handle_step(h, 1) == ESF_EINPUT && strstr(esf_handle_message(h), "another"),
        "step refused on an ODE handle: %s", esf_handle_message(h));
  free(y);
  free(dy);
  esf_handle_close(&h);
}

static void stepping(const char *head_on) {
  esf_handle *a = NULL, *b = NULL;
  CHECK(esf_handle_open(&a, head_on, NULL, 0) == ESF_OK, "open a");
  const char *sets[] = {"integrator.frac=0.05"};
  CHECK(esf_handle_open(&b, head_on, sets, 1) == ESF_OK, "open b");
  CHECK(esf_handle_set_threads(a, 1) == ESF_OK &&
            esf_handle_set_threads(b, 0) == ESF_EINPUT,
        "threads");
  CHECK(fabs(esf_handle_dt(b) / esf_handle_dt(a) - 0.5) < 1e-12, "override: dt halved");
  CHECK(strcmp(esf_handle_method(a), "leapfrog") == 0 && esf_handle_dim(a) == 3,
        "method, dim");
  long k = (long)ceil(esf_handle_end_time(a) / esf_handle_dt(a) - 1e-9);
  CHECK(esf_handle_step(a, k) == ESF_OK, "step: %s", esf_handle_message(a));
  CHECK(esf_handle_steps(a) == k &&
            fabs(esf_handle_time(a) - k * esf_handle_dt(a)) < 1e-15,
        "k steps of dt: %ld %.17g", esf_handle_steps(a), esf_handle_time(a));
  CHECK(esf_handle_steps(b) == 0 && esf_handle_time(b) == 0, "b untouched");
  CHECK(esf_handle_set_threads(a, 2) == ESF_EINPUT, "threads fixed once started");
  double row[ESF_ENERGY_COLUMNS];
  CHECK(esf_handle_energies(a, row) == ESF_OK, "energies");
  CHECK(strcmp(esf_energy_column(9), "total_error") == 0 && !esf_energy_column(-1) &&
            !esf_energy_column(ESF_ENERGY_COLUMNS),
        "column names");
  CHECK(row[5] > 1e-4 && fabs(row[9]) < 1e-2 * row[5],
        "ledger closes: error %.3g of %.3g", row[9], row[5]);
  size_t len = 0;
  const double *v = esf_handle_array(a, ESF_ARRAY_VELOCITY, &len);
  double e = (v[3] - v[0]) / 2.0; /* relative speed after / before (2 m/s) */
  CHECK(e > 0.5 && e < 0.6, "the spheres rebound: %.6f", e);
  CHECK(esf_handle_y0(a, (double[32]){0}) == ESF_EINPUT, "ODE refused on a stepping one");
  esf_handle_close(&a);
  esf_handle_close(&b);
}

int main(int argc, char **argv) {
  char head_on[4096];
  snprintf(head_on, sizeof head_on, "%s/scenes/head_on.yaml", argc > 1 ? argv[1] : ".");
  CHECK(strcmp(esf_version(), "") != 0 && esf_api_version() == ESF_API_VERSION,
        "versions");
  errors(head_on);
  ode_view(head_on);
  stepping(head_on);
  return check_finish("api");
}
