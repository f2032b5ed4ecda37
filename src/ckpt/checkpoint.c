/* checkpoint.c — writing and verifying checkpoints (checkpoint.h); restoring is in
 * checkpoint_restore.c.
 *
 * Writing assembles the whole file in memory (one esf_blob; sizes in
 * docs/checkpoints.md#format) and hands it to esf_atomic_write (temporary file, fsync,
 * rename, fsync of the directory), so the previous checkpoint is replaced only by a
 * complete new one. Each section carries a CRC-32 (IEEE 802.3, bitwise); loading reads
 * the whole file and checks the signature, byte order, format version, every section's
 * bounds and checksum, the END marker, the presence of every section and the strings'
 * termination before anything is used. The records whose layout other branches extend
 * (esf_contact_hist, esf_contact_bond, esf_ledger) are stored raw with their size and a
 * layout string (LAYOUT section); a checkpoint from a build with another layout is
 * refused with both layouts in the message. Units: SI throughout, as in the sim. */
#include "ckpt/checkpoint.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "ckpt/checkpoint_format.h"
#include "ckpt/loads_ckpt.h"
#include "loads/insert.h"
#include "util/atomic_file.h"
#include "util/blob.h"
#include "util/version.h"

/* Update with every field added to esf_contact_hist, esf_contact_bond or
 * esf_contact_roll (contact_law.h): a checkpoint records it and a resume refuses
 * another. */
#define HIST_LAYOUT                                                                      \
  "xi f64[3], n f64[3]; bond: s f64, on i32, spare i32; roll: m f64[3], t f64"
_Static_assert(sizeof(esf_contact_hist) == 6 * sizeof(double) &&
                   sizeof(esf_contact_bond) == 2 * sizeof(double) &&
                   sizeof(esf_contact_roll) == 4 * sizeof(double),
               "esf_contact_hist, _bond or _roll changed: update HIST_LAYOUT");

/* 2: bond states apart; 3: rolling states apart; 4: INSERT section (particles
 * inserted during the run), the ledger's energy_inserted; 5: the PERIODIC section
 * (periodic image counters, pair images, Lees-Edwards offset) */
enum { CK_VERSION = 5, CK_BOM = 0x01020304 };
static const char ck_magic[8] = "ESFCKPT";

static uint32_t crc32(const unsigned char *p, size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; i++) {
    c ^= p[i];
    for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

static void layout(char *buf, size_t size) {
  snprintf(buf, size,
           "esf_contact_hist %zu: %s\nesf_ledger %zu\nck_sim %zu\nesf_material %zu\n"
           "esf_pair_params %zu\nesf_ckpt_run %zu\n",
           sizeof(esf_contact_hist), HIST_LAYOUT, sizeof(esf_ledger), sizeof(ck_sim),
           sizeof(esf_material), sizeof(esf_pair_params), sizeof(esf_ckpt_run));
}

/* Section writing: the tag and a length placeholder, payload, then the CRC. */
static size_t sec_begin(esf_blob *b, const char *tag) {
  char t[8] = {0};
  memcpy(t, tag, strlen(tag) < 8 ? strlen(tag) : 8);
  esf_blob_put(b, t, 8);
  uint64_t len = 0;
  esf_blob_put(b, &len, 8);
  return b->n;
}

static void sec_end(esf_blob *b, size_t start) {
  if (b->nomem) return;
  uint64_t len = b->n - start;
  memcpy(b->d + start - 8, &len, 8);
  uint32_t c = crc32(b->d + start, (size_t)len);
  esf_blob_put(b, &c, 4);
}

static void put_sec(esf_blob *b, const char *tag, const void *p, size_t n) {
  size_t s = sec_begin(b, tag);
  esf_blob_put(b, p, n);
  sec_end(b, s);
}

static void put_contacts(esf_blob *b, const char *tag, const esf_candidates *c) {
  size_t s = sec_begin(b, tag);
  uint64_t n = c->n;
  uint8_t has_vc0 = c->vc0 != NULL, has_bond = c->bond != NULL,
          has_roll = c->roll != NULL;
  esf_blob_put(b, &n, 8);
  esf_blob_put(b, &has_vc0, 1);
  esf_blob_put(b, &has_bond, 1);
  esf_blob_put(b, &has_roll, 1);
  esf_blob_put(b, c->a, n * sizeof *c->a);
  esf_blob_put(b, c->b, n * sizeof *c->b);
  esf_blob_put(b, c->h, n * sizeof *c->h);
  esf_blob_put(b, c->touch, n * sizeof *c->touch);
  /* vc0 is meaningful only while touching (a candidate new since the last build has
     none yet: its entry is uninitialised memory); zeros are written for the others */
  static const double zero[3] = {0, 0, 0};
  for (uint64_t k = 0; has_vc0 && k < n; k++)
    esf_blob_put(b, c->touch[k] ? c->vc0 + 3 * k : zero, 3 * sizeof *c->vc0);
  for (uint64_t k = 0; has_vc0 && has_roll && k < n; k++) /* the rolling carry, alike */
    esf_blob_put(b, c->touch[k] ? c->wr0 + 3 * k : zero, 3 * sizeof *c->wr0);
  if (has_bond) esf_blob_put(b, c->bond, n * sizeof *c->bond);
  if (has_roll) esf_blob_put(b, c->roll, n * sizeof *c->roll);
  sec_end(b, s);
}

static void put_meta(esf_blob *b, const esf_sim *s, const esf_ckpt_scene *sc,
                     const esf_ckpt_run *run) {
  char m[4096];
  snprintf(m, sizeof m,
           "esfera_version: %s\nscene: %s\nscene_file: %s\noverrides: %d\nmethod: %s\n"
           "time: %.17g\nstep: %ld\ndt: %.17g\nparticles: %zu\npair_candidates: %zu\n"
           "wall_candidates: %zu\ntouching: %zu\nremoved: %ld\nframes: %ld\n"
           "energy_rows: %ld\ncheckpoint_every: %.17g\ncheckpoint_number: %ld\n",
           ESF_VERSION, s->cfg.name, sc->path, sc->nsets, s->cfg.method, s->t, s->step,
           s->dt, s->p.n, s->nb.pp.n, s->nb.pw.n, esf_neighbor_touching(&s->nb),
           s->removed, run->frames, run->erows, s->cfg.ckpt_every, run->count);
  put_sec(b, "META", m, strlen(m));
}

int esf_ckpt_write(const char *path, esf_sim *s, const esf_integrator_type *it, void *ist,
                   const esf_ckpt_scene *sc, const esf_ckpt_run *run, esf_error *err) {
  if (!it->save)
    return esf_fail(err, ESF_EINPUT,
                    "integrator %s cannot write checkpoints (leapfrog and erk: methods "
                    "can)",
                    s->cfg.method);
  int rc = esf_sim_forces_sync(s, err);
  if (rc) return rc;
  esf_blob integ = {0};
  rc = it->save(s, ist, &integ, err);
  if (rc) {
    esf_blob_release(&integ);
    return rc;
  }
  esf_blob b = {0};
  uint32_t head[2] = {CK_BOM, CK_VERSION};
  esf_blob_put(&b, ck_magic, 8);
  esf_blob_put(&b, head, sizeof head);
  put_meta(&b, s, sc, run);
  size_t st;
  char lay[512];
  layout(lay, sizeof lay);
  put_sec(&b, "LAYOUT", lay, strlen(lay));
  st = sec_begin(&b, "SCENE"); /* strings are stored with their NUL */
  esf_blob_put(&b, sc->text, sc->len);
  esf_blob_put(&b, "", 1);
  sec_end(&b, st);
  put_sec(&b, "SCNPATH", sc->path, strlen(sc->path) + 1);
  st = sec_begin(&b, "SETS");
  for (int k = 0; k < sc->nsets; k++)
    esf_blob_put(&b, sc->sets[k], strlen(sc->sets[k]) + 1);
  sec_end(&b, st);
  put_sec(&b, "METHOD", s->cfg.method, strlen(s->cfg.method) + 1);

  ck_sim cs = {
      s->t,       s->dt,   s->led_time, s->alpha_r,   s->alpha_t,   s->contacts_sum,
      s->walls.t, s->step, s->removed,  s->rhs_evals, s->nb.builds, {0},
      0,          0};
  memcpy(cs.rng, s->rng.s, sizeof cs.rng);
  cs.bonds_formed = s->bonds.formed;
  cs.bonds_broken = s->bonds.broken;
  put_sec(&b, "SIM", &cs, sizeof cs);
  put_sec(&b, "LEDGER", &s->led, sizeof s->led);
  put_sec(&b, "RUN", run, sizeof *run);

  st = sec_begin(&b, "WALLS");
  int32_t ng = s->walls.ngroups;
  uint64_t ne = s->walls.n;
  esf_blob_put(&b, &ng, 4);
  esf_blob_put(&b, &ne, 8);
  for (int g = 0; g < ng; g++) {
    esf_blob_put(&b, s->walls.g[g].disp_mark, 3 * sizeof(double));
    esf_blob_put(&b, &s->walls.g[g].angle_mark, sizeof(double));
  }
  sec_end(&b, st);
  st = sec_begin(&b, "SAND"); /* servo walls, events, fluid (loads_ckpt.c) */
  esf_loads_ckpt_save(s, &b);
  sec_end(&b, st);
  st = sec_begin(&b, "INSERT"); /* insertion's streams and counts (loads/insert.c) */
  esf_inserts_save(s, &b);
  sec_end(&b, st);

  st = sec_begin(&b, "MATS");
  int32_t nm = s->mats.n;
  esf_blob_put(&b, &nm, 4);
  esf_blob_put(&b, s->mats.m, (size_t)nm * sizeof *s->mats.m);
  for (size_t k = 0; k < (size_t)nm * (size_t)nm; k++) { /* the law pointer differs */
    esf_pair_params pp = s->mats.pair[k];                /* between processes: 0 */
    pp.law = NULL;
    esf_blob_put(&b, &pp, sizeof pp);
  }
  sec_end(&b, st);

  const esf_particles *p = &s->p;
  st = sec_begin(&b, "PART");
  uint64_t n = p->n;
  esf_blob_put(&b, &n, 8);
  esf_blob_put(&b, p->y, 9 * n * sizeof(double));
  esf_blob_put(&b, p->f, 3 * n * sizeof(double));
  esf_blob_put(&b, p->t, 3 * n * sizeof(double));
  const double *cols[] = {p->radius, p->mass, p->inv_mass, p->inertia, p->inv_inertia};
  for (int k = 0; k < 5; k++) esf_blob_put(&b, cols[k], n * sizeof(double));
  esf_blob_put(&b, p->material, n * sizeof *p->material);
  esf_blob_put(&b, p->id, n * sizeof *p->id);
  sec_end(&b, st);

  put_contacts(&b, "CONTPP", &s->nb.pp);
  put_contacts(&b, "CONTPW", &s->nb.pw);
  st = sec_begin(&b, "NBREF");
  uint64_t nref = s->nb.xref ? s->nb.nref : 0;
  esf_blob_put(&b, &nref, 8);
  esf_blob_put(&b, s->nb.xref, 3 * nref * sizeof(double));
  sec_end(&b, st);

  { /* the adaptive skin's state (neighbor.h): the lists' skin and build step */
    const double sk[2] = {s->nb.skin, (double)s->nb.built_step};
    put_sec(&b, "NBSKIN", sk, sizeof sk);
  }
  if (p->img) { /* periodic axes: the image counters and the pairs' images */
    st = sec_begin(&b, "PERIODIC");
    esf_blob_put(&b, p->img, 3 * n * sizeof *p->img);
    esf_blob_put(&b, s->nb.pp.img, 3 * s->nb.pp.n * sizeof *s->nb.pp.img);
    if (s->cfg.per.le) { /* Lees-Edwards: the list's offset reference and build time */
      const double le[2] = {s->nb.pp.le_ref, s->nb.pp.le_tb};
      esf_blob_put(&b, le, sizeof le);
    }
    sec_end(&b, st);
  }
  put_sec(&b, "INTEG", integ.d, integ.n);
  esf_blob_release(&integ);
  put_sec(&b, "END", NULL, 0);
  if (b.nomem)
    rc = esf_fail(err, ESF_ENOMEM, "out of memory assembling the checkpoint");
  else
    rc = esf_atomic_write(path, b.d, b.n, err);
  esf_blob_release(&b);
  return rc;
}

void esf_ckpt_free(esf_ckpt **c) {
  if (!c || !*c) return;
  free((*c)->data);
  free(*c);
  *c = NULL;
}

int esf_ckpt_is(const char *path) {
  FILE *f = fopen(path, "rb");
  char m[8] = {0};
  int ok = f && fread(m, 1, 8, f) == 8 && memcmp(m, ck_magic, 8) == 0;
  if (f) fclose(f);
  return ok;
}

static int bad(esf_ckpt *c, esf_error *err, const char *what) {
  int rc = esf_fail(err, ESF_EINPUT, "%s: %s; cannot resume from it", c->path, what);
  esf_ckpt_free(&c);
  return rc;
}

int esf_ckpt_load(const char *path, esf_ckpt **out, esf_error *err) {
  *out = NULL;
  esf_ckpt *c = calloc(1, sizeof *c);
  if (!c) return esf_fail(err, ESF_ENOMEM, "out of memory");
  struct stat sb;
  if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
    snprintf(c->path, sizeof c->path, "%s/%s", path, ESF_CKPT_NAME);
  else
    snprintf(c->path, sizeof c->path, "%s", path);
  int rc = esf_read_file(c->path, &c->data, &c->len, err);
  if (rc) {
    esf_ckpt_free(&c);
    return rc;
  }
  const unsigned char *d = (const unsigned char *)c->data;
  if (c->len < 16 || memcmp(d, ck_magic, 8) != 0)
    return bad(c, err,
               c->len < 8 && c->len > 0 && memcmp(d, ck_magic, c->len) == 0
                   ? "truncated (shorter than its header)"
                   : "not an esfera checkpoint (no ESFCKPT signature)");
  uint32_t head[2];
  memcpy(head, d + 8, 8);
  if (head[0] != CK_BOM) return bad(c, err, "written on a machine of another byte order");
  if (head[1] != CK_VERSION) {
    char m[96];
    snprintf(m, sizeof m, "checkpoint format %u, this esfera reads %d", head[1],
             CK_VERSION);
    return bad(c, err, m);
  }
  size_t pos = 16;
  int ended = 0;
  while (!ended) {
    char m[160];
    if (c->len - pos < 16) {
      snprintf(m, sizeof m, "truncated at byte %zu of %zu (no end marker)", pos, c->len);
      return bad(c, err, m);
    }
    char tag[9] = {0}, shown[9] = {0}; /* shown: the tag as text, for messages */
    memcpy(tag, d + pos, 8);
    for (int k = 0; k < 8 && tag[k]; k++)
      shown[k] = tag[k] >= 0x20 && tag[k] < 0x7f ? tag[k] : '?';
    uint64_t len;
    memcpy(&len, d + pos + 8, 8);
    if (len > c->len - pos - 16 || c->len - pos - 16 - len < 4) {
      snprintf(m, sizeof m, "truncated: section '%s' cut short at byte %zu", shown,
               c->len);
      return bad(c, err, m);
    }
    uint32_t crc;
    memcpy(&crc, d + pos + 16 + len, 4);
    if (crc32(d + pos + 16, (size_t)len) != crc) {
      snprintf(m, sizeof m, "corrupted: section '%s' fails its checksum", shown);
      return bad(c, err, m);
    }
    if (c->nsec == 32) return bad(c, err, "corrupted: too many sections");
    memcpy(c->sec[c->nsec].tag, tag, 9);
    c->sec[c->nsec].p = d + pos + 16;
    c->sec[c->nsec].len = (size_t)len;
    c->nsec++;
    pos += 16 + (size_t)len + 4;
    ended = strcmp(tag, "END") == 0;
  }
  char lay[512];
  layout(lay, sizeof lay);
  for (int k = 0; k < c->nsec; k++)
    if (strcmp(c->sec[k].tag, "LAYOUT") == 0 &&
        (c->sec[k].len != strlen(lay) || memcmp(c->sec[k].p, lay, strlen(lay)) != 0)) {
      char m[1400];
      snprintf(m, sizeof m,
               "written by an esfera build with other record layouts:\n%.*s\nthis "
               "build has:\n%s",
               (int)c->sec[k].len, (const char *)c->sec[k].p, lay);
      return bad(c, err, m);
    }
  const char *str_secs[] = {"META",   "SCENE", "SCNPATH", "METHOD", "SETS", "SIM",
                            "LEDGER", "RUN",   "WALLS",   "MATS",   "PART", "CONTPP",
                            "CONTPW", "NBREF", "INTEG",   "INSERT"};
  for (size_t k = 0; k < sizeof str_secs / sizeof *str_secs; k++) {
    esf_blob_in in = esf_ckpt_sec(c, str_secs[k]);
    char m[96];
    snprintf(m, sizeof m, "incomplete: no section '%s'", str_secs[k]);
    if (in.short_read) return bad(c, err, m);
    int is_str = k >= 1 && k <= 3;
    if ((is_str || (k == 4 && in.n > 0)) && (in.n == 0 || in.d[in.n - 1] != '\0')) {
      snprintf(m, sizeof m, "corrupted: section '%s' is not a string", str_secs[k]);
      return bad(c, err, m);
    }
  }
  esf_blob_in st = esf_ckpt_sec(c, "SETS");
  for (size_t i = 0; i < st.n; i += strlen((const char *)st.d + i) + 1) {
    if (c->nsets == 256) return bad(c, err, "corrupted: more than 256 overrides");
    c->sets[c->nsets++] = (const char *)st.d + i;
  }
  *out = c;
  return ESF_OK;
}

void esf_ckpt_scene_of(const esf_ckpt *c, esf_ckpt_scene *sc) {
  esf_blob_in t = esf_ckpt_sec(c, "SCENE"), p = esf_ckpt_sec(c, "SCNPATH");
  sc->text = (const char *)t.d;
  sc->len = t.n - 1;
  sc->path = (const char *)p.d;
  sc->sets = c->sets;
  sc->nsets = c->nsets;
}

/* Section by tag as a reader; NULL reader (short) when missing. */
esf_blob_in esf_ckpt_sec(const esf_ckpt *c, const char *tag) {
  for (int k = 0; k < c->nsec; k++)
    if (strcmp(c->sec[k].tag, tag) == 0)
      return (esf_blob_in){c->sec[k].p, c->sec[k].len, 0, 0};
  return (esf_blob_in){NULL, 0, 0, 1};
}
