/* setup.c — setting up and tearing down a simulation (model.h).
 *
 * esf_sim_setup, on entry: cfg, particles (positions, velocities, radii, materials,
 * ids), materials and walls filled in by the scene reader (or a test). On exit: masses
 * and inertias set (spheres m = 4/3 pi r^3 rho, I = 2/5 m r^2, 000 3-4..3-5; disks
 * m = pi r^2 rho thickness, I = 1/2 m r^2), the pair table mixed, Rayleigh factors set
 * (001 3.59–3.60: omega = 2 pi f, alpha = 2 omega zeta, beta = 2 zeta / omega), the
 * step chosen (auto: FRAC x the rule's critical step) or checked against the rule, and
 * the candidate lists allocated (built on the first step). */
#include "model/model.h"

#include <math.h>
#include <stdlib.h>

#include "core/bonds.h"
#include "loads/drag.h"
#include "loads/events.h"
#include "loads/insert.h"
#include "loads/servo.h"
#include "par/par.h"
#include "util/threads.h"
#include "util/vec3.h"

static int set_masses(esf_sim *s, esf_error *err) {
  esf_particles *p = &s->p;
  for (size_t i = 0; i < p->n; i++) {
    const esf_material *m = &s->mats.m[p->material[i]];
    double r = p->radius[i];
    if (!(m->density > 0))
      return esf_fail(err, ESF_EINPUT,
                      "%s: material '%s' of particle id %lld needs a positive density",
                      esf_config_where(&s->cfg, "materials"), m->name,
                      (long long)p->id[i]);
    esf_particle_mass(s->cfg.dim, r, m->density, s->cfg.disk_thickness, &p->mass[i],
                      &p->inertia[i]);
    if (s->cfg.dim == 2) {
      if (p->x[3 * i + 1] != 0.0 || p->v[3 * i + 1] != 0.0 || p->w[3 * i] != 0.0 ||
          p->w[3 * i + 2] != 0.0)
        return esf_fail(
            err, ESF_EINPUT,
            "%s: particle id %lld: a 2D scene moves disks in the x-z plane, so y, "
            "vy, wx and wz must be 0",
            esf_config_where(&s->cfg, "particles"), (long long)p->id[i]);
    }
    p->inv_mass[i] = 1.0 / p->mass[i];
    p->inv_inertia[i] = 1.0 / p->inertia[i];
  }
  return ESF_OK;
}

/* Periodic axes (search/periodic.h): the minimum-image condition L > 2 (2 r_max + skin)
 * checked (an adaptive skin kept below it), the image counters, the lists' box, and
 * the removal test unbounded on the periodic axes. */
static int periodic_setup(esf_sim *s, esf_error *err) {
  esf_config *c = &s->cfg;
  double rmax = 0;
  for (size_t i = 0; i < s->p.n; i++) rmax = fmax(rmax, s->p.radius[i]);
  const double half = esf_periodic_reach(&c->per), room = half - 2 * rmax;
  if (c->skin_auto && s->nb.skin_hi > 0.99 * room) s->nb.skin_hi = 0.99 * room;
  if (!(c->skin < room) || (c->skin_auto && !(s->nb.skin_hi > s->nb.skin_lo)))
    return esf_fail(err, ESF_EINPUT,
                    "%s: domain.periodic: each period must exceed twice the largest "
                    "diameter plus the skin, 2 x (%g + %g) m, but the shortest is %g m "
                    "(widen the domain or lower search.skin)",
                    esf_config_where(c, "domain"), 2 * rmax, c->skin, 2 * half);
  if (c->per.le && s->led.on)
    return esf_fail(err, ESF_EINPUT,
                    "%s: domain.shear: the energy ledger does not book the work of the "
                    "Lees-Edwards boundaries; set output.energy_every: 0",
                    esf_config_where(c, "domain"));
  if (s->bonds.on)
    return esf_fail(err, ESF_EINPUT,
                    "%s: domain.periodic: bonds are not supported "
                    "with periodic axes",
                    esf_config_where(c, "domain"));
  s->nb.per = &c->per;
  s->nb.dom_lo = c->keep_lo;
  s->nb.dom_hi = c->keep_hi;
  return esf_particles_images(&s->p, err);
}

int esf_sim_setup(esf_sim *s, esf_error *err) {
  esf_config *c = &s->cfg;
  c->threads_auto = c->threads <= 0;
  if (c->threads_auto) c->threads = esf_threads_available(); /* all the run may use */
  s->local = c->local_form == ESF_LOCAL_COMPONENT ? &esf_local_component
             : c->local_form == ESF_LOCAL_VECTOR  ? &esf_local_vector
                                                  : NULL;
  if (c->rayleigh) {
    double omega = 2.0 * ESF_PI * c->rayleigh_freq;
    c->alpha_r = c->alpha_t = 2.0 * omega * c->rayleigh_zeta;
    s->beta = 2.0 * c->rayleigh_zeta / omega;
    s->mats.rayleigh_beta = s->beta;
  }
  s->mats.rolling_model = c->rolling;
  s->mats.hertz_constant = c->hertz_damping == 1;
  s->mats.impact_speed = c->impact_speed;
  int rc = esf_materials_mix(&s->mats, err);
  if (!rc) rc = set_masses(s, err);
  if (!rc) rc = esf_walls_freeze(&s->walls, s->t, err); /* moving walls placed at t0 */
  if (rc) return rc;

  if (c->dim == 2 && s->mats.all_hertz) /* disks are cylinders: another contact law */
    return esf_fail(err, ESF_EINPUT,
                    "%s: the Hertz-Mindlin law (youngs_modulus) is the law of spheres; "
                    "2D disks (dimension: 2) need kn (the linear law)",
                    esf_config_where(c, "dimension"));
  if (c->dt_rule == ESF_DT_RAYLEIGH && !s->mats.all_hertz)
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.dt_rule: rayleigh needs the Hertz-Mindlin law "
                    "(materials with youngs_modulus and poisson_ratio); this scene's "
                    "materials give kn",
                    esf_config_where(c, "integrator.dt_rule"));
  if (s->insert) { /* the critical step with the particles it may insert too */
    esf_particles probes;
    rc = esf_inserts_probes(s, &probes, err);
    if (rc) return rc;
    esf_sim *tmp = malloc(sizeof *tmp);
    if (!tmp) {
      esf_particles_release(&probes);
      return esf_fail(err, ESF_ENOMEM, "out of memory");
    }
    *tmp = *s;
    tmp->p = probes;
    esf_dt_estimate_compute(tmp, &s->dte);
    free(tmp);
    esf_particles_release(&probes);
  } else {
    esf_dt_estimate_compute(s, &s->dte);
  }
  double crit = s->dte.crit[c->dt_rule];
  if (c->dt_auto) {
    if (!isfinite(crit))
      return esf_fail(err, ESF_EINPUT,
                      "%s: integrator.dt is auto but the scene has no particles or no "
                      "stiffness to take a critical step from; give dt in seconds",
                      esf_config_where(c, "integrator.dt"));
    s->dt = c->frac * crit;
    if (c->frac > 1 && !c->allow_unstable)
      return esf_fail(
          err, ESF_EINPUT,
          "%s: integrator.frac = %.4g is above 1: dt would be %.4g x the "
          "critical step of the '%s' rule, %.6g s, and the run unstable. Use "
          "frac <= 1 (seeds: 0.1), or set integrator.allow_unstable: true for "
          "stability studies",
          esf_config_where(c, "integrator.frac"), c->frac, c->frac,
          esf_dt_rule_names[c->dt_rule], crit);
  } else {
    s->dt = c->dt;
    if (s->dt > crit && !c->allow_unstable)
      return esf_fail(err, ESF_EINPUT,
                      "%s: integrator.dt = %.6g s is above the critical step of the "
                      "'%s' rule, %.6g s (m_min = %.4g kg, k_max = %.4g N/m): the run "
                      "would be unstable. Use dt: auto with frac <= 1 (seeds: 0.1), a "
                      "smaller dt, or set integrator.allow_unstable: true for stability "
                      "studies",
                      esf_config_where(c, "integrator.dt"), s->dt,
                      esf_dt_rule_names[c->dt_rule], crit, s->dte.m_min, s->dte.k_max);
  }
  if (!(s->dt > 0) || !isfinite(s->dt))
    return esf_fail(err, ESF_EINPUT,
                    "%s: %s: the time step must be a positive finite number of seconds, "
                    "got %g s%s",
                    esf_config_where(c, c->dt_auto ? "integrator.frac" : "integrator.dt"),
                    c->dt_auto ? "integrator.frac" : "integrator.dt", s->dt,
                    c->dt_auto ? " (frac x the critical step)" : "");

  if (c->stability == ESF_STAB_AUTO)
    c->stability = c->allow_unstable ? ESF_STAB_WARN : ESF_STAB_STOP;
  s->stab.dt_limit = INFINITY;

  double omega = s->dte.k_max > 0 ? sqrt(s->dte.k_max / s->dte.m_min) : 1.0;
  if (c->autod.alpha_min < 0) c->autod.alpha_min = 1e-4 * omega;
  if (c->autod.alpha_max < 0) c->autod.alpha_max = 1.0 / s->dt;
  s->alpha_r = c->alpha_r;
  s->alpha_t = c->alpha_t;
  if (c->autod.on) {
    if (s->alpha_r < c->autod.alpha_min) s->alpha_r = c->autod.alpha_min;
    if (s->alpha_t < c->autod.alpha_min) s->alpha_t = c->autod.alpha_min;
  }

  /* No skin given: the reference sref = 0.4 r_mean (neighbor.h). In a bonded scene the
     bond's reach may raise it, and it stays fixed (bonds.c). Otherwise the skin adapts
     (esf_neighbor_skin_tune) within 0.05-1 r_mean and starts low, at 0.1 r_mean: a
     skin too small costs a few early rebuilds (each at most doubles it), one too large
     a long first list with several times the idle candidates (a settled bed keeps
     0.06-0.08 r_mean, and its first list at 0.4 r_mean lasted about 1 000 steps). */
  int skin_auto = !(c->skin > 0);
  double sref = c->skin; /* m */
  if (skin_auto) {
    double rsum = 0;
    for (size_t i = 0; i < s->p.n; i++) rsum += s->p.radius[i];
    double rmean = s->p.n ? rsum / (double)s->p.n : 0.0;
    if (!s->p.n && s->insert) /* only inserted particles: their mean size */
      rmean = 0.5 * (s->insert->e[0].rmin + s->insert->e[0].rmax);
    c->skin = sref = rmean > 0 ? ESF_SKIN_DEFAULT * rmean : 1e-3;
  }
  rc = esf_bonds_setup(s, skin_auto, err);
  if (rc) return rc;
  c->skin_auto = skin_auto && !s->bonds.on; /* a bond's reach fixes the skin */
  if (c->skin_auto) c->skin = ESF_SKIN_START * sref;
  s->led.on = c->energy_every > 0;
  rc = esf_servo_setup(s, err);            /* servo walls (servo.c) */
  if (!rc) rc = esf_events_setup(s, err);  /* scene events (events.c) */
  if (!rc) rc = esf_inserts_setup(s, err); /* insertion (insert.c) */
  if (!rc) rc = esf_drag_setup(s, err);    /* fluid force (drag.c) */
  if (rc) return rc;
  rc = esf_neighbor_init(&s->nb, c->skin, s->led.on, err);
  if (rc) return rc;
  s->nb.bonds = s->bonds.on;           /* the lists keep bond states (bonds.c) */
  s->nb.rolling = s->mats.any_rolling; /* and rolling states (contact_rolling.h) */
  if (c->has_domain) {
    s->nb.dom_lo = c->domain_min;
    s->nb.dom_hi = c->domain_max;
  }
  if (c->skin_auto) esf_neighbor_skin_range(&s->nb, sref / 8.0, 2.5 * sref);
  return c->per.any ? periodic_setup(s, err) : ESF_OK;
}

void esf_sim_release(esf_sim *s) {
  esf_par_detach(s);
  esf_particles_release(&s->p);
  esf_materials_release(&s->mats);
  esf_walls_release(&s->walls);
  esf_neighbor_release(&s->nb);
  esf_events_free(&s->events);
  esf_inserts_free(&s->insert);
  esf_drag_free(&s->drag);
  free(s->led_rows);
  free(s->led_blocks);
  s->led_rows = s->led_blocks = NULL;
  s->led_cap = 0;
}
