/* run_ckpt.h — the run driver's side of checkpoints (run.c): writing one with the
 * outputs it counts made durable, and reopening the outputs of a resumed run cut back
 * to exactly what the checkpoint counted. */
#ifndef ESF_RUN_CKPT_H
#define ESF_RUN_CKPT_H

#include <stdio.h>

#include "ckpt/checkpoint.h"
#include "output/frames.h"

/* Makes energy.csv (ef, may be NULL) and frames.h5 durable, records their sizes in
 * run, counts the checkpoint and writes OUT/checkpoint.esf atomically. */
int esf_run_ckpt_save(const char *out_dir, esf_sim *s, const esf_integrator_type *it,
                      void *ist, const esf_ckpt_scene *sc, esf_ckpt_run *run, FILE *ef,
                      esf_frames *fr, esf_error *err);

/* A resumed run's outputs: energy.csv (when the ledger is on) truncated to the
 * checkpoint's size and opened for appending; frames.h5 rewritten to name the
 * checkpoint's frames and energy rows (segments a killed run wrote after it are
 * removed; nothing is copied, esf_frames_resume); an unreadable index is kept as
 * frames.h5.damaged (warning in log.txt) and a new one started. */
int esf_run_ckpt_reopen(const char *out_dir, const esf_sim *s, const esf_ckpt_run *run,
                        FILE **ef, esf_frames **fr, esf_error *err);

/* A new run into out_dir: removes a checkpoint and its temporary an earlier run left
 * there (they describe output this run overwrites). */
void esf_run_ckpt_forget(const char *out_dir);

#endif
