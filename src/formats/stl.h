/* stl.h — reading STL triangle meshes, ASCII or binary, checked triangle by triangle.
 *
 * Which form a file has is decided by its size, not its first word: a binary STL is
 * exactly 84 + 50 N bytes with N the count in its header (binary files may begin with
 * "solid" too); anything else must be ASCII ("solid ... endsolid"). Every triangle is
 * checked: finite vertices and a non-degenerate shape (its height over its longest edge
 * above ESF_STL_SLIVER). Errors are ESF_EINPUT naming the file and the line (ASCII) or
 * the triangle's index and byte offset (binary); a missing file is ESF_EIO. */
#ifndef ESF_STL_H
#define ESF_STL_H

#include <stddef.h>

#include "util/esf_error.h"

/* A triangle is degenerate when 2 area / longest edge^2 (its height over its longest
 * edge) is at most this. */
#define ESF_STL_SLIVER 1e-10

typedef struct esf_stl {
  size_t n;          /* triangles */
  double (*v)[3][3]; /* n triangles x 3 vertices x (x, y, z), file units */
  long *line;        /* ASCII: line of each triangle's `facet`; binary: 0 */
  int binary;        /* 1 when the file was binary */
} esf_stl;

/* Reads path into *out (zeroed first). */
int esf_stl_read(const char *path, esf_stl *out, esf_error *err);

/* Checks one triangle; 0 when sound, else ESF_EINPUT with a message saying why
 * (non-finite coordinate, coincident vertices, zero or near-zero area, an edge longer
 * than the largest double), whatever the scale of the coordinates. */
int esf_stl_check_triangle(const double v[3][3], esf_error *err);

void esf_stl_release(esf_stl *s);

#endif
