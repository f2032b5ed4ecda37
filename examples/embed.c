/* embed.c — a program that embeds esfera through its public API (esfera.h): loads a
 * scene, runs it to its end with the scene's own integrator, reads the state and the
 * energy ledger, then opens the scene again as an ODE and evaluates the right-hand side
 * at its initial state. Build against an installed esfera with pkg-config alone:
 *
 *   cc embed.c $(pkg-config --cflags --libs esfera) -o embed
 *   ./embed scenes/head_on.yaml [KEY=VALUE]...
 *
 * For scenes/head_on.yaml it prints the restitution of the two spheres' collision
 * (relative speed after / before) next to the no-tension closed form, 0.550283: the
 * leapfrog at the scene's step (a tenth of the Hart step) gives 0.5612, at
 * integrator.frac=0.01 0.5482 (examples/scipy_head_on.py meets it to 1e-7). */
#include <esfera.h>
#include <stdio.h>
#include <stdlib.h>

/* Prints the message of a failed call and closes the handle; returns exit status 1. */
static int fail(esf_handle **h, const char *what) {
  fprintf(stderr, "embed: %s: %s\n", what, esf_handle_message(*h));
  esf_handle_close(h);
  return 1;
}

int main(int argc, char **argv) {
  const char *scene = argc > 1 ? argv[1] : "scenes/head_on.yaml";
  const char *const *sets = (const char *const *)(argv + 2);
  int nsets = argc > 2 ? argc - 2 : 0;
  printf("esfera %s (API %d)\n", esf_version(), esf_api_version());

  /* 1. Run the scene with its integrator. */
  esf_handle *h = NULL;
  if (esf_handle_open(&h, scene, sets, nsets)) return fail(&h, "open");
  size_t n = esf_handle_count(h), len = 0;
  const double *v = esf_handle_array(h, ESF_ARRAY_VELOCITY, &len);
  double rel0 =
      n >= 2 ? v[3] - v[0] : 0.0; /* x-velocity of the 2nd relative to the 1st */
  double dt = esf_handle_dt(h), t_end = esf_handle_end_time(h);
  long steps = (long)(t_end / dt); /* whole steps to the end time */
  if ((double)steps * dt < t_end * (1 - 1e-12)) steps++;
  if (esf_handle_step(h, steps)) return fail(&h, "step");
  printf("%s: %zu particles, %ld steps of %s to t = %.6g s\n", scene, n,
         esf_handle_steps(h), esf_handle_method(h), esf_handle_time(h));
  const double *x = esf_handle_array(h, ESF_ARRAY_POSITION, &len);
  v = esf_handle_array(h, ESF_ARRAY_VELOCITY, &len);
  const int64_t *id = esf_handle_ids(h);
  for (size_t i = 0; i < n && i < 4; i++)
    printf("  particle %lld: x = (%.6g, %.6g, %.6g) m, v = (%.6g, %.6g, %.6g) m/s\n",
           (long long)id[i], x[3 * i], x[3 * i + 1], x[3 * i + 2], v[3 * i], v[3 * i + 1],
           v[3 * i + 2]);
  double row[ESF_ENERGY_COLUMNS];
  if (esf_handle_energies(h, row) == ESF_OK)
    printf("  ledger at t = %.6g s: kinetic %.6g J, %s %.6g J, %s %.3g J\n", row[0],
           row[1] + row[2], esf_energy_column(5), row[5], esf_energy_column(9), row[9]);
  if (n == 2 && rel0 != 0.0)
    printf("restitution %.6f (closed form, no tension: 0.550283)\n",
           -(v[3] - v[0]) / rel0);
  esf_handle_close(&h);

  /* 2. The same scene as an ODE y' = f(t, y): the accelerations at the start. */
  if (esf_handle_open(&h, scene, sets, nsets)) return fail(&h, "open");
  size_t m = esf_handle_ode_size(h);
  if (m == 0) return fail(&h, "ode_size");
  double *y = malloc(m * sizeof *y), *dy = malloc(m * sizeof *dy);
  if (!y || !dy) return fprintf(stderr, "embed: out of memory\n"), 1;
  if (esf_handle_y0(h, y) || esf_handle_rhs(h, esf_handle_time(h), y, dy)) {
    free(y);
    free(dy);
    return fail(&h, "rhs");
  }
  printf("ODE view: %zu entries; particle 0: a = (%.6g, %.6g, %.6g) m/s^2\n", m,
         dy[3 * n], dy[3 * n + 1], dy[3 * n + 2]);
  free(y);
  free(dy);
  esf_handle_close(&h);
  return 0;
}
