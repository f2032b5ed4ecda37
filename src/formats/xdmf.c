/* xdmf.c — the XDMF 3 description of frames.h5 (xdmf.h).
 *
 * Writes the whole file each time: NAME.tmp is written with stdio, flushed, fsync'ed
 * and renamed over NAME (rename is atomic on POSIX file systems); the directory is
 * fsync'ed afterwards, best effort. Times are printed with 17 significant digits, so
 * they read back as the frames' exact `time` attributes. On failure NAME.tmp is
 * removed and NAME keeps its previous content. State: none kept between calls. */
#include "formats/xdmf.h"

#include "util/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* Writes s with the XML special characters escaped. */
static void put_escaped(FILE *f, const char *s) {
  for (; *s; s++) {
    switch (*s) {
    case '&':
      fputs("&amp;", f);
      break;
    case '<':
      fputs("&lt;", f);
      break;
    case '>':
      fputs("&gt;", f);
      break;
    case '"':
      fputs("&quot;", f);
      break;
    default:
      fputc(*s, f);
    }
  }
}

/* A DataItem: dims "N" or "N C", type Float (8) or Int (4 or 8), HDF5 path. */
static void data_item(FILE *f, const char *indent, size_t n, int cols, const char *type,
                      int prec, const char *h5, long frame, const char *dset) {
  fprintf(f, "%s<DataItem Dimensions=\"%zu", indent, n);
  if (cols > 1) fprintf(f, " %d", cols);
  fprintf(f, "\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">", type, prec);
  put_escaped(f, h5);
  fprintf(f, ":/frames/%06ld/%s</DataItem>\n", frame, dset);
}

static void attribute(FILE *f, const char *name, const char *kind, const char *center,
                      size_t n, int cols, const char *type, int prec, const char *h5,
                      long frame, const char *dset) {
  fprintf(f, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"%s\">\n", name,
          kind, center);
  data_item(f, "          ", n, cols, type, prec, h5, frame, dset);
  fputs("        </Attribute>\n", f);
}

static void grid_open(FILE *f, const char *what, const esf_xdmf_frame *fr) {
  fprintf(f, "      <Grid Name=\"%s_%06ld\" GridType=\"Uniform\">\n", what, fr->index);
  fprintf(f, "        <Time Value=\"%.17g\"/>\n", fr->time);
}

static void geometry(FILE *f, size_t n, const char *h5, long frame, const char *dset) {
  fputs("        <Geometry GeometryType=\"XYZ\">\n", f);
  data_item(f, "          ", n, 3, "Float", 8, h5, frame, dset);
  fputs("        </Geometry>\n", f);
}

static void particles(FILE *f, const char *h5, const esf_xdmf_frame *fr) {
  size_t n = fr->particles;
  long k = fr->index;
  grid_open(f, "particles", fr);
  fprintf(f,
          "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%zu\" "
          "NodesPerElement=\"1\"/>\n",
          n);
  geometry(f, n, h5, k, "position");
  attribute(f, "radius", "Scalar", "Node", n, 1, "Float", 8, h5, k, "radius");
  attribute(f, "velocity", "Vector", "Node", n, 3, "Float", 8, h5, k, "velocity");
  attribute(f, "angular_velocity", "Vector", "Node", n, 3, "Float", 8, h5, k,
            "angular_velocity");
  attribute(f, "force", "Vector", "Node", n, 3, "Float", 8, h5, k, "force");
  attribute(f, "material", "Scalar", "Node", n, 1, "Int", 4, h5, k, "material");
  attribute(f, "id", "Scalar", "Node", n, 1, "Int", 8, h5, k, "id");
  fputs("      </Grid>\n", f);
}

static void walls(FILE *f, const char *h5, const esf_xdmf_frame *fr) {
  long k = fr->index;
  grid_open(f, "walls", fr);
  fprintf(f, "        <Topology TopologyType=\"Triangle\" NumberOfElements=\"%zu\">\n",
          fr->wall_triangles);
  data_item(f, "          ", fr->wall_triangles, 3, "Int", 4, h5, k, "walls/triangles");
  fputs("        </Topology>\n", f);
  geometry(f, fr->wall_points, h5, k, "walls/points");
  attribute(f, "group", "Scalar", "Cell", fr->wall_triangles, 1, "Int", 4, h5, k,
            "walls/group");
  attribute(f, "material", "Scalar", "Cell", fr->wall_triangles, 1, "Int", 4, h5, k,
            "walls/material");
  fputs("      </Grid>\n", f);
}

static void contacts(FILE *f, const char *h5, const esf_xdmf_frame *fr) {
  long k = fr->index;
  grid_open(f, "contacts", fr);
  fprintf(f,
          "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"%zu\" "
          "NodesPerElement=\"2\">\n",
          fr->contacts);
  data_item(f, "          ", fr->contacts, 2, "Int", 8, h5, k, "contacts/pairs");
  fputs("        </Topology>\n", f);
  geometry(f, fr->particles, h5, k, "position");
  attribute(f, "normal_force", "Scalar", "Cell", fr->contacts, 1, "Float", 8, h5, k,
            "contacts/normal_force");
  fputs("      </Grid>\n", f);
}

typedef void (*grid_fn)(FILE *, const char *, const esf_xdmf_frame *);

/* One Temporal collection of the frames selected by `want` (0: all). */
static void collection(FILE *f, const char *name, grid_fn grid, int want_walls,
                       int want_contacts, const char *h5, const esf_xdmf_frame *frames,
                       size_t nframes) {
  size_t count = 0;
  for (size_t k = 0; k < nframes; k++)
    count += (!want_walls || frames[k].has_walls) &&
             (!want_contacts || frames[k].has_contacts);
  if (count == 0) return;
  fprintf(f,
          "    <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
          name);
  for (size_t k = 0; k < nframes; k++)
    if ((!want_walls || frames[k].has_walls) &&
        (!want_contacts || frames[k].has_contacts))
      grid(f, h5, &frames[k]);
  fputs("    </Grid>\n", f);
}

int esf_xdmf_write(const char *path, const char *h5_name, const esf_xdmf_frame *frames,
                   size_t nframes, esf_error *err) {
  char tmp[1100];
  if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
    return esf_fail(err, ESF_EIO, "path too long: %s", path);
  FILE *f = fopen(tmp, "w");
  if (!f) return esf_fail(err, ESF_EIO, "cannot write '%s': %s", tmp, strerror(errno));
  fputs("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
        "<Xdmf Version=\"3.0\">\n  <Domain>\n",
        f);
  collection(f, "particles", particles, 0, 0, h5_name, frames, nframes);
  collection(f, "walls", walls, 1, 0, h5_name, frames, nframes);
  collection(f, "contacts", contacts, 0, 1, h5_name, frames, nframes);
  fputs("  </Domain>\n</Xdmf>\n", f);
  int ok = fflush(f) == 0 && !ferror(f) && fsync(fileno(f)) == 0;
  int e = ok ? 0 : errno;
  if (fclose(f) != 0 && ok) {
    ok = 0;
    e = errno;
  }
  if (ok && rename(tmp, path) != 0) {
    ok = 0;
    e = errno;
  }
  if (!ok) {
    remove(tmp);
    return esf_fail(err, ESF_EIO, "cannot write '%s': %s", path, strerror(e));
  }
  (void)esf_fsync_parent(path, NULL); /* best effort: makes the rename durable */
  return ESF_OK;
}
