/* fuzz.h — what the fuzz harnesses (tests/fuzz/fuzz_*.c) share: one entry point per
 * harness, run by libFuzzer in the fuzz build (fuzz_main.c) and by the replay program
 * in every build (replay.c, the regression tests), and small file helpers.
 *
 * A harness takes the fuzzer's bytes, hands them to one reader of the library the way
 * the esfera program does, frees everything it made and returns the library's status
 * (ESF_OK or an ESF_E* code with err's message), which the replay compares with the
 * exit status the program would give (esf_error_exit_status). */
#ifndef ESF_FUZZ_H
#define ESF_FUZZ_H

#include <stddef.h>
#include <stdint.h>

#include "util/esf_error.h"

/* The harness: one input, the library's status. Defined once per fuzz_*.c. */
int esf_fuzz_one(const uint8_t *data, size_t size, esf_error *err);

/* The harness's name, for messages ("scene", "csv", ...). */
extern const char esf_fuzz_name[];

/* The rest of `esfera run` up to its first step on a parsed scene (fuzz_sim.c): read
 * into a sim (source names the scene in messages), set up on one thread, the
 * integrator created and destroyed; everything freed. The first failing status. */
typedef struct esf_ydoc esf_ydoc;
int esf_fuzz_scene(esf_ydoc *doc, const char *source, esf_error *err);

/* A path in this process's scratch directory (made on first use, removed at exit):
 * "<tmp>/esf-fuzz-XXXXXX/<name>". The returned buffer stays valid until exit. */
const char *esf_fuzz_path(const char *name);

/* Writes data to the scratch file `name` (replacing it); its path, or NULL with a
 * message on stderr when it cannot be written. */
const char *esf_fuzz_write(const char *name, const uint8_t *data, size_t size);

/* The whole file at path with a NUL after it (free it), or NULL. */
char *esf_fuzz_read(const char *path, size_t *size);

/* ESF_FUZZ_DATA: tests/fuzz/data in the source tree (small fixed files the harnesses
 * use: a CSV and an STL the scenes may name, the checkpoint scenes). */
#ifndef ESF_FUZZ_DATA
#define ESF_FUZZ_DATA "tests/fuzz/data"
#endif

#endif
