/* fuzz_ckpt.c — fuzzes the checkpoint reader: esf_ckpt_load (signature, sections,
 * checksums, strings), esf_ckpt_describe (`esfera info`) and, for a checkpoint of one
 * of the fixed scenes in ESF_FUZZ_DATA (ckpt_*.yaml), the resume: the stored scene
 * loaded and set up, the integrator created, esf_ckpt_restore (checkpoint_restore.c).
 * How: the section checksums are recomputed before loading (a stored CRC of 0 is kept,
 * so the checksum test is still reached), so that mutated payloads get past the CRC
 * to the field validation; in the fuzz build a custom mutator mutates one section's
 * payload at a time (or, one time in eight, the raw bytes) and keeps the framing.
 * Restores run only when the stored scene is one of the fixed scenes, byte for byte,
 * with no overrides: a mutated scene is fuzz_scene.c's business and could ask for any
 * amount of work.
 * What holds: ESF_OK or an error with a message, never a crash, undefined behaviour or
 * a leak: a checkpoint that passes its checksums but does not fit its scene or itself
 * is refused cleanly (checkpoint.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ckpt/checkpoint.h"
#include "fuzz.h"
#include "integrators/integrator.h"
#include "model/model.h"

const char esf_fuzz_name[] = "ckpt";

static const char *const scene_files[] = {"ckpt_bed.yaml", "ckpt_erk.yaml",
                                          "ckpt_bond.yaml", "ckpt_sand.yaml", NULL};
enum { NSCENES = 4 };
static char *scene_text[NSCENES];
static size_t scene_len[NSCENES];

static uint32_t crc32(const uint8_t *p, size_t n) { /* as checkpoint.c */
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; i++) {
    c ^= p[i];
    for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

/* Calls fn(payload offset, length) for each section whose frame fits in n bytes,
 * up to and including END; returns the offset after the last one. */
static size_t walk(const uint8_t *d, size_t n, void (*fn)(uint8_t *, size_t, size_t),
                   uint8_t *w) {
  size_t pos = 16;
  while (n >= 16 && pos <= n - 16) {
    uint64_t len;
    memcpy(&len, d + pos + 8, 8);
    if (len > n - pos - 16 || n - pos - 16 - len < 4) break;
    if (fn) fn(w, pos + 16, (size_t)len);
    int end = !memcmp(d + pos, "END\0\0\0\0\0", 8);
    pos += 16 + (size_t)len + 4;
    if (end) break;
  }
  return pos;
}

static void fix_crc(uint8_t *d, size_t off, size_t len) {
  uint32_t old, c = crc32(d + off, len);
  memcpy(&old, d + off + len, 4);
  if (old != 0) memcpy(d + off + len, &c, 4);
}

static void load_scenes(void) {
  static int done;
  if (done) return;
  done = 1;
  for (int k = 0; k < NSCENES; k++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", ESF_FUZZ_DATA, scene_files[k]);
    if (!(scene_text[k] = esf_fuzz_read(path, &scene_len[k]))) {
      fprintf(stderr, "fuzz_ckpt: cannot read %s\n", path);
      abort();
    }
  }
}

static void free_scenes(void) {
  for (int k = 0; k < NSCENES; k++) free(scene_text[k]);
}

/* The resume of a loaded checkpoint whose scene is a fixed one, as `esfera run
 * --resume` does up to its first step. */
static int resume(const esf_ckpt *c, esf_error *err) {
  esf_ckpt_scene sc;
  esf_ckpt_scene_of(c, &sc);
  int known = 0;
  for (int k = 0; k < NSCENES; k++)
    known |= sc.len == scene_len[k] && !memcmp(sc.text, scene_text[k], sc.len);
  if (!known || sc.nsets) return ESF_OK;
  esf_sim s;
  memset(&s, 0, sizeof s);
  int rc = esf_ckpt_load_scene(c, NULL, 0, &s, err);
  const esf_integrator_type *it = rc ? NULL : esf_integrator_find(s.cfg.method);
  if (!rc && !it) rc = esf_fail(err, ESF_EINPUT, "unknown method '%s'", s.cfg.method);
  s.cfg.threads = 1;
  if (!rc) rc = esf_sim_setup(&s, err);
  void *ist = NULL;
  if (!rc) rc = it->create(&s, &ist, err);
  esf_ckpt_run run;
  if (!rc) rc = esf_ckpt_restore(c, &s, it, ist, &run, err);
  if (ist) it->destroy(&ist);
  esf_sim_release(&s);
  return rc;
}

int esf_fuzz_one(const uint8_t *data, size_t size, esf_error *err) {
  static int registered;
  if (!registered) {
    registered = 1;
    load_scenes();
    atexit(free_scenes);
  }
  uint8_t *d = malloc(size ? size : 1);
  if (!d) abort();
  memcpy(d, data, size);
  walk(d, size, fix_crc, d);
  const char *path = esf_fuzz_write(ESF_CKPT_NAME, d, size);
  free(d);
  FILE *null = fopen("/dev/null", "w");
  esf_error e2;
  esf_error_clear(&e2);
  esf_ckpt_describe(path, null, &e2);
  fclose(null);
  esf_ckpt *c = NULL;
  int rc = esf_ckpt_load(path, &c, err);
  if (!rc) rc = resume(c, err);
  esf_ckpt_free(&c);
  return rc;
}

#ifdef ESF_FUZZ_LIBFUZZER
size_t LLVMFuzzerMutate(uint8_t *data, size_t size, size_t max_size);
size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max_size,
                               unsigned int seed);

static size_t sec_off[64], sec_len[64];
static int nsec;

static void note(uint8_t *unused, size_t off, size_t len) {
  (void)unused;
  if (nsec < 64) sec_off[nsec] = off, sec_len[nsec] = len, nsec++;
}

/* One section's payload mutated in place, its length field updated and the rest of
 * the file moved after it; the stored scene (SCENE, SCNPATH, SETS) left alone but one
 * time in eight, and the raw bytes mutated one time in eight. */
size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max_size,
                               unsigned int seed) {
  nsec = 0;
  walk(data, size, note, NULL);
  srand(seed);
  if (nsec == 0 || rand() % 8 == 0) return LLVMFuzzerMutate(data, size, max_size);
  int k = rand() % nsec;
  for (int tries = 0; tries < 8; tries++) {
    const uint8_t *tag = data + sec_off[k] - 16;
    int scene = !memcmp(tag, "SCENE\0", 6) || !memcmp(tag, "SCNPATH", 7) ||
                !memcmp(tag, "SETS\0", 5);
    if (!scene || rand() % 8 == 0) break;
    k = rand() % nsec;
  }
  size_t off = sec_off[k], len = sec_len[k], tail = size - (off + len);
  if (max_size < size || max_size - size + len == 0) return size;
  size_t room = max_size - size + len; /* the payload may grow into the free room */
  uint8_t *p = malloc(room ? room : 1);
  if (!p) return size;
  memcpy(p, data + off, len);
  size_t nlen = LLVMFuzzerMutate(p, len, room);
  memmove(data + off + nlen, data + off + len, tail);
  memcpy(data + off, p, nlen);
  uint64_t l64 = nlen;
  memcpy(data + off - 8, &l64, 8);
  free(p);
  return size - len + nlen;
}
#endif
