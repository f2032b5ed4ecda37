/* h5table.h — a growing time-series table in an HDF5 file: a group holding one 1-D
 * extendible double dataset per column (chunked, shuffle + deflate) and the attribute
 * `columns` (the column names in order). Rows are buffered and reach the file in
 * blocks: when the buffer is full, on esf_h5table_flush and on close. */
#ifndef ESF_H5TABLE_H
#define ESF_H5TABLE_H

#include <hdf5.h>
#include <stddef.h>

#include "util/esf_error.h"

typedef struct esf_h5table esf_h5table;

/* Creates group `name` under parent with ncols empty column datasets named by
 * names[] (copied). path names the file in error messages (ESF_EIO). */
int esf_h5table_create(hid_t parent, const char *name, int ncols,
                       const char *const *names, const char *path, esf_h5table **out,
                       esf_error *err);

/* Appends one row of ncols values. */
int esf_h5table_append(esf_h5table *t, const double *row, esf_error *err);

/* Writes the buffered rows to the file (HDF5's cache; the caller flushes the file). */
int esf_h5table_flush(esf_h5table *t, esf_error *err);

/* Rows appended so far; the table's column count. */
size_t esf_h5table_rows(const esf_h5table *t);
int esf_h5table_ncols(const esf_h5table *t);

/* Flushes and closes; sets *t to NULL. Safe on NULL. */
int esf_h5table_close(esf_h5table **t, esf_error *err);

#endif
