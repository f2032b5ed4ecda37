/* wall_motion.c — prescribed rigid motions of wall groups
 * (docs/physics.md#walls-and-prescribed-motion: walls are never integrated; their
 * motion is a function of time, each term on its clock tau = clamp(t, start, stop) -
 * start when windowed, else tau = t; velocity zero outside [start, stop)).
 * translate: d = vel tau.  rotate: angle = rate tau about the axis through pivot, a
 *   reference point x0 at pivot + d + R(angle)(x0 - pivot) (Rodrigues), velocity at q
 *   omega x (q - center).  oscillate: d = amp sin(2 pi freq tau + phase) dir.
 * table: d piecewise linear between rows, held before the first, d_last + tail (tau -
 *   t_last) after the last; velocity the slope of the segment holding tau (right-
 *   continuous), so a row's time gives its row exactly.  A sequence sums its terms.
 * Elements are re-made from their transformed reference vertices (plane: point and
 * normal) with the wall_geom constructors, so edge normals and bounds stay exact. The
 * group's vel, omega and center feed esf_wall_point_velocity, hence the contact's
 * relative velocity and the work walls do in the energy ledger.
 * servo: not a function of time: the group drifts by vel (t - t_prev), vel set after
 *   each committed force evaluation by servo.c (leapfrog only).
 * Candidate lists: esf_walls_moved bounds the displacement of any wall point since the
 * last list build by |d - d_mark| + |angle - angle_mark| reach. Units: SI. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodies/walls.h"
#include "util/vec3.h"

/* table displacement and velocity at tau (rows: t increasing): the row segment
 * [t_i, t_i+1) holding tau, right-continuous; d(tau) = d_0 before the first row, then
 * linear; after the last row d_last + tail (tau - t_last). */
static void table_at(const esf_wall_motion *m, double tau, double d[3], double v[3]) {
  const double *T = m->row_t, *D = m->row_d;
  const int n = m->nrow;
  if (tau < T[0]) {
    v3_copy(d, D);
    return;
  }
  if (tau >= T[n - 1]) {
    const double h = tau - T[n - 1];
    for (int q = 0; q < 3; q++) d[q] = D[3 * (n - 1) + q] + m->tail[q] * h;
    v3_copy(v, m->tail);
    return;
  }
  int lo = 0, hi = n - 1; /* T[lo] <= tau < T[hi] */
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (T[mid] <= tau)
      lo = mid;
    else
      hi = mid;
  }
  const double *d0 = D + 3 * lo, *d1 = D + 3 * hi, h = T[hi] - T[lo];
  const double s = (tau - T[lo]) / h;
  for (int q = 0; q < 3; q++) {
    d[q] = d0[q] + s * (d1[q] - d0[q]);
    v[q] = (d1[q] - d0[q]) / h;
  }
}

/* one term at time t: adds its displacement, velocity, angle and angular speed */
static void term_at(const esf_wall_motion *m, double t, double d[3], double v[3],
                    double *angle, double *rate) {
  double tau = t, dd[3] = {0, 0, 0}, vv[3] = {0, 0, 0};
  int on = 1;
  if (m->timed) { /* the window: the motion sees clamp(t, start, stop) - start */
    on = t >= m->start && t < m->stop;
    tau = (t < m->start ? m->start : t > m->stop ? m->stop : t) - m->start;
  }
  switch (m->kind) {
  case ESF_MOTION_TRANSLATE:
    v3_scale(dd, tau, m->vel);
    v3_copy(vv, m->vel);
    break;
  case ESF_MOTION_ROTATE:
    *angle += m->rate * tau;
    if (on) *rate += m->rate;
    break;
  case ESF_MOTION_OSCILLATE: {
    double w = 2 * ESF_PI * m->freq, ph = w * tau + m->phase;
    v3_scale(dd, m->amp * sin(ph), m->dir);
    v3_scale(vv, m->amp * w * cos(ph), m->dir);
    break;
  }
  case ESF_MOTION_TABLE:
    table_at(m, tau, dd, vv);
    break;
  default:
    break;
  }
  v3_add(d, d, dd);
  if (on) v3_add(v, v, vv);
}

/* the group's motion at time t: the sum of its terms (rotations share one axis) */
static void motion_at(const esf_wall_group *g, double t, double d[3], double v[3],
                      double *angle, double *rate) {
  v3_set(d, 0, 0, 0);
  v3_set(v, 0, 0, 0);
  *angle = 0;
  *rate = 0;
  term_at(&g->motion, t, d, v, angle, rate);
  for (int k = 0; k < g->nmore; k++) term_at(&g->more[k], t, d, v, angle, rate);
}

/* reference point x0 placed with displacement d and rotation angle about the axis */
static void place(const esf_wall_group *g, const double x0[3], double out[3]) {
  const esf_wall_motion *m = &g->motion;
  if (m->kind == ESF_MOTION_ROTATE) {
    double r[3], rr[3];
    v3_sub(r, x0, m->pivot);
    v3_rotate_cs(rr, r, m->axis, g->cos_a, g->sin_a);
    v3_add(out, m->pivot, rr);
  } else {
    v3_copy(out, x0);
  }
  v3_add(out, out, g->disp);
}

int esf_walls_freeze(esf_walls *w, double t0, esf_error *err) {
  w->moving = 0;
  for (int k = 0; k < w->ngroups; k++) w->moving |= w->g[k].motion.kind != 0;
  if (!w->moving) return ESF_OK;
  free(w->e0);
  w->e0 = malloc((w->n ? w->n : 1) * sizeof *w->e0);
  if (!w->e0) return esf_fail(err, ESF_ENOMEM, "out of memory for moving walls");
  memcpy(w->e0, w->e, w->n * sizeof *w->e);
  for (size_t i = 0; i < w->n; i++) { /* reach: vertex distance from the axis */
    esf_wall_group *g = &w->g[w->e[i].group];
    g->moving = g->motion.kind != 0;
    if (g->motion.kind != ESF_MOTION_ROTATE) continue;
    for (int j = 0; j < w->e[i].nv; j++) {
      double r[3];
      v3_sub(r, w->e[i].v[j], g->motion.pivot);
      v3_axpy(r, -v3_dot(r, g->motion.axis), g->motion.axis);
      g->reach = fmax(g->reach, v3_norm(r));
    }
  }
  w->t = NAN;
  esf_walls_set_time(w, t0);
  esf_walls_mark(w);
  return ESF_OK;
}

void esf_walls_set_time(esf_walls *w, double t) {
  if (!w->moving || t == w->t) return;
  double t_prev = w->t;
  w->t = t;
  for (int k = 0; k < w->ngroups; k++) {
    esf_wall_group *g = &w->g[k];
    if (!g->moving) continue;
    if (g->motion.kind == ESF_MOTION_SERVO) { /* drifts with the velocity servo.c set */
      if (isfinite(t_prev)) v3_axpy(g->disp, t - t_prev, g->vel);
      continue;
    }
    double rate = 0;
    motion_at(g, t, g->disp, g->vel, &g->angle, &rate);
    if (g->motion.kind == ESF_MOTION_ROTATE) {
      v3_scale(g->omega, rate, g->motion.axis);
      v3_add(g->center, g->motion.pivot, g->disp);
      g->cos_a = cos(g->angle); /* once for all its vertices */
      g->sin_a = sin(g->angle);
    }
  }
  esf_error ignore;
  for (size_t i = 0; i < w->n; i++) {
    const esf_wall_elem *r = &w->e0[i];
    const esf_wall_group *g = &w->g[r->group];
    if (!g->moving) continue;
    esf_wall_elem *e = &w->e[i];
    if (r->kind == ESF_WALL_PLANE) {
      double pt[3], nn[3];
      place(g, r->p, pt);
      if (g->motion.kind == ESF_MOTION_ROTATE)
        v3_rotate_cs(nn, r->n, g->motion.axis, g->cos_a, g->sin_a);
      else
        v3_copy(nn, r->n);
      esf_wall_plane_init(e, pt, nn, r->material, r->group, &ignore);
    } else {
      double v[ESF_WALL_MAX_VERTS][3];
      for (int j = 0; j < r->nv; j++) place(g, r->v[j], v[j]);
      /* a rigid motion keeps a valid polygon valid: its geometry without the checks */
      esf_wall_polygon_set(e, r->nv, (const double(*)[3])v, r->material, r->group);
    }
  }
}

double esf_walls_moved(const esf_walls *w) {
  double worst = 0;
  for (int k = 0; k < w->ngroups && w->moving; k++) {
    const esf_wall_group *g = &w->g[k];
    if (!g->moving) continue;
    double d[3];
    v3_sub(d, g->disp, g->disp_mark);
    worst = fmax(worst, v3_norm(d) + fabs(g->angle - g->angle_mark) * g->reach);
  }
  return worst;
}

void esf_walls_mark(esf_walls *w) {
  for (int k = 0; k < w->ngroups; k++) {
    v3_copy(w->g[k].disp_mark, w->g[k].disp);
    w->g[k].angle_mark = w->g[k].angle;
  }
}
