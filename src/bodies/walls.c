/* walls.c — storage of wall elements and groups. */
#include "bodies/walls.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int esf_walls_add_group(esf_walls *w, const char *label, int *group, esf_error *err) {
  esf_wall_group *g = realloc(w->g, (size_t)(w->ngroups + 1) * sizeof *g);
  if (!g) return esf_fail(err, ESF_ENOMEM, "out of memory for walls");
  w->g = g;
  memset(&g[w->ngroups], 0, sizeof *g);
  snprintf(g[w->ngroups].label, sizeof g->label, "%s", label);
  *group = w->ngroups++;
  return ESF_OK;
}

int esf_walls_add_elem(esf_walls *w, const esf_wall_elem *e, esf_error *err) {
  if (e->group < 0 || e->group >= w->ngroups)
    return esf_fail(err, ESF_EINTERNAL, "wall element of unknown group %d", e->group);
  if (w->n == w->cap) {
    size_t cap = w->cap ? 2 * w->cap : 8;
    esf_wall_elem *ne = realloc(w->e, cap * sizeof *ne);
    if (!ne) return esf_fail(err, ESF_ENOMEM, "out of memory for walls");
    w->e = ne;
    w->cap = cap;
  }
  w->e[w->n++] = *e;
  return ESF_OK;
}

int esf_walls_own(esf_walls *w, void *block, esf_error *err) {
  void **o = block ? realloc(w->own, (size_t)(w->nown + 1) * sizeof *o) : NULL;
  if (!o) {
    free(block);
    return esf_fail(err, ESF_ENOMEM, "out of memory for wall motions");
  }
  w->own = o;
  o[w->nown++] = block;
  return ESF_OK;
}

int esf_walls_find(const esf_walls *w, const char *name) {
  for (int k = 0; k < w->ngroups; k++)
    if (w->g[k].named && strcmp(w->g[k].label, name) == 0) return k;
  return -1;
}

void esf_walls_release(esf_walls *w) {
  for (int k = 0; k < w->nown; k++) free(w->own[k]);
  free(w->own);
  free(w->e);
  free(w->e0);
  free(w->g);
  free(w->gforce);
  free(w->gforce_blk);
  memset(w, 0, sizeof *w);
}
