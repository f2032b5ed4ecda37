/* loads_ckpt.c — checkpoint section "SAND" (loads_ckpt.h).
 * Layout (native): int32 servo count, then per servo group int32 group index, disp[3]
 * (m), vel[3] (m/s), sigma (Pa); int32 event count, then per event int32 done, int64
 * deleted, double t_done (s); int32 fluid present, int32 its log state. */
#include "ckpt/loads_ckpt.h"

#include <math.h>
#include <stdint.h>

#include "loads/drag.h"
#include "loads/events.h"

void esf_loads_ckpt_save(const esf_sim *s, esf_blob *b) {
  const esf_walls *w = &s->walls;
  int32_t ns = 0;
  for (int g = 0; g < w->ngroups; g++) ns += w->g[g].motion.kind == ESF_MOTION_SERVO;
  esf_blob_put(b, &ns, 4);
  for (int32_t g = 0; g < w->ngroups; g++) {
    const esf_wall_group *G = &w->g[g];
    if (G->motion.kind != ESF_MOTION_SERVO) continue;
    esf_blob_put(b, &g, 4);
    esf_blob_put(b, G->disp, 3 * sizeof(double));
    esf_blob_put(b, G->vel, 3 * sizeof(double));
    esf_blob_put(b, &G->motion.sigma, sizeof(double));
  }
  int32_t ne = s->events ? s->events->n : 0;
  esf_blob_put(b, &ne, 4);
  for (int k = 0; k < ne; k++) {
    const esf_event *ev = &s->events->e[k];
    int32_t done = ev->done;
    int64_t del = ev->deleted;
    esf_blob_put(b, &done, 4);
    esf_blob_put(b, &del, 8);
    esf_blob_put(b, &ev->t_done, sizeof(double));
  }
  int32_t fl[2] = {s->drag != NULL, s->drag ? s->drag->logged : 0};
  esf_blob_put(b, fl, sizeof fl);
}

int esf_loads_ckpt_restore(esf_sim *s, esf_blob_in *in) {
  esf_walls *w = &s->walls;
  int32_t ns_scene = 0, ne_scene = s->events ? s->events->n : 0;
  for (int g = 0; g < w->ngroups; g++)
    ns_scene += w->g[g].motion.kind == ESF_MOTION_SERVO;
  if (!in->d) return ns_scene == 0 && ne_scene == 0 && !s->drag ? 0 : -1;
  int32_t ns = -1;
  esf_blob_get(in, &ns, 4);
  if (ns != ns_scene) return -1;
  for (int k = 0; k < ns; k++) {
    int32_t g = -1;
    esf_blob_get(in, &g, 4);
    if (g < 0 || g >= w->ngroups || w->g[g].motion.kind != ESF_MOTION_SERVO) return -1;
    esf_blob_get(in, w->g[g].disp, 3 * sizeof(double));
    esf_blob_get(in, w->g[g].vel, 3 * sizeof(double));
    esf_blob_get(in, &w->g[g].motion.sigma, sizeof(double));
    const esf_wall_group *gr = &w->g[g];
    for (int q = 0; q < 3; q++)
      if (!isfinite(gr->disp[q]) || !isfinite(gr->vel[q])) return -1;
    if (!isfinite(gr->motion.sigma)) return -1;
  }
  int32_t ne = -1;
  esf_blob_get(in, &ne, 4);
  if (ne != ne_scene) return -1;
  for (int k = 0; k < ne; k++) {
    esf_event *ev = &s->events->e[k];
    int32_t done = 0;
    int64_t del = 0;
    esf_blob_get(in, &done, 4);
    esf_blob_get(in, &del, 8);
    esf_blob_get(in, &ev->t_done, sizeof(double));
    if ((done != 0 && done != 1) || del < 0 || !isfinite(ev->t_done)) return -1;
    ev->done = done;
    ev->deleted = (long)del;
  }
  if (ne > 0) esf_events_wall_state(s); /* the walls the applied events removed */
  int32_t fl[2] = {-1, 0};
  esf_blob_get(in, fl, sizeof fl);
  if (fl[0] != (s->drag != NULL)) return -1;
  if (s->drag) s->drag->logged = fl[1];
  return in->short_read || in->pos != in->n ? -1 : 0;
}
