/* timestep.c — the critical time step rules (docs/physics.md#time-step).
 *
 * m_min the smallest particle mass, k_max the largest stiffness (k_n or k_t) of any
 * material pair the scene can bring into contact (adhesive: the largest tangent
 * stiffness of its bonded law, contact_adhesive.c; Hertz-Mindlin: max(2 E*, 8 G*)
 * sqrt(R* u_p) at the peak overlap u_p = (15 m* v^2/(16 E* sqrt(R*)))^(2/5) of an impact
 * at v = integrator.impact_speed of two particles of the smallest mass, m* = m/2,
 * R* = r/2, or of one on a wall, m* = m, R* = r), FRAC = 1:
 *   cundall (000 3-27): sqrt(m_min / k_max) (the seed's 0.1 is FRAC);
 *   hart (004 2.48): 2 sqrt(m_min / (2 k_max));
 *   damped (001 3.64, 3.66): 2 sqrt(m_min / k_max) (sqrt(1 + xi^2) - xi), xi the largest
 *     contact damping ratio gamma (or beta omega/2 with Rayleigh damping) plus the
 *     global damping's alpha/(2 omega), omega = sqrt(k_max / m_min);
 *   rayleigh (Hertz only): the smallest pi r sqrt(rho/G)/(0.1631 nu + 0.8766);
 *   collision: the Hertz contact time 2.868 (m*^2/(R* E*^2 v))^(1/5) of those impacts
 *     (Johnson 1985 §11.4), for the linear law pi sqrt(m_min / (2 k_max)).
 * The adopted step is FRAC x dt_c of the chosen rule (001 3.65). */
#include <math.h>

#include "contact/contact_law.h"
#include "core/sim.h"

const char *const esf_dt_rule_names[] = {"cundall",  "hart",      "damped",
                                         "rayleigh", "collision", NULL};

/* A Hertz impact of reduced mass ms, radius rs at speed v for the pair pp: raises *k to
 * the tangent stiffness at its peak overlap, lowers *tc to its contact time. */
static void hertz_impact(const esf_pair_params *pp, double ms, double rs, double v,
                         double *k, double *tc) {
  const double es = pp->estar;
  const double up = pow(15.0 * ms * v * v / (16.0 * es * sqrt(rs)), 0.4);
  *k = fmax(*k, fmax(2.0 * es, 8.0 * pp->gstar) * sqrt(rs * up));
  *tc = fmin(*tc, 2.868 * pow(ms * ms / (rs * es * es * v), 0.2));
}
const char *const esf_stab_names[] = {"auto", "stop", "warn", "off", NULL};

void esf_dt_estimate_compute(const esf_sim *s, esf_dt_estimate *e) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  double m_min = INFINITY, r_m = 0.0, t_ray = INFINITY;
  for (size_t i = 0; i < p->n; i++)
    if (p->mass[i] < m_min) m_min = p->mass[i], r_m = p->radius[i];
  if (mt->all_hertz) /* the Rayleigh time of each particle, at its material */
    for (size_t i = 0; i < p->n; i++) {
      const esf_material *M = &mt->m[p->material[i]];
      const double G = M->youngs_modulus / (2.0 * (1.0 + M->poisson_ratio));
      const double rho = M->density;
      t_ray = fmin(t_ray, ESF_PI * p->radius[i] * sqrt(rho / G) /
                              (0.1631 * M->poisson_ratio + 0.8766));
    }
  double t_col = INFINITY;
  /* which materials are present on particles and on walls */
  unsigned char used_p[256] = {0}, used_w[256] = {0};
  int many = mt->n > 256;
  for (size_t i = 0; i < p->n && !many; i++) used_p[p->material[i]] = 1;
  for (size_t k = 0; k < s->walls.n && !many; k++) used_w[s->walls.e[k].material] = 1;
  double k_max = 0.0, g_max = 0.0;
  for (int a = 0; a < mt->n; a++) {
    if (!many && !used_p[a]) continue;
    for (int b = 0; b < mt->n; b++) {
      if (!many && !used_p[b] && !used_w[b]) continue;
      const esf_pair_params *pp = &mt->pair[a * mt->n + b];
      /* the adhesive law's largest tangent stiffness (contact_adhesive.c) */
      double kn = pp->law->flags & ESF_LAW_TENSION ? pp->adh.k_max : pp->kn;
      k_max = fmax(k_max, fmax(kn, pp->kt));
      if (pp->law == &esf_contact_hertz && m_min < INFINITY) {
        const double v = s->cfg.impact_speed;
        if (many || used_p[b])
          hertz_impact(pp, 0.5 * m_min, 0.5 * r_m, v, &k_max, &t_col);
        if (many || used_w[b]) hertz_impact(pp, m_min, r_m, v, &k_max, &t_col);
      }
      g_max = fmax(g_max, fmax(pp->gamma_n, pp->gamma_t));
    }
  }
  e->m_min = m_min;
  e->k_max = k_max;
  double omega = (k_max > 0 && m_min < INFINITY) ? sqrt(k_max / m_min) : 0.0;
  double xi = g_max;
  if (s->beta > 0) xi = fmax(xi, 0.5 * s->beta * omega);
  if (omega > 0) xi += fmax(s->cfg.alpha_r, s->cfg.alpha_t) / (2.0 * omega);
  e->xi = xi;
  if (!(omega > 0)) {
    for (int r = 0; r < ESF_DT_RULES; r++) e->crit[r] = INFINITY;
    return;
  }
  e->crit[ESF_DT_CUNDALL] = sqrt(m_min / k_max);
  e->crit[ESF_DT_HART] = 2.0 * sqrt(m_min / (2.0 * k_max));
  e->crit[ESF_DT_DAMPED] = 2.0 * sqrt(m_min / k_max) * (sqrt(1.0 + xi * xi) - xi);
  e->crit[ESF_DT_RAYLEIGH] = t_ray;
  e->crit[ESF_DT_COLLISION] =
      mt->all_hertz ? t_col : ESF_PI * sqrt(m_min / (2.0 * k_max));
}
