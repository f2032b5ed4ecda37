/* particle_source.h — where particles come from: CSV files and generators (a lattice
 * fill and a random non-overlapping fill of a box, with a size distribution and a
 * material mix, reproducible from a seed). Each appends esf_particle_def entries. */
#ifndef ESF_PARTICLE_SOURCE_H
#define ESF_PARTICLE_SOURCE_H

#include <stddef.h>
#include <stdint.h>

#include "bodies/fill.h"
#include "bodies/particles.h"
#include "util/esf_error.h"

/* Resolves a material name from a CSV `material` column to its index; returns ESF_OK or
 * an error (ESF_EINPUT) whose message the reader prefixes with file and line. */
typedef int (*esf_material_lookup_fn)(void *ctx, const char *name, int32_t *index,
                                      esf_error *err);

/* Reads a CSV file whose header row names at least x, y, z, radius (any order, extra
 * columns are an error unless they are among vx, vy, vz, wx, wy, wz, material). Blank
 * lines and lines starting with '#' are skipped. Rows without a material column use
 * default_material (which may be -1 only when the file has the column). Errors name
 * "path:line:column" (column = 1-based field number): unreadable file (ESF_EIO), missing
 * header columns, wrong field count, non-numeric or non-finite value, radius <= 0. */
int esf_particles_read_csv(const char *path, int32_t default_material,
                           esf_material_lookup_fn lookup, void *lookup_ctx,
                           esf_particle_defs *out, esf_error *err);

/* Random non-overlapping fill: radii are drawn first and placed largest first at random
 * positions, rejecting overlaps with each other and with `existing` (may be NULL);
 * materials are drawn from the mix. Error (ESF_EINPUT) when the count cannot be placed
 * after a bounded number of attempts (the message gives the solid fraction asked for). */
int esf_generate_random(const esf_fill_spec *spec, const esf_particle_defs *existing,
                        esf_particle_defs *out, esf_error *err);

/* Simple cubic (square in 2D) lattice filling the region at the given spacing, first
 * `count` sites (all when 0); radii and materials drawn as above (radii must not exceed
 * half the spacing). */
int esf_generate_lattice(const esf_fill_spec *spec, esf_particle_defs *out,
                         esf_error *err);

#endif
