/* h5table.c — the growing time-series table (h5table.h).
 *
 * Layout: group NAME with attribute `columns` (1-D, variable-length UTF-8 strings) and
 * one dataset per column, 1-D, double (IEEE little-endian), maximum size unlimited,
 * chunks of CHUNK rows with shuffle + deflate. Rows collect in a column-major buffer
 * of BUF rows; a flush extends every dataset by the buffered rows and writes them with
 * one hyperslab each. Between calls the group and the column datasets stay open; the
 * caller brackets calls with esf_h5_quiet (h5io.h) to keep HDF5 silent. */
#include "formats/h5table.h"

#include <stdlib.h>
#include <string.h>

#include "formats/h5io.h"

enum { CHUNK = 1024, BUF = 256 };

struct esf_h5table {
  hid_t group;
  int ncols;
  hid_t *dset;    /* ncols datasets */
  double *buf;    /* BUF x ncols, column-major */
  size_t nbuf;    /* rows buffered */
  size_t written; /* rows in the file */
  char *path;     /* for messages */
};

static int create_column(hid_t group, const char *name, hid_t *out) {
  hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {CHUNK};
  hid_t space = H5Screate_simple(1, dims, maxdims), dcpl = H5Pcreate(H5P_DATASET_CREATE);
  int ok = space >= 0 && dcpl >= 0 && H5Pset_chunk(dcpl, 1, chunk) >= 0;
  if (ok && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0)
    ok = H5Pset_shuffle(dcpl) >= 0 && H5Pset_deflate(dcpl, ESF_H5_DEFLATE) >= 0;
  *out =
      ok ? H5Dcreate2(group, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT)
         : -1;
  if (dcpl >= 0) H5Pclose(dcpl);
  if (space >= 0) H5Sclose(space);
  return *out >= 0 ? 0 : -1;
}

static void destroy(esf_h5table *t) {
  for (int c = 0; t->dset && c < t->ncols; c++)
    if (t->dset[c] >= 0) H5Dclose(t->dset[c]);
  if (t->group >= 0) H5Gclose(t->group);
  free(t->dset);
  free(t->buf);
  free(t->path);
  free(t);
}

int esf_h5table_create(hid_t parent, const char *name, int ncols,
                       const char *const *names, const char *path, esf_h5table **out,
                       esf_error *err) {
  *out = NULL;
  if (ncols < 1) return esf_fail(err, ESF_EINTERNAL, "h5table: %d columns", ncols);
  esf_h5table *t = calloc(1, sizeof *t);
  size_t plen = strlen(path);
  if (t) {
    t->group = -1;
    t->ncols = ncols;
    t->dset = malloc((size_t)ncols * sizeof *t->dset);
    t->buf = malloc((size_t)ncols * BUF * sizeof *t->buf);
    t->path = malloc(plen + 1);
  }
  if (!t || !t->dset || !t->buf || !t->path) {
    if (t) {
      t->ncols = 0;
      destroy(t);
    }
    return esf_fail(err, ESF_ENOMEM, "out of memory for table /%s in '%s'", name, path);
  }
  memcpy(t->path, path, plen + 1);
  for (int c = 0; c < ncols; c++) t->dset[c] = -1;
  t->group = H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int ok = t->group >= 0 &&
           esf_h5_attr_write_strings(t->group, "columns", (size_t)ncols, names) == 0;
  for (int c = 0; ok && c < ncols; c++)
    ok = create_column(t->group, names[c], &t->dset[c]) == 0;
  if (!ok) {
    int rc = esf_h5_fail(err, "cannot create the table in", path);
    destroy(t);
    return rc;
  }
  *out = t;
  return ESF_OK;
}

int esf_h5table_flush(esf_h5table *t, esf_error *err) {
  if (!t || t->nbuf == 0) return ESF_OK;
  hsize_t start[1] = {(hsize_t)t->written}, count[1] = {(hsize_t)t->nbuf};
  hsize_t size[1] = {(hsize_t)(t->written + t->nbuf)};
  hid_t mem = H5Screate_simple(1, count, NULL);
  int ok = mem >= 0;
  for (int c = 0; ok && c < t->ncols; c++) {
    hid_t fs = -1;
    ok = H5Dset_extent(t->dset[c], size) >= 0 && (fs = H5Dget_space(t->dset[c])) >= 0 &&
         H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
         H5Dwrite(t->dset[c], H5T_NATIVE_DOUBLE, mem, fs, H5P_DEFAULT,
                  t->buf + (size_t)c * BUF) >= 0;
    if (fs >= 0) H5Sclose(fs);
  }
  if (mem >= 0) H5Sclose(mem);
  if (!ok) return esf_h5_fail(err, "cannot write table rows to", t->path);
  t->written += t->nbuf;
  t->nbuf = 0;
  return ESF_OK;
}

int esf_h5table_append(esf_h5table *t, const double *row, esf_error *err) {
  if (!t) return esf_fail(err, ESF_EINTERNAL, "h5table: append to a closed table");
  if (t->nbuf == BUF) {
    int rc = esf_h5table_flush(t, err);
    if (rc) return rc;
  }
  for (int c = 0; c < t->ncols; c++) t->buf[(size_t)c * BUF + t->nbuf] = row[c];
  t->nbuf++;
  return ESF_OK;
}

size_t esf_h5table_rows(const esf_h5table *t) { return t ? t->written + t->nbuf : 0; }

int esf_h5table_ncols(const esf_h5table *t) { return t ? t->ncols : 0; }

int esf_h5table_close(esf_h5table **tp, esf_error *err) {
  if (!tp || !*tp) return ESF_OK;
  esf_h5table *t = *tp;
  *tp = NULL;
  int rc = esf_h5table_flush(t, err);
  destroy(t);
  return rc;
}
