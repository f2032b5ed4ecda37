/* frames_index.h — frames.h5 as an index of segment files (frames.h, frames.c).
 *
 * The frames of a run live in segment files DIR.d/SSSSSS.h5 beside the index DIR.h5
 * (SSSSSS: the number of the segment's first frame; inside, the same /frames/NNNNNN
 * groups). The index holds the root attributes (scene, esfera_version, kind =
 * "frames"), /frames with one HDF5 external link per frame, /frames/NNNNNN ->
 * DIR.d/SSSSSS.h5:/frames/NNNNNN (a relative file name, which HDF5 resolves against
 * the index's own directory), and the /energy table (h5table.h). It is small and is
 * only ever replaced whole, atomically (temporary file, rename), so a process killed
 * at any instant leaves the previous index or the new one. */
#ifndef ESF_FRAMES_INDEX_H
#define ESF_FRAMES_INDEX_H

#include "formats/xdmf.h"
#include "util/esf_error.h"

/* What an index names. seg[k]: the segment (its first frame's number) of frame k;
 * rows: nrows x ncols energy rows, row-major (ncols 0: no /energy). */
typedef struct esf_frames_index {
  const char *scene, *version;
  const char
      *seg_dir; /* the segment directory's name relative to the index: "frames.d" */
  long nframes;
  const long *seg;
  int ncols;
  const char *const *names;
  long nrows;
  const double *rows;
  size_t vertices; /* the most particles of any frame: /vertex_index holds 0..that - 1
                      (int32), the particles' vertex cells in the XDMF (xdmf.h) */
} esf_frames_index;

/* Replaces the index at path with ix: written to PATH.tmp and renamed over path; with
 * durable, PATH.tmp is fsync'ed before and the directory after the rename. ESF_EIO
 * naming the path on failure (path untouched, PATH.tmp removed). */
int esf_frames_index_write(const char *path, const esf_frames_index *ix, int durable,
                           esf_error *err);

/* The frames and energy rows the index at path names (before reading them: a count
 * to allocate by). ESF_EIO naming the path when it cannot be read. */
int esf_frames_index_counts(const char *path, long *nframes, long *nrows, esf_error *err);

/* Reads back from the index at path the first nframes frames (seg[k], and the XDMF
 * records xf[k], from the frames themselves through their links) and the first nrows
 * energy rows of columns names (rows: nrows x ncols, row-major). ESF_EIO naming the
 * path when it lacks them. */
int esf_frames_index_read(const char *path, long nframes, long *seg, esf_xdmf_frame *xf,
                          long nrows, int ncols, const char *const *names, double *rows,
                          esf_error *err);

#endif
