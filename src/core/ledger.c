/* ledger.c — energy balance bookkeeping and the energy row (energy.csv, and the /energy
 * table of frames.h5): esf_ledger_columns names the columns, esf_ledger_values gives
 * them, esf_ledger_header and esf_ledger_row print them as CSV (time with 10
 * significant digits, energies in J with 13, alpha in 1/s with 7). Columns added
 * later (work_fluid, work_tangential_stiffness, energy_inserted) go at the end, so
 * readers by position keep working. A step's channels are summed over the blocks
 * exactly (util/xsum.h) and rounded once, so they do not depend on the blocks' order or
 * on how they are shared among processes. */
#include "core/ledger.h"

const char *const esf_ledger_columns[ESF_LEDGER_NCOLS] = {"time",
                                                          "kinetic_translational",
                                                          "kinetic_rotational",
                                                          "potential_gravity",
                                                          "elastic",
                                                          "dissipated_contact",
                                                          "dissipated_friction",
                                                          "dissipated_damping",
                                                          "work_walls",
                                                          "total_error",
                                                          "elastic_normal",
                                                          "elastic_tangential",
                                                          "dissipated_normal",
                                                          "dissipated_tangential",
                                                          "dissipated_global",
                                                          "dissipated_local",
                                                          "energy_removed",
                                                          "alpha_global",
                                                          "dissipated_bonds",
                                                          "work_fluid",
                                                          "elastic_rolling",
                                                          "dissipated_rolling",
                                                          "work_tangential_stiffness",
                                                          "energy_inserted"};

double esf_ledger_stored(const esf_ledger *l) {
  return l->kin_t + l->kin_r + l->pot_g + l->el_n + l->el_t + l->el_r;
}

double esf_ledger_dissipated(const esf_ledger *l) {
  return l->d_normal + l->d_tangential + l->d_friction + l->d_global + l->d_local +
         l->d_bonds + l->d_rolling;
}

double esf_ledger_total_error(const esf_ledger *l) {
  return esf_ledger_stored(l) - l->e0 - l->w_walls - l->w_fluid - l->w_stiff +
         esf_ledger_dissipated(l) + l->e_removed - l->e_inserted;
}

void esf_ledger_values(double t, const esf_ledger *l, double alpha,
                       double row[ESF_LEDGER_NCOLS]) {
  const double v[ESF_LEDGER_NCOLS] = {t,
                                      l->kin_t,
                                      l->kin_r,
                                      l->pot_g,
                                      l->el_n + l->el_t,
                                      l->d_normal + l->d_tangential,
                                      l->d_friction,
                                      l->d_global + l->d_local,
                                      l->w_walls,
                                      esf_ledger_total_error(l),
                                      l->el_n,
                                      l->el_t,
                                      l->d_normal,
                                      l->d_tangential,
                                      l->d_global,
                                      l->d_local,
                                      l->e_removed,
                                      alpha,
                                      l->d_bonds,
                                      l->w_fluid,
                                      l->el_r,
                                      l->d_rolling,
                                      l->w_stiff,
                                      l->e_inserted};
  for (int k = 0; k < ESF_LEDGER_NCOLS; k++) row[k] = v[k];
}

void esf_ledger_header(FILE *f) {
  for (int k = 0; k < ESF_LEDGER_NCOLS; k++)
    fprintf(f, "%s%c", esf_ledger_columns[k], k + 1 < ESF_LEDGER_NCOLS ? ',' : '\n');
}

void esf_ledger_row(FILE *f, double t, const esf_ledger *l, double alpha) {
  double row[ESF_LEDGER_NCOLS];
  esf_ledger_values(t, l, alpha, row);
  fprintf(f, "%.9e", row[0]);
  for (int k = 1; k < ESF_LEDGER_NCOLS; k++)
    fprintf(f, k == ESF_LEDGER_ALPHA ? ",%.6e" : ",%.12e", row[k]);
  fputc('\n', f);
}

void esf_ledger_block_sums(const double *blocks, size_t nb, esf_xsum acc[ESF_LB_N]) {
  for (int c = 0; c < ESF_LB_N; c++) esf_xsum_add_n(&acc[c], blocks + c, nb, ESF_LB_N);
}

void esf_ledger_step(esf_ledger *l, const double *blocks, size_t nb) {
  esf_xsum acc[ESF_LB_N];
  double t[ESF_LB_N];
  for (int c = 0; c < ESF_LB_N; c++) esf_xsum_zero(&acc[c]);
  esf_ledger_block_sums(blocks, nb, acc);
  for (int c = 0; c < ESF_LB_N; c++) t[c] = esf_xsum_value(&acc[c]);
  esf_ledger_step_sums(l, t);
}

void esf_ledger_step_sums(esf_ledger *l, const double t[ESF_LB_N]) {
  l->kin_t = t[ESF_LB_KT];
  l->kin_r = t[ESF_LB_KR];
  l->pot_g = t[ESF_LB_PE];
  l->el_n = t[ESF_LB_EN];
  l->el_t = t[ESF_LB_ET];
  l->d_global += t[ESF_LB_DG];
  l->d_local += t[ESF_LB_DL];
  l->d_normal += t[ESF_LB_DN];
  l->d_tangential += t[ESF_LB_DT];
  l->d_friction += t[ESF_LB_SL];
  l->w_walls += t[ESF_LB_WW];
  l->d_bonds += t[ESF_LB_BD];
  l->w_fluid += t[ESF_LB_WF];
  l->el_r = t[ESF_LB_ER];
  l->d_rolling += t[ESF_LB_DR];
  l->w_stiff += t[ESF_LB_SW];
  if (!l->started) {
    l->e0 = t[ESF_LB_KO] + t[ESF_LB_PO] + l->el_n + l->el_t + l->el_r;
    l->started = 1;
  }
}
