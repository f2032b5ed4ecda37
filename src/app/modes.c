/* modes.c — assembled contact stiffness and its highest frequency (see modes.h).
 *
 * Per touching contact between A and B (or A and a fixed wall), with unit normal n from
 * A toward B and lever arms lA, lB to the contact point (forces.c), the contact point
 * moves by dc = dxB + lB [n]x dthB - dxA + lA [n]x dthA ([n]x the cross-product matrix;
 * for a wall only A's terms), and the springs resist it with S = kn n n^T + kt (I - n
 * n^T) (the linear law's normal and sticking tangential stiffness; geometric stiffness
 * from the turning normal is neglected, as in every critical-step rule of the seeds).
 * With G the 3 x 12 map q = [dxA, dthA, dxB, dthB] -> dc, the contact adds G^T S G to K.
 * omega_max^2 is the largest eigenvalue of D K D, D = M^{-1/2} (mass for translations,
 * moment of inertia for rotations); GSL's symmetric eigensolver (gsl_eigen_symm).
 * In 2D only x, z and the rotation about y are degrees of freedom.
 * Damped bounds dt = (2/omega_max)(sqrt(1 + xi^2) - xi), the central-difference limit
 * of a damped mode: with xi the largest contact damping ratio (dt_damped), and with the
 * top mode's own ratio xi_mode = phi^T (D C D) phi / (2 omega_max), C the dashpots
 * assembled like K (dt_mode; a tangential mode on a wall is damped sqrt(3.5) times the
 * contact's ratio, so dt_damped is unsafe there: studies/results/critical_dt).
 * Units: SI. Entry: a set-up sim (the candidate lists are built here if needed); the
 * state is not changed, the force accumulators and contact flags are. */
#include "app/modes.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdlib.h>

#include "model/forces.h"
#include "model/model.h"
#include "model/stability.h"
#include "util/vec3.h"

/* global dof index of particle i's local dof j (0-2 translation, 3-5 rotation), or -1 */
static long dof_index(int dim, size_t i, int j) {
  if (dim == 3) return (long)(6 * i + (size_t)j);
  static const int map2[6] = {0, -1, 1, -1, 2, -1}; /* x, z, rotation about y */
  return map2[j] < 0 ? -1 : (long)(3 * i + (size_t)map2[j]);
}

/* Adds G^T S G for one contact to M (stability.c's esf_stab_contact_apply on the 12
 * local unit vectors: the one source of a contact's stiffness), with the springs
 * (which = 0) or the dashpots (which = 2) of contact c. */
static void add_contact(gsl_matrix *M, int dim, const esf_stab_contact *c, int which) {
  const int pair = c->b >= 0, nloc = pair ? 12 : 6;
  long idx[12];
  for (int j = 0; j < 6; j++) {
    idx[j] = dof_index(dim, c->a, j);
    idx[6 + j] = pair ? dof_index(dim, (size_t)c->b, j) : -1;
  }
  for (int q = 0; q < nloc; q++) {
    if (idx[q] < 0) continue;
    double x[12] = {0}, y[12] = {0};
    x[q] = 1.0;
    esf_stab_contact_apply(c->n, c->slip ? c->t : NULL, c->la, c->lb, c->kc[which],
                           c->kc[which + 1], x, pair ? x + 6 : NULL, y,
                           pair ? y + 6 : NULL);
    if (c->roll) /* the rolling resistance's springs or dashpots */
      esf_stab_roll_apply(c->n, c->kr[which], c->kr[which + 1], x, pair ? x + 6 : NULL, y,
                          pair ? y + 6 : NULL);
    for (int p = 0; p < nloc; p++)
      if (idx[p] >= 0) *gsl_matrix_ptr(M, (size_t)idx[p], (size_t)idx[q]) += y[p];
  }
}

/* The network (esf_stab_contacts) into K and C: C's top-mode quadratic form gives that
 * mode's damping ratio; xi_max the contacts' largest normal ratio cn / (2 sqrt(kn m*)).
 */
typedef struct assembly {
  gsl_matrix *K, *C;
  const esf_sim *s;
  double xi_max;
} assembly;

static void add_one(const esf_stab_contact *c, void *ctx) {
  assembly *A = ctx;
  const esf_particles *p = &A->s->p;
  add_contact(A->K, A->s->cfg.dim, c, 0);
  add_contact(A->C, A->s->cfg.dim, c, 2);
  double ms = c->b >= 0 ? p->mass[c->a] * p->mass[c->b] / (p->mass[c->a] + p->mass[c->b])
                        : p->mass[c->a];
  if (c->kc[0] > 0) A->xi_max = fmax(A->xi_max, c->kc[2] / (2 * sqrt(c->kc[0] * ms)));
}

int esf_modes_compute(esf_sim *s, esf_modes *out, esf_error *err) {
  const esf_particles *p = &s->p;
  int dim = s->cfg.dim;
  size_t per = dim == 3 ? 6 : 3, nd = per * p->n;
  *out = (esf_modes){0};
  out->dofs = nd;
  if (nd > ESF_MODES_MAX_DOFS)
    return esf_fail(err, ESF_EINPUT,
                    "modes: %zu degrees of freedom; the dense eigenproblem is limited to "
                    "%d (use at most %d particles)",
                    nd, ESF_MODES_MAX_DOFS, ESF_MODES_MAX_DOFS / (int)per);
  size_t touching = 0;
  int rc = esf_sim_refresh(s, NULL, err);
  if (!rc)
    rc = esf_forces_eval(s, p->x, p->v, p->w, 0.0, ESF_FORCES_COMMIT, &touching, err);
  if (rc) return rc;
  gsl_matrix *K = gsl_matrix_calloc(nd ? nd : 1, nd ? nd : 1);
  gsl_matrix *C = gsl_matrix_calloc(nd ? nd : 1, nd ? nd : 1);
  if (!K || !C) {
    gsl_matrix_free(K);
    gsl_matrix_free(C);
    return esf_fail(err, ESF_ENOMEM, "modes: out of memory for %zu dofs", nd);
  }
  assembly A = {.K = K, .C = C, .s = s};
  out->contacts = esf_stab_contacts(s, add_one, &A);
  out->xi_max = A.xi_max;
  /* D K D with D = M^{-1/2} */
  double *dscale = malloc((nd ? nd : 1) * sizeof *dscale);
  gsl_vector *eval = gsl_vector_alloc(nd ? nd : 1);
  gsl_eigen_symmv_workspace *ws = nd ? gsl_eigen_symmv_alloc(nd) : NULL;
  gsl_matrix *evec = gsl_matrix_alloc(nd ? nd : 1, nd ? nd : 1);
  if (!dscale || !eval || !evec || (nd && !ws)) {
    rc = esf_fail(err, ESF_ENOMEM, "modes: out of memory for %zu dofs", nd);
    goto done;
  }
  for (size_t i = 0; i < p->n; i++)
    for (int j = 0; j < 6; j++) {
      long g = dof_index(dim, i, j);
      if (g >= 0) dscale[g] = j < 3 ? sqrt(p->inv_mass[i]) : sqrt(p->inv_inertia[i]);
    }
  for (size_t r = 0; r < nd; r++)
    for (size_t q = 0; q < nd; q++) {
      *gsl_matrix_ptr(K, r, q) *= dscale[r] * dscale[q];
      *gsl_matrix_ptr(C, r, q) *= dscale[r] * dscale[q];
    }
  if (nd && out->contacts) {
    /* dt^2 A + 2 dt B at the scene's dt, dense, for the live check's Lanczos */
    double dt = s->dt, fl = s->local ? 1.0 + s->cfg.local_coef : 1.0;
    gsl_matrix *L = gsl_matrix_alloc(nd, nd);
    if (!L) {
      rc = esf_fail(err, ESF_ENOMEM, "modes: out of memory for %zu dofs", nd);
      goto done;
    }
    for (size_t r = 0; r < nd; r++)
      for (size_t q = 0; q < nd; q++)
        gsl_matrix_set(
            L, r, q,
            fl * (dt * dt * gsl_matrix_get(K, r, q) + 2 * dt * gsl_matrix_get(C, r, q)));
    gsl_eigen_symm_workspace *w1 = gsl_eigen_symm_alloc(nd); /* values only */
    if (w1) gsl_eigen_symm(L, eval, w1);
    out->lambda = w1 ? gsl_vector_max(eval) : NAN;
    if (w1) gsl_eigen_symm_free(w1);
    gsl_matrix_free(L);
    gsl_eigen_symmv(K, eval, evec, ws);
    size_t imax = gsl_vector_max_index(eval);
    double lam = gsl_vector_get(eval, imax);
    out->omega_max = lam > 0 ? sqrt(lam) : 0.0;
    double best = -1, cq = 0;
    for (size_t r = 0; r < nd; r++) {
      double v = fabs(gsl_matrix_get(evec, r, imax));
      if (v > best) best = v, out->argmax_dof = r;
      double row = 0;
      for (size_t q = 0; q < nd; q++)
        row += gsl_matrix_get(C, r, q) * gsl_matrix_get(evec, q, imax);
      cq += gsl_matrix_get(evec, r, imax) * row;
    }
    /* the top mode's own damping ratio phi^T (D C D) phi / (2 omega), phi unit */
    if (out->omega_max > 0) out->xi_mode = cq / (2 * out->omega_max);
  }
  if (out->omega_max > 0) {
    out->dt_undamped = 2.0 / out->omega_max;
    double x = out->xi_max;
    out->dt_damped = out->dt_undamped * (sqrt(1 + x * x) - x);
    x = out->xi_mode;
    out->dt_mode = out->dt_undamped * (sqrt(1 + x * x) - x);
  }
  if (!rc) {
    esf_stability st;
    rc = esf_stability_estimate(s, s->dt, 0, &st, err);
    out->lambda_live = st.lambda;
    if (!rc) rc = esf_stability_limit(s, &out->dt_live, &st, err);
  }
done:
  if (ws) gsl_eigen_symmv_free(ws);
  gsl_matrix_free(evec);
  gsl_vector_free(eval);
  free(dscale);
  gsl_matrix_free(K);
  gsl_matrix_free(C);
  return rc;
}
