/* test_frames.c — the HDF5 frames writer: three frames of a small set, a large frame
 * (chunked and compressed) and an empty one are read back with the HDF5 C API and
 * compared exactly (every dataset, its shape and type class, the time attribute, the
 * root attributes, the group names); frames with walls and a contact network give back
 * the wall mesh (wall_mesh.h) and the pairs and forces exactly; 600 energy rows (more
 * than one buffer) come back exactly from /energy with their column names; frames.xdmf
 * describes every frame flushed so far after each of the first 10 writes, never more
 * than were flushed later, and all of them after close; an unwritable path is an
 * ESF_EIO error naming the file (for the XDMF too); particles held out of id order are
 * written in id order with the contact pairs renumbered to match; HDF5's automatic
 * error printing is left as it was found. (tests/check_xdmf.py parses the XDMF of a
 * real run.) */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <dirent.h>
#include <hdf5.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bodies/wall_mesh.h"
#include "check.h"
#include "formats/xdmf.h"
#include "output/frames.h"

static char tmpdir[256];

/* Removes path (an .h5 frames file) and its segment directory (.d). */
static void remove_frames(const char *path) {
  char dir[600];
  size_t n = strlen(path);
  snprintf(dir, sizeof dir, "%.*s.d", (int)(n - 3), path);
  DIR *d = opendir(dir);
  for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
    char p[900];
    snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
    if (e->d_name[0] != '.') unlink(p);
  }
  if (d) closedir(d);
  rmdir(dir);
  unlink(path);
}

/* Fills p deterministically from a frame number. */
static void fill(esf_particles *p, int frame) {
  for (size_t i = 0; i < p->n; i++) {
    p->id[i] = (int64_t)(1000 + 7 * i) + ((int64_t)1 << 40);
    p->radius[i] = 0.001 * (1.0 + (double)i / 3.0);
    p->material[i] = (int32_t)(i % 3) - (i == 1 ? 5 : 0);
    for (int k = 0; k < 3; k++) {
      double b = (double)(3 * i + (size_t)k) + 0.1 * frame;
      p->x[3 * i + k] = b / 7.0;
      p->v[3 * i + k] = -b / 11.0;
      p->w[3 * i + k] = b * 1e-300; /* tiny numbers survive exactly */
      p->f[3 * i + k] = b * 1e300;
    }
  }
}

/* Reads dataset `name` of group g; checks rank, shape (n or n x 3), class; data into buf
 * as mtype. */
static int read_dataset(hid_t g, const char *name, hid_t mtype, size_t n, int cols,
                        void *buf, const char *what) {
  hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
  CHECK(d >= 0, "%s: no dataset %s", what, name);
  if (d < 0) return -1;
  hid_t s = H5Dget_space(d);
  int rank = H5Sget_simple_extent_ndims(s);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(s, dims, NULL);
  int want_rank = cols == 1 ? 1 : 2;
  CHECK(rank == want_rank, "%s/%s: rank %d, expected %d", what, name, rank, want_rank);
  CHECK(dims[0] == n && (cols == 1 || dims[1] == (hsize_t)cols),
        "%s/%s: shape %llu x %llu, expected %zu x %d", what, name,
        (unsigned long long)dims[0], (unsigned long long)dims[1], n, cols);
  hid_t ft = H5Dget_type(d);
  CHECK(H5Tget_class(ft) == H5Tget_class(mtype) && H5Tget_size(ft) == H5Tget_size(mtype),
        "%s/%s: stored type differs in class or size", what, name);
  H5Tclose(ft);
  int rc = 0;
  if (n > 0) rc = H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) < 0 ? -1 : 0;
  CHECK(rc == 0, "%s/%s: read failed", what, name);
  H5Sclose(s);
  H5Dclose(d);
  return rc;
}

/* 1 when the dataset uses the deflate filter. */
static int is_compressed(hid_t g, const char *name) {
  hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t pl = H5Dget_create_plist(d);
  int nf = H5Pget_nfilters(pl), deflate = 0;
  for (int k = 0; k < nf; k++) {
    unsigned flags;
    size_t nelem = 8;
    unsigned cd[8];
    char fname[64];
    unsigned config;
    if (H5Pget_filter2(pl, (unsigned)k, &flags, &nelem, cd, sizeof fname, fname,
                       &config) == H5Z_FILTER_DEFLATE)
      deflate = 1;
  }
  H5Pclose(pl);
  H5Dclose(d);
  return deflate;
}

/* Compares frame group `name` with p and time t exactly. */
static void check_frame(hid_t file, const char *name, const esf_particles *p, double t,
                        int nlinks) {
  hid_t g = H5Gopen2(file, name, H5P_DEFAULT);
  CHECK(g >= 0, "no group %s", name);
  if (g < 0) return;
  double time = -1;
  hid_t a = H5Aopen(g, "time", H5P_DEFAULT);
  CHECK(a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &time) >= 0, "%s: no time attribute",
        name);
  if (a >= 0) H5Aclose(a);
  CHECK(time == t, "%s: time %.17g, expected %.17g", name, time, t);

  size_t n = p->n, m = n ? n : 1;
  int64_t *id = calloc(m, sizeof *id);
  int32_t *mat = calloc(m, sizeof *mat);
  double *r = calloc(m, sizeof *r), *vec = calloc(3 * m, sizeof *vec);
  read_dataset(g, "id", H5T_NATIVE_INT64, n, 1, id, name);
  CHECK(n == 0 || memcmp(id, p->id, n * sizeof *id) == 0, "%s: id differs", name);
  read_dataset(g, "material", H5T_NATIVE_INT32, n, 1, mat, name);
  CHECK(n == 0 || memcmp(mat, p->material, n * sizeof *mat) == 0, "%s: material differs",
        name);
  read_dataset(g, "radius", H5T_NATIVE_DOUBLE, n, 1, r, name);
  CHECK(n == 0 || memcmp(r, p->radius, n * sizeof *r) == 0, "%s: radius differs", name);
  const char *vnames[4] = {"position", "velocity", "angular_velocity", "force"};
  const double *src[4] = {p->x, p->v, p->w, p->f};
  for (int k = 0; k < 4; k++) {
    memset(vec, 0, 3 * m * sizeof *vec);
    read_dataset(g, vnames[k], H5T_NATIVE_DOUBLE, n, 3, vec, name);
    CHECK(n == 0 || memcmp(vec, src[k], 3 * n * sizeof *vec) == 0, "%s: %s differs", name,
          vnames[k]);
  }
  H5G_info_t info = {0};
  H5Gget_info(g, &info);
  hsize_t nobj = info.nlinks;
  CHECK(nobj == (hsize_t)nlinks, "%s: %llu links, expected %d", name,
        (unsigned long long)nobj, nlinks);
  free(id);
  free(mat);
  free(r);
  free(vec);
  H5Gclose(g);
}

static void check_string_attr(hid_t file, const char *name, const char *want) {
  hid_t a = H5Aopen(file, name, H5P_DEFAULT);
  CHECK(a >= 0, "no root attribute %s", name);
  if (a < 0) return;
  hid_t t = H5Aget_type(a); /* the reader's idiom: read with the stored type */
  CHECK(H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) > 0 &&
            H5Tget_cset(t) == H5T_CSET_UTF8,
        "attribute %s must be a variable-length UTF-8 string", name);
  char *s = NULL;
  CHECK(H5Aread(a, t, &s) >= 0, "cannot read attribute %s", name);
  CHECK(s && strcmp(s, want) == 0, "attribute %s = '%s', expected '%s'", name,
        s ? s : "(null)", want);
  if (s) H5free_memory(s);
  H5Tclose(t);
  H5Aclose(a);
}

static void test_roundtrip(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/frames.h5", tmpdir);
  esf_error err = {0};
  esf_frames *fr = NULL;
  int rc = esf_frames_open(path, "hopper", "0.1.0", &fr, &err);
  CHECK_OK(rc, err);
  if (rc) return;
  CHECK(esf_frames_count(fr) == 0, "fresh file has %ld frames", esf_frames_count(fr));

  esf_particles p, big, none;
  CHECK_OK(esf_particles_alloc(&p, 5, &err), err);
  CHECK_OK(esf_particles_alloc(&big, 3000, &err), err);
  CHECK_OK(esf_particles_alloc(&none, 0, &err), err);
  const double times[3] = {0.0, 1.0e-4, 2.5e-4};
  for (int f = 0; f < 3; f++) {
    fill(&p, f);
    rc = esf_frames_write(fr, times[f], &p, NULL, NULL, &err);
    CHECK_OK(rc, err);
  }
  fill(&big, 7);
  CHECK_OK(esf_frames_write(fr, 1.0, &big, NULL, NULL, &err), err);
  CHECK_OK(esf_frames_write(fr, 2.0, &none, NULL, NULL, &err), err);
  CHECK(esf_frames_count(fr) == 5, "%ld frames written, expected 5",
        esf_frames_count(fr));
  rc = esf_frames_close(&fr, &err);
  CHECK_OK(rc, err);
  CHECK(fr == NULL, "close must set the pointer to NULL");
  CHECK(esf_frames_close(&fr, &err) == ESF_OK, "close on NULL is a no-op");

  hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(file >= 0, "cannot reopen %s", path);
  if (file >= 0) {
    check_string_attr(file, "scene", "hopper");
    check_string_attr(file, "esfera_version", "0.1.0");
    check_string_attr(file, "kind", "frames");
    CHECK(H5Lexists(file, "energy", H5P_DEFAULT) == 0, "no energy rows: no /energy");
    hid_t g = H5Gopen2(file, "frames", H5P_DEFAULT);
    H5G_info_t info = {0};
    H5Gget_info(g, &info);
    hsize_t nobj = info.nlinks;
    CHECK(nobj == 5, "/frames holds %llu groups, expected 5", (unsigned long long)nobj);
    H5Gclose(g);
    for (int f = 0; f < 3; f++) {
      fill(&p, f);
      char name[32];
      snprintf(name, sizeof name, "/frames/%06d", f);
      check_frame(file, name, &p, times[f], 7);
    }
    check_frame(file, "/frames/000003", &big, 1.0, 7);
    check_frame(file, "/frames/000004", &none, 2.0, 7);
    hid_t g3 = H5Gopen2(file, "/frames/000003", H5P_DEFAULT);
    CHECK(is_compressed(g3, "position") == 1 && is_compressed(g3, "id") == 1,
          "a 3000-particle frame must be deflate-compressed");
    H5Gclose(g3);
    hid_t g0 = H5Gopen2(file, "/frames/000000", H5P_DEFAULT);
    CHECK(is_compressed(g0, "position") == 0, "a 5-particle frame must be contiguous");
    H5Gclose(g0);
    H5Fclose(file);
  }
  esf_particles_release(&p);
  esf_particles_release(&big);
  esf_particles_release(&none);
  remove_frames(path);
  snprintf(path, sizeof path, "%s/frames.xdmf", tmpdir);
  unlink(path);
}

/* Reads dataset `name` of loc (rank 1 or 2) into a new buffer as mtype. */
static void *read_all(hid_t loc, const char *name, hid_t mtype, size_t *rows,
                      size_t *cols) {
  *rows = *cols = 0;
  hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
  CHECK(d >= 0, "no dataset %s", name);
  if (d < 0) return NULL;
  hid_t sp = H5Dget_space(d);
  hsize_t dims[2] = {0, 1};
  int rank = H5Sget_simple_extent_dims(sp, dims, NULL);
  *rows = (size_t)dims[0];
  *cols = rank == 2 ? (size_t)dims[1] : 1;
  void *buf = calloc(*rows * *cols + 1, H5Tget_size(mtype));
  if (*rows && H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) < 0)
    CHECK(0, "cannot read %s", name);
  H5Sclose(sp);
  H5Dclose(d);
  return buf;
}

/* Compares dataset `name` of g with n x cols values of data (size bytes each). */
static void check_exact(hid_t g, const char *name, hid_t mtype, const void *data,
                        size_t n, size_t cols, const char *what) {
  size_t rows, c;
  void *buf = read_all(g, name, mtype, &rows, &c);
  CHECK(rows == n && (n == 0 || c == cols), "%s/%s: %zu x %zu, expected %zu x %zu", what,
        name, rows, c, n, cols);
  if (buf && rows == n && c == cols && n > 0)
    CHECK(memcmp(buf, data, n * cols * H5Tget_size(mtype)) == 0, "%s/%s differs", what,
          name);
  free(buf);
}

static int count_in_file(const char *path, const char *needle) {
  FILE *f = fopen(path, "r");
  if (!f) return -1;
  static char text[1 << 20];
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[n] = '\0';
  int count = 0;
  for (const char *c = strstr(text, needle); c; c = strstr(c + 1, needle)) count++;
  return count;
}

static void test_walls_contacts_energy(void) {
  char path[512], xdmf[512];
  snprintf(path, sizeof path, "%s/run.h5", tmpdir);
  snprintf(xdmf, sizeof xdmf, "%s/run.xdmf", tmpdir);
  esf_error err = {0};
  esf_walls w = {0};
  int gb, gp;
  esf_wall_elem faces[6], plane;
  int nf = 0;
  const double lo[3] = {-0.01, -0.01, 0}, hi[3] = {0.5, 0.4, 0.3};
  const double pt[3] = {0, 0, -0.5}, up[3] = {0.1, 0, 1};
  CHECK_OK(esf_walls_add_group(&w, "box", &gb, &err), err);
  CHECK_OK(esf_wall_box(lo, hi, 32, 1, gb, faces, &nf, &err), err);
  for (int k = 0; k < nf; k++) CHECK_OK(esf_walls_add_elem(&w, &faces[k], &err), err);
  CHECK_OK(esf_walls_add_group(&w, "plane", &gp, &err), err);
  CHECK_OK(esf_wall_plane_init(&plane, pt, up, 2, gp, &err), err);
  CHECK_OK(esf_walls_add_elem(&w, &plane, &err), err);

  esf_particles p;
  CHECK_OK(esf_particles_alloc(&p, 5, &err), err);
  int64_t pairs[4] = {0, 1, 2, 4};
  double fn[2] = {1.5, 0.0}, ft[6] = {0.1, 0.2, 0.3, 0, 0, 0};
  esf_contact_net net = {0}, empty = {0};
  net.pp = (esf_contact_set){.n = 2, .cap = 2, .pair = pairs, .fn = fn, .ft = ft};
  const esf_contact_net *nets[3] = {&net, NULL, &empty};
  const char *cols[3] = {"time", "a", "b"};
  esf_frames *fr = NULL;
  CHECK_OK(esf_frames_open(path, "walls", "9.9", &fr, &err), err);
  if (!fr) return;
  for (int f = 0; f < 3; f++) {
    fill(&p, f);
    for (int k = 200 * f; k < 200 * (f + 1); k++) {
      double row[3] = {1e-3 * k, sin((double)k), k * 1e300};
      CHECK_OK(esf_frames_append_energy(fr, 3, cols, row, &err), err);
    }
    CHECK_OK(esf_frames_write(fr, 0.5 * f, &p, &w, nets[f], &err), err);
    CHECK(count_in_file(xdmf, "<Grid Name=\"particles_") == f + 1,
          "after frame %d the XDMF describes %d frames", f,
          count_in_file(xdmf, "<Grid Name=\"particles_"));
  }
  double row2[2] = {0, 0};
  CHECK(esf_frames_append_energy(fr, 2, cols, row2, &err) == ESF_EINTERNAL,
        "a row of another width must be refused");
  CHECK(esf_frames_energy_rows(fr) == 600, "%ld energy rows", esf_frames_energy_rows(fr));
  CHECK(esf_frames_seconds(fr) > 0, "writing time must be measured");
  CHECK_OK(esf_frames_close(&fr, &err), err);
  CHECK(count_in_file(xdmf, "<Grid Name=\"walls_") == 3 &&
            count_in_file(xdmf, "<Grid Name=\"contacts_") == 2,
        "XDMF: %d wall grids (want 3), %d contact grids (want 2)",
        count_in_file(xdmf, "<Grid Name=\"walls_"),
        count_in_file(xdmf, "<Grid Name=\"contacts_"));

  hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(file >= 0, "cannot reopen %s", path);
  if (file < 0) return;
  esf_wall_mesh m = {0};
  for (int f = 0; f < 3; f++) {
    fill(&p, f);
    double blo[3], bhi[3];
    for (size_t i = 0; i < p.n; i++)
      for (int q = 0; q < 3; q++) {
        double a = p.x[3 * i + q] - p.radius[i], b = p.x[3 * i + q] + p.radius[i];
        blo[q] = i ? fmin(blo[q], a) : a;
        bhi[q] = i ? fmax(bhi[q], b) : b;
      }
    CHECK_OK(esf_wall_mesh_build(&w, 0.5 * f, blo, bhi, &m, &err), err);
    char name[64];
    snprintf(name, sizeof name, "/frames/%06d", f);
    check_frame(file, name, &p, 0.5 * f, nets[f] ? 10 : 8); /* + contacts, coordination */
    hid_t g = H5Gopen2(file, name, H5P_DEFAULT);
    hid_t wg = H5Gopen2(g, "walls", H5P_DEFAULT);
    CHECK(m.np == 24 && m.nt == 12, "mesh: %zu points, %zu triangles", m.np, m.nt);
    check_exact(wg, "points", H5T_NATIVE_DOUBLE, m.points, m.np, 3, name);
    check_exact(wg, "triangles", H5T_NATIVE_INT32, m.tri, m.nt, 3, name);
    check_exact(wg, "group", H5T_NATIVE_INT32, m.group, m.nt, 1, name);
    check_exact(wg, "material", H5T_NATIVE_INT32, m.material, m.nt, 1, name);
    H5Gclose(wg);
    if (nets[f]) {
      hid_t cg = H5Gopen2(g, "contacts", H5P_DEFAULT);
      const esf_contact_set *cs = &nets[f]->pp;
      check_exact(cg, "pairs", H5T_NATIVE_INT64, cs->pair, cs->n, 2, name);
      check_exact(cg, "normal_force", H5T_NATIVE_DOUBLE, cs->fn, cs->n, 1, name);
      check_exact(cg, "tangential_force", H5T_NATIVE_DOUBLE, cs->ft, cs->n, 3, name);
      H5Gclose(cg);
    }
    H5Gclose(g);
  }
  esf_wall_mesh_release(&m);
  hid_t eg = H5Gopen2(file, "energy", H5P_DEFAULT);
  CHECK(eg >= 0, "no /energy group");
  if (eg >= 0) {
    double want[600];
    for (int c = 0; c < 3; c++) {
      for (int k = 0; k < 600; k++)
        want[k] = c == 0 ? 1e-3 * k : c == 1 ? sin((double)k) : k * 1e300;
      check_exact(eg, cols[c], H5T_NATIVE_DOUBLE, want, 600, 1, "/energy");
    }
    hid_t a = H5Aopen(eg, "columns", H5P_DEFAULT), t = H5Aget_type(a);
    char *names[3] = {NULL, NULL, NULL};
    CHECK(H5Aread(a, t, names) >= 0, "cannot read /energy's columns");
    for (int c = 0; c < 3; c++) {
      CHECK(names[c] && strcmp(names[c], cols[c]) == 0,
            "column %d is '%s', expected '%s'", c, names[c] ? names[c] : "(null)",
            cols[c]);
      if (names[c]) H5free_memory(names[c]);
    }
    H5Tclose(t);
    H5Aclose(a);
    H5Gclose(eg);
  }
  H5Fclose(file);
  esf_particles_release(&p);
  esf_walls_release(&w);
  remove_frames(path);
  unlink(xdmf);
}

/* Particles kept in another order than their ids (reorder.h) are written in ascending
 * id, whatever order the run holds them in, and the contact pairs name their rows. */
static void test_id_order(void) {
  char path[512], xdmf[512];
  snprintf(path, sizeof path, "%s/order.h5", tmpdir);
  snprintf(xdmf, sizeof xdmf, "%s/order.xdmf", tmpdir);
  esf_error err = {0};
  esf_particles p, q;
  CHECK_OK(esf_particles_alloc(&p, 5, &err), err);
  CHECK_OK(esf_particles_alloc(&q, 5, &err), err);
  fill(&p, 1);
  fill(&q, 1);
  const size_t shuffle[5] = {3, 0, 4, 1, 2}; /* q[k] = p[shuffle[k]] */
  CHECK_OK(esf_particles_permute(&q, shuffle, 1, &err), err);
  CHECK(q.id[0] == p.id[3] && q.x[3 * 2] == p.x[3 * 4] &&
            q.f[3 * 4 + 2] == p.f[3 * 2 + 2],
        "permute: particle k is the old shuffle[k]");
  int64_t pairs[6] = {0, 1, 2, 4, 3, 0};      /* q's numbers */
  const int64_t rows[6] = {3, 0, 4, 2, 1, 3}; /* p's (id order) */
  double fn[3] = {1.5, 2.5, 0.5}, ft[9] = {0};
  int64_t wpairs[2] = {4, 1}; /* q's particle 4 (p's row 2) on wall 1 */
  const int64_t wrows[2] = {2, 1};
  double wfn[1] = {0.75}, wft[3] = {0.1, 0, 0}, wpc[3] = {1, 2, 3};
  esf_contact_net net = {0};
  net.pp = (esf_contact_set){.n = 3, .cap = 3, .pair = pairs, .fn = fn, .ft = ft};
  net.pw = (esf_contact_set){
      .n = 1, .cap = 1, .pair = wpairs, .fn = wfn, .ft = wft, .pc = wpc};
  esf_frames *fr = NULL;
  CHECK_OK(esf_frames_open(path, "order", "9.9", &fr, &err), err);
  if (!fr) return;
  CHECK_OK(esf_frames_write(fr, 0.25, &q, NULL, &net, &err), err);
  CHECK_OK(esf_frames_close(&fr, &err), err);
  hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(file >= 0, "cannot reopen %s", path);
  if (file >= 0) {
    check_frame(file, "/frames/000000", &p, 0.25, 9);
    hid_t cg = H5Gopen2(file, "/frames/000000/contacts", H5P_DEFAULT);
    check_exact(cg, "pairs", H5T_NATIVE_INT64, rows, 3, 2, "order");
    check_exact(cg, "normal_force", H5T_NATIVE_DOUBLE, fn, 3, 1, "order");
    check_exact(cg, "wall_pairs", H5T_NATIVE_INT64, wrows, 1, 2, "order");
    check_exact(cg, "wall_normal_force", H5T_NATIVE_DOUBLE, wfn, 1, 1, "order");
    check_exact(cg, "wall_tangential_force", H5T_NATIVE_DOUBLE, wft, 1, 3, "order");
    check_exact(cg, "wall_point", H5T_NATIVE_DOUBLE, wpc, 1, 3, "order");
    H5Gclose(cg);
    /* coordination by row: p's rows 3 0 4 2 1 3 in pairs, row 2 on a wall */
    const int32_t z[5] = {1, 1, 2, 2, 1};
    hid_t fg = H5Gopen2(file, "/frames/000000", H5P_DEFAULT);
    check_exact(fg, "coordination", H5T_NATIVE_INT32, z, 5, 1, "order");
    H5Gclose(fg);
    H5Fclose(file);
  }
  esf_particles_release(&p);
  esf_particles_release(&q);
  remove_frames(path);
  unlink(xdmf);
}

/* 150 small frames: the XDMF follows every one of the first 10, may lag after that
 * (it is rewritten only when cheap against the time since the last rewrite), and is
 * complete after close. */
static void test_xdmf_schedule(void) {
  char path[512], xdmf[512];
  snprintf(path, sizeof path, "%s/many.h5", tmpdir);
  snprintf(xdmf, sizeof xdmf, "%s/many.xdmf", tmpdir);
  esf_error err = {0};
  esf_particles p;
  CHECK_OK(esf_particles_alloc(&p, 2, &err), err);
  fill(&p, 0);
  esf_frames *fr = NULL;
  CHECK_OK(esf_frames_open(path, "many", "0", &fr, &err), err);
  if (!fr) return;
  int lag_ok = 1, first_ok = 1;
  for (int f = 0; f < 150; f++) {
    CHECK_OK(esf_frames_write(fr, 1e-3 * f, &p, NULL, NULL, &err), err);
    int described = count_in_file(xdmf, "<Grid Name=\"particles_");
    if (f < 10 && described != f + 1) first_ok = 0;
    if (f >= 10 && (described < 10 || described > f + 1)) lag_ok = 0;
  }
  CHECK(first_ok, "the XDMF must follow each of the first 10 frames");
  CHECK(lag_ok, "later the XDMF may lag, never lead or fall below 10 frames");
  CHECK_OK(esf_frames_close(&fr, &err), err);
  CHECK(count_in_file(xdmf, "<Grid Name=\"particles_") == 150,
        "after close the XDMF describes %d frames, expected 150",
        count_in_file(xdmf, "<Grid Name=\"particles_"));
  esf_particles_release(&p);
  remove_frames(path);
  unlink(xdmf);
}

static void test_errors(void) {
  H5E_auto2_t before_func = NULL;
  void *before_data = NULL;
  H5Eget_auto2(H5E_DEFAULT, &before_func, &before_data);

  char path[512];
  snprintf(path, sizeof path, "%s/no/such/dir/frames.h5", tmpdir);
  esf_error err = {0};
  esf_frames *fr = (esf_frames *)&err; /* must be overwritten with NULL */
  int rc = esf_frames_open(path, "s", "v", &fr, &err);
  CHECK(rc == ESF_EIO && err.code == ESF_EIO, "unwritable path: status %d", rc);
  CHECK(fr == NULL, "failed open must leave NULL");
  char want[600];
  snprintf(want, sizeof want, "cannot create frames file '%s'", path);
  CHECK(strncmp(err.msg, want, strlen(want)) == 0, "message '%s'", err.msg);
  rc = esf_frames_open(path, "s", "v", &fr, NULL);
  CHECK(rc == ESF_EIO, "unwritable path, NULL err: %d", rc);

  H5E_auto2_t after_func = NULL;
  void *after_data = NULL;
  H5Eget_auto2(H5E_DEFAULT, &after_func, &after_data);
  CHECK(after_func == before_func && after_data == before_data,
        "HDF5's automatic error printing must be restored");
  CHECK(esf_frames_count(NULL) == 0, "count of NULL");

  /* the XDMF writer: an unwritable place is ESF_EIO naming the file */
  esf_xdmf_frame x = {0.5, 0, 3, 0, 0, 0, 0, 0, 0};
  snprintf(path, sizeof path, "%s/no/such/dir/frames.xdmf", tmpdir);
  rc = esf_xdmf_write(path, "frames.h5", ESF_XDMF_ALL, &x, 1, 1, &err);
  CHECK(rc == ESF_EIO && strstr(err.msg, path) != NULL, "XDMF to '%s': %d '%s'", path, rc,
        err.msg);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/esf_frames_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  test_roundtrip();
  test_walls_contacts_energy();
  test_id_order();
  test_xdmf_schedule();
  test_errors();
  if (rmdir(tmpdir) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return check_finish("test_frames");
}
