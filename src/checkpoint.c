/* checkpoint.c — writing, verifying and restoring checkpoints (checkpoint.h).
 *
 * Writing assembles the whole file in memory (one esf_blob: the settle scene's 3000
 * particles take about 0.8 MB) and hands it to esf_atomic_write (temporary file, fsync,
 * rename, fsync of the directory), so the previous checkpoint is replaced only by a
 * complete new one. Each section carries a CRC-32 (IEEE 802.3, bitwise); loading reads
 * the whole file and checks the signature, byte order, format version, every section's
 * bounds and checksum and the END marker before anything is used.
 * Restoring (on a sim set up from the stored scene, the integrator created): the
 * particle arrays are replaced (n may differ from the scene's: particles leave the
 * domain), the candidate lists are rebuilt once to size the derived scratch and then
 * overwritten with the saved lists, xref and build count; walls are placed at the saved
 * time (esf_walls_set_time is a function of time) with their rebuild marks restored.
 * The records whose layout other branches extend (esf_contact_hist, esf_ledger) are
 * stored raw with their size and a layout string (LAYOUT section); a checkpoint from a
 * build with another layout is refused with both layouts in the message. */
#include "checkpoint.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "atomic_file.h"
#include "blob.h"
#include "scene.h"
#include "version.h"

/* Update with every field added to esf_contact_hist (contact_law.h): a checkpoint
 * records it and a resume refuses another. */
#define HIST_LAYOUT "xi f64[3], n f64[3]"
_Static_assert(sizeof(esf_contact_hist) == 6 * sizeof(double),
               "esf_contact_hist changed: update HIST_LAYOUT in checkpoint.c");

enum { CK_VERSION = 1, CK_BOM = 0x01020304 };
static const char ck_magic[8] = "ESFCKPT";

/* Scalars of the sim between steps. */
typedef struct ck_sim {
  double t, dt, led_time, alpha_r, alpha_t, contacts_sum, walls_t;
  int64_t step, removed, rhs_evals, builds;
  uint64_t rng[4];
} ck_sim;

struct esf_ckpt {
  char *data;
  size_t len;
  char path[1200];
  int nsec;
  const char *sets[256]; /* the stored overrides */
  int nsets;
  struct {
    char tag[9];
    const unsigned char *p;
    size_t len;
  } sec[32];
};

static uint32_t crc32(const unsigned char *p, size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; i++) {
    c ^= p[i];
    for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

static esf_blob_in sec(const esf_ckpt *c, const char *tag);

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

static void put_contacts(esf_blob *b, const char *tag, const esf_contacts *c) {
  size_t s = sec_begin(b, tag);
  uint64_t n = c->n;
  uint8_t has_vc0 = c->vc0 != NULL;
  esf_blob_put(b, &n, 8);
  esf_blob_put(b, &has_vc0, 1);
  esf_blob_put(b, c->a, n * sizeof *c->a);
  esf_blob_put(b, c->b, n * sizeof *c->b);
  esf_blob_put(b, c->h, n * sizeof *c->h);
  esf_blob_put(b, c->touch, n * sizeof *c->touch);
  /* vc0 is meaningful only while touching (a candidate new since the last build has
     none yet: its entry is uninitialised memory); zeros are written for the others */
  static const double zero[3] = {0, 0, 0};
  for (uint64_t k = 0; has_vc0 && k < n; k++)
    esf_blob_put(b, c->touch[k] ? c->vc0 + 3 * k : zero, 3 * sizeof *c->vc0);
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
  esf_blob integ = {0};
  int rc = it->save(s, ist, &integ, err);
  if (rc) {
    esf_blob_free(&integ);
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

  ck_sim cs = {s->t,       s->dt,           s->led_time,  s->alpha_r,
               s->alpha_t, s->contacts_sum, s->walls.t,   s->step,
               s->removed, s->rhs_evals,    s->nb.builds, {0}};
  memcpy(cs.rng, s->rng.s, sizeof cs.rng);
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

  st = sec_begin(&b, "MATS");
  int32_t nm = s->mats.n;
  esf_blob_put(&b, &nm, 4);
  esf_blob_put(&b, s->mats.m, (size_t)nm * sizeof *s->mats.m);
  esf_blob_put(&b, s->mats.pair, (size_t)nm * (size_t)nm * sizeof *s->mats.pair);
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

  put_sec(&b, "INTEG", integ.d, integ.n);
  esf_blob_free(&integ);
  put_sec(&b, "END", NULL, 0);
  if (b.nomem)
    rc = esf_fail(err, ESF_ENOMEM, "out of memory assembling the checkpoint");
  else
    rc = esf_atomic_write(path, b.d, b.n, err);
  esf_blob_free(&b);
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
    char tag[9] = {0};
    memcpy(tag, d + pos, 8);
    uint64_t len;
    memcpy(&len, d + pos + 8, 8);
    if (len > c->len - pos - 16 || c->len - pos - 16 - len < 4) {
      snprintf(m, sizeof m, "truncated: section '%.8s' cut short at byte %zu", tag,
               c->len);
      return bad(c, err, m);
    }
    uint32_t crc;
    memcpy(&crc, d + pos + 16 + len, 4);
    if (crc32(d + pos + 16, (size_t)len) != crc) {
      snprintf(m, sizeof m, "corrupted: section '%.8s' fails its checksum", tag);
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
  const char *str_secs[] = {"META", "SCENE",  "SCNPATH", "METHOD", "SETS",
                            "SIM",  "LEDGER", "RUN",     "WALLS",  "MATS",
                            "PART", "CONTPP", "CONTPW",  "NBREF",  "INTEG"};
  for (size_t k = 0; k < sizeof str_secs / sizeof *str_secs; k++) {
    esf_blob_in in = sec(c, str_secs[k]);
    char m[96];
    snprintf(m, sizeof m, "incomplete: no section '%s'", str_secs[k]);
    if (in.short_read) return bad(c, err, m);
    int is_str = k >= 1 && k <= 3;
    if ((is_str || (k == 4 && in.n > 0)) && (in.n == 0 || in.d[in.n - 1] != '\0')) {
      snprintf(m, sizeof m, "corrupted: section '%s' is not a string", str_secs[k]);
      return bad(c, err, m);
    }
  }
  esf_blob_in st = sec(c, "SETS");
  for (size_t i = 0; i < st.n; i += strlen((const char *)st.d + i) + 1) {
    if (c->nsets == 256) return bad(c, err, "corrupted: more than 256 overrides");
    c->sets[c->nsets++] = (const char *)st.d + i;
  }
  *out = c;
  return ESF_OK;
}

/* Section by tag as a reader; NULL reader (short) when missing. */
static esf_blob_in sec(const esf_ckpt *c, const char *tag) {
  for (int k = 0; k < c->nsec; k++)
    if (strcmp(c->sec[k].tag, tag) == 0)
      return (esf_blob_in){c->sec[k].p, c->sec[k].len, 0, 0};
  return (esf_blob_in){NULL, 0, 0, 1};
}

void esf_ckpt_scene_of(const esf_ckpt *c, esf_ckpt_scene *sc) {
  esf_blob_in t = sec(c, "SCENE"), p = sec(c, "SCNPATH");
  sc->text = (const char *)t.d;
  sc->len = t.n - 1;
  sc->path = (const char *)p.d;
  sc->sets = c->sets;
  sc->nsets = c->nsets;
}

int esf_ckpt_load_scene(const esf_ckpt *c, const char *const *extra, int nextra,
                        esf_sim *s, esf_error *err) {
  esf_ckpt_scene sc;
  esf_ckpt_scene_of(c, &sc);
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_parse_as(sc.text, sc.len, sc.path, &doc, err);
  for (int k = 0; k < sc.nsets && !rc; k++) rc = esf_ydoc_override(doc, sc.sets[k], err);
  for (int k = 0; k < nextra && !rc; k++) rc = esf_ydoc_override(doc, extra[k], err);
  esf_config_default(&s->cfg);
  snprintf(s->cfg.source, sizeof s->cfg.source, "%s", sc.path);
  if (!rc) rc = esf_scene_read(doc, s, err);
  esf_ydoc_free(&doc);
  if (rc) esf_error_prefix(err, "the scene stored in %s: ", c->path);
  return rc;
}

static int mismatch(const esf_ckpt *c, esf_error *err, const char *what) {
  return esf_fail(err, ESF_EINPUT,
                  "%s does not fit its own scene: %s (written by another esfera "
                  "version?); cannot resume",
                  c->path, what);
}

static int get_contacts(const esf_ckpt *c, const char *tag, esf_contacts *dst, size_t np,
                        size_t nb_other, esf_error *err) {
  esf_blob_in in = sec(c, tag);
  uint64_t m = 0;
  uint8_t has_vc0 = 0;
  esf_blob_get(&in, &m, 8);
  esf_blob_get(&in, &has_vc0, 1);
  if (in.short_read || m > in.n || (m > 0 && (has_vc0 != 0) != (dst->vc0 != NULL)))
    return mismatch(c, err, "a contact list's header");
  esf_blob_get(&in, dst->a, m * sizeof *dst->a);
  esf_blob_get(&in, dst->b, m * sizeof *dst->b);
  esf_blob_get(&in, dst->h, m * sizeof *dst->h);
  esf_blob_get(&in, dst->touch, m * sizeof *dst->touch);
  if (has_vc0 && dst->vc0) esf_blob_get(&in, dst->vc0, 3 * m * sizeof *dst->vc0);
  if (in.short_read || in.pos != in.n) return mismatch(c, err, "a contact list's size");
  for (uint64_t k = 0; k < m; k++)
    if (dst->a[k] >= np || dst->b[k] >= nb_other)
      return mismatch(c, err, "a contact names a particle or wall that does not exist");
  dst->n = (size_t)m;
  return ESF_OK;
}

int esf_ckpt_restore(const esf_ckpt *c, esf_sim *s, const esf_integrator_type *it,
                     void *ist, esf_ckpt_run *run, esf_error *err) {
  esf_blob_in in = sec(c, "METHOD");
  if (strcmp((const char *)in.d, s->cfg.method) != 0)
    return mismatch(c, err, "integrator.method differs");
  if (!it->restore) return mismatch(c, err, "the integrator cannot restore");
  ck_sim cs;
  in = sec(c, "SIM");
  if (esf_blob_get(&in, &cs, sizeof cs) || in.pos != in.n)
    return mismatch(c, err, "the SIM section's size");
  if (memcmp(&cs.dt, &s->dt, sizeof cs.dt) != 0) {
    char m[160];
    snprintf(m, sizeof m, "dt %.17g s saved, %.17g s from the scene", cs.dt, s->dt);
    return mismatch(c, err, m);
  }
  in = sec(c, "MATS");
  int32_t nm = 0;
  esf_blob_get(&in, &nm, 4);
  size_t mb = (size_t)s->mats.n * sizeof *s->mats.m;
  size_t pb = (size_t)s->mats.n * (size_t)s->mats.n * sizeof *s->mats.pair;
  const void *mm = nm == s->mats.n ? esf_blob_take(&in, mb) : NULL;
  const void *pm = mm ? esf_blob_take(&in, pb) : NULL;
  if (!pm || in.pos != in.n || memcmp(mm, s->mats.m, mb) || memcmp(pm, s->mats.pair, pb))
    return mismatch(c, err, "the materials or their pair table differ");
  in = sec(c, "WALLS");
  int32_t ng = 0;
  uint64_t ne = 0;
  esf_blob_get(&in, &ng, 4);
  esf_blob_get(&in, &ne, 8);
  if (ng != s->walls.ngroups || ne != s->walls.n)
    return mismatch(c, err, "the walls differ");
  for (int g = 0; g < ng; g++) {
    esf_blob_get(&in, s->walls.g[g].disp_mark, 3 * sizeof(double));
    esf_blob_get(&in, &s->walls.g[g].angle_mark, sizeof(double));
  }
  if (in.short_read || in.pos != in.n)
    return mismatch(c, err, "the WALLS section's size");

  /* particles: every array, any n */
  in = sec(c, "PART");
  uint64_t n = 0;
  esf_blob_get(&in, &n, 8);
  size_t need = (size_t)n * (9 + 3 + 3 + 5) * sizeof(double) +
                (size_t)n * (sizeof(int32_t) + sizeof(int64_t));
  if (in.short_read || n > in.n || in.n - in.pos != need)
    return mismatch(c, err, "the particle section's size");
  esf_particles *p = &s->p;
  esf_particles_release(p);
  int rc = esf_particles_alloc(p, (size_t)n, err);
  if (rc) return rc;
  esf_blob_get(&in, p->y, 9 * n * sizeof(double));
  esf_blob_get(&in, p->f, 3 * n * sizeof(double));
  esf_blob_get(&in, p->t, 3 * n * sizeof(double));
  double *cols[] = {p->radius, p->mass, p->inv_mass, p->inertia, p->inv_inertia};
  for (int k = 0; k < 5; k++) esf_blob_get(&in, cols[k], n * sizeof(double));
  esf_blob_get(&in, p->material, n * sizeof *p->material);
  esf_blob_get(&in, p->id, n * sizeof *p->id);
  for (size_t i = 0; i < p->n; i++)
    if (p->material[i] < 0 || p->material[i] >= s->mats.n)
      return mismatch(c, err, "a particle's material index");

  /* scalars, rng, ledger, walls at the saved time */
  s->t = cs.t;
  s->led_time = cs.led_time;
  s->alpha_r = cs.alpha_r;
  s->alpha_t = cs.alpha_t;
  s->contacts_sum = cs.contacts_sum;
  s->step = cs.step;
  s->removed = cs.removed;
  s->rhs_evals = cs.rhs_evals;
  memcpy(s->rng.s, cs.rng, sizeof cs.rng);
  in = sec(c, "LEDGER");
  if (esf_blob_get(&in, &s->led, sizeof s->led) || in.pos != in.n)
    return mismatch(c, err, "the LEDGER section's size");
  s->walls.t = NAN; /* so that set_time places moving walls at the saved time */
  esf_walls_set_time(&s->walls, cs.walls_t);
  s->walls.t = cs.walls_t;

  /* candidate lists: one build sizes the derived scratch, then the saved lists */
  rc = esf_neighbor_build(&s->nb, p, &s->walls, err);
  uint64_t npp = 0, npw = 0;
  memcpy(&npp, sec(c, "CONTPP").d, 8);
  memcpy(&npw, sec(c, "CONTPW").d, 8);
  if (!rc && (npp > sec(c, "CONTPP").n || npw > sec(c, "CONTPW").n))
    return mismatch(c, err, "a contact list's size");
  if (!rc) rc = esf_neighbor_reserve(&s->nb, (size_t)npp, (size_t)npw, err);
  if (!rc) rc = get_contacts(c, "CONTPP", &s->nb.pp, p->n, p->n, err);
  if (!rc) rc = get_contacts(c, "CONTPW", &s->nb.pw, p->n, s->walls.n, err);
  if (rc) return rc;
  in = sec(c, "NBREF");
  uint64_t nref = 0;
  esf_blob_get(&in, &nref, 8);
  if (in.short_read || (nref != 0 && nref != n) ||
      in.n - in.pos != 3 * nref * sizeof(double))
    return mismatch(c, err, "the list reference positions");
  free(s->nb.xref);
  s->nb.xref = NULL;
  s->nb.nref = 0;
  if (nref) {
    s->nb.xref = malloc(3 * nref * sizeof(double));
    if (!s->nb.xref) return esf_fail(err, ESF_ENOMEM, "out of memory");
    esf_blob_get(&in, s->nb.xref, 3 * nref * sizeof(double));
    s->nb.nref = (size_t)nref;
  }
  s->nb.builds = cs.builds;

  in = sec(c, "RUN");
  if (esf_blob_get(&in, run, sizeof *run) || in.pos != in.n)
    return mismatch(c, err, "the RUN section's size");
  in = sec(c, "INTEG");
  rc = it->restore(s, ist, &in, err);
  if (rc) esf_error_prefix(err, "%s: ", c->path);
  return rc;
}

int esf_ckpt_describe(const char *path, FILE *out, esf_error *err) {
  esf_ckpt *c = NULL;
  int rc = esf_ckpt_load(path, &c, err);
  if (rc) return rc;
  esf_blob_in m = sec(c, "META");
  fprintf(out, "kind: checkpoint\nfile: %s\nbytes: %zu\n", c->path, c->len);
  fwrite(m.d, 1, m.n, out);
  esf_ckpt_run run;
  esf_blob_in r = sec(c, "RUN");
  esf_blob_get(&r, &run, sizeof run);
  uint64_t n = 0;
  memcpy(&n, sec(c, "PART").d, 8);
  if (n) fprintf(out, "bytes_per_particle: %.1f\n", (double)c->len / (double)n);
  for (int k = 0; k < c->nsets; k++) fprintf(out, "override: %s\n", c->sets[k]);
  char dir[1200];
  snprintf(dir, sizeof dir, "%s", c->path);
  char *slash = strrchr(dir, '/');
  if (slash)
    *slash = '\0';
  else
    snprintf(dir, sizeof dir, ".");
  fprintf(out, "resume: esfera run --resume %s\n", dir);
  esf_ckpt_free(&c);
  return ESF_OK;
}
