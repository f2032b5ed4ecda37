/* info.h — `esfera info FILE.h5`: what an esfera HDF5 file holds.
 *
 * The file's kind is read from the root attribute `kind` ("frames" for the frames
 * file of a run; files written before the attribute existed are recognised by their
 * esfera_version attribute and /frames group). Each kind has its own describer, so a
 * later HDF5 kind adds one entry to the table in info.c. Checkpoints (checkpoint.h) are
 * not HDF5: they are recognised by their signature and described by checkpoint.c. */
#ifndef ESF_INFO_H
#define ESF_INFO_H

#include <stdio.h>

#include "util/esf_error.h"

/* Prints a description of the esfera file at path (a directory: its frames.h5) to out,
 * one `key: value` per line.
 * Errors: ESF_EIO when the file cannot be opened or read (missing, unreadable), naming
 * it; ESF_EINPUT when it is not HDF5, is HDF5 but not written by esfera, or is of a
 * kind this version does not know. */
int esf_info_print(const char *path, FILE *out, esf_error *err);

#endif
