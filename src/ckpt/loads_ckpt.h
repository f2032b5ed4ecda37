/* loads_ckpt.h — the loads' state a checkpoint must carry (checkpoint.h, section
 * "SAND", named when the loads served only the sand-production scenes): servo walls'
 * displacement, velocity and measured stress (their placement is not a function of time),
 * which events have been applied, and the fluid force's log state. */
#ifndef ESF_LOADS_CKPT_H
#define ESF_LOADS_CKPT_H

#include "core/sim.h"
#include "util/blob.h"

/* Appends the state to b. */
void esf_loads_ckpt_save(const esf_sim *s, esf_blob *b);

/* Restores it (before the walls are placed at the saved time). An absent section
 * (in->d NULL) is accepted when the scene has no servo wall, event or fluid force.
 * 0 ok, -1 when the section does not fit the scene. */
int esf_loads_ckpt_restore(esf_sim *s, esf_blob_in *in);

#endif
