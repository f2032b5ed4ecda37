/* h5io.c — HDF5 helpers (h5io.h).
 *
 * HDF5 prints its error stack to stderr by default, which a library must not do. That
 * printing is process-global state, so public functions of the writers and readers
 * bracket their HDF5 calls with esf_h5_quiet_begin/_end: save the handler, disable it,
 * restore it; nothing changes outside those calls. (Serial HDF5 is not thread-safe
 * anyway, so the save/restore needs no locking.) esf_h5_fail reports the innermost
 * HDF5 message (H5Ewalk2). File types are little-endian IEEE / two's complement;
 * datasets of ESF_H5_CHUNK_MIN rows or more are chunked (at most ESF_H5_CHUNK_ROWS rows
 * per chunk) with the shuffle and deflate filters when deflate is available. */
#include "formats/h5io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void esf_h5_quiet_begin(esf_h5_quiet *q) {
  q->saved = H5Eget_auto2(H5E_DEFAULT, &q->func, &q->data) >= 0;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

void esf_h5_quiet_end(const esf_h5_quiet *q) {
  if (q->saved) H5Eset_auto2(H5E_DEFAULT, q->func, q->data);
}

/* H5Ewalk2 callback keeping the innermost (first, walking upward) description. */
static herr_t walk_first(unsigned n, const H5E_error2_t *e, void *data) {
  char *buf = data;
  if (n == 0 && e->desc) snprintf(buf, 256, "%s", e->desc);
  return 0;
}

int esf_h5_fail(esf_error *err, const char *what, const char *path) {
  char detail[256] = "";
  int e = errno; /* a write failure's cause (full disk, file-size limit) */
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk_first, detail);
  H5Eclear2(H5E_DEFAULT);
  if (!detail[0] && (e == ENOSPC || e == EFBIG || e == EDQUOT || e == EIO || e == EROFS))
    snprintf(detail, sizeof detail, "%s", strerror(e));
  if (detail[0]) return esf_fail(err, ESF_EIO, "%s '%s': %s", what, path, detail);
  return esf_fail(err, ESF_EIO, "%s '%s'", what, path);
}

/* A variable-length UTF-8 string type (close with H5Tclose), or -1. */
static hid_t vlen_utf8(void) {
  hid_t type = H5Tcopy(H5T_C_S1);
  if (type < 0) return -1;
  if (H5Tset_size(type, H5T_VARIABLE) < 0 || H5Tset_cset(type, H5T_CSET_UTF8) < 0) {
    H5Tclose(type);
    return -1;
  }
  return type;
}

/* Writes attribute `name` of type `type` over `space` from buf (memory type mtype). */
static int write_attr(hid_t obj, const char *name, hid_t type, hid_t mtype, hid_t space,
                      const void *buf) {
  hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  int ok = attr >= 0 && H5Awrite(attr, mtype, buf) >= 0;
  if (attr >= 0) ok = (H5Aclose(attr) >= 0) && ok;
  return ok ? 0 : -1;
}

int esf_h5_attr_write_string(hid_t obj, const char *name, const char *value) {
  hid_t type = vlen_utf8(), space = H5Screate(H5S_SCALAR);
  int ok =
      type >= 0 && space >= 0 && write_attr(obj, name, type, type, space, &value) == 0;
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  return ok ? 0 : -1;
}

int esf_h5_attr_write_strings(hid_t obj, const char *name, size_t n,
                              const char *const *values) {
  hsize_t dims[1] = {(hsize_t)n};
  hid_t type = vlen_utf8(), space = H5Screate_simple(1, dims, NULL);
  int ok =
      type >= 0 && space >= 0 && write_attr(obj, name, type, type, space, values) == 0;
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  return ok ? 0 : -1;
}

int esf_h5_attr_write_double(hid_t obj, const char *name, double value) {
  hid_t space = H5Screate(H5S_SCALAR);
  int ok = space >= 0 &&
           write_attr(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space, &value) == 0;
  if (space >= 0) H5Sclose(space);
  return ok ? 0 : -1;
}

int esf_h5_dataset_write(hid_t group, const char *name, hid_t ftype, hid_t mtype,
                         size_t n, int cols, const void *data) {
  hsize_t dims[2] = {(hsize_t)n, (hsize_t)cols};
  int rank = cols == 1 ? 1 : 2;
  hid_t space = H5Screate_simple(rank, dims, NULL), dcpl = H5Pcreate(H5P_DATASET_CREATE);
  hid_t dset = -1;
  int ok = space >= 0 && dcpl >= 0;
  if (ok && n >= ESF_H5_CHUNK_MIN && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    hsize_t rows = n < ESF_H5_CHUNK_ROWS ? n : ESF_H5_CHUNK_ROWS;
    hsize_t chunk[2] = {rows, (hsize_t)cols};
    ok = H5Pset_chunk(dcpl, rank, chunk) >= 0 && H5Pset_shuffle(dcpl) >= 0 &&
         H5Pset_deflate(dcpl, ESF_H5_DEFLATE) >= 0;
  }
  if (ok) dset = H5Dcreate2(group, name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  ok = ok && dset >= 0;
  if (ok && n > 0) ok = H5Dwrite(dset, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
  if (dset >= 0) ok = (H5Dclose(dset) >= 0) && ok;
  if (dcpl >= 0) H5Pclose(dcpl);
  if (space >= 0) H5Sclose(space);
  return ok ? 0 : -1;
}

long esf_h5_rows(hid_t loc, const char *path) {
  if (H5Lexists(loc, path, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(loc, path, H5P_DEFAULT), s = d >= 0 ? H5Dget_space(d) : -1;
  hsize_t dims[H5S_MAX_RANK] = {0};
  long rows = s >= 0 && H5Sget_simple_extent_ndims(s) >= 1 &&
                      H5Sget_simple_extent_dims(s, dims, NULL) >= 1
                  ? (long)dims[0]
                  : -1;
  if (s >= 0) H5Sclose(s);
  if (d >= 0) H5Dclose(d);
  return rows;
}

int esf_h5_elink_file(hid_t g, const char *name, char *file, size_t n) {
  H5L_info_t li;
  char val[4096];
  const char *f = NULL, *obj = NULL;
  unsigned flags = 0;
  if (H5Lget_info(g, name, &li, H5P_DEFAULT) < 0 || li.type != H5L_TYPE_EXTERNAL ||
      li.u.val_size == 0 || li.u.val_size > sizeof val ||
      H5Lget_val(g, name, val, li.u.val_size, H5P_DEFAULT) < 0 ||
      H5Lunpack_elink_val(val, li.u.val_size, &flags, &f, &obj) < 0 || !f ||
      strlen(f) >= n)
    return -1;
  memcpy(file, f, strlen(f) + 1);
  return 0;
}
