/* h5io.h — small HDF5 helpers shared by the result writers and readers (frames.c,
 * h5table.c, info.c): silencing HDF5's automatic error printing around a call, turning
 * the HDF5 error stack into an esf_error, attributes and whole datasets.
 *
 * Helpers that return int give 0 on success and -1 on an HDF5 failure, leaving the
 * HDF5 error stack for esf_h5_fail to report; they open nothing that outlives them. */
#ifndef ESF_H5IO_H
#define ESF_H5IO_H

#include <hdf5.h>
#include <stddef.h>

#include "util/esf_error.h"

/* Saved automatic error reporting of HDF5. */
typedef struct esf_h5_quiet {
  H5E_auto2_t func;
  void *data;
  int saved;
} esf_h5_quiet;

/* Saves HDF5's automatic error printing and turns it off (a library must not print). */
void esf_h5_quiet_begin(esf_h5_quiet *q);
/* Restores what esf_h5_quiet_begin saved. */
void esf_h5_quiet_end(const esf_h5_quiet *q);

/* Sets ESF_EIO "WHAT 'PATH': <innermost HDF5 message>" and clears the HDF5 error
 * stack; returns ESF_EIO. */
int esf_h5_fail(esf_error *err, const char *what, const char *path);

/* Scalar attributes: a variable-length UTF-8 string, a double. */
int esf_h5_attr_write_string(hid_t obj, const char *name, const char *value);
int esf_h5_attr_write_double(hid_t obj, const char *name, double value);
/* A 1-D attribute of n variable-length UTF-8 strings. */
int esf_h5_attr_write_strings(hid_t obj, const char *name, size_t n,
                              const char *const *values);

/* Rows at and above which datasets are chunked and compressed (shuffle + deflate);
 * smaller ones are contiguous (a chunk index costs more than it saves). */
enum { ESF_H5_CHUNK_MIN = 1024, ESF_H5_CHUNK_ROWS = 32768, ESF_H5_DEFLATE = 1 };

/* Creates and writes dataset `name` of n rows: cols 1 gives rank 1, else n x cols.
 * ftype is the file type, mtype the type of data in memory. */
int esf_h5_dataset_write(hid_t group, const char *name, hid_t ftype, hid_t mtype,
                         size_t n, int cols, const void *data);

/* Rows (first dimension) of dataset `path` under loc; -1 when it is missing or not a
 * dataset with at least one dimension. */
long esf_h5_rows(hid_t loc, const char *path);

/* The file an external link `name` in g points to, copied into file[n]; -1 when name is
 * not an external link or its value does not fit. */
int esf_h5_elink_file(hid_t g, const char *name, char *file, size_t n);

#endif
