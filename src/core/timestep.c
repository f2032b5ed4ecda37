/* timestep.c — the critical time step rules of the seeds (docs/physics.md#time-step).
 *
 * With m_min the smallest particle mass, k_max the largest stiffness (k_n or k_t) of any
 * material pair the scene can bring into contact (for an adhesive pair, the largest
 * tangent stiffness |df/du| of its bonded law over the bonded range, k_n max(1,
 * |1 - L e^{-alpha u_r}|), contact_adhesive.c), and FRAC = 1:
 *   cundall (000 3-27):          dt_c = sqrt(m_min / k_max)       (the seed's 0.1 is
 * FRAC) hart    (004 2.48):          dt_c = 2 sqrt(m_min / (2 k_max)) damped
 * (001 3.64, 3.66):    dt_c = 2 sqrt(m_min / k_max) (sqrt(1 + xi^2) - xi) where xi is the
 * largest damping ratio: the contact dashpots' gamma (Tsuji: gamma is the damping ratio
 * of the reduced-mass oscillator) or, with Rayleigh damping, beta omega/2, plus the
 * global damping's alpha/(2 omega), omega = sqrt(k_max / m_min). The adopted step is FRAC
 * x dt_c of the chosen rule (001 3.65). */
#include <math.h>

#include "core/sim.h"

const char *const esf_dt_rule_names[] = {"cundall", "hart", "damped", NULL};
const char *const esf_stab_names[] = {"auto", "stop", "warn", "off", NULL};

void esf_dt_estimate_compute(const esf_sim *s, esf_dt_estimate *e) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  double m_min = INFINITY;
  for (size_t i = 0; i < p->n; i++)
    if (p->mass[i] < m_min) m_min = p->mass[i];
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
}
