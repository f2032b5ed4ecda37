/* xdmf.h — frames.xdmf, the XDMF 3 description of frames.h5 that ParaView (and VisIt)
 * open directly. It names no data of its own: every DataItem points into the HDF5 file
 * by a path relative to the XDMF file's directory.
 *
 * One Domain with up to three Temporal collections of Uniform grids, one grid per
 * frame, each with its Time:
 *   particles — N vertex cells (Polyvertex on the index's /vertex_index, whole or its
 *               first N entries as a hyperslab) on /frames/NNNNNN/position, node
 *               attributes radius, velocity, angular_velocity, force, material, id
 *               and, in frames with contacts, coordination (frames with particles);
 *   walls     — Triangle topology /frames/NNNNNN/walls/triangles on .../walls/points,
 *               cell attributes group and material (only frames with walls);
 *   contacts  — Polyline topology of 2 nodes /frames/NNNNNN/contacts/pairs on the
 *               particle positions, cell attributes normal_force and tangential_force
 *               (frames with contacts).
 * An empty set of walls or contacts is a topology of no cells without data (docs/
 * output.md#paraview says which reader shows what).
 * The file is replaced atomically (written to NAME.tmp, fsync'ed, renamed over NAME),
 * so a reader, or a run killed at any moment, sees a complete file. */
#ifndef ESF_XDMF_H
#define ESF_XDMF_H

#include <stddef.h>

#include "util/esf_error.h"

/* What the XDMF needs to know of one frame. */
typedef struct esf_xdmf_frame {
  double time;      /* s */
  long index;       /* the frame's number: group /frames/%06ld */
  size_t particles; /* rows of the particle datasets */
  int has_walls;    /* the frame has a walls group */
  size_t wall_points, wall_triangles;
  int has_contacts; /* the frame has a contacts group */
  size_t contacts;
  int has_image; /* the particles have periodic image counters (`image`) */
} esf_xdmf_frame;

/* The kinds of grid, as bits: a file may hold any of them. */
enum {
  ESF_XDMF_PARTICLES = 1,
  ESF_XDMF_WALLS = 2,
  ESF_XDMF_CONTACTS = 4,
  ESF_XDMF_ALL = 7
};

/* Writes the XDMF of the grids of `kinds` for nframes frames of h5_name (the HDF5
 * file's name as the XDMF should reference it, normally its base name) to path,
 * atomically. A file of the particles alone also gives their positions as a node
 * attribute `position` (what meshio's time series reader returns per frame). With
 * durable, the file and its directory are fsync'ed (a checkpoint, the run's end);
 * without, the replacement is atomic for a killed process but not across a power
 * loss. Errors: ESF_EIO naming the path. */
int esf_xdmf_write(const char *path, const char *h5_name, int kinds,
                   const esf_xdmf_frame *frames, size_t nframes, int durable,
                   esf_error *err);

/* Whether some frame has a grid of this kind (one bit). */
int esf_xdmf_any(int kind, const esf_xdmf_frame *frames, size_t nframes);

#endif
