/* atomic_file.h — durable whole-file replacement and syncing for checkpoints.
 *
 * esf_atomic_write replaces a file so that a process killed at any instant (SIGKILL
 * included) or a machine losing power leaves either the old file or the new one, never
 * a mixture: the data go to PATH.tmp, which is fsync'ed, renamed over PATH, and the
 * directory is fsync'ed so the rename itself is durable. A failure (full disk, EFBIG,
 * an unwritable directory) removes PATH.tmp and leaves PATH untouched. */
#ifndef ESF_ATOMIC_FILE_H
#define ESF_ATOMIC_FILE_H

#include <stddef.h>

#include "util/esf_error.h"

/* Replaces path with len bytes of data, atomically and durably. ESF_EIO naming the
 * path and the system's reason on failure. */
int esf_atomic_write(const char *path, const void *data, size_t len, esf_error *err);

/* fsync of an existing file by path (its data and size reach the disk). */
int esf_fsync_path(const char *path, esf_error *err);

/* fsync of the directory containing path (a rename or creation in it is durable). */
int esf_fsync_parent(const char *path, esf_error *err);

/* Reads a whole file into a new buffer (NUL-terminated past len; free it). ESF_EIO
 * naming the path when it cannot be opened or read. */
int esf_read_file(const char *path, char **data, size_t *len, esf_error *err);

#endif
