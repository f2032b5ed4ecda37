/* wall_loads.h — loads for output, from the contact network of a state
 * (contact_net.h; docs/output.md#walls-csv, #stress-csv, docs/physics.md#wall-loads-and-
 * region-stress): each wall's force and moment (walls.csv, output.walls) and the
 * average stress of boxes (stress.csv, output.stress), a row per wall or region at
 * every energy row. Computed on one thread in list order at the rows only: the bits do
 * not depend on the thread count, and scenes that ask for neither pay nothing. */
#ifndef ESF_WALL_LOADS_H
#define ESF_WALL_LOADS_H

#include <stdio.h>

#include "core/sim.h"
#include "output/contact_net.h"

/* stress.csv's columns after time and region: particles in the region, the symmetric
 * stress (compression positive, Pa) sxx syy szz syz sxz sxy, pressure p = tr/3, the
 * deviatoric invariant q = sqrt(3 J2), and the kinetic part's pressure. */
enum { ESF_STRESS_COLS = 10 };

/* The force (3, N) the particles exert on each wall group and its moment (3, N m)
 * about the group's reference point (a rotating wall's axis point `center` at the
 * state's time, else the origin) into fm (6 per group), from net's wall contacts. */
void esf_wall_loads(const esf_sim *s, const esf_contact_net *net, double *fm);

/* The stress of box (min 3, max 3) into out (ESF_STRESS_COLS): particles whose centre
 * lies in [min, max) with their contacts (net, pairs and walls) and velocities. */
void esf_region_stress(const esf_sim *s, const esf_contact_net *net, const double box[6],
                       double out[ESF_STRESS_COLS]);

/* The run's load files: walls.csv and stress.csv in the output folder when asked. */
typedef struct esf_load_out {
  FILE *walls, *stress; /* NULL: not asked */
  esf_contact_net net;
  double *fm; /* 6 per wall group */
} esf_load_out;

/* Opens the files the scene asks for: a new run (erows < 0) writes their headers (and
 * removes an earlier run's file the scene does not ask for, in an overwritten folder); a
 * resumed one keeps their header and the rows of the checkpoint's erows energy rows
 * (ESF_EINPUT when a file is shorter) and appends. Nothing when neither is asked. */
int esf_load_out_open(const char *dir, const esf_sim *s, long erows, esf_load_out *o,
                      esf_error *err);

/* At an energy row: the rows of the current state (time s->t). */
int esf_load_out_row(esf_sim *s, esf_load_out *o, esf_error *err);

/* Before a checkpoint: the files' rows flushed and fsync'ed. */
int esf_load_out_sync(esf_load_out *o, esf_error *err);

void esf_load_out_close(esf_load_out *o);

#endif
