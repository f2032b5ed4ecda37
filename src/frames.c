/* frames.c — the frames writer: frames.h5 and frames.xdmf (frames.h, INTERFACE.md
 * "Output directory").
 *
 * Each esf_frames_write creates the group /frames/%06ld (k from 0, more digits past
 * 999999) with its time attribute and datasets (h5io.h: chunked with shuffle + deflate
 * from 1024 rows), the walls mesh (wall_mesh.h) sized to the particles' bounding box
 * (centres +- radii) and the contacts, flushes the pending /energy rows and the file,
 * then rewrites frames.xdmf (xdmf.h) from the list of frames kept here. A frame that
 * fails half-way is unlinked again (best effort) so the frame count stays consistent.
 * Every public function keeps HDF5 from printing (esf_h5_quiet) and adds its wall time
 * to `seconds`. The file, /frames and the /energy table stay open between
 * esf_frames_open and esf_frames_close; every other identifier is closed before
 * returning. */
#include "frames.h"

#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "atomic_file.h"
#include "h5io.h"
#include "h5table.h"
#include "wall_mesh.h"
#include "xdmf.h"

/* The XDMF is rewritten after each of the first XDMF_EVERY_FRAME_MAX frames; later
 * only once the time since the last rewrite is XDMF_COST_RATIO times what that rewrite
 * took (its whole-file cost then stays near 1% of the run), and at close. */
enum { XDMF_EVERY_FRAME_MAX = 100, XDMF_COST_RATIO = 100 };

struct esf_frames {
  hid_t file, frames;
  long count;
  char *path, *xdmf_path, *h5_name; /* h5_name: the base name, as the XDMF says it */
  esf_h5table *energy;
  esf_wall_mesh mesh;
  esf_xdmf_frame *xf; /* one record per frame written */
  size_t xf_cap;
  long xdmf_written; /* frames the XDMF on disk describes */
  double xdmf_last;  /* monotonic time at the end of its last rewrite, s */
  double xdmf_cost;  /* what that rewrite took, s */
  double seconds;    /* wall time spent writing */
};

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static char *dup_str(const char *s, size_t extra) {
  size_t n = strlen(s);
  char *c = malloc(n + extra + 1);
  if (c) memcpy(c, s, n + 1);
  return c;
}

static void destroy(esf_frames *fr) {
  if (fr->frames >= 0) H5Gclose(fr->frames);
  if (fr->file >= 0) H5Fclose(fr->file);
  esf_wall_mesh_release(&fr->mesh);
  free(fr->xf);
  free(fr->path);
  free(fr->xdmf_path);
  free(fr->h5_name);
  free(fr);
}

int esf_frames_open(const char *path, const char *scene_name, const char *version,
                    esf_frames **out, esf_error *err) {
  *out = NULL;
  esf_frames *fr = calloc(1, sizeof *fr);
  if (fr) {
    fr->file = fr->frames = -1;
    fr->path = dup_str(path, 0);
    fr->xdmf_path = dup_str(path, 5);
    const char *slash = strrchr(path, '/');
    fr->h5_name = dup_str(slash ? slash + 1 : path, 0);
  }
  if (!fr || !fr->path || !fr->xdmf_path || !fr->h5_name) {
    if (fr) destroy(fr);
    return esf_fail(err, ESF_ENOMEM, "out of memory opening '%s'", path);
  }
  size_t len = strlen(path);
  if (len >= 3 && strcmp(path + len - 3, ".h5") == 0) fr->xdmf_path[len - 3] = '\0';
  strcat(fr->xdmf_path, ".xdmf");
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = ESF_OK;
  /* chunk-index B-tree nodes of 8 entries, not 64: most datasets have one chunk, and
     the default node (~2.5 kB each) made up 11% of a 3000-particle frame */
  hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0) H5Pset_istore_k(fcpl, 4);
  fr->file = H5Fcreate(path, H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, H5P_DEFAULT);
  if (fcpl >= 0) H5Pclose(fcpl);
  if (fr->file < 0) {
    rc = esf_h5_fail(err, "cannot create frames file", path);
  } else if (esf_h5_attr_write_string(fr->file, "scene", scene_name ? scene_name : "") <
                 0 ||
             esf_h5_attr_write_string(fr->file, "esfera_version",
                                      version ? version : "") < 0 ||
             esf_h5_attr_write_string(fr->file, "kind", "frames") < 0) {
    rc = esf_h5_fail(err, "cannot write the root attributes of", path);
  } else {
    fr->frames = H5Gcreate2(fr->file, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (fr->frames < 0) rc = esf_h5_fail(err, "cannot create group /frames in", path);
  }
  if (rc) {
    destroy(fr);
    H5Eclear2(H5E_DEFAULT);
  } else {
    *out = fr;
  }
  esf_h5_quiet_end(&q);
  return rc;
}

/* The particles' bounding box (centres +- radii); 0 when there are none. */
static int particle_box(const esf_particles *p, double lo[3], double hi[3]) {
  for (size_t i = 0; i < p->n; i++)
    for (int q = 0; q < 3; q++) {
      double a = p->x[3 * i + q] - p->radius[i], b = p->x[3 * i + q] + p->radius[i];
      lo[q] = i ? (a < lo[q] ? a : lo[q]) : a;
      hi[q] = i ? (b > hi[q] ? b : hi[q]) : b;
    }
  return p->n > 0;
}

static int write_particles(hid_t g, const esf_particles *p) {
  size_t n = p->n;
  hid_t f64 = H5T_IEEE_F64LE, d = H5T_NATIVE_DOUBLE;
  return esf_h5_dataset_write(g, "id", H5T_STD_I64LE, H5T_NATIVE_INT64, n, 1, p->id) ||
         esf_h5_dataset_write(g, "position", f64, d, n, 3, p->x) ||
         esf_h5_dataset_write(g, "velocity", f64, d, n, 3, p->v) ||
         esf_h5_dataset_write(g, "angular_velocity", f64, d, n, 3, p->w) ||
         esf_h5_dataset_write(g, "force", f64, d, n, 3, p->f) ||
         esf_h5_dataset_write(g, "radius", f64, d, n, 1, p->radius) ||
         esf_h5_dataset_write(g, "material", H5T_STD_I32LE, H5T_NATIVE_INT32, n, 1,
                              p->material);
}

static int write_walls(hid_t frame, const esf_wall_mesh *m) {
  hid_t g = H5Gcreate2(frame, "walls", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  hid_t i32 = H5T_STD_I32LE, ni32 = H5T_NATIVE_INT32;
  int bad = g < 0 ||
            esf_h5_dataset_write(g, "points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, m->np, 3,
                                 m->points) ||
            esf_h5_dataset_write(g, "triangles", i32, ni32, m->nt, 3, m->tri) ||
            esf_h5_dataset_write(g, "group", i32, ni32, m->nt, 1, m->group) ||
            esf_h5_dataset_write(g, "material", i32, ni32, m->nt, 1, m->material);
  if (g >= 0 && H5Gclose(g) < 0) bad = 1;
  return bad ? -1 : 0;
}

static int write_contacts(hid_t frame, const esf_contact_net *c) {
  hid_t g = H5Gcreate2(frame, "contacts", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int bad = g < 0 ||
            esf_h5_dataset_write(g, "pairs", H5T_STD_I64LE, H5T_NATIVE_INT64, c->n, 2,
                                 c->pair) ||
            esf_h5_dataset_write(g, "normal_force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                                 c->n, 1, c->fn);
  if (g >= 0 && H5Gclose(g) < 0) bad = 1;
  return bad ? -1 : 0;
}

/* Rewrites the XDMF when due (force: always, if it is behind). */
static int update_xdmf(esf_frames *fr, int force, esf_error *err) {
  if (fr->xdmf_written == fr->count) return ESF_OK;
  double t = now_s();
  if (!force && fr->count > XDMF_EVERY_FRAME_MAX &&
      t - fr->xdmf_last < XDMF_COST_RATIO * fr->xdmf_cost)
    return ESF_OK;
  int rc = esf_xdmf_write(fr->xdmf_path, fr->h5_name, fr->xf, (size_t)fr->count, err);
  if (!rc) {
    fr->xdmf_written = fr->count;
    fr->xdmf_last = now_s();
    fr->xdmf_cost = fr->xdmf_last - t;
  }
  return rc;
}

/* Appends the XDMF record of the frame being written. */
static int record(esf_frames *fr, const esf_xdmf_frame *x, esf_error *err) {
  if ((size_t)fr->count == fr->xf_cap) {
    size_t cap = fr->xf_cap ? 2 * fr->xf_cap : 64;
    esf_xdmf_frame *n = realloc(fr->xf, cap * sizeof *n);
    if (!n) return esf_fail(err, ESF_ENOMEM, "out of memory for the frame list");
    fr->xf = n;
    fr->xf_cap = cap;
  }
  fr->xf[fr->count] = *x;
  return ESF_OK;
}

int esf_frames_write(esf_frames *fr, double time, const esf_particles *p,
                     const esf_walls *walls, const esf_contact_net *contacts,
                     esf_error *err) {
  if (!fr) return esf_fail(err, ESF_EINTERNAL, "frames: write on a closed file");
  double t0 = now_s();
  char name[32];
  snprintf(name, sizeof name, "%06ld", fr->count);
  esf_xdmf_frame x = {time, fr->count, p->n, 0, 0, 0, 0, 0};
  int with_walls = walls && walls->n > 0;
  double lo[3], hi[3];
  int have_box = particle_box(p, lo, hi);
  int rc = with_walls ? esf_wall_mesh_build(walls, time, have_box ? lo : NULL,
                                            have_box ? hi : NULL, &fr->mesh, err)
                      : ESF_OK;
  if (!rc) rc = record(fr, &x, err);
  if (rc) return rc;
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  hid_t g = H5Gcreate2(fr->frames, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int ok = g >= 0 && esf_h5_attr_write_double(g, "time", time) == 0 &&
           write_particles(g, p) == 0 &&
           (!with_walls || write_walls(g, &fr->mesh) == 0) &&
           (!contacts || write_contacts(g, contacts) == 0);
  if (!ok) {
    char what[96];
    snprintf(what, sizeof what, "cannot write frame %s to", name);
    rc = esf_h5_fail(err, what, fr->path);
  }
  if (g >= 0 && H5Gclose(g) < 0 && rc == ESF_OK)
    rc = esf_h5_fail(err, "cannot close a frame group in", fr->path);
  if (!rc) rc = esf_h5table_flush(fr->energy, err);
  if (!rc && H5Fflush(fr->file, H5F_SCOPE_LOCAL) < 0)
    rc = esf_h5_fail(err, "cannot flush", fr->path);
  if (rc == ESF_OK) {
    fr->xf[fr->count].has_walls = with_walls;
    fr->xf[fr->count].wall_points = with_walls ? fr->mesh.np : 0;
    fr->xf[fr->count].wall_triangles = with_walls ? fr->mesh.nt : 0;
    fr->xf[fr->count].has_contacts = contacts != NULL;
    fr->xf[fr->count].contacts = contacts ? contacts->n : 0;
    fr->count++;
    rc = update_xdmf(fr, 0, err);
  } else if (g >= 0) {
    H5Ldelete(fr->frames, name, H5P_DEFAULT); /* best effort: keep the count coherent */
    H5Eclear2(H5E_DEFAULT);
  }
  esf_h5_quiet_end(&q);
  fr->seconds += now_s() - t0;
  return rc;
}

int esf_frames_append_energy(esf_frames *fr, int ncols, const char *const *names,
                             const double *row, esf_error *err) {
  if (!fr) return esf_fail(err, ESF_EINTERNAL, "frames: energy row on a closed file");
  if (fr->energy && esf_h5table_ncols(fr->energy) != ncols)
    return esf_fail(err, ESF_EINTERNAL, "frames: energy rows of %d and %d columns",
                    esf_h5table_ncols(fr->energy), ncols);
  double t0 = now_s();
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = ESF_OK;
  if (!fr->energy)
    rc = esf_h5table_create(fr->file, "energy", ncols, names, fr->path, &fr->energy, err);
  if (!rc) rc = esf_h5table_append(fr->energy, row, err);
  esf_h5_quiet_end(&q);
  fr->seconds += now_s() - t0;
  return rc;
}

long esf_frames_count(const esf_frames *fr) { return fr ? fr->count : 0; }

long esf_frames_energy_rows(const esf_frames *fr) {
  return fr ? (long)esf_h5table_rows(fr->energy) : 0;
}

double esf_frames_seconds(const esf_frames *fr) { return fr ? fr->seconds : 0.0; }

int esf_frames_close(esf_frames **frp, esf_error *err) {
  if (!frp || !*frp) return ESF_OK;
  esf_frames *fr = *frp;
  *frp = NULL;
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = esf_h5table_close(&fr->energy, err);
  int rc2 = update_xdmf(fr, 1, rc ? NULL : err);
  if (!rc) rc = rc2;
  if (H5Gclose(fr->frames) < 0 && rc == ESF_OK)
    rc = esf_h5_fail(err, "cannot close group /frames in", fr->path);
  fr->frames = -1;
  if (H5Fflush(fr->file, H5F_SCOPE_LOCAL) < 0 && rc == ESF_OK)
    rc = esf_h5_fail(err, "cannot flush", fr->path);
  if (H5Fclose(fr->file) < 0 && rc == ESF_OK)
    rc = esf_h5_fail(err, "cannot close", fr->path);
  fr->file = -1;
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  destroy(fr);
  return rc;
}

/* ---- checkpoints (checkpoint.h): syncing, and a resumed run's copy of the frames
 * written before its checkpoint ---- */

int esf_frames_sync(esf_frames *fr, esf_error *err) {
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = esf_h5table_flush(fr->energy, err);
  if (!rc && H5Fflush(fr->file, H5F_SCOPE_LOCAL) < 0)
    rc = esf_h5_fail(err, "cannot flush", fr->path);
  esf_h5_quiet_end(&q);
  if (!rc) rc = esf_fsync_path(fr->path, err);
  if (!rc) rc = update_xdmf(fr, 1, err);
  return rc;
}

/* Rows of the first dimension (and the second, 0 for rank 1) of dataset loc/name. */
static int dims_of(hid_t loc, const char *name, size_t *d0) {
  hid_t d = H5Dopen2(loc, name, H5P_DEFAULT), s = d >= 0 ? H5Dget_space(d) : -1;
  hsize_t dims[2] = {0, 0};
  int ok = s >= 0 && H5Sget_simple_extent_ndims(s) >= 1 &&
           H5Sget_simple_extent_dims(s, dims, NULL) >= 1;
  if (s >= 0) H5Sclose(s);
  if (d >= 0) H5Dclose(d);
  *d0 = (size_t)dims[0];
  return ok ? 0 : -1;
}

/* Copies frame `name` of src into fr as its next frame, with its XDMF record. */
static int copy_frame(esf_frames *fr, hid_t src, const char *name) {
  if (H5Ocopy(src, name, fr->frames, name, H5P_DEFAULT, H5P_DEFAULT) < 0) return -1;
  hid_t g = H5Gopen2(fr->frames, name, H5P_DEFAULT);
  if (g < 0) return -1;
  esf_xdmf_frame x = {0};
  x.index = fr->count;
  hid_t a = H5Aopen(g, "time", H5P_DEFAULT);
  int ok = a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &x.time) >= 0;
  if (a >= 0) H5Aclose(a);
  ok = ok && dims_of(g, "position", &x.particles) == 0;
  x.has_walls = H5Lexists(g, "walls", H5P_DEFAULT) > 0;
  if (ok && x.has_walls)
    ok = dims_of(g, "walls/points", &x.wall_points) == 0 &&
         dims_of(g, "walls/triangles", &x.wall_triangles) == 0;
  x.has_contacts = H5Lexists(g, "contacts", H5P_DEFAULT) > 0;
  if (ok && x.has_contacts) ok = dims_of(g, "contacts/normal_force", &x.contacts) == 0;
  H5Gclose(g);
  if (!ok || record(fr, &x, NULL)) return -1;
  fr->count++;
  return 0;
}

int esf_frames_copy(esf_frames *fr, const char *src_path, long nframes, long nrows,
                    int ncols, const char *const *names, esf_error *err) {
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = ESF_OK;
  hid_t f = H5Fopen(src_path, H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t src = f >= 0 ? H5Gopen2(f, "frames", H5P_DEFAULT) : -1;
  if (src < 0) rc = esf_h5_fail(err, "cannot read the frames of", src_path);
  for (long k = 0; !rc && k < nframes; k++) {
    char name[32];
    snprintf(name, sizeof name, "%06ld", k);
    if (copy_frame(fr, src, name)) {
      char what[96];
      snprintf(what, sizeof what, "cannot copy frame %s (of %ld) from", name, nframes);
      rc = esf_h5_fail(err, what, src_path);
    }
  }
  double *cols = NULL;
  if (!rc && nrows > 0) {
    cols = malloc((size_t)nrows * (size_t)ncols * sizeof *cols);
    if (!cols) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
    for (int j = 0; !rc && j < ncols; j++) {
      char path[160];
      snprintf(path, sizeof path, "energy/%s", names[j]);
      hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
      hid_t fs = d >= 0 ? H5Dget_space(d) : -1;
      hsize_t start = 0, cnt = (hsize_t)nrows, dims[1] = {0};
      int ok = fs >= 0 && H5Sget_simple_extent_dims(fs, dims, NULL) == 1 &&
               dims[0] >= cnt &&
               H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &cnt, NULL) >= 0;
      hid_t ms = ok ? H5Screate_simple(1, &cnt, NULL) : -1;
      ok = ok && ms >= 0 &&
           H5Dread(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, cols + (size_t)j * nrows) >=
               0;
      if (ms >= 0) H5Sclose(ms);
      if (fs >= 0) H5Sclose(fs);
      if (d >= 0) H5Dclose(d);
      if (!ok) rc = esf_h5_fail(err, "cannot read the energy rows of", src_path);
    }
  }
  if (src >= 0) H5Gclose(src);
  if (f >= 0) H5Fclose(f);
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  double *row = !rc && nrows > 0 ? malloc((size_t)ncols * sizeof *row) : NULL;
  if (!rc && nrows > 0 && !row) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
  for (long r = 0; !rc && r < nrows; r++) {
    for (int j = 0; j < ncols; j++) row[j] = cols[(size_t)j * nrows + r];
    rc = esf_frames_append_energy(fr, ncols, names, row, err);
  }
  free(row);
  free(cols);
  if (!rc) rc = esf_frames_sync(fr, err);
  return rc;
}
