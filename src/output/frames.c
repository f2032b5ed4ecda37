/* frames.c — the frames writer: frames.h5, its segment files and frames.xdmf
 * (frames.h, frames_index.h, docs/output.md#frames).
 *
 * Frames go into segment files DIR.d/SSSSSS.h5 (SSSSSS: the segment's first frame); a
 * segment is created at the first frame after the start or after a checkpoint, and
 * each esf_frames_write adds the group /frames/%06ld (k from 0) with its time
 * attribute and datasets (h5io.h: chunked with shuffle + deflate from 1024 rows), the
 * walls mesh (wall_mesh.h) sized to the particles' bounding box (centres +- radii) and
 * the contacts, and flushes the segment. A frame that fails half-way is unlinked again
 * (best effort) so the frame count stays consistent. Energy rows are kept here (all of
 * them, row-major). "Publishing" rewrites the index frames.h5 (external links to every
 * frame, the energy rows; frames_index.c, replaced atomically) and then frames.xdmf
 * (xdmf.h, which reads through the index): after each of the first PUBLISH_EVERY_MAX
 * frames, later when due by cost, at every checkpoint and at close. A checkpoint
 * (esf_frames_sync) closes the segment and fsyncs it and the segment directory, then
 * publishes durably: from then on nothing touches the frames it counts, so a process
 * killed at any instant cannot damage them, and a resume (esf_frames_resume) only drops
 * later segments and writes a new index. Every public function keeps HDF5 from printing
 * (esf_h5_quiet) and adds its wall time to `seconds`. Between calls only the open
 * segment (file and /frames) stays open. */
#include "output/frames.h"
#include "util/clock.h"

#include <dirent.h>
#include <errno.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bodies/wall_mesh.h"
#include "formats/h5io.h"
#include "formats/xdmf.h"
#include "output/frames_index.h"
#include "util/atomic_file.h"

/* The index and XDMF are rewritten after each of the first PUBLISH_EVERY_MAX frames;
 * later only once the time since the last rewrite is PUBLISH_COST_RATIO times what
 * that rewrite took (its whole-run cost then stays near 1%), and at checkpoints and
 * close. */
enum { PUBLISH_EVERY_MAX = 10, PUBLISH_COST_RATIO = 100 };

struct esf_frames {
  hid_t seg, segframes; /* the open segment and its /frames; -1: none open */
  long seg_start;       /* the open segment's first frame */
  long count;
  char *path, *xdmf_path, *h5_name; /* h5_name: the base name, as the XDMF says it */
  char *kind_path[3];       /* BASE_particles.xdmf, BASE_walls.xdmf, BASE_contacts.xdmf */
  char *seg_dir, *seg_name; /* DIR.d as a path and relative to the index */
  char *scene, *version;
  esf_wall_mesh mesh;
  esf_xdmf_frame *xf; /* one record per frame written */
  long *seg_of;       /* the segment of each frame */
  size_t xf_cap;
  int ncols;                /* energy columns (0: no row yet) */
  const char *const *names; /* their names (the caller's, outliving fr) */
  double *rows;             /* energy rows, row-major */
  long nrows;
  size_t rows_cap;
  long pub_frames, pub_rows; /* what the index on disk holds (-1: nothing yet) */
  double pub_last;           /* monotonic time at the end of the last publishing, s */
  double pub_cost;           /* what it took, s */
  double seconds;            /* wall time spent writing */
};

static char *dup_str(const char *s, size_t extra) {
  size_t n = strlen(s);
  char *c = malloc(n + extra + 1);
  if (c) memcpy(c, s, n + 1);
  return c;
}

static void destroy(esf_frames *fr) {
  if (fr->segframes >= 0) H5Gclose(fr->segframes);
  if (fr->seg >= 0) H5Fclose(fr->seg);
  esf_wall_mesh_release(&fr->mesh);
  free(fr->xf);
  free(fr->seg_of);
  free(fr->rows);
  free(fr->path);
  free(fr->xdmf_path);
  for (int i = 0; i < 3; i++) free(fr->kind_path[i]);
  free(fr->h5_name);
  free(fr->seg_dir);
  free(fr->seg_name);
  free(fr->scene);
  free(fr->version);
  free(fr);
}

/* A writer for path with its names set, nothing on disk yet. */
static int create(const char *path, const char *scene, const char *version,
                  esf_frames **out, esf_error *err) {
  *out = NULL;
  esf_frames *fr = calloc(1, sizeof *fr);
  if (fr) {
    fr->seg = fr->segframes = -1;
    fr->pub_frames = fr->pub_rows = -1;
    fr->path = dup_str(path, 0);
    fr->xdmf_path = dup_str(path, 5);
    fr->seg_dir = dup_str(path, 2);
    const char *slash = strrchr(path, '/');
    fr->h5_name = dup_str(slash ? slash + 1 : path, 0);
    fr->seg_name = dup_str(slash ? slash + 1 : path, 2);
    fr->scene = dup_str(scene ? scene : "", 0);
    fr->version = dup_str(version ? version : "", 0);
  }
  if (!fr || !fr->path || !fr->xdmf_path || !fr->h5_name || !fr->seg_dir ||
      !fr->seg_name || !fr->scene || !fr->version) {
    if (fr) destroy(fr);
    return esf_fail(err, ESF_ENOMEM, "out of memory opening '%s'", path);
  }
  size_t len = strlen(path), blen = strlen(fr->seg_name);
  int h5 = len >= 3 && strcmp(path + len - 3, ".h5") == 0;
  if (h5) {
    fr->xdmf_path[len - 3] = fr->seg_dir[len - 3] = fr->seg_name[blen - 3] = '\0';
  }
  for (int i = 0; i < 3; i++) {
    static const char *const kind[3] = {"_particles.xdmf", "_walls.xdmf",
                                        "_contacts.xdmf"};
    fr->kind_path[i] = malloc(strlen(fr->xdmf_path) + strlen(kind[i]) + 1);
    if (!fr->kind_path[i]) {
      destroy(fr);
      return esf_fail(err, ESF_ENOMEM, "out of memory opening '%s'", path);
    }
    strcat(strcpy(fr->kind_path[i], fr->xdmf_path), kind[i]);
  }
  strcat(fr->xdmf_path, ".xdmf");
  strcat(fr->seg_dir, ".d");
  strcat(fr->seg_name, ".d");
  *out = fr;
  return ESF_OK;
}

/* Removes the segments of seg_dir whose first frame is from or later (and temporary
 * files), creating the directory if needed; then syncs it. */
static int drop_segments(esf_frames *fr, long from, esf_error *err) {
  if (mkdir(fr->seg_dir, 0777) != 0 && errno != EEXIST)
    return esf_fail(err, ESF_EIO,
                    "cannot create frames file '%s': its directory '%s': %s", fr->path,
                    fr->seg_dir, strerror(errno));
  DIR *d = opendir(fr->seg_dir);
  if (!d)
    return esf_fail(err, ESF_EIO, "cannot read '%s': %s", fr->seg_dir, strerror(errno));
  int rc = ESF_OK;
  for (struct dirent *e; !rc && (e = readdir(d)) != NULL;) {
    char *end = NULL;
    long s = strtol(e->d_name, &end, 10);
    if (end == e->d_name || s < from || strncmp(end, ".h5", 3) != 0) continue;
    char p[1400];
    snprintf(p, sizeof p, "%s/%s", fr->seg_dir, e->d_name);
    if (unlink(p) != 0 && errno != ENOENT)
      rc = esf_fail(err, ESF_EIO, "cannot remove '%s': %s", p, strerror(errno));
  }
  closedir(d);
  char probe[1400];
  snprintf(probe, sizeof probe, "%s/.", fr->seg_dir);
  return rc ? rc : esf_fsync_parent(probe, err);
}

/* The segment file of frames starting at start. */
static void seg_path(const esf_frames *fr, long start, char *p, size_t n) {
  snprintf(p, n, "%s/%06ld.h5", fr->seg_dir, start);
}

/* Creates the segment whose first frame is the next one. */
static int seg_open(esf_frames *fr, esf_error *err) {
  char p[1400];
  seg_path(fr, fr->count, p, sizeof p);
  /* chunk-index B-tree nodes of 8 entries, not 64: most datasets have one chunk, and
     the default node (~2.5 kB each) is a large share of a small frame
     (docs/performance.md#frame-files) */
  hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0) H5Pset_istore_k(fcpl, 4);
  fr->seg = H5Fcreate(p, H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, H5P_DEFAULT);
  if (fcpl >= 0) H5Pclose(fcpl);
  if (fr->seg < 0) return esf_h5_fail(err, "cannot create frames segment", p);
  fr->seg_start = fr->count;
  if (esf_h5_attr_write_string(fr->seg, "scene", fr->scene) < 0 ||
      esf_h5_attr_write_string(fr->seg, "esfera_version", fr->version) < 0 ||
      esf_h5_attr_write_string(fr->seg, "kind", "frames") < 0 ||
      (fr->segframes =
           H5Gcreate2(fr->seg, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)) < 0)
    return esf_h5_fail(err, "cannot start frames segment", p);
  return ESF_OK;
}

/* Closes the open segment (if any); with durable, fsyncs it and its directory. */
static int seg_close(esf_frames *fr, int durable, esf_error *err) {
  if (fr->seg < 0) return ESF_OK;
  char p[1400];
  seg_path(fr, fr->seg_start, p, sizeof p);
  int bad = H5Gclose(fr->segframes) < 0;
  bad |= H5Fclose(fr->seg) < 0;
  fr->seg = fr->segframes = -1;
  if (bad) return esf_h5_fail(err, "cannot close frames segment", p);
  int rc = durable ? esf_fsync_path(p, err) : ESF_OK;
  return !rc && durable ? esf_fsync_parent(p, err) : rc;
}

/* Rewrites the index, then the XDMF, when due (force: whenever behind; durable: the
 * index is fsync'ed). */
static int publish(esf_frames *fr, int force, int durable, esf_error *err) {
  if (fr->pub_frames == fr->count && (!force || fr->pub_rows == fr->nrows)) return ESF_OK;
  double t = esf_now_s();
  if (!force && fr->count > PUBLISH_EVERY_MAX &&
      t - fr->pub_last < PUBLISH_COST_RATIO * fr->pub_cost)
    return ESF_OK;
  size_t nmax = 0; /* the vertex cells' index covers the largest frame */
  for (long k = 0; k < fr->count; k++)
    if (fr->xf[k].particles > nmax) nmax = fr->xf[k].particles;
  esf_frames_index ix = {fr->scene, fr->version, fr->seg_name, fr->count, fr->seg_of,
                         fr->ncols, fr->names,   fr->nrows,    fr->rows,  nmax};
  int rc = esf_frames_index_write(fr->path, &ix, durable, err);
  const size_t nf = (size_t)fr->count;
  if (!rc && fr->count > 0)
    rc = esf_xdmf_write(fr->xdmf_path, fr->h5_name, ESF_XDMF_ALL, fr->xf, nf, durable,
                        err);
  /* each kind alone, for the readers that merge a file's grids into one dataset */
  for (int i = 0; i < 3 && !rc && fr->count > 0; i++)
    if (esf_xdmf_any(1 << i, fr->xf, nf))
      rc =
          esf_xdmf_write(fr->kind_path[i], fr->h5_name, 1 << i, fr->xf, nf, durable, err);
  if (!rc) {
    fr->pub_frames = fr->count;
    fr->pub_rows = fr->nrows;
    fr->pub_last = esf_now_s();
    fr->pub_cost = fr->pub_last - t;
  }
  return rc;
}

int esf_frames_open(const char *path, const char *scene_name, const char *version,
                    esf_frames **out, esf_error *err) {
  *out = NULL;
  esf_frames *fr = NULL;
  int rc = create(path, scene_name, version, &fr, err);
  if (!rc) rc = drop_segments(fr, 0, err);
  if (!rc) rc = publish(fr, 1, 0, err);
  if (rc && fr) destroy(fr);
  if (!rc) *out = fr;
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

/* Frames list the particles in ascending id whatever order the run keeps them in
 * (reorder.h): ord[r] is the particle written in row r, row[i] the row of particle i;
 * both NULL when the ids already ascend. */
typedef struct id_order {
  size_t *ord, *row;
  void *buf; /* 3 n doubles of scratch */
} id_order;

static int by_id(const void *x, const void *y) {
  const int64_t *a = x, *b = y; /* (id, index) */
  return (a[0] > b[0]) - (a[0] < b[0]);
}

static int id_order_make(const esf_particles *p, id_order *o, esf_error *err) {
  memset(o, 0, sizeof *o);
  size_t n = p->n, i = 1;
  while (i < n && p->id[i - 1] < p->id[i]) i++;
  if (i >= n) return ESF_OK;
  int64_t *kv = malloc(2 * n * sizeof *kv);
  o->ord = malloc(n * sizeof *o->ord);
  o->row = malloc(n * sizeof *o->row);
  o->buf = malloc(3 * n * sizeof(double));
  if (!kv || !o->ord || !o->row || !o->buf) {
    free(kv);
    free(o->ord);
    free(o->row);
    free(o->buf);
    return esf_fail(err, ESF_ENOMEM, "out of memory for a frame of %zu particles", n);
  }
  for (i = 0; i < n; i++) kv[2 * i] = p->id[i], kv[2 * i + 1] = (int64_t)i;
  qsort(kv, n, 2 * sizeof *kv, by_id);
  for (size_t r = 0; r < n; r++) {
    o->ord[r] = (size_t)kv[2 * r + 1];
    o->row[o->ord[r]] = r;
  }
  free(kv);
  return ESF_OK;
}

static void id_order_free(id_order *o) {
  free(o->ord);
  free(o->row);
  free(o->buf);
}

/* src (n rows of `width` elements of `size` bytes) in row order: src itself, or its
 * rows gathered into o->buf */
static const void *rows(const id_order *o, const void *src, size_t n, size_t width,
                        size_t size) {
  if (!o->ord) return src;
  const size_t w = width * size;
  for (size_t r = 0; r < n; r++)
    memcpy((char *)o->buf + r * w, (const char *)src + o->ord[r] * w, w);
  return o->buf;
}

static int write_particles(hid_t g, const esf_particles *p, const id_order *o) {
  size_t n = p->n, D = sizeof(double);
  hid_t f64 = H5T_IEEE_F64LE, d = H5T_NATIVE_DOUBLE;
  return esf_h5_dataset_write(g, "id", H5T_STD_I64LE, H5T_NATIVE_INT64, n, 1,
                              rows(o, p->id, n, 1, sizeof *p->id)) ||
         esf_h5_dataset_write(g, "position", f64, d, n, 3, rows(o, p->x, n, 3, D)) ||
         esf_h5_dataset_write(g, "velocity", f64, d, n, 3, rows(o, p->v, n, 3, D)) ||
         esf_h5_dataset_write(g, "angular_velocity", f64, d, n, 3,
                              rows(o, p->w, n, 3, D)) ||
         esf_h5_dataset_write(g, "force", f64, d, n, 3, rows(o, p->f, n, 3, D)) ||
         esf_h5_dataset_write(g, "radius", f64, d, n, 1, rows(o, p->radius, n, 1, D)) ||
         esf_h5_dataset_write(g, "material", H5T_STD_I32LE, H5T_NATIVE_INT32, n, 1,
                              rows(o, p->material, n, 1, sizeof *p->material)) ||
         (p->img && esf_h5_dataset_write(g, "image", H5T_STD_I32LE, H5T_NATIVE_INT32, n,
                                         3, rows(o, p->img, n, 3, sizeof *p->img)));
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

/* The contact pairs name particles by their rows in the frame; particle-wall contacts
 * by the particle's row and the wall's index in the scene. Beside them, each
 * particle's coordination number (contacts with particles and walls). */
static int write_contacts(hid_t frame, const esf_particles *p, const esf_contact_net *c,
                          const id_order *o) {
  const esf_contact_set *pp = &c->pp, *pw = &c->pw;
  const size_t n = p->n, np = 2 * pp->n;
  int64_t *pr = malloc((np + 2 * pw->n + 1) * sizeof *pr);
  int32_t *z = malloc((n + 1) * sizeof *z);
  if (!pr || !z) {
    free(pr);
    free(z);
    return -1;
  }
  for (size_t k = 0; k < np; k++)
    pr[k] = o->row ? (int64_t)o->row[pp->pair[k]] : pp->pair[k];
  for (size_t k = 0; k < 2 * pw->n; k++) /* particle rows, wall indices */
    pr[np + k] = o->row && !(k & 1) ? (int64_t)o->row[pw->pair[k]] : pw->pair[k];
  esf_contact_net_coordination(c, n, z);
  hid_t i64 = H5T_STD_I64LE, ni64 = H5T_NATIVE_INT64, f64 = H5T_IEEE_F64LE,
        d = H5T_NATIVE_DOUBLE;
  int bad = esf_h5_dataset_write(frame, "coordination", H5T_STD_I32LE, H5T_NATIVE_INT32,
                                 n, 1, rows(o, z, n, 1, sizeof *z));
  hid_t g =
      bad ? -1 : H5Gcreate2(frame, "contacts", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  bad = g < 0 || esf_h5_dataset_write(g, "pairs", i64, ni64, pp->n, 2, pr) ||
        esf_h5_dataset_write(g, "normal_force", f64, d, pp->n, 1, pp->fn) ||
        esf_h5_dataset_write(g, "tangential_force", f64, d, pp->n, 3, pp->ft) ||
        esf_h5_dataset_write(g, "wall_pairs", i64, ni64, pw->n, 2, pr + np) ||
        esf_h5_dataset_write(g, "wall_normal_force", f64, d, pw->n, 1, pw->fn) ||
        esf_h5_dataset_write(g, "wall_tangential_force", f64, d, pw->n, 3, pw->ft) ||
        esf_h5_dataset_write(g, "wall_point", f64, d, pw->n, 3, pw->pc);
  if (g >= 0 && H5Gclose(g) < 0) bad = 1;
  free(pr);
  free(z);
  return bad ? -1 : 0;
}

/* Appends the XDMF record (and segment) of the frame being written. */
static int record(esf_frames *fr, const esf_xdmf_frame *x, long seg, esf_error *err) {
  if ((size_t)fr->count == fr->xf_cap) {
    size_t cap = fr->xf_cap ? 2 * fr->xf_cap : 64;
    esf_xdmf_frame *n = realloc(fr->xf, cap * sizeof *n);
    if (n) fr->xf = n;
    long *s = n ? realloc(fr->seg_of, cap * sizeof *s) : NULL;
    if (s) fr->seg_of = s;
    if (!n || !s) return esf_fail(err, ESF_ENOMEM, "out of memory for the frame list");
    fr->xf_cap = cap;
  }
  fr->xf[fr->count] = *x;
  fr->seg_of[fr->count] = seg;
  return ESF_OK;
}

int esf_frames_write(esf_frames *fr, double time, const esf_particles *p,
                     const esf_walls *walls, const esf_contact_net *contacts,
                     esf_error *err) {
  if (!fr) return esf_fail(err, ESF_EINTERNAL, "frames: write on a closed file");
  double t0 = esf_now_s();
  char name[32], sp[1400];
  snprintf(name, sizeof name, "%06ld", fr->count);
  esf_xdmf_frame x = {time, fr->count, p->n, 0, 0, 0, 0, 0, p->img != NULL};
  int with_walls = walls && walls->n > 0;
  double lo[3], hi[3];
  int have_box = particle_box(p, lo, hi);
  int rc = with_walls ? esf_wall_mesh_build(walls, time, have_box ? lo : NULL,
                                            have_box ? hi : NULL, &fr->mesh, err)
                      : ESF_OK;
  id_order o = {0};
  if (!rc) rc = id_order_make(p, &o, err);
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  if (!rc && fr->seg < 0) rc = seg_open(fr, err);
  if (!rc) rc = record(fr, &x, fr->seg_start, err);
  if (rc) {
    H5Eclear2(H5E_DEFAULT);
    esf_h5_quiet_end(&q);
    id_order_free(&o);
    return rc;
  }
  seg_path(fr, fr->seg_start, sp, sizeof sp);
  hid_t g = H5Gcreate2(fr->segframes, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int ok = g >= 0 && esf_h5_attr_write_double(g, "time", time) == 0 &&
           write_particles(g, p, &o) == 0 &&
           (!with_walls || write_walls(g, &fr->mesh) == 0) &&
           (!contacts || write_contacts(g, p, contacts, &o) == 0);
  id_order_free(&o);
  if (!ok) {
    char what[96];
    snprintf(what, sizeof what, "cannot write frame %s to", name);
    rc = esf_h5_fail(err, what, sp);
  }
  if (g >= 0 && H5Gclose(g) < 0 && rc == ESF_OK)
    rc = esf_h5_fail(err, "cannot close a frame group in", sp);
  if (!rc && H5Fflush(fr->seg, H5F_SCOPE_LOCAL) < 0)
    rc = esf_h5_fail(err, "cannot flush", sp);
  if (rc == ESF_OK) {
    fr->xf[fr->count].has_walls = with_walls;
    fr->xf[fr->count].wall_points = with_walls ? fr->mesh.np : 0;
    fr->xf[fr->count].wall_triangles = with_walls ? fr->mesh.nt : 0;
    fr->xf[fr->count].has_contacts = contacts != NULL;
    fr->xf[fr->count].contacts = contacts ? contacts->pp.n : 0;
    fr->count++;
    rc = publish(fr, 0, 0, err);
  } else if (g >= 0) {
    H5Ldelete(fr->segframes, name,
              H5P_DEFAULT); /* best effort: keep the count coherent */
    H5Eclear2(H5E_DEFAULT);
  }
  esf_h5_quiet_end(&q);
  fr->seconds += esf_now_s() - t0;
  return rc;
}

int esf_frames_append_energy(esf_frames *fr, int ncols, const char *const *names,
                             const double *row, esf_error *err) {
  if (!fr) return esf_fail(err, ESF_EINTERNAL, "frames: energy row on a closed file");
  if (fr->ncols && fr->ncols != ncols)
    return esf_fail(err, ESF_EINTERNAL, "frames: energy rows of %d and %d columns",
                    fr->ncols, ncols);
  if (ncols < 1) return esf_fail(err, ESF_EINTERNAL, "frames: %d energy columns", ncols);
  size_t need = (size_t)(fr->nrows + 1) * (size_t)ncols;
  if (need > fr->rows_cap) {
    size_t cap = fr->rows_cap ? 2 * fr->rows_cap : 256 * (size_t)ncols;
    double *n = realloc(fr->rows, cap * sizeof *n);
    if (!n) return esf_fail(err, ESF_ENOMEM, "out of memory for energy rows");
    fr->rows = n;
    fr->rows_cap = cap;
  }
  fr->ncols = ncols;
  fr->names = names;
  memcpy(fr->rows + (size_t)fr->nrows * (size_t)ncols, row, (size_t)ncols * sizeof *row);
  fr->nrows++;
  return ESF_OK;
}

long esf_frames_count(const esf_frames *fr) { return fr ? fr->count : 0; }

long esf_frames_energy_rows(const esf_frames *fr) { return fr ? fr->nrows : 0; }

double esf_frames_seconds(const esf_frames *fr) { return fr ? fr->seconds : 0.0; }

int esf_frames_sync(esf_frames *fr, esf_error *err) {
  double t0 = esf_now_s();
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc = seg_close(fr, 1, err);
  if (!rc) rc = publish(fr, 1, 1, err);
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  fr->seconds += esf_now_s() - t0;
  return rc;
}

int esf_frames_close(esf_frames **frp, esf_error *err) {
  if (!frp || !*frp) return ESF_OK;
  esf_frames *fr = *frp;
  *frp = NULL;
  int rc = esf_frames_sync(fr, err);
  destroy(fr);
  return rc;
}

int esf_frames_resume(const char *path, const char *scene_name, const char *version,
                      long nframes, long nrows, int ncols, const char *const *names,
                      esf_frames **out, esf_error *err) {
  *out = NULL;
  esf_frames *fr = NULL;
  long have_f = 0, have_r = 0; /* allocate by what the index holds, not by the caller */
  int rc = esf_frames_index_counts(path, &have_f, &have_r, err);
  if (!rc && (nframes < 0 || nrows < 0 || nframes > have_f || nrows > have_r))
    rc = esf_fail(err, ESF_EIO,
                  "'%s' names %ld frames and %ld energy rows, fewer than the %ld and %ld "
                  "to resume from",
                  path, have_f, have_r, nframes, nrows);
  if (rc) return rc;
  rc = create(path, scene_name, version, &fr, err);
  if (rc) return rc;
  size_t cap = nframes > 64 ? (size_t)nframes : 64;
  fr->xf = malloc(cap * sizeof *fr->xf);
  fr->seg_of = malloc(cap * sizeof *fr->seg_of);
  fr->xf_cap = cap;
  if (nrows > 0) {
    fr->rows_cap = (size_t)nrows * (size_t)ncols;
    fr->rows = malloc(fr->rows_cap * sizeof *fr->rows);
  }
  if (!fr->xf || !fr->seg_of || (nrows > 0 && !fr->rows))
    rc = esf_fail(err, ESF_ENOMEM, "out of memory resuming '%s'", path);
  if (!rc)
    rc = esf_frames_index_read(path, nframes, fr->seg_of, fr->xf, nrows, ncols, names,
                               fr->rows, err);
  if (!rc) {
    fr->count = nframes;
    fr->nrows = nrows;
    fr->ncols = nrows > 0 ? ncols : 0;
    fr->names = nrows > 0 ? names : NULL;
    rc = drop_segments(fr, nframes, err);
  }
  if (!rc) rc = esf_frames_sync(fr, err);
  if (rc)
    destroy(fr);
  else
    *out = fr;
  return rc;
}
