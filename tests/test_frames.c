/* test_frames.c — the HDF5 frames writer: three frames of a small set, a large frame
 * (chunked and compressed) and an empty one are read back with the HDF5 C API and
 * compared exactly (every dataset, its shape and type class, the time attribute, the
 * root attributes, the group names); an unwritable path is an ESF_EIO error naming the
 * file; HDF5's automatic error printing is left as it was found. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <hdf5.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "frames.h"

static char tmpdir[256];

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
static void check_frame(hid_t file, const char *name, const esf_particles *p, double t) {
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
  CHECK(nobj == 7, "%s: %llu datasets, expected 7", name, (unsigned long long)nobj);
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
      check_frame(file, name, &p, times[f]);
    }
    check_frame(file, "/frames/000003", &big, 1.0);
    check_frame(file, "/frames/000004", &none, 2.0);
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
  unlink(path);
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
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/esf_frames_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  test_roundtrip();
  test_errors();
  if (rmdir(tmpdir) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return check_finish("test_frames");
}
