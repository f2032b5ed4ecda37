/* sim.h — the simulation object: configuration, particles, materials, walls, contact
 * lists, damping state, energy ledger and counters. One esf_sim is one run; it holds no
 * global state, so several can coexist (tests do that). */
#ifndef ESF_SIM_H
#define ESF_SIM_H

#include <stdio.h>

#include "bodies/particles.h"
#include "bodies/walls.h"
#include "contact/contact_law.h"
#include "contact/material.h"
#include "core/bonds.h"
#include "core/damping.h"
#include "core/ledger.h"
#include "search/neighbor.h"
#include "util/esf_error.h"
#include "util/rng.h"

enum {
  ESF_DT_CUNDALL = 0,
  ESF_DT_HART = 1,
  ESF_DT_DAMPED = 2,
  ESF_DT_RAYLEIGH = 3,  /* Hertz-Mindlin scenes only (INFINITY otherwise) */
  ESF_DT_COLLISION = 4, /* the collision time at integrator.impact_speed */
  ESF_DT_RULES = 5
};
/* "cundall", "hart", "damped", "rayleigh", "collision", NULL */
extern const char *const esf_dt_rule_names[];

/* How ODE methods treat contact history (integrators/dem_ode.h). */
enum { ESF_HIST_FROZEN = 0, ESF_HIST_STATE = 1 };
extern const char *const esf_history_names[]; /* "frozen", "state", NULL */

/* The leapfrog's live stability check (model/stability.h): AUTO is stop, or warn with
 * allow_unstable. */
enum { ESF_STAB_AUTO = 0, ESF_STAB_STOP = 1, ESF_STAB_WARN = 2, ESF_STAB_OFF = 3 };
extern const char *const esf_stab_names[]; /* "auto", "stop", "warn", "off", NULL */
#define ESF_STAB_EVERY 8000                /* default steps between checks */

enum { ESF_LOCAL_OFF = 0, ESF_LOCAL_COMPONENT = 1, ESF_LOCAL_VECTOR = 2 };

/* The place in the scene of a key that set-up, the integrators and the run driver check
 * after reading ("scene.yaml:12:5", or "--set KEY=VALUE"), for located messages. */
#define ESF_WHERE_N    32
#define ESF_STRESS_MAX 16 /* output.stress: regions at most */
typedef struct esf_where {
  char key[40];
  char place[280];
} esf_where;

/* An explicit Butcher table given in the scene (integrator.table, for method erk; read
 * and checked by scene/scene_butcher.c against integrators/butcher.h). s = 0: none. */
#define ESF_BUTCHER_MAX 16 /* stages */
typedef struct esf_butcher {
  int s;     /* stages; 0: no table given */
  int q, p;  /* order of b; order of d (0: no embedding) */
  int has_d; /* b_embedded given */
  double c[ESF_BUTCHER_MAX], b[ESF_BUTCHER_MAX], d[ESF_BUTCHER_MAX];
  double A[ESF_BUTCHER_MAX][ESF_BUTCHER_MAX]; /* strictly lower triangular */
} esf_butcher;

/* Everything a scene sets, with SI units. esf_config_default gives the defaults. */
typedef struct esf_config {
  char name[128];
  char source[1024];     /* scene file path */
  int dim;               /* 3, or 2 (disks in the x-z plane) */
  double disk_thickness; /* 2D: disk mass = rho pi r^2 thickness, m */
  double gravity[3];     /* m/s^2 */
  int has_domain;
  double domain_min[3], domain_max[3]; /* m; particles leaving it are removed */
  esf_periodic per; /* domain.periodic: the periodic axes (search/periodic.h) */
  double keep_lo[3], keep_hi[3]; /* the domain with the periodic axes unbounded: the
                                    removal test's box, m */

  char method[128]; /* integrator name */
  double dt;        /* s; <= 0 with dt_auto */
  int dt_auto;
  int dt_rule;          /* ESF_DT_* */
  double frac;          /* dt = frac x critical (auto) */
  int allow_unstable;   /* accept dt above the rule's critical value */
  int stability;        /* the live stability check: ESF_STAB_* (set-up resolves AUTO) */
  long stability_every; /* steps between its checks (> 0) */

  double rtol, atol; /* adaptive ODE methods: tolerances (rtol 0: fixed step) */
  int history;       /* ODE methods: ESF_HIST_FROZEN or ESF_HIST_STATE */
  long max_steps;    /* ODE methods: step limit per call */
  int roots;         /* adaptive ERK: end steps at contact onset and separation */
  esf_butcher table; /* method erk: the scene's Butcher table (integrator.table) */

  double alpha_r, alpha_t;             /* global viscous damping, 1/s */
  int local_form;                      /* ESF_LOCAL_* */
  double local_coef;                   /* alpha_c of 001 */
  int rayleigh;                        /* damping.rayleigh given */
  double rayleigh_zeta, rayleigh_freq; /* zeta, f (Hz) */
  esf_auto_damping autod;              /* adaptive global damping */

  int tframe;                /* ESF_TFRAME_* */
  int rolling;               /* contact.rolling: ESF_ROLL_* (material.h) */
  int hertz_damping;         /* contact.hertz_damping: 0 tsuji, 1 constant */
  double impact_speed;       /* integrator.impact_speed, m/s (the Hertz time rule) */
  int wall_lever;            /* ESF_WALL_LEVER_* (bodies/walls.h) */
  double max_overlap;        /* failure when overlap > this x the smaller radius */
  int allow_initial_overlap; /* explicit particles may start overlapping */
  double skin;               /* m; <= 0: automatic (0.4 x mean radius, then adaptive) */
  int skin_auto;             /* set up: the skin is retuned at rebuilds (neighbor.h) */
  int reorder;               /* renumber particles along cells at rebuilds (reorder.h) */

  double duration;     /* s (when steps == 0) */
  long steps;          /* steps, or 0 */
  double out_every;    /* s between frames; 0: final frame only */
  double energy_every; /* s between energy rows; 0: no ledger */
  int energy_off;      /* energy_every: 0 given explicitly */
  int out_contacts;    /* output.contacts: the contact network in every frame */
  int out_walls;       /* output.walls: walls.csv at every energy row (wall_loads.h) */
  int n_stress;        /* output.stress: regions of stress.csv (wall_loads.h) */
  double stress_box[ESF_STRESS_MAX][6]; /* each region's min (3) and max (3), m */
  double stress_every; /* output.stress_every: s between load rows; 0: at energy rows */
  double ckpt_every;   /* output.checkpoint_every: s between checkpoints; 0: none */
  char out_dir[1024];
  int threads;      /* worker threads (results independent of it); 0: all available,
                      esf_sim_setup then sets the count (util/threads.h) */
  int threads_auto; /* set up: threads was 0 (all available) */
  int fused;        /* leapfrog: take the fused step when the scene allows (default 1) */
  int range_work;   /* fused step: least estimated work per range (0: its default;
                       tests set 1 for one range per thread; ESF_RANGE_WORK) */
  char isa[16];     /* fused step: the kernels' instruction set, "" for the CPU's
                       widest (base, avx2, avx512; ESF_ISA) */
  int erk_arkode;   /* fixed-step erk: 1 steps with ARKODE's ERKStep instead of esfera's
                       driver (the same bits; ESF_ERK_DRIVER=arkode) */
  esf_where where[ESF_WHERE_N]; /* places of keys, set by the scene reader (key "" is
                                   the document itself) */
  int nwhere;
} esf_config;

void esf_config_default(esf_config *c);

/* The most steps one run takes (run.steps, or run.duration / dt; checked by the run
 * driver and by checkpoint restores): beyond it a count would not end in any useful
 * time (and soon not fit a long). */
#define ESF_STEPS_MAX 1e12

/* The place of key (dotted path, "integrator.dt") in the scene: its own when the scene
 * gave it, else that of its nearest given parent ("integrator"), else of the document,
 * else cfg.source; never NULL. */
const char *esf_config_where(const esf_config *c, const char *key);

/* Records the place of key (esf_config_where); later entries for the same key win.
 * Silently ignores keys beyond ESF_WHERE_N. */
void esf_config_set_where(esf_config *c, const char *key, const char *place);

/* Critical-step estimates (timestep.c). */
typedef struct esf_dt_estimate {
  double m_min;              /* smallest particle mass, kg */
  double k_max;              /* largest stiffness of any used material pair, N/m
                                (Hertz-Mindlin: the tangent stiffness at the peak
                                overlap of an impact at integrator.impact_speed) */
  double xi;                 /* largest damping ratio (contact + global) */
  double crit[ESF_DT_RULES]; /* each rule's critical step (FRAC = 1), s */
} esf_dt_estimate;

typedef struct esf_sim {
  esf_config cfg;
  esf_particles p;
  esf_materials mats;
  esf_walls walls;
  esf_neighbor nb;
  esf_ledger led;
  esf_bonds bonds;                /* the adhesive law's bonds (bonds.h) */
  const esf_local_damping *local; /* NULL when off */
  double beta;                    /* Rayleigh stiffness-proportional factor (0: off), s */
  double alpha_r, alpha_t; /* current global damping (adaptive changes them), 1/s */
  double t, dt;            /* s */
  double led_time;         /* the time the ledger's stored energies refer to, s */
  long step;
  long burst; /* steps the next call of a fixed-step scheme may take at once (the
                 driver's budget to its next output; <= 1: one) */
  esf_dt_estimate dte;
  struct {
    long checks;     /* live stability checks done (model/stability.h) */
    double worst;    /* largest lambda / 4 they found */
    double dt_limit; /* the first check's limit of the top mode, s (INFINITY: none) */
    double seconds;  /* wall time they took, s */
    int warned;      /* stability: warn logged its warning */
  } stab;
  esf_rng rng;
  /* counters */
  long removed;                  /* particles removed (left the domain, or deleted by
                                    events) */
  double contacts_sum;           /* sum over steps of touching contacts */
  long rhs_evals;                /* force evaluations */
  FILE *log;                     /* the run's log, or NULL */
  struct esf_force_tally *tally; /* filled by force evaluations when not NULL */
  struct esf_events *events;     /* scene events (events.c), or NULL */
  struct esf_inserts *insert;    /* particles inserted during the run (insert.c), or
                                    NULL: no cost */
  struct esf_drag *drag;         /* fluid force (drag.c), or NULL: no cost */
  int reorder_ok; /* the scheme keeps no per-particle state of its own between steps, so
                     particles may be renumbered at rebuilds (set by its create) */
  /* F_n and M_n of the last fused step (fused/fused.c), ESF_FT_STRIDE doubles per
   * particle (force 3, N; one spare; torque 3, N m; one spare), not yet copied to p.f and
   * p.t (which are then released: NULL); NULL when p.f and p.t are current.
   * esf_sim_forces_sync copies them. */
  const double *ft_lazy;
  /* The leapfrog's energy ledger of the step (ledger.h): ESF_LR rows per particle
   * (line-aligned, zeroed before each committing evaluation), ESF_LB_N channels per
   * block of ESF_LEDGER_BLOCK particles; NULL with the ledger off (esf_sim_ledger_room)
   */
  double *led_rows, *led_blocks;
  size_t led_cap; /* particles they have room for */
  size_t led_lr;  /* a particle's rows in led_rows: esf_ledger_lr(mats.any_rolling) */
  /* MPI (par/par.h): this process's part of the run, or NULL: one process holds every
   * particle. With it, the particles [own_lo, own_hi) are this process's own, the
   * others ghosts: copies of other processes' particles near its part, in the global
   * order with them, read by the pair forces and never integrated here. */
  struct esf_par *par;
  size_t own_lo, own_hi;
  const struct esf_reduce *red; /* MPI: its sums across processes (par.c), or NULL */
} esf_sim;

/* Sums across an MPI run's processes for the modules below par (par.c fills the
 * table; NULL: one process). A fold over particles or list entries in the global
 * order is taken as one process takes it: each process starts from chain_in (the
 * lower ranks' running value; `start` on rank 0) and ends with chain_out, which passes
 * its value on and returns the total to every process. */
typedef struct esf_reduce {
  double (*chain_in)(const struct esf_sim *s, double start);
  double (*chain_out)(const struct esf_sim *s, double v);
  long long (*sum)(const struct esf_sim *s, long long v);
  /* before particles with keep[i] == 0 are removed from the local arrays: the
     decomposition's own per-particle state follows */
  void (*compact)(struct esf_sim *s, const unsigned char *keep);
} esf_reduce;

static inline double esf_sim_chain_in(const esf_sim *s, double start) {
  return s->red ? s->red->chain_in(s, start) : start;
}
static inline double esf_sim_chain_out(const esf_sim *s, double v) {
  return s->red ? s->red->chain_out(s, v) : v;
}
static inline long long esf_sim_sum(const esf_sim *s, long long v) {
  return s->red ? s->red->sum(s, v) : v;
}
/* Particle i (a local index) is this process's own. */
static inline int esf_sim_owns(const esf_sim *s, size_t i) {
  return !s->par || (i >= s->own_lo && i < s->own_hi);
}

/* The particles this process integrates: [lo, hi) (all of them without MPI). */
static inline size_t esf_sim_own_lo(const esf_sim *s) { return s->par ? s->own_lo : 0; }
static inline size_t esf_sim_own_hi(const esf_sim *s) {
  return s->par ? s->own_hi : s->p.n;
}

#define ESF_FT_STRIDE 8

/* Threads worth using for a pass over n particles (list builds, renumbering): the run's
 * threads from ESF_PARALLEL_MIN particles on, one below, where starting the threads
 * costs more than they save. */
#define ESF_PARALLEL_MIN 1024
static inline int esf_sim_threads_for(const esf_sim *s, size_t n) {
  return n >= ESF_PARALLEL_MIN && s->cfg.threads > 1 ? s->cfg.threads : 1;
}

/* Makes p.f and p.t current (copies the fused step's forces when it left them in its
 * accumulators), allocating them when released (zero when nothing holds forces).
 * Called by whoever reads p.f, p.t: frames, checkpoints, compaction. */
int esf_sim_forces_sync(esf_sim *s, esf_error *err);

/* p.f and p.t allocated (zeroed) if released: for a force evaluation that writes them. */
int esf_sim_forces_room(esf_sim *s, esf_error *err);

/* Releases p.f and p.t (48 bytes a particle) while nothing needs them: the fused step
 * holds F_n, M_n in its accumulators (ft_lazy), or the scheme has not evaluated forces
 * yet. esf_sim_forces_sync and esf_sim_forces_room allocate them again. */
void esf_sim_forces_release(esf_sim *s);

/* Writes a line to the run's log (if any), printf style. */
void esf_sim_log(const esf_sim *s, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Critical-step estimates for the sim's particles, materials and damping. */
void esf_dt_estimate_compute(const esf_sim *s, esf_dt_estimate *e);

/* Room in led_rows and led_blocks for the current particles, zeroed when zero is 1
 * (the leapfrog's ledger, ledger.h). */
int esf_sim_ledger_room(esf_sim *s, int zero, esf_error *err);

/* Adaptive global damping after a leapfrog step (damping.h): alpha_r from the kinetic
 * energies either side of the kick, summed exactly from the nb ledger blocks (the same
 * bits in any order), alpha_t scaled alike. */
void esf_sim_adapt_damping(esf_sim *s, const double *blocks, size_t nb);
/* Its two halves, for sums spread over processes: adds the blocks' kinetic energies
 * before the kick (acc[0]) and after it (acc[1], translational and rotational) to the
 * accumulators; then the update from the totals (acc's values), J. */
void esf_sim_damping_sums(const double *blocks, size_t nb, esf_xsum acc[2]);
void esf_sim_damping_apply(esf_sim *s, double ke_old, double ke_new);

/* Blocks of the ledger's sums for n particles. */
static inline size_t esf_ledger_nblocks(size_t n) {
  return (n + ESF_LEDGER_BLOCK - 1) / ESF_LEDGER_BLOCK;
}

/* Removes the particles outside the domain (if one is set) and logs them. Their energy
 * is booked as removed once the ledger's balance has started (before, e0 leaves them
 * out: particles that start outside the domain never enter the balance). */
int esf_sim_remove_escaped(esf_sim *s, esf_error *err);

#endif
