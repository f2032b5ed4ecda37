/* frames.h — the frames file (INTERFACE.md "Output directory"): frames.h5 and, beside
 * it, frames.xdmf (xdmf.h) describing it for ParaView.
 *
 * frames.h5 layout:
 *   /            attributes scene, esfera_version, kind = "frames" (strings)
 *   /frames/NNNNNN  one group per frame (from 000000), attribute time (s), datasets
 *                id (N, int64), position, velocity, angular_velocity, force (N x 3,
 *                double: m, m/s, rad/s, N), radius (N, double, m), material (N, int32)
 *     walls/     (when the scene has walls) the walls at the frame's time as a triangle
 *                mesh (wall_mesh.h): points (M x 3, double, m), triangles (K x 3,
 *                int32, rows of points), group and material (K, int32); planes are
 *                square patches covering the frame's particle bounding box
 *     contacts/  (when asked for) pairs (C x 2, int64, rows of the frame's particle
 *                datasets) and normal_force (C, double, N) of touching particle pairs
 *   /energy      (when energy rows are written) one 1-D double dataset per column of
 *                energy.csv, in the attribute `columns`' order (h5table.h) */
#ifndef ESF_FRAMES_H
#define ESF_FRAMES_H

#include "contact_net.h"
#include "esf_error.h"
#include "particles.h"
#include "walls.h"

typedef struct esf_frames esf_frames;

/* Creates (truncates) the HDF5 file at path and names the XDMF file beside it (path
 * with .h5 replaced by .xdmf, or .xdmf appended). Error ESF_EIO names the path. */
int esf_frames_open(const char *path, const char *scene_name, const char *version,
                    esf_frames **out, esf_error *err);

/* Appends a frame: the particles, the walls (NULL or none: no walls group) and the
 * contact network (NULL: no contacts group) at `time`. Then flushes the file and
 * rewrites the XDMF, so a run that dies leaves both describing every complete frame.
 * (After 100 frames the XDMF is rewritten only when that costs no more than about 1%
 * of the time since its last rewrite, and at close.) */
int esf_frames_write(esf_frames *fr, double time, const esf_particles *p,
                     const esf_walls *walls, const esf_contact_net *contacts,
                     esf_error *err);

/* Appends a row to /energy (created at the first row with these column names; ncols
 * must not change). Rows reach the file in blocks, at the latest with the next frame. */
int esf_frames_append_energy(esf_frames *fr, int ncols, const char *const *names,
                             const double *row, esf_error *err);

/* Number of frames written so far; energy rows appended so far. */
long esf_frames_count(const esf_frames *fr);
long esf_frames_energy_rows(const esf_frames *fr);

/* Wall time spent in esf_frames_write and esf_frames_append_energy so far, s. */
double esf_frames_seconds(const esf_frames *fr);

/* Checkpoints: writes the pending energy rows, flushes the file, fsyncs it and
 * rewrites the XDMF, so that what a checkpoint counts is on disk. */
int esf_frames_sync(esf_frames *fr, esf_error *err);

/* A resumed run: copies the first nframes frames (groups copied whole, H5Ocopy) and
 * the first nrows energy rows (columns `names`) of the frames file src_path into fr,
 * which must be new, then syncs it. ESF_EIO naming src_path when it lacks them. */
int esf_frames_copy(esf_frames *fr, const char *src_path, long nframes, long nrows,
                    int ncols, const char *const *names, esf_error *err);

/* Flushes, writes the final XDMF and closes; sets *fr to NULL. Safe on NULL. */
int esf_frames_close(esf_frames **fr, esf_error *err);

#endif
