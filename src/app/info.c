/* info.c — `esfera info` (info.h): describe an esfera HDF5 file.
 *
 * A directory stands for the frames.h5 in it. Order of checks: the file opens (else
 * ESF_EIO with the system's reason), carries the HDF5 signature (else ESF_EINPUT "not an
 * HDF5 file"), has the root attribute esfera_version (else "not an esfera file"), and its
 * kind (root attribute `kind`, or "frames" for files from before that attribute when
 * /frames exists) has a describer in `kinds` (else "unknown kind"). The frames describer
 * prints the scene, version, frame count, time span, particle counts of the first and
 * last frames, the datasets of the first frame with type and shape, the energy table's
 * rows and columns and the size per particle and frame (the file's, plus, for frames
 * that are external links into segment files (frames.h), those files'). Only metadata,
 * the frame times and the energy time column are read. A file starting with the
 * checkpoint signature is described by checkpoint.c (esf_ckpt_describe: verified, what it
 * holds and the resume command) instead. HDF5 is kept silent (esf_h5_quiet); everything
 * opened is closed. */
#include "app/info.h"

#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "ckpt/checkpoint.h"
#include "formats/h5io.h"

/* Reads string attribute `name` of obj (variable or fixed length) into buf; -1 when
 * absent or not a string. */
static int read_string_attr(hid_t obj, const char *name, char *buf, size_t size) {
  buf[0] = '\0';
  if (H5Aexists(obj, name) <= 0) return -1;
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT), t = a >= 0 ? H5Aget_type(a) : -1;
  int ok = t >= 0 && H5Tget_class(t) == H5T_STRING;
  if (ok && H5Tis_variable_str(t) > 0) {
    char *s = NULL;
    ok = H5Aread(a, t, &s) >= 0 && s;
    if (ok) snprintf(buf, size, "%s", s);
    if (s) H5free_memory(s);
  } else if (ok) {
    size_t n = H5Tget_size(t);
    char *s = calloc(n + 1, 1);
    ok = s && H5Aread(a, t, s) >= 0;
    if (ok) snprintf(buf, size, "%s", s);
    free(s);
  }
  if (t >= 0) H5Tclose(t);
  if (a >= 0) H5Aclose(a);
  return ok ? 0 : -1;
}

static double read_time(hid_t frames, const char *name) {
  double t = NAN;
  hid_t g = H5Gopen2(frames, name, H5P_DEFAULT);
  hid_t a = g >= 0 && H5Aexists(g, "time") > 0 ? H5Aopen(g, "time", H5P_DEFAULT) : -1;
  if (a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &t) < 0) t = NAN;
  if (a >= 0) H5Aclose(a);
  if (g >= 0) H5Gclose(g);
  return t;
}

/* H5Lvisit callback: prints each dataset as " name type [d0xd1]". */
static herr_t list_dataset(hid_t g, const char *name, const H5L_info_t *info,
                           void *data) {
  (void)info;
  FILE *out = data;
  hid_t o = H5Oopen(g, name, H5P_DEFAULT);
  if (o < 0) return 0;
  if (H5Iget_type(o) == H5I_DATASET) {
    hid_t t = H5Dget_type(o), s = H5Dget_space(o);
    hsize_t dims[H5S_MAX_RANK] = {0};
    int rank = H5Sget_simple_extent_dims(s, dims, NULL);
    H5T_class_t cl = H5Tget_class(t);
    const char *kind = cl == H5T_FLOAT ? "float" : cl == H5T_INTEGER ? "int" : "other";
    fprintf(out, "  %s: %s%zu [", name, kind, 8 * H5Tget_size(t));
    for (int k = 0; k < rank; k++)
      fprintf(out, "%s%llu", k ? " x " : "", (unsigned long long)dims[k]);
    fputs("]\n", out);
    H5Sclose(s);
    H5Tclose(t);
  }
  H5Oclose(o);
  return 0;
}

static void describe_energy(hid_t file, FILE *out) {
  if (H5Lexists(file, "energy", H5P_DEFAULT) <= 0) {
    fputs("energy rows: 0 (no /energy table)\n", out);
    return;
  }
  hid_t g = H5Gopen2(file, "energy", H5P_DEFAULT);
  H5G_info_t gi = {0};
  H5Gget_info(g, &gi);
  long n = esf_h5_rows(g, "time");
  fprintf(out, "energy rows: %ld (%llu columns in /energy)\n", n < 0 ? 0 : n,
          (unsigned long long)gi.nlinks);
  if (n > 0) {
    double *t = malloc((size_t)n * sizeof *t);
    hid_t d = H5Dopen2(g, "time", H5P_DEFAULT);
    if (t && d >= 0 &&
        H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t) >= 0)
      fprintf(out, "energy time: %.9g .. %.9g s\n", t[0], t[n - 1]);
    if (d >= 0) H5Dclose(d);
    free(t);
  }
  H5Gclose(g);
}

/* The segment files the frames link to (frames.h: consecutive frames share one). */
typedef struct segments {
  long count;
  double bytes;
  char last[1200]; /* the previous frame's file name */
} segments;

/* Counts the file frame `name` of fg links to, if it is an external link to a file
 * other than the previous frame's; its size from its path relative to the index's. */
static void segments_add(hid_t fg, const char *name, const char *path, segments *sg) {
  char file[sizeof sg->last];
  if (esf_h5_elink_file(fg, name, file, sizeof file) || strcmp(file, sg->last) == 0)
    return;
  snprintf(sg->last, sizeof sg->last, "%s", file);
  const char *slash = strrchr(path, '/');
  char full[2500];
  snprintf(full, sizeof full, "%.*s%s", slash ? (int)(slash - path + 1) : 0, path, file);
  struct stat sb;
  sg->count++;
  if (stat(full, &sb) == 0) sg->bytes += (double)sb.st_size;
}

static int describe_frames(hid_t file, const char *path, FILE *out, esf_error *err) {
  char buf[256];
  read_string_attr(file, "scene", buf, sizeof buf);
  fprintf(out, "scene: %s\n", buf);
  read_string_attr(file, "esfera_version", buf, sizeof buf);
  fprintf(out, "esfera version: %s\n", buf);
  hid_t fg = H5Gopen2(file, "frames", H5P_DEFAULT);
  if (fg < 0) return esf_h5_fail(err, "no group /frames in", path);
  H5G_info_t gi = {0};
  H5Gget_info(fg, &gi);
  long nf = (long)gi.nlinks;
  segments segs = {0, 0.0, ""};
  fprintf(out, "frames: %ld\n", nf);
  double sum = 0;
  if (nf > 0) {
    char first[64] = "", last[64] = "", name[64];
    H5Lget_name_by_idx(fg, ".", H5_INDEX_NAME, H5_ITER_INC, 0, first, sizeof first,
                       H5P_DEFAULT);
    H5Lget_name_by_idx(fg, ".", H5_INDEX_NAME, H5_ITER_INC, (hsize_t)(nf - 1), last,
                       sizeof last, H5P_DEFAULT);
    fprintf(out, "time: %.9g .. %.9g s\n", read_time(fg, first), read_time(fg, last));
    snprintf(name, sizeof name, "%s/id", first);
    long n0 = esf_h5_rows(fg, name);
    snprintf(name, sizeof name, "%s/id", last);
    fprintf(out, "particles: %ld (first frame), %ld (last frame)\n", n0,
            esf_h5_rows(fg, name));
    for (long k = 0; k < nf; k++) {
      if (H5Lget_name_by_idx(fg, ".", H5_INDEX_NAME, H5_ITER_INC, (hsize_t)k, name,
                             sizeof name, H5P_DEFAULT) < 0)
        continue;
      segments_add(fg, name, path, &segs);
      size_t l = strlen(name);
      snprintf(name + l, sizeof name - l, "/id");
      long n = esf_h5_rows(fg, name);
      sum += n > 0 ? (double)n : 0.0;
    }
    fprintf(out, "datasets (frame %s):\n", first);
    hid_t g0 = H5Gopen2(fg, first, H5P_DEFAULT);
    if (g0 >= 0) {
      H5Lvisit(g0, H5_INDEX_NAME, H5_ITER_INC, list_dataset, out);
      H5Gclose(g0);
    }
  }
  H5Gclose(fg);
  describe_energy(file, out);
  struct stat sb;
  if (stat(path, &sb) == 0) {
    double size = (double)sb.st_size + segs.bytes;
    if (segs.count > 0)
      fprintf(out, "segments: %ld files, %.0f bytes (the index: %lld bytes)\n",
              segs.count, segs.bytes, (long long)sb.st_size);
    fprintf(out, "size: %.0f bytes (%.1f bytes per particle per frame)\n", size,
            sum > 0 ? size / sum : 0.0);
  }
  H5Eclear2(H5E_DEFAULT);
  return ESF_OK;
}

typedef struct info_kind {
  const char *name;
  int (*describe)(hid_t file, const char *path, FILE *out, esf_error *err);
} info_kind;

static const info_kind kinds[] = {{"frames", describe_frames}, {NULL, NULL}};

static int describe(hid_t file, const char *path, FILE *out, esf_error *err) {
  char version[256], kind[64];
  if (read_string_attr(file, "esfera_version", version, sizeof version) < 0)
    return esf_fail(err, ESF_EINPUT,
                    "'%s' is an HDF5 file but not an esfera file (no esfera_version "
                    "attribute at its root)",
                    path);
  if (read_string_attr(file, "kind", kind, sizeof kind) < 0) {
    if (H5Lexists(file, "frames", H5P_DEFAULT) <= 0)
      return esf_fail(err, ESF_EINPUT, "'%s': esfera file of no known kind", path);
    snprintf(kind, sizeof kind, "frames");
  }
  for (const info_kind *k = kinds; k->name; k++)
    if (strcmp(k->name, kind) == 0) {
      fprintf(out, "file: %s\nkind: %s\n", path, kind);
      return k->describe(file, path, out, err);
    }
  return esf_fail(err, ESF_EINPUT,
                  "'%s': esfera file of kind '%s', which this version (reading: frames) "
                  "cannot describe",
                  path, kind);
}

int esf_info_print(const char *path, FILE *out, esf_error *err) {
  char in_dir[1200];
  struct stat sb;
  if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode)) { /* a result directory */
    snprintf(in_dir, sizeof in_dir, "%s/frames.h5", path);
    path = in_dir;
  }
  FILE *probe = fopen(path, "rb");
  if (!probe)
    return esf_fail(err, ESF_EIO, "cannot open '%s': %s", path, strerror(errno));
  fclose(probe);
  if (esf_ckpt_is(path)) /* checkpoints are esfera's own format, not HDF5 */
    return esf_ckpt_describe(path, out, err);
  esf_h5_quiet q;
  esf_h5_quiet_begin(&q);
  int rc;
#if H5_VERSION_GE(1, 12, 0)
  htri_t is_h5 = H5Fis_accessible(path, H5P_DEFAULT);
#else
  htri_t is_h5 = H5Fis_hdf5(path);
#endif
  if (is_h5 <= 0) {
    rc = esf_fail(err, ESF_EINPUT, "'%s' is not an HDF5 file", path);
  } else {
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0) {
      rc = esf_h5_fail(err, "cannot open HDF5 file", path);
    } else {
      rc = describe(file, path, out, err);
      H5Fclose(file);
    }
  }
  H5Eclear2(H5E_DEFAULT);
  esf_h5_quiet_end(&q);
  return rc;
}
