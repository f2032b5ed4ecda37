/* reorder.h — particles renumbered along cells at list rebuilds (reorder.c), so that
 * a pair's particles lie close in memory whatever order the scene defined them in.
 * Only for schemes that keep no per-particle state of their own between steps (the
 * leapfrog: s->reorder); frames are written in id order all the same (frames.c). */
#ifndef ESF_REORDER_H
#define ESF_REORDER_H

#include "core/sim.h"

/* Renumbers the particles in cell order when that differs from the current order
 * (*changed = 1); the candidate lists are then renumbered and a build must follow
 * before they are used. Call it right before esf_neighbor_build. */
int esf_reorder_particles(esf_sim *s, int *changed, esf_error *err);

#endif
