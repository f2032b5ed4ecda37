/* xdmf.c — the XDMF 3 description of frames.h5 (xdmf.h).
 *
 * Writes the whole file each time: NAME.tmp is written with stdio, flushed (and, when
 * durable, fsync'ed) and renamed over NAME (rename is atomic on POSIX file systems);
 * when durable the directory is fsync'ed afterwards, best effort. Times are printed with
 * 17 significant digits, so they read back as the frames' exact `time` attributes. On
 * failure NAME.tmp is removed and NAME keeps its previous content. State: none kept
 * between calls. */
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

/* What every grid of one file needs: the HDF5 file's name, the length of its
 * /vertex_index, and whether the file holds the particles alone. */
typedef struct ctx {
  const char *h5;
  size_t nmax;
  int solo;
} ctx;

static void grid_open(FILE *f, const char *what, const esf_xdmf_frame *fr) {
  fprintf(f, "      <Grid Name=\"%s_%06ld\" GridType=\"Uniform\">\n", what, fr->index);
  fprintf(f, "        <Time Value=\"%.17g\"/>\n", fr->time);
}

static void geometry(FILE *f, size_t n, const char *h5, long frame, const char *dset) {
  fputs("        <Geometry GeometryType=\"XYZ\">\n", f);
  data_item(f, "          ", n, 3, "Float", 8, h5, frame, dset);
  fputs("        </Geometry>\n", f);
}

/* N vertex cells on points 0..N-1: the index's /vertex_index whole, or its first N
 * entries as a hyperslab (start 0, stride 1, count N). A Polyvertex without this
 * connectivity loads as points without cells in ParaView's Xdmf3 readers. */
static void vertex_cells(FILE *f, const ctx *c, size_t n) {
  fprintf(f,
          "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%zu\" "
          "NodesPerElement=\"1\">\n",
          n);
  const char *in = "          ";
  if (n < c->nmax) {
    fprintf(f,
            "%s<DataItem ItemType=\"HyperSlab\" Dimensions=\"%zu\" Type=\"HyperSlab\">\n",
            in, n);
    fprintf(f, "%s  <DataItem Dimensions=\"3 1\" Format=\"XML\">0 1 %zu</DataItem>\n", in,
            n);
    in = "            ";
  }
  fprintf(f,
          "%s<DataItem Dimensions=\"%zu\" NumberType=\"Int\" Precision=\"4\" "
          "Format=\"HDF\">",
          in, c->nmax);
  put_escaped(f, c->h5);
  fputs(":/vertex_index</DataItem>\n", f);
  if (n < c->nmax) fputs("          </DataItem>\n", f);
  fputs("        </Topology>\n", f);
}

/* A topology of no cells: no DataItem (an empty HDF5 dataset stops the XDMF 2 reader:
 * "Error in Update() of Topology"), and no cell attributes. */
static void no_cells(FILE *f, const char *type, int nodes) {
  fprintf(f,
          "        <Topology TopologyType=\"%s\" NumberOfElements=\"0\" "
          "NodesPerElement=\"%d\"/>\n",
          type, nodes);
}

static void particles(FILE *f, const ctx *c, const esf_xdmf_frame *fr) {
  const char *h5 = c->h5;
  size_t n = fr->particles;
  long k = fr->index;
  grid_open(f, "particles", fr);
  if (n == 0) { /* every particle gone: an empty grid (docs/output.md#paraview) */
    no_cells(f, "Polyvertex", 1);
    geometry(f, n, h5, k, "position");
    fputs("      </Grid>\n", f);
    return;
  }
  vertex_cells(f, c, n);
  geometry(f, n, h5, k, "position");
  if (c->solo) /* meshio's time series gives attributes per frame, not the geometry */
    attribute(f, "position", "Vector", "Node", n, 3, "Float", 8, h5, k, "position");
  attribute(f, "radius", "Scalar", "Node", n, 1, "Float", 8, h5, k, "radius");
  attribute(f, "velocity", "Vector", "Node", n, 3, "Float", 8, h5, k, "velocity");
  attribute(f, "angular_velocity", "Vector", "Node", n, 3, "Float", 8, h5, k,
            "angular_velocity");
  attribute(f, "force", "Vector", "Node", n, 3, "Float", 8, h5, k, "force");
  attribute(f, "material", "Scalar", "Node", n, 1, "Int", 4, h5, k, "material");
  attribute(f, "id", "Scalar", "Node", n, 1, "Int", 8, h5, k, "id");
  if (fr->has_contacts) /* written with the contact network */
    attribute(f, "coordination", "Scalar", "Node", n, 1, "Int", 4, h5, k, "coordination");
  if (fr->has_image)
    attribute(f, "image", "Vector", "Node", n, 3, "Int", 4, h5, k, "image");
  fputs("      </Grid>\n", f);
}

static void walls(FILE *f, const ctx *c, const esf_xdmf_frame *fr) {
  const char *h5 = c->h5;
  long k = fr->index;
  grid_open(f, "walls", fr);
  if (fr->wall_triangles == 0) {
    no_cells(f, "Triangle", 3);
  } else {
    fprintf(f, "        <Topology TopologyType=\"Triangle\" NumberOfElements=\"%zu\">\n",
            fr->wall_triangles);
    data_item(f, "          ", fr->wall_triangles, 3, "Int", 4, h5, k, "walls/triangles");
    fputs("        </Topology>\n", f);
  }
  geometry(f, fr->wall_points, h5, k, "walls/points");
  if (fr->wall_triangles > 0) {
    attribute(f, "group", "Scalar", "Cell", fr->wall_triangles, 1, "Int", 4, h5, k,
              "walls/group");
    attribute(f, "material", "Scalar", "Cell", fr->wall_triangles, 1, "Int", 4, h5, k,
              "walls/material");
  }
  fputs("      </Grid>\n", f);
}

static void contacts(FILE *f, const ctx *c, const esf_xdmf_frame *fr) {
  const char *h5 = c->h5;
  long k = fr->index;
  grid_open(f, "contacts", fr);
  if (fr->contacts == 0) {
    no_cells(f, "Polyline", 2);
  } else {
    fprintf(f,
            "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"%zu\" "
            "NodesPerElement=\"2\">\n",
            fr->contacts);
    data_item(f, "          ", fr->contacts, 2, "Int", 8, h5, k, "contacts/pairs");
    fputs("        </Topology>\n", f);
  }
  geometry(f, fr->particles, h5, k, "position");
  if (fr->contacts > 0) {
    attribute(f, "normal_force", "Scalar", "Cell", fr->contacts, 1, "Float", 8, h5, k,
              "contacts/normal_force");
    attribute(f, "tangential_force", "Vector", "Cell", fr->contacts, 3, "Float", 8, h5, k,
              "contacts/tangential_force");
  }
  fputs("      </Grid>\n", f);
}

typedef void (*grid_fn)(FILE *, const ctx *, const esf_xdmf_frame *);

/* Whether frame fr has a grid of kind `kind`. */
static int has(int kind, const esf_xdmf_frame *fr) {
  return kind == ESF_XDMF_PARTICLES || (kind == ESF_XDMF_WALLS && fr->has_walls) ||
         (kind == ESF_XDMF_CONTACTS && fr->has_contacts);
}

/* One Temporal collection of the frames that have a grid of this kind. */
static void collection(FILE *f, const char *name, int kind, grid_fn grid, const ctx *c,
                       const esf_xdmf_frame *frames, size_t nframes) {
  size_t count = 0;
  for (size_t k = 0; k < nframes; k++) count += has(kind, &frames[k]);
  if (count == 0) return;
  fprintf(f,
          "    <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
          name);
  for (size_t k = 0; k < nframes; k++)
    if (has(kind, &frames[k])) grid(f, c, &frames[k]);
  fputs("    </Grid>\n", f);
}

int esf_xdmf_any(int kind, const esf_xdmf_frame *frames, size_t nframes) {
  for (size_t k = 0; k < nframes; k++)
    if (has(kind, &frames[k])) return 1;
  return 0;
}

int esf_xdmf_write(const char *path, const char *h5_name, int kinds,
                   const esf_xdmf_frame *frames, size_t nframes, int durable,
                   esf_error *err) {
  char tmp[1100];
  if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
    return esf_fail(err, ESF_EIO, "path too long: %s", path);
  FILE *f = fopen(tmp, "w");
  if (!f) return esf_fail(err, ESF_EIO, "cannot write '%s': %s", tmp, strerror(errno));
  fputs("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
        "<Xdmf Version=\"3.0\">\n  <Domain>\n",
        f);
  ctx c = {h5_name, 0, kinds == ESF_XDMF_PARTICLES};
  for (size_t k = 0; k < nframes; k++)
    if (frames[k].particles > c.nmax) c.nmax = frames[k].particles;
  if (kinds & ESF_XDMF_PARTICLES)
    collection(f, "particles", ESF_XDMF_PARTICLES, particles, &c, frames, nframes);
  if (kinds & ESF_XDMF_WALLS)
    collection(f, "walls", ESF_XDMF_WALLS, walls, &c, frames, nframes);
  if (kinds & ESF_XDMF_CONTACTS)
    collection(f, "contacts", ESF_XDMF_CONTACTS, contacts, &c, frames, nframes);
  fputs("  </Domain>\n</Xdmf>\n", f);
  int ok = fflush(f) == 0 && !ferror(f) && (!durable || fsync(fileno(f)) == 0);
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
  if (durable) (void)esf_fsync_parent(path, NULL); /* best effort: the rename */
  return ESF_OK;
}
