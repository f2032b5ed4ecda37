/* frames_index.c — writing and reading the frames index (frames_index.h).
 *
 * Writing: H5Fcreate on PATH.tmp, the root attributes, /frames with one external link
 * per frame (H5Lcreate_external, target DIR.d/SSSSSS.h5 and /frames/NNNNNN),
 * /vertex_index (0..N-1, int32, N the most particles of a frame: the XDMF's vertex
 * cells), the /energy table through h5table.h, H5Fclose; then (durable) fsync of
 * PATH.tmp, rename over PATH and (durable) fsync of the directory. Nothing of the
 * segments is opened. Reading (a resume): each of the first nframes links must be an
 * external link into DIR.d/SSSSSS.h5; the frame is opened through it (the segment must be
 * readable) for its time attribute and the first dimensions of its datasets (the XDMF
 * record); the energy columns are read with one hyperslab each. HDF5 printing is off
 * throughout (esf_h5_quiet); every identifier is closed before returning. */
#include "output/frames_index.h"

#include <hdf5.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/h5io.h"
#include "formats/h5table.h"
#include "util/atomic_file.h"

static int write_file(const char *tmp, const esf_frames_index *ix, esf_error *err) {
  hid_t f = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f < 0) return esf_h5_fail(err, "cannot create frames index", tmp);
  int ok = esf_h5_attr_write_string(f, "scene", ix->scene ? ix->scene : "") == 0 &&
           esf_h5_attr_write_string(f, "esfera_version",
                                    ix->version ? ix->version : "") == 0 &&
           esf_h5_attr_write_string(f, "kind", "frames") == 0;
  hid_t g = ok ? H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT) : -1;
  ok = g >= 0;
  for (long k = 0; ok && k < ix->nframes; k++) {
    char name[32], target[1100], obj[48];
    snprintf(name, sizeof name, "%06ld", k);
    snprintf(target, sizeof target, "%s/%06ld.h5", ix->seg_dir, ix->seg[k]);
    snprintf(obj, sizeof obj, "/frames/%06ld", k);
    ok = H5Lcreate_external(target, obj, g, name, H5P_DEFAULT, H5P_DEFAULT) >= 0;
  }
  if (g >= 0 && H5Gclose(g) < 0) ok = 0;
  if (ok && ix->vertices > 0) { /* the particles' vertex cells (xdmf.h) */
    int32_t *v = malloc(ix->vertices * sizeof *v);
    if (!v) {
      H5Fclose(f);
      return esf_fail(err, ESF_ENOMEM, "out of memory writing '%s'", tmp);
    }
    for (size_t i = 0; i < ix->vertices; i++) v[i] = (int32_t)i;
    ok = esf_h5_dataset_write(f, "vertex_index", H5T_STD_I32LE, H5T_NATIVE_INT32,
                              ix->vertices, 1, v) == 0;
    free(v);
  }
  int rc = ok ? ESF_OK : esf_h5_fail(err, "cannot write frames index", tmp);
  if (!rc && ix->ncols > 0) {
    esf_h5table *t = NULL;
    rc = esf_h5table_create(f, "energy", ix->ncols, ix->names, tmp, &t, err);
    for (long r = 0; !rc && r < ix->nrows; r++)
      rc = esf_h5table_append(t, ix->rows + (size_t)r * (size_t)ix->ncols, err);
    int rc2 = esf_h5table_close(&t, rc ? NULL : err);
    if (!rc) rc = rc2;
  }
  if (H5Fclose(f) < 0 && !rc) rc = esf_h5_fail(err, "cannot close frames index", tmp);
  return rc;
}

int esf_frames_index_write(const char *path, const esf_frames_index *ix, int durable,
                           esf_error *err) {
  char tmp[1200];
  if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
    return esf_fail(err, ESF_EIO, "path too long: %s", path);
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = write_file(tmp, ix, err);
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  if (!rc && durable) rc = esf_fsync_path(tmp, err);
  if (!rc && rename(tmp, path) != 0)
    rc = esf_fail(err, ESF_EIO, "cannot replace '%s' by '%s'", path, tmp);
  if (rc) {
    remove(tmp);
    return rc;
  }
  return durable ? esf_fsync_parent(path, err) : ESF_OK;
}

/* Rows of the first dimension of dataset loc/name. */
static int dims_of(hid_t loc, const char *name, size_t *d0) {
  const long rows = esf_h5_rows(loc, name);
  *d0 = rows > 0 ? (size_t)rows : 0;
  return rows >= 0 ? 0 : -1;
}

/* The segment of link `name` in g (an external link to SEG_DIR/SSSSSS.h5). */
static int link_segment(hid_t g, const char *name, long *seg) {
  char file[4096];
  if (esf_h5_elink_file(g, name, file, sizeof file)) return -1;
  const char *slash = strrchr(file, '/');
  char *end = NULL;
  *seg = slash ? strtol(slash + 1, &end, 10) : -1;
  return *seg >= 0 && end && strcmp(end, ".h5") == 0 ? 0 : -1;
}

/* The XDMF record of frame k (group name in g). */
static int frame_record(hid_t g, const char *name, long k, esf_xdmf_frame *x) {
  hid_t fg = H5Gopen2(g, name, H5P_DEFAULT);
  if (fg < 0) return -1;
  memset(x, 0, sizeof *x);
  x->index = k;
  hid_t a = H5Aopen(fg, "time", H5P_DEFAULT);
  int ok = a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &x->time) >= 0;
  if (a >= 0) H5Aclose(a);
  ok = ok && dims_of(fg, "position", &x->particles) == 0;
  x->has_walls = H5Lexists(fg, "walls", H5P_DEFAULT) > 0;
  if (ok && x->has_walls)
    ok = dims_of(fg, "walls/points", &x->wall_points) == 0 &&
         dims_of(fg, "walls/triangles", &x->wall_triangles) == 0;
  x->has_contacts = H5Lexists(fg, "contacts", H5P_DEFAULT) > 0;
  x->has_image = H5Lexists(fg, "image", H5P_DEFAULT) > 0;
  if (ok && x->has_contacts) ok = dims_of(fg, "contacts/normal_force", &x->contacts) == 0;
  H5Gclose(fg);
  return ok ? 0 : -1;
}

static int read_column(hid_t f, const char *col, long nrows, double *out) {
  char path[160];
  snprintf(path, sizeof path, "energy/%s", col);
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  hid_t fs = d >= 0 ? H5Dget_space(d) : -1;
  hsize_t start = 0, cnt = (hsize_t)nrows, dims[1] = {0};
  int ok = fs >= 0 && H5Sget_simple_extent_dims(fs, dims, NULL) == 1 && dims[0] >= cnt &&
           H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &cnt, NULL) >= 0;
  hid_t ms = ok ? H5Screate_simple(1, &cnt, NULL) : -1;
  ok = ok && ms >= 0 && H5Dread(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, out) >= 0;
  if (ms >= 0) H5Sclose(ms);
  if (fs >= 0) H5Sclose(fs);
  if (d >= 0) H5Dclose(d);
  return ok ? 0 : -1;
}

int esf_frames_index_counts(const char *path, long *nframes, long *nrows,
                            esf_error *err) {
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  *nframes = *nrows = 0;
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t g = f >= 0 ? H5Gopen2(f, "frames", H5P_DEFAULT) : -1;
  H5G_info_t info;
  int rc = g >= 0 && H5Gget_info(g, &info) >= 0
               ? ESF_OK
               : esf_h5_fail(err, "cannot read the frames of", path);
  if (!rc) *nframes = (long)info.nlinks;
  size_t rows = 0;
  if (!rc && H5Lexists(f, "energy", H5P_DEFAULT) > 0 &&
      H5Lexists(f, "energy/time", H5P_DEFAULT) > 0 && dims_of(f, "energy/time", &rows))
    rc = esf_h5_fail(err, "cannot read the energy rows of", path);
  *nrows = (long)rows;
  if (g >= 0) H5Gclose(g);
  if (f >= 0) H5Fclose(f);
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  return rc;
}

int esf_frames_index_read(const char *path, long nframes, long *seg, esf_xdmf_frame *xf,
                          long nrows, int ncols, const char *const *names, double *rows,
                          esf_error *err) {
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = ESF_OK;
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t g = f >= 0 ? H5Gopen2(f, "frames", H5P_DEFAULT) : -1;
  if (g < 0) rc = esf_h5_fail(err, "cannot read the frames of", path);
  for (long k = 0; !rc && k < nframes; k++) {
    char name[32];
    snprintf(name, sizeof name, "%06ld", k);
    if (link_segment(g, name, &seg[k]) || frame_record(g, name, k, &xf[k])) {
      char what[96];
      snprintf(what, sizeof what, "cannot read frame %s (of %ld) through", name, nframes);
      rc = esf_h5_fail(err, what, path);
    }
  }
  double *col = !rc && nrows > 0 ? malloc((size_t)nrows * sizeof *col) : NULL;
  if (!rc && nrows > 0 && !col) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
  for (int j = 0; !rc && nrows > 0 && j < ncols; j++) {
    if (read_column(f, names[j], nrows, col)) {
      rc = esf_h5_fail(err, "cannot read the energy rows of", path);
      break;
    }
    for (long r = 0; r < nrows; r++) rows[(size_t)r * (size_t)ncols + (size_t)j] = col[r];
  }
  free(col);
  if (g >= 0) H5Gclose(g);
  if (f >= 0) H5Fclose(f);
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  return rc;
}
