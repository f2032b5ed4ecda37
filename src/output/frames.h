/* frames.h — the frames file (docs/output.md#frames): frames.h5, the segment
 * directory frames.d/ beside it, and frames.xdmf (xdmf.h) describing it for ParaView.
 *
 * frames.h5 (frames_index.h) is what readers open:
 *   /            attributes scene, esfera_version, kind = "frames" (strings)
 *   /frames/NNNNNN  one per frame (from 000000): an HDF5 external link to the group
 *                /frames/NNNNNN of the segment file frames.d/SSSSSS.h5 (SSSSSS: the
 *                segment's first frame; a new segment starts after each checkpoint).
 *                HDF5 (h5py, ParaView) follows the links transparently. The group has
 *                attribute time (s), datasets id (N, int64), position, velocity,
 *                angular_velocity, force (N x 3, double: m, m/s, rad/s, N), radius (N,
 *                double, m), material (N, int32)
 *     walls/     (when the scene has walls) the walls at the frame's time as a triangle
 *                mesh (wall_mesh.h): points (M x 3, double, m), triangles (K x 3,
 *                int32, rows of points), group and material (K, int32); planes are
 *                square patches covering the frame's particle bounding box
 *     contacts/  (when asked for) pairs (C x 2, int64, rows of the frame's particle
 *                datasets), normal_force (C, double, N) and tangential_force (C x 3) of
 *                touching particle pairs; wall_pairs (W x 2: particle row, wall index),
 *                wall_normal_force, wall_tangential_force, wall_point of the particle-
 *                wall contacts; beside it coordination (N, int32) per particle
 *   /energy      (when energy rows are written) one 1-D double dataset per column of
 *                energy.csv, in the attribute `columns`' order (h5table.h)
 * frames.h5 is only ever replaced whole and atomically; segments are appended to only
 * until the next checkpoint. */
#ifndef ESF_FRAMES_H
#define ESF_FRAMES_H

#include "bodies/particles.h"
#include "bodies/walls.h"
#include "output/contact_net.h"
#include "util/esf_error.h"

typedef struct esf_frames esf_frames;

/* Starts a new frames file at path: creates the segment directory (path with .h5
 * replaced by .d, or .d appended) and empties it of segments, writes an empty index
 * and names the XDMF file beside it (.xdmf likewise). Error ESF_EIO names the path. */
int esf_frames_open(const char *path, const char *scene_name, const char *version,
                    esf_frames **out, esf_error *err);

/* Appends a frame: the particles, the walls (NULL or none: no walls group) and the
 * contact network (NULL: no contacts group) at `time`, to the current segment (started
 * here if none is open). Then flushes the segment and rewrites the index and the XDMF,
 * so a run that dies leaves both describing every complete frame. (After 100 frames
 * they are rewritten only when that costs no more than about 1% of the time since
 * their last rewrite, and at checkpoints and close.) */
int esf_frames_write(esf_frames *fr, double time, const esf_particles *p,
                     const esf_walls *walls, const esf_contact_net *contacts,
                     esf_error *err);

/* Appends a row to /energy (created at the first row with these column names, which
 * must outlive fr; ncols must not change). Rows reach the index when it is next
 * rewritten (with a frame, at a checkpoint, at close). */
int esf_frames_append_energy(esf_frames *fr, int ncols, const char *const *names,
                             const double *row, esf_error *err);

/* Number of frames written so far; energy rows appended so far. */
long esf_frames_count(const esf_frames *fr);
long esf_frames_energy_rows(const esf_frames *fr);

/* Wall time spent in esf_frames_write and esf_frames_append_energy so far, s. */
double esf_frames_seconds(const esf_frames *fr);

/* Checkpoints: closes the current segment, fsyncs it and the segment directory, then
 * rewrites the index (fsync'ed, atomic) and the XDMF, so that what a checkpoint counts
 * is on disk and is never written again. */
int esf_frames_sync(esf_frames *fr, esf_error *err);

/* A resumed run: reads the first nframes frames and the first nrows energy rows
 * (columns `names`, outliving fr) from the index at path (frames written after the
 * checkpoint that counted them are dropped: their segments are removed), then syncs.
 * No frame is copied. ESF_EIO naming path when it lacks them. */
int esf_frames_resume(const char *path, const char *scene_name, const char *version,
                      long nframes, long nrows, int ncols, const char *const *names,
                      esf_frames **out, esf_error *err);

/* Closes the segment (fsync'ed), writes the final index and XDMF and frees; sets *fr to
 * NULL. Safe on NULL. */
int esf_frames_close(esf_frames **fr, esf_error *err);

#endif
