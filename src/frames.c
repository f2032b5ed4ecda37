/* frames.c — the HDF5 frames writer (frames.h, INTERFACE.md "Output directory").
 *
 * Layout: root attributes `scene` and `esfera_version` (variable-length UTF-8 strings,
 * so h5py reads them as str); group /frames; frame k is the group /frames/%06d (k from
 * 0, more digits past 999999) with a scalar double attribute `time` (s) and the
 * datasets id (N, int64), position, velocity, angular_velocity, force (N x 3, double:
 * the particles' x, v, w, f in m, m/s, rad/s, N), radius (N, double, m) and material
 * (N, int32). File types are little-endian IEEE/two's complement. A frame with N = 0
 * particles has every dataset, with zero rows. Datasets with N >= CHUNK_MIN rows are
 * chunked (at most CHUNK_ROWS rows per chunk) with the shuffle and deflate (level 1)
 * filters; smaller ones are contiguous. The file is flushed after every frame, so a run
 * that dies leaves every completed frame readable; a frame that fails half-way is
 * unlinked again (best effort) so the frame count stays consistent.
 *
 * HDF5 errors: HDF5 prints its error stack to stderr by default, which a library must
 * not do. The automatic printing is process-global state, so every public function here
 * saves the current handler (H5Eget_auto2), disables it, and restores it before
 * returning; nothing is changed outside these calls. The innermost HDF5 error message
 * (H5Ewalk2) is appended to our ESF_EIO message, which always names the file. (Serial
 * HDF5 is not thread-safe anyway, so the save/restore needs no locking.)
 *
 * Every identifier opened here is closed before returning; the file and the /frames
 * group stay open between esf_frames_open and esf_frames_close. */
#include "frames.h"

#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { CHUNK_MIN = 1024, CHUNK_ROWS = 32768, DEFLATE_LEVEL = 1 };

struct esf_frames {
  hid_t file, frames;
  long count;
  char *path;
};

/* Saved automatic error reporting of HDF5 (restored on leaving each public function). */
typedef struct h5_quiet {
  H5E_auto2_t func;
  void *data;
  int saved;
} h5_quiet;

static void quiet_begin(h5_quiet *q) {
  q->saved = H5Eget_auto2(H5E_DEFAULT, &q->func, &q->data) >= 0;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

static void quiet_end(const h5_quiet *q) {
  if (q->saved) H5Eset_auto2(H5E_DEFAULT, q->func, q->data);
}

/* H5Ewalk2 callback keeping the innermost (first, walking upward) description. */
static herr_t walk_first(unsigned n, const H5E_error2_t *e, void *data) {
  char *buf = data;
  if (n == 0 && e->desc) snprintf(buf, 256, "%s", e->desc);
  return 0;
}

/* ESF_EIO "WHAT 'PATH': hdf5 detail" from the current HDF5 error stack. */
static int h5_fail(esf_error *err, const char *what, const char *path) {
  char detail[256] = "";
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk_first, detail);
  H5Eclear2(H5E_DEFAULT);
  if (detail[0]) return esf_fail(err, ESF_EIO, "%s '%s': %s", what, path, detail);
  return esf_fail(err, ESF_EIO, "%s '%s'", what, path);
}

/* Writes a variable-length string attribute on obj. */
static int write_string_attr(hid_t obj, const char *name, const char *value) {
  hid_t type = H5Tcopy(H5T_C_S1), space = H5Screate(H5S_SCALAR), attr = -1;
  int ok = type >= 0 && space >= 0 && H5Tset_size(type, H5T_VARIABLE) >= 0 &&
           H5Tset_cset(type, H5T_CSET_UTF8) >= 0;
  if (ok) attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  ok = ok && attr >= 0 && H5Awrite(attr, type, &value) >= 0;
  if (attr >= 0) ok = (H5Aclose(attr) >= 0) && ok;
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  return ok ? 0 : -1;
}

static int write_double_attr(hid_t obj, const char *name, double value) {
  hid_t space = H5Screate(H5S_SCALAR), attr = -1;
  int ok = space >= 0;
  if (ok) attr = H5Acreate2(obj, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
  ok = ok && attr >= 0 && H5Awrite(attr, H5T_NATIVE_DOUBLE, &value) >= 0;
  if (attr >= 0) ok = (H5Aclose(attr) >= 0) && ok;
  if (space >= 0) H5Sclose(space);
  return ok ? 0 : -1;
}

/* Creates and writes dataset `name` of n rows (cols 1: rank 1, else n x cols). */
static int write_dataset(hid_t group, const char *name, hid_t ftype, hid_t mtype,
                         size_t n, int cols, const void *data) {
  hsize_t dims[2] = {(hsize_t)n, (hsize_t)cols};
  int rank = cols == 1 ? 1 : 2;
  hid_t space = H5Screate_simple(rank, dims, NULL), dcpl = H5Pcreate(H5P_DATASET_CREATE);
  hid_t dset = -1;
  int ok = space >= 0 && dcpl >= 0;
  if (ok && n >= CHUNK_MIN && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    hsize_t chunk[2] = {(hsize_t)(n < CHUNK_ROWS ? n : CHUNK_ROWS), (hsize_t)cols};
    ok = H5Pset_chunk(dcpl, rank, chunk) >= 0 && H5Pset_shuffle(dcpl) >= 0 &&
         H5Pset_deflate(dcpl, DEFLATE_LEVEL) >= 0;
  }
  if (ok) dset = H5Dcreate2(group, name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  ok = ok && dset >= 0;
  if (ok && n > 0) ok = H5Dwrite(dset, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
  if (dset >= 0) ok = (H5Dclose(dset) >= 0) && ok;
  if (dcpl >= 0) H5Pclose(dcpl);
  if (space >= 0) H5Sclose(space);
  return ok ? 0 : -1;
}

int esf_frames_open(const char *path, const char *scene_name, const char *version,
                    esf_frames **out, esf_error *err) {
  *out = NULL;
  esf_frames *fr = calloc(1, sizeof *fr);
  size_t len = strlen(path);
  char *copy = malloc(len + 1);
  if (!fr || !copy) {
    free(fr);
    free(copy);
    return esf_fail(err, ESF_ENOMEM, "out of memory opening '%s'", path);
  }
  memcpy(copy, path, len + 1);
  fr->path = copy;
  fr->frames = -1;
  h5_quiet q;
  quiet_begin(&q);
  int rc = ESF_OK;
  fr->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (fr->file < 0) {
    rc = h5_fail(err, "cannot create frames file", path);
  } else if (write_string_attr(fr->file, "scene", scene_name ? scene_name : "") < 0 ||
             write_string_attr(fr->file, "esfera_version", version ? version : "") < 0) {
    rc = h5_fail(err, "cannot write the root attributes of", path);
  } else {
    fr->frames = H5Gcreate2(fr->file, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (fr->frames < 0) rc = h5_fail(err, "cannot create group /frames in", path);
  }
  if (rc) {
    if (fr->frames >= 0) H5Gclose(fr->frames);
    if (fr->file >= 0) H5Fclose(fr->file);
    H5Eclear2(H5E_DEFAULT);
    free(fr->path);
    free(fr);
  } else {
    *out = fr;
  }
  quiet_end(&q);
  return rc;
}

int esf_frames_write(esf_frames *fr, double time, const esf_particles *p,
                     esf_error *err) {
  if (!fr) return esf_fail(err, ESF_EINTERNAL, "frames: write on a closed file");
  char name[32];
  snprintf(name, sizeof name, "%06ld", fr->count);
  h5_quiet q;
  quiet_begin(&q);
  size_t n = p->n;
  hid_t g = H5Gcreate2(fr->frames, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int ok =
      g >= 0 && write_double_attr(g, "time", time) == 0 &&
      write_dataset(g, "id", H5T_STD_I64LE, H5T_NATIVE_INT64, n, 1, p->id) == 0 &&
      write_dataset(g, "position", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 3, p->x) == 0 &&
      write_dataset(g, "velocity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 3, p->v) == 0 &&
      write_dataset(g, "angular_velocity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 3,
                    p->w) == 0 &&
      write_dataset(g, "force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 3, p->f) == 0 &&
      write_dataset(g, "radius", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 1, p->radius) ==
          0 &&
      write_dataset(g, "material", H5T_STD_I32LE, H5T_NATIVE_INT32, n, 1, p->material) ==
          0;
  int rc = ESF_OK;
  if (!ok) {
    char what[96];
    snprintf(what, sizeof what, "cannot write frame %s to", name);
    rc = h5_fail(err, what, fr->path);
  }
  if (g >= 0 && H5Gclose(g) < 0 && rc == ESF_OK) {
    rc = h5_fail(err, "cannot close a frame group in", fr->path);
    ok = 0;
  }
  if (ok && H5Fflush(fr->file, H5F_SCOPE_LOCAL) < 0)
    rc = h5_fail(err, "cannot flush", fr->path);
  if (rc == ESF_OK) {
    fr->count++;
  } else if (g >= 0) {
    H5Ldelete(fr->frames, name, H5P_DEFAULT); /* best effort: keep the count coherent */
    H5Eclear2(H5E_DEFAULT);
  }
  quiet_end(&q);
  return rc;
}

long esf_frames_count(const esf_frames *fr) { return fr ? fr->count : 0; }

int esf_frames_close(esf_frames **frp, esf_error *err) {
  if (!frp || !*frp) return ESF_OK;
  esf_frames *fr = *frp;
  *frp = NULL;
  h5_quiet q;
  quiet_begin(&q);
  int rc = ESF_OK;
  if (fr->frames >= 0 && H5Gclose(fr->frames) < 0)
    rc = h5_fail(err, "cannot close group /frames in", fr->path);
  if (fr->file >= 0 && H5Fflush(fr->file, H5F_SCOPE_LOCAL) < 0 && rc == ESF_OK)
    rc = h5_fail(err, "cannot flush", fr->path);
  if (fr->file >= 0 && H5Fclose(fr->file) < 0 && rc == ESF_OK)
    rc = h5_fail(err, "cannot close", fr->path);
  H5Eclear2(H5E_DEFAULT);
  quiet_end(&q);
  free(fr->path);
  free(fr);
  return rc;
}
