/* test_frames_resume.c — the segmented frames file (frames.h, frames_index.h): every
 * /frames/NNNNNN of frames.h5 is an external link into frames.d/SSSSSS.h5, a
 * checkpoint (esf_frames_sync) closes the segment so the next frame starts a new one
 * named by its number; a resume (esf_frames_resume) at a checkpoint's counts keeps
 * exactly the checkpoint's frames and energy rows, removes the segments written after
 * it, copies nothing, and its continuation gives frames and rows equal to an
 * uninterrupted writer's; a resume asking for more frames than the index holds fails
 * with ESF_EIO naming the file. */
#include <dirent.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "output/frames.h"

static char tmpdir[256];
static const char *const cols[2] = {"time", "e"};

static void fill(esf_particles *p, int frame) {
  for (size_t i = 0; i < p->n; i++) {
    p->id[i] = (int64_t)i;
    p->radius[i] = 1e-3;
    p->material[i] = 0;
    for (int k = 0; k < 3; k++)
      p->x[3 * i + k] = p->v[3 * i + k] = p->w[3 * i + k] = p->f[3 * i + k] =
          (double)frame + 0.1 * (double)(3 * i + (size_t)k);
  }
}

static int exists(const char *dir, const char *name) {
  char p[700];
  struct stat sb;
  snprintf(p, sizeof p, "%s/%s", dir, name);
  return stat(p, &sb) == 0;
}

/* Frames [from, to) with an energy row before each; sync after the frame `sync_at`. */
static void write_frames(esf_frames *fr, esf_particles *p, int from, int to,
                         int sync_at) {
  esf_error err = {0};
  for (int f = from; f < to; f++) {
    double row[2] = {0.1 * f, 1.0 / (f + 1)};
    CHECK_OK(esf_frames_append_energy(fr, 2, cols, row, &err), err);
    fill(p, f);
    CHECK_OK(esf_frames_write(fr, 0.1 * f, p, NULL, NULL, &err), err);
    if (f == sync_at) CHECK_OK(esf_frames_sync(fr, &err), err);
  }
}

/* Frame k's position[0][0] and link target, the /energy column e's rows. */
static void check_file(const char *path, int nframes, int nrows, const char *what) {
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(f >= 0, "%s: cannot open %s", what, path);
  if (f < 0) return;
  hid_t g = H5Gopen2(f, "frames", H5P_DEFAULT);
  H5G_info_t gi = {0};
  H5Gget_info(g, &gi);
  CHECK((int)gi.nlinks == nframes, "%s: %llu frames, expected %d", what,
        (unsigned long long)gi.nlinks, nframes);
  for (int k = 0; k < nframes; k++) {
    char name[32];
    snprintf(name, sizeof name, "%06d", k);
    H5L_info_t li;
    CHECK(H5Lget_info(g, name, &li, H5P_DEFAULT) >= 0 && li.type == H5L_TYPE_EXTERNAL,
          "%s: frame %d is not an external link", what, k);
    char dset[64];
    snprintf(dset, sizeof dset, "%s/position", name);
    hid_t d = H5Dopen2(g, dset, H5P_DEFAULT);
    double x[3 * 4] = {0};
    CHECK(d >= 0 && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) >= 0,
          "%s: frame %d unreadable through its link", what, k);
    CHECK(x[0] == (double)k, "%s: frame %d holds %g", what, k, x[0]);
    if (d >= 0) H5Dclose(d);
  }
  H5Gclose(g);
  hid_t d = H5Dopen2(f, "energy/e", H5P_DEFAULT);
  hid_t s = d >= 0 ? H5Dget_space(d) : -1;
  hsize_t n = 0;
  if (s >= 0) H5Sget_simple_extent_dims(s, &n, NULL);
  CHECK((int)n == nrows, "%s: %llu energy rows, expected %d", what, (unsigned long long)n,
        nrows);
  double e[64] = {0};
  if (n > 0 && n <= 64) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, e);
  for (int r = 0; r < nrows && r < 64; r++)
    CHECK(e[r] == 1.0 / (r + 1), "%s: energy row %d is %g", what, r, e[r]);
  if (s >= 0) H5Sclose(s);
  if (d >= 0) H5Dclose(d);
  H5Fclose(f);
}

static void rm_dir(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return;
  for (struct dirent *e; (e = readdir(d)) != NULL;) {
    if (e->d_name[0] == '.') continue;
    char p[700];
    snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
    unlink(p);
  }
  closedir(d);
  rmdir(dir);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/esf_fresume_XXXXXX");
  if (!mkdtemp(tmpdir)) return 1;
  char path[512], segs[512];
  snprintf(path, sizeof path, "%s/frames.h5", tmpdir);
  snprintf(segs, sizeof segs, "%s/frames.d", tmpdir);
  esf_error err = {0};
  esf_particles p;
  CHECK_OK(esf_particles_alloc(&p, 4, &err), err);

  /* a "killed" writer: frames 0-4, checkpoint after frame 2 (3 frames, 3 rows) */
  esf_frames *fr = NULL;
  CHECK_OK(esf_frames_open(path, "s", "v", &fr, &err), err);
  write_frames(fr, &p, 0, 5, 2);
  CHECK(exists(segs, "000000.h5") && exists(segs, "000003.h5") &&
            !exists(segs, "000001.h5"),
        "segments 000000 (frames 0-2) and 000003 (frames 3-4) expected");
  check_file(path, 5, 5, "before the resume");
  CHECK_OK(esf_frames_close(&fr, &err), err);

  /* resuming at the checkpoint's counts: 3 frames, 3 rows, segment 000003 gone */
  CHECK_OK(esf_frames_resume(path, "s", "v", 3, 3, 2, cols, &fr, &err), err);
  CHECK(esf_frames_count(fr) == 3 && esf_frames_energy_rows(fr) == 3,
        "resumed with %ld frames and %ld rows", esf_frames_count(fr),
        esf_frames_energy_rows(fr));
  CHECK(!exists(segs, "000003.h5"), "the segment after the checkpoint is removed");
  check_file(path, 3, 3, "right after the resume");
  write_frames(fr, &p, 3, 6, -1);
  CHECK_OK(esf_frames_close(&fr, &err), err);
  check_file(path, 6, 6, "after the continuation");

  /* the uninterrupted reference */
  char ref[512];
  snprintf(ref, sizeof ref, "%s/ref.h5", tmpdir);
  CHECK_OK(esf_frames_open(ref, "s", "v", &fr, &err), err);
  write_frames(fr, &p, 0, 6, 2);
  CHECK_OK(esf_frames_close(&fr, &err), err);
  check_file(ref, 6, 6, "uninterrupted");

  /* more frames than the index holds */
  int rc = esf_frames_resume(path, "s", "v", 9, 3, 2, cols, &fr, &err);
  CHECK(rc == ESF_EIO && fr == NULL && strstr(err.msg, path) != NULL,
        "resume past the index: %d '%s'", rc, err.msg);

  esf_particles_release(&p);
  char x[512];
  snprintf(x, sizeof x, "%s/ref.d", tmpdir);
  rm_dir(x);
  rm_dir(segs);
  const char *files[] = {"frames.h5", "frames.xdmf", "ref.h5", "ref.xdmf"};
  for (int k = 0; k < 4; k++) {
    snprintf(x, sizeof x, "%s/%s", tmpdir, files[k]);
    unlink(x);
  }
  if (rmdir(tmpdir) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return check_finish("test_frames_resume");
}
