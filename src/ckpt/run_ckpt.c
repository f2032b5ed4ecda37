/* run_ckpt.c — checkpoints in the run driver (run_ckpt.h).
 *
 * Saving: energy.csv is flushed and fsync'ed and its size recorded; frames.h5 gets its
 * pending energy rows, an HDF5 flush and an fsync (esf_frames_sync), and the frame and
 * row counts are recorded; then the checkpoint file is replaced atomically. Everything
 * a checkpoint counts is thus on disk before the checkpoint names it.
 * Reopening (resume): energy.csv must be at least the recorded size (else it was
 * damaged: an error) and is cut back to it. frames.h5 is a small index replaced only
 * atomically, and the segment files holding the checkpoint's frames were closed and
 * fsync'ed before the checkpoint named them and never written again (frames.h), so a
 * kill at any instant damages neither: the resume reads the checkpoint's frames and
 * rows through the index, removes the segments written after it and writes a new
 * index (esf_frames_resume). Should the index be unreadable all the same (changed by
 * hand), it is kept as frames.h5.damaged (frames.d as frames.d.damaged) with a warning
 * in log.txt and the resumed run starts a new frames.h5 at the checkpoint, so the
 * resume itself does not fail. */
#include "ckpt/run_ckpt.h"
#include "util/clock.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "util/atomic_file.h"
#include "util/version.h"

int esf_run_ckpt_save(const char *out_dir, esf_sim *s, const esf_integrator_type *it,
                      void *ist, const esf_ckpt_scene *sc, esf_ckpt_run *run, FILE *ef,
                      esf_frames *fr, esf_error *err) {
  double t0 = esf_now_s();
  char path[1200];
  run->csv_bytes = -1;
  if (ef) {
    long pos = fflush(ef) == 0 && fsync(fileno(ef)) == 0 ? ftell(ef) : -1;
    if (pos < 0) {
      snprintf(path, sizeof path, "%s/energy.csv", out_dir);
      return esf_fail(err, ESF_EIO, "cannot write '%s': %s", path, strerror(errno));
    }
    run->csv_bytes = pos;
  }
  int rc = esf_frames_sync(fr, err);
  if (rc) return rc;
  run->frames = esf_frames_count(fr);
  run->erows = esf_frames_energy_rows(fr);
  run->count++;
  snprintf(path, sizeof path, "%s/%s", out_dir, ESF_CKPT_NAME);
  rc = esf_ckpt_write(path, s, it, ist, sc, run, err);
  if (rc)
    run->count--;
  else
    esf_sim_log(s,
                "checkpoint %ld at step %ld, t = %.9g s: %.3f s to sync the output "
                "and write it",
                run->count, s->step, s->t, esf_now_s() - t0);
  return rc;
}

static int reopen_csv(const char *out_dir, long bytes, FILE **ef, esf_error *err) {
  char path[1200];
  snprintf(path, sizeof path, "%s/energy.csv", out_dir);
  FILE *f = fopen(path, "r+");
  if (!f) return esf_fail(err, ESF_EIO, "cannot reopen '%s': %s", path, strerror(errno));
  setvbuf(f, NULL, _IOLBF, 1 << 14); /* whole rows only reach the file (run.c) */
  struct stat sb;
  if (fstat(fileno(f), &sb) != 0 || sb.st_size < bytes) {
    fclose(f);
    return esf_fail(err, ESF_EINPUT,
                    "'%s' is shorter (%lld bytes) than the checkpoint recorded (%ld): it "
                    "was changed after the checkpoint; cannot resume",
                    path, (long long)sb.st_size, bytes);
  }
  if (ftruncate(fileno(f), bytes) != 0 || fseek(f, 0, SEEK_END) != 0) {
    int e = errno;
    fclose(f);
    return esf_fail(err, ESF_EIO, "cannot cut back '%s': %s", path, strerror(e));
  }
  *ef = f;
  return ESF_OK;
}

int esf_run_ckpt_reopen(const char *out_dir, const esf_sim *s, const esf_ckpt_run *run,
                        FILE **ef, esf_frames **fr, esf_error *err) {
  *ef = NULL;
  *fr = NULL;
  int rc = s->led.on && run->csv_bytes >= 0 ? reopen_csv(out_dir, run->csv_bytes, ef, err)
                                            : ESF_OK;
  if (rc) return rc;
  char path[1200];
  snprintf(path, sizeof path, "%s/frames.h5", out_dir);
  rc = esf_frames_resume(path, s->cfg.name, ESF_VERSION, run->frames, run->erows,
                         ESF_LEDGER_NCOLS, esf_ledger_columns, fr, err);
  if (rc == ESF_EIO) { /* the index is damaged: keep it aside, go on */
    char damaged[1220], segs[1220], segs_damaged[1240];
    snprintf(damaged, sizeof damaged, "%s.damaged", path);
    snprintf(segs, sizeof segs, "%s/frames.d", out_dir);
    snprintf(segs_damaged, sizeof segs_damaged, "%s.damaged", segs);
    const int kept = rename(segs, segs_damaged) == 0; /* its segments, for the user */
    const int why = errno;
    if (!kept && why != ENOENT) { /* new frames would overwrite them: stop instead */
      esf_error_clear(err);
      rc = esf_fail(err, ESF_EIO,
                    "the frame index '%s' is damaged and its segments '%s' cannot be "
                    "moved aside to '%s' (%s); nothing was changed: move them away "
                    "and resume again",
                    path, segs, segs_damaged, strerror(why));
    } else {
      esf_sim_log(s,
                  "WARNING: %s; it is kept as %s%s and the resumed run writes a new "
                  "frames.h5 from the checkpoint on (energy.csv keeps every row)",
                  err->msg, damaged, kept ? ", its frames in frames.d.damaged/," : "");
      esf_error_clear(err);
      rc = rename(path, damaged) != 0
               ? esf_fail(err, ESF_EIO, "cannot move '%s' aside: %s", path,
                          strerror(errno))
               : esf_fsync_parent(path, err);
      if (!rc) rc = esf_frames_open(path, s->cfg.name, ESF_VERSION, fr, err);
    }
  }
  if (rc) {
    esf_error e2;
    esf_frames_close(fr, &e2);
    if (*ef) fclose(*ef);
    *ef = NULL;
  }
  return rc;
}

void esf_run_ckpt_forget(const char *out_dir) {
  const char *names[] = {ESF_CKPT_NAME, ESF_CKPT_NAME ".tmp"};
  char path[1200];
  for (int k = 0; k < 2; k++) {
    snprintf(path, sizeof path, "%s/%s", out_dir, names[k]);
    unlink(path); /* absent is fine */
  }
}
