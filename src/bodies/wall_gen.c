/* wall_gen.c — generated wall meshes (wall_gen.h): faceted cylinders and screws.
 *
 * Frame: unit axis a, u = unit(a x e) with e the coordinate axis least aligned with a,
 * v = a x u; the point (r, theta, z) is base + r (cos theta u + sin theta v) + z a.
 * Cylinder: `segments` vertices per ring at theta_k = 2 pi k / segments on the radius;
 * each side facet (k, k+1) a quadrilateral, or two triangles split along the diagonal
 * (k, 0)-(k+1, h); caps are triangle fans about the end's centre. Vertex order makes
 * the right-hand normal point outward (or inward when asked); the polygons are
 * two-sided for contact (wall_geom.h), so facing only orients the output mesh.
 * Screw (004 §4.3, Figs. 4.4-4.5): a shaft (a cylinder of shaft_radius over length,
 * `segments` facets) and a helicoid flight: grid points (r_j, theta_i) with
 * r_j = r_s + (r_o - r_s) j / radial, theta_i = 2 pi i / segments for
 * i = 0..round(turns segments), at height start + pitch theta_i / (2 pi); each grid
 * cell is two triangles. Flight and shaft share the angles, so the flight's inner edge
 * lies on the shaft's facets. A grain not turning with the screw sees the flight's
 * surface under it move axially at -pitch omega / (2 pi) for a rotation rate omega
 * about the axis: with pitch > 0 (right-handed), turning about -axis lifts. Units: m. */
#include "bodies/wall_gen.h"

#include <math.h>

#include "util/vec3.h"

typedef struct frame {
  double o[3], a[3], u[3], v[3];
} frame;

static int make_frame(frame *f, const double base[3], const double axis[3],
                      esf_error *err) {
  double len = v3_norm(axis);
  if (!(len > 0) || !isfinite(len))
    return esf_fail(err, ESF_EINPUT, "axis (%g, %g, %g) is zero or not finite", axis[0],
                    axis[1], axis[2]);
  v3_copy(f->o, base);
  v3_scale(f->a, 1 / len, axis);
  v3_basis(f->u, f->v, f->a);
  return ESF_OK;
}

static void at(const frame *f, double r, double th, double z, double out[3]) {
  v3_copy(out, f->o);
  v3_axpy(out, r * cos(th), f->u);
  v3_axpy(out, r * sin(th), f->v);
  v3_axpy(out, z, f->a);
}

/* adds polygon p[0..nv) (reversed when flip) */
static int add(esf_walls *w, int nv, double p[][3], int flip, int32_t mat, int32_t group,
               esf_error *err) {
  double q[4][3];
  for (int k = 0; k < nv; k++) v3_copy(q[k], p[flip ? nv - 1 - k : k]);
  esf_wall_elem e;
  int rc = esf_wall_polygon_init(&e, nv, (const double(*)[3])q, mat, group, err);
  if (!rc) rc = esf_walls_add_elem(w, &e, err);
  return rc;
}

/* side facets of ring radius r from z0 to z1, and caps */
static int tube(esf_walls *w, const frame *f, double r, double z0, double z1, int segs,
                int quads, int inward, int cap0, int cap1, int32_t mat, int32_t group,
                esf_error *err) {
  int rc = ESF_OK;
  for (int k = 0; k < segs && !rc; k++) {
    double t0 = 2 * ESF_PI * k / segs, t1 = 2 * ESF_PI * (k + 1) / segs, p[4][3];
    at(f, r, t0, z0, p[0]);
    at(f, r, t1, z0, p[1]);
    at(f, r, t1, z1, p[2]);
    at(f, r, t0, z1, p[3]);
    if (quads) {
      rc = add(w, 4, p, inward, mat, group, err);
    } else {
      double t[3][3];
      v3_copy(t[0], p[0]), v3_copy(t[1], p[1]), v3_copy(t[2], p[2]);
      rc = add(w, 3, t, inward, mat, group, err);
      v3_copy(t[0], p[0]), v3_copy(t[1], p[2]), v3_copy(t[2], p[3]);
      if (!rc) rc = add(w, 3, t, inward, mat, group, err);
    }
    /* caps: the bottom's outward normal is -a, the top's +a */
    double c[3][3];
    if (!rc && cap0) {
      at(f, 0, 0, z0, c[0]);
      at(f, r, t1, z0, c[1]);
      at(f, r, t0, z0, c[2]);
      rc = add(w, 3, c, inward, mat, group, err);
    }
    if (!rc && cap1) {
      at(f, 0, 0, z1, c[0]);
      at(f, r, t0, z1, c[1]);
      at(f, r, t1, z1, c[2]);
      rc = add(w, 3, c, inward, mat, group, err);
    }
  }
  return rc;
}

int esf_wall_gen_cylinder(const esf_cylinder_spec *c, int32_t material, int32_t group,
                          esf_walls *w, esf_error *err) {
  frame f;
  int rc = make_frame(&f, c->base, c->axis, err);
  if (rc) return rc;
  if (!(c->radius > 0) || !(c->height > 0))
    return esf_fail(err, ESF_EINPUT,
                    "cylinder radius (%g m) and height (%g m) must be "
                    "positive",
                    c->radius, c->height);
  if (c->segments < 3)
    return esf_fail(err, ESF_EINPUT, "a cylinder needs at least 3 segments (got %d)",
                    c->segments);
  return tube(w, &f, c->radius, 0, c->height, c->segments, c->quads, c->inward,
              c->cap_bottom, c->cap_top, material, group, err);
}

int esf_wall_gen_screw(const esf_screw_spec *c, int32_t material, int32_t group,
                       esf_walls *w, esf_error *err) {
  frame f;
  int rc = make_frame(&f, c->base, c->axis, err);
  if (rc) return rc;
  if (!(c->shaft_radius > 0) || !(c->radius > c->shaft_radius))
    return esf_fail(err, ESF_EINPUT,
                    "a screw needs 0 < shaft_radius (%g m) < radius "
                    "(%g m)",
                    c->shaft_radius, c->radius);
  if (!(c->pitch != 0) || !(c->turns > 0) || !isfinite(c->pitch) || !isfinite(c->turns))
    return esf_fail(err, ESF_EINPUT,
                    "a screw needs a non-zero pitch (%g m) and turns > 0 "
                    "(%g)",
                    c->pitch, c->turns);
  if (c->segments < 3 || c->radial < 1)
    return esf_fail(err, ESF_EINPUT,
                    "a screw needs segments >= 3 (got %d) and radial "
                    ">= 1 (got %d)",
                    c->segments, c->radial);
  double top = c->start + c->turns * fabs(c->pitch), bottom = c->start;
  if (!(c->start >= 0) || !(c->length >= top * (1 - 1e-12)))
    return esf_fail(err, ESF_EINPUT,
                    "the flight (from %g m to %g m along the axis) must "
                    "lie on the shaft (0 to length %g m)",
                    bottom, top, c->length);
  rc = tube(w, &f, c->shaft_radius, 0, c->length, c->segments, c->quads, 0, c->cap_bottom,
            c->cap_top, material, group, err);
  int steps = (int)lround(c->turns * c->segments);
  if (steps < 1) steps = 1;
  double dth = 2 * ESF_PI * c->turns / steps;
  double z0 = c->pitch > 0 ? c->start : c->start + c->turns * -c->pitch;
  for (int i = 0; i < steps && !rc; i++)
    for (int j = 0; j < c->radial && !rc; j++) {
      double r0 = c->shaft_radius + (c->radius - c->shaft_radius) * j / c->radial;
      double r1 = c->shaft_radius + (c->radius - c->shaft_radius) * (j + 1) / c->radial;
      double t0 = i * dth, t1 = (i + 1) * dth, p[4][3], t[3][3];
      double h0 = z0 + c->pitch * t0 / (2 * ESF_PI),
             h1 = z0 + c->pitch * t1 / (2 * ESF_PI);
      at(&f, r0, t0, h0, p[0]);
      at(&f, r1, t0, h0, p[1]);
      at(&f, r1, t1, h1, p[2]);
      at(&f, r0, t1, h1, p[3]);
      v3_copy(t[0], p[0]), v3_copy(t[1], p[1]), v3_copy(t[2], p[2]);
      rc = add(w, 3, t, c->pitch < 0, material, group, err);
      v3_copy(t[0], p[0]), v3_copy(t[1], p[2]), v3_copy(t[2], p[3]);
      if (!rc) rc = add(w, 3, t, c->pitch < 0, material, group, err);
    }
  return rc;
}
