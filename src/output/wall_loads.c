/* wall_loads.c — walls.csv and stress.csv (wall_loads.h; docs/physics.md#wall-loads-
 * and-region-stress).
 *
 * Wall loads: for each particle-wall contact of particle A (centre xA) with group g,
 * f the force on A and tA its torque about xA (lever arm x ft plus rolling
 * resistance), the wall receives -f at the contact point; about the group's reference
 * point c its moment is -[(xA - c) x f + tA] (the contact point's lever, written
 * through A's torque so rolling resistance counts). Summed per group in list order.
 * Region stress (Love 1927, Weber 1966; Christoffersen, Mehrabadi & Nemat-Nasser
 * 1981), compression positive, region volume V, particles P with centre in the box:
 *   sigma_ij = -(1/V) sum_{P} sum_{c of P} f^c_i (x^c - x_P)_j    (contact part)
 *            + (1/V) sum_{P} m_P v'_i v'_j,  v' = w_P - (sum m w)/(sum m)  (kinetic)
 * with w = v, or under Lees-Edwards shear w = v - rate y_g e_flow (the imposed flow)
 * with f^c the force on P (a pair with both particles in gives f (x_B - x_A), the
 * branch vector form; one particle out: its part is cut at the contact point). The
 * symmetric part is written, p = tr/3, q = sqrt(3 J2). Units: SI. Entry: the net of
 * the state (contact_net.h). Rows use %.17g, so equal doubles give equal files. */
#include "output/wall_loads.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "util/vec3.h"

void esf_wall_loads(const esf_sim *s, const esf_contact_net *net, double *fm) {
  const esf_contact_set *w = &net->pw;
  memset(fm, 0, 6 * (size_t)s->walls.ngroups * sizeof *fm);
  for (size_t k = 0; k < w->n; k++) {
    const size_t a = (size_t)w->pair[2 * k];
    const int g = (int)w->pair[2 * k + 1];
    double r[3], m[3], *o = fm + 6 * g;
    const double *f = w->f + 3 * k;
    v3_sub(r, s->p.x + 3 * a, s->walls.g[g].center);
    v3_cross(m, r, f);
    v3_add(m, m, w->ta + 3 * k);
    v3_sub(o, o, f);
    v3_sub(o + 3, o + 3, m);
  }
}

/* Whether x lies in the region box; with periodic axes its image in the periodic box
 * (positions stray past a face by up to skin/2 between the wraps) is tested. */
static int inside_at(const esf_sim *s, const double *xp, const double box[6],
                     double x[3]) {
  const esf_periodic *pb = &s->cfg.per;
  double mid[3];
  v3_copy(x, xp);
  if (pb->any) {
    for (int q = 0; q < 3; q++) mid[q] = pb->lo[q] + 0.5 * pb->len[q];
    esf_periodic_nearest(pb, s->nb.pp.le_off, mid, xp, x);
  }
  for (int q = 0; q < 3; q++)
    if (!(x[q] >= box[q] && x[q] < box[q + 3])) return 0;
  return 1;
}

static int inside(const esf_sim *s, const double *xp, const double box[6]) {
  double x[3];
  return inside_at(s, xp, box, x);
}

/* The velocity the kinetic stress measures from: v, less under Lees-Edwards shear the
 * imposed flow rate y_g at the image x (whose velocity is v + rate (x_g - xp_g) along
 * the flow axis), so that the streaming shear is not counted as agitation. */
static void kin_velocity(const esf_periodic *pb, const double *v, const double *xp,
                         const double *x, double w[3]) {
  v3_copy(w, v);
  if (pb->le)
    w[pb->flow] += pb->rate * (x[pb->grad] - xp[pb->grad]) - pb->rate * x[pb->grad];
}

/* t -= f (pc - x)^T: a contact's part with P's force f at point pc, centre x. */
static void add_contact(double t[9], const double *f, const double *pc, const double *x) {
  double l[3];
  v3_sub(l, pc, x);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) t[3 * i + j] -= f[i] * l[j];
}

void esf_region_stress(const esf_sim *s, const esf_contact_net *net, const double box[6],
                       double out[ESF_STRESS_COLS]) {
  const esf_particles *p = &s->p;
  const double V = (box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2]);
  double t[9] = {0}, tk[9] = {0}, mv[3] = {0, 0, 0}, m = 0, mf[3];
  size_t np = 0;
  for (size_t i = 0; i < p->n; i++) {
    double x[3], w[3];
    if (!inside_at(s, p->x + 3 * i, box, x)) continue;
    np++;
    m += p->mass[i];
    kin_velocity(&s->cfg.per, p->v + 3 * i, p->x + 3 * i, x, w);
    v3_axpy(mv, p->mass[i], w);
  }
  if (m > 0) v3_scale(mv, 1.0 / m, mv); /* the region's mean (less the shear flow) */
  for (size_t i = 0; np && i < p->n; i++) {
    double x[3], u[3];
    if (!inside_at(s, p->x + 3 * i, box, x)) continue;
    kin_velocity(&s->cfg.per, p->v + 3 * i, p->x + 3 * i, x, u);
    v3_sub(u, u, mv);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) tk[3 * a + b] += p->mass[i] * u[a] * u[b];
  }
  const esf_contact_set *pp = &net->pp, *pw = &net->pw;
  for (size_t k = 0; np && k < pp->n; k++) {
    const size_t a = (size_t)pp->pair[2 * k], b = (size_t)pp->pair[2 * k + 1];
    const double *f = pp->f + 3 * k, *pc = pp->pc + 3 * k;
    if (inside(s, p->x + 3 * a, box)) add_contact(t, f, pc, p->x + 3 * a);
    v3_scale(mf, -1.0,
             f); /* B's force, its branch from its image on the contact's side */
    double xb[3];
    if (s->cfg.per.any)
      esf_periodic_nearest(&s->cfg.per, s->nb.pp.le_off, pc, p->x + 3 * b, xb);
    else
      v3_copy(xb, p->x + 3 * b);
    if (inside(s, p->x + 3 * b, box)) add_contact(t, mf, pc, xb);
  }
  for (size_t k = 0; np && k < pw->n; k++) {
    const size_t a = (size_t)pw->pair[2 * k];
    if (inside(s, p->x + 3 * a, box))
      add_contact(t, pw->f + 3 * k, pw->pc + 3 * k, p->x + 3 * a);
  }
  double sg[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      sg[3 * i + j] = (0.5 * (t[3 * i + j] + t[3 * j + i]) + tk[3 * i + j]) / V;
  const double pr = (sg[0] + sg[4] + sg[8]) / 3.0;
  const double sx = sg[0] - pr, sy = sg[4] - pr, sz = sg[8] - pr;
  const double j2 =
      0.5 * (sx * sx + sy * sy + sz * sz) + sg[5] * sg[5] + sg[2] * sg[2] + sg[1] * sg[1];
  const double o[ESF_STRESS_COLS] = {
      (double)np, sg[0], sg[4], sg[8],          sg[5],
      sg[2],      sg[1], pr,    sqrt(3.0 * j2), (tk[0] + tk[4] + tk[8]) / (3.0 * V)};
  memcpy(out, o, sizeof o);
}

/* Opens dir/name; new (keep < 0): writes header; resumed: keeps the header line and
 * `keep` rows. */
static int open_csv(const char *dir, const char *name, const char *header, long keep,
                    FILE **out, esf_error *err) {
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, keep < 0 ? "w" : "r+");
  if (!f) return esf_fail(err, ESF_EIO, "cannot open '%s': %s", path, strerror(errno));
  setvbuf(f, NULL, _IOLBF, 1 << 14); /* whole rows reach the file (run.c) */
  if (keep >= 0) {                   /* the end of line 1 + keep */
    long lines = 0, at = 0;
    int ch;
    while (lines < keep + 1 && (ch = fgetc(f)) != EOF) {
      at++;
      if (ch == '\n') lines++;
    }
    if (lines < keep + 1) {
      fclose(f);
      return esf_fail(err, ESF_EINPUT,
                      "'%s' has %ld rows, fewer than the checkpoint's %ld: it was "
                      "changed after the checkpoint; cannot resume",
                      path, lines ? lines - 1 : 0, keep);
    }
    if (fflush(f) != 0 || ftruncate(fileno(f), at) != 0 || fseek(f, 0, SEEK_END) != 0) {
      const int e = errno;
      fclose(f);
      return esf_fail(err, ESF_EIO, "cannot cut back '%s': %s", path, strerror(e));
    }
  }
  if (keep < 0) fprintf(f, "%s\n", header);
  *out = f;
  return ESF_OK;
}

int esf_load_out_open(const char *dir, const esf_sim *s, long erows, esf_load_out *o,
                      esf_error *err) {
  memset(o, 0, sizeof *o);
  const long nw = s->walls.ngroups, ns = s->cfg.n_stress;
  int rc = ESF_OK;
  const char *names[2] = {"walls.csv", "stress.csv"};
  for (int k = 0; k < 2 && erows < 0; k++) { /* a new run: no earlier run's file stays */
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, names[k]);
    if (!(k ? ns : s->cfg.out_walls)) unlink(path);
  }
  if (s->cfg.out_walls) {
    o->fm = calloc(6 * (size_t)(nw ? nw : 1), sizeof *o->fm);
    if (!o->fm) return esf_fail(err, ESF_ENOMEM, "out of memory for walls.csv");
    rc = open_csv(dir, "walls.csv", "time,wall,fx,fy,fz,mx,my,mz",
                  erows < 0 ? -1 : erows * nw, &o->walls, err);
  }
  if (!rc && ns)
    rc = open_csv(dir, "stress.csv",
                  "time,region,particles,sxx,syy,szz,syz,sxz,sxy,p,q,p_kinetic",
                  erows < 0 ? -1 : erows * ns, &o->stress, err);
  if (rc) esf_load_out_close(o);
  return rc;
}

int esf_load_out_row(esf_sim *s, esf_load_out *o, esf_error *err) {
  if (!o->walls && !o->stress) return ESF_OK;
  int rc = esf_contact_net_build(s, 1, &o->net, err);
  if (rc) return rc;
  if (o->walls) {
    esf_wall_loads(s, &o->net, o->fm);
    for (int g = 0; g < s->walls.ngroups; g++) {
      const double *v = o->fm + 6 * g;
      fprintf(o->walls, "%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", s->t, g, v[0],
              v[1], v[2], v[3], v[4], v[5]);
    }
    if (ferror(o->walls))
      return esf_fail(err, ESF_EIO, "cannot write walls.csv: %s", strerror(errno));
  }
  for (int r = 0; o->stress && r < s->cfg.n_stress; r++) {
    double v[ESF_STRESS_COLS];
    esf_region_stress(s, &o->net, s->cfg.stress_box[r], v);
    fprintf(o->stress, "%.17g,%d,%.0f", s->t, r, v[0]);
    for (int k = 1; k < ESF_STRESS_COLS; k++) fprintf(o->stress, ",%.17g", v[k]);
    fputc('\n', o->stress);
    if (ferror(o->stress))
      return esf_fail(err, ESF_EIO, "cannot write stress.csv: %s", strerror(errno));
  }
  return ESF_OK;
}

int esf_load_out_sync(esf_load_out *o, esf_error *err) {
  FILE *fs[2] = {o->walls, o->stress};
  for (int k = 0; k < 2; k++)
    if (fs[k] && (fflush(fs[k]) != 0 || fsync(fileno(fs[k])) != 0))
      return esf_fail(err, ESF_EIO, "cannot flush %s: %s", k ? "stress.csv" : "walls.csv",
                      strerror(errno));
  return ESF_OK;
}

void esf_load_out_close(esf_load_out *o) {
  if (o->walls) fclose(o->walls);
  if (o->stress) fclose(o->stress);
  esf_contact_net_release(&o->net);
  free(o->fm);
  memset(o, 0, sizeof *o);
}
