/* frames.h — the frames file (INTERFACE.md): frames.h5 with one group per frame,
 * /frames/NNNNNN, attribute `time` (s) and datasets id (N, int64), position, velocity,
 * angular_velocity, force (N x 3, double), radius (N, double), material (N, int32).
 * The root carries attributes `scene` and `esfera_version`. */
#ifndef ESF_FRAMES_H
#define ESF_FRAMES_H

#include "esf_error.h"
#include "particles.h"

typedef struct esf_frames esf_frames;

/* Creates (truncates) the file. Error ESF_EIO names the path. */
int esf_frames_open(const char *path, const char *scene_name, const char *version,
                    esf_frames **out, esf_error *err);

/* Appends a frame of the current particle state. */
int esf_frames_write(esf_frames *fr, double time, const esf_particles *p, esf_error *err);

/* Number of frames written so far. */
long esf_frames_count(const esf_frames *fr);

/* Flushes and closes; sets *fr to NULL. Safe on NULL. */
int esf_frames_close(esf_frames **fr, esf_error *err);

#endif
