/* ledger.c — energy balance bookkeeping and the energy.csv format. */
#include "ledger.h"

double esf_ledger_stored(const esf_ledger *l) {
  return l->kin_t + l->kin_r + l->pot_g + l->el_n + l->el_t;
}

double esf_ledger_dissipated(const esf_ledger *l) {
  return l->d_normal + l->d_tangential + l->d_friction + l->d_global + l->d_local;
}

double esf_ledger_total_error(const esf_ledger *l) {
  return esf_ledger_stored(l) - l->e0 - l->w_walls + esf_ledger_dissipated(l) +
         l->e_removed;
}

void esf_ledger_header(FILE *f) {
  fprintf(f, "time,kinetic_translational,kinetic_rotational,potential_gravity,elastic,"
             "dissipated_contact,dissipated_friction,dissipated_damping,work_walls,"
             "total_error,elastic_normal,elastic_tangential,dissipated_normal,"
             "dissipated_tangential,dissipated_global,dissipated_local,energy_removed,"
             "alpha_global\n");
}

void esf_ledger_row(FILE *f, double t, const esf_ledger *l, double alpha) {
  fprintf(f,
          "%.9e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,"
          "%.12e,%.12e,%.12e,%.12e,%.6e\n",
          t, l->kin_t, l->kin_r, l->pot_g, l->el_n + l->el_t,
          l->d_normal + l->d_tangential, l->d_friction, l->d_global + l->d_local,
          l->w_walls, esf_ledger_total_error(l), l->el_n, l->el_t, l->d_normal,
          l->d_tangential, l->d_global, l->d_local, l->e_removed, alpha);
}
