/* main.c — the esfera command line (docs/usage.md#commands, #exit-status):
 *   esfera run SCENE.yaml [--out DIR] [--overwrite] [--set KEY=VALUE]... [--threads N]
 *              [--quiet] [--checkpoint-every T]
 *   esfera run --resume DIR [--checkpoint-every T] [--threads N] [--quiet]
 *   esfera info FILE.h5
 *   esfera modes SCENE.yaml [--set KEY=VALUE]...   (highest contact frequency)
 *   esfera generate SCENE.yaml --out PACKING.csv [--set KEY=VALUE]... (generate_copies.h)
 *   esfera --help | --version
 * Exit status: 0 success, 1 the simulation failed, 2 bad input; a run stopped by
 * SIGINT or SIGTERM writes a checkpoint (when its integrator can) and exits with 128 +
 * the signal's number.
 * Signals: the handlers only set `stop_signal`, which the run polls once per step
 * (esf_run_opts.stop); a second SIGINT or SIGTERM ends the process at once (the default
 * action). SIGXFSZ is ignored so that a file-size limit reaches the writers as EFBIG, a
 * clear error, instead of killing the process. */
#include <limits.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef ESF_MPI
#include <mpi.h>
#endif

#include "app/generate_copies.h"
#include "app/info.h"
#include "app/modes.h"
#include "app/run.h"
#include "ckpt/checkpoint.h"
#include "integrators/integrator.h"
#include "loads/insert.h"
#include "model/model.h"
#include "fused/fused.h"
#include "par/par.h"
#include "scene/scene.h"

#define ESF_MMAP_MIN (256 * 1024) /* bytes */
#include "util/atomic_file.h"
#include "util/version.h"

static void usage(FILE *f) {
  fprintf(f,
          "usage: esfera run SCENE.yaml [--out DIR] [--overwrite] [--set KEY=VALUE]...\n"
          "                  [--threads N] [--quiet] [--checkpoint-every T]\n"
          "       esfera run --resume DIR [--checkpoint-every T] [--threads N] "
          "[--quiet]\n"
          "       esfera info FILE.h5|DIR/checkpoint.esf\n"
          "       esfera modes SCENE.yaml [--set KEY=VALUE]...\n"
          "       esfera generate SCENE.yaml --out PACKING.csv [--set KEY=VALUE]...\n"
          "       esfera --help | --version\n\n"
          "  run       integrate a scene; writes log.txt, energy.csv and frames.h5 into\n"
          "            DIR (default: output.dir of the scene, else out/<scene name>)\n"
          "  generate  settle the scene's particles in generate.box, copy them\n"
          "            generate.copies times, settle again, write a packing CSV\n"
          "  --set     override a scene key by its dotted path, e.g.\n"
          "            --set integrator.frac=0.2 --set gravity=[0,0,-9.81]\n"
          "  --threads worker threads (default: all available cores; results do not\n"
          "            depend on it)\n"
          "  --quiet   no progress display\n"
          "  --overwrite  replace the results of an earlier run in DIR (without it a\n"
          "            run refuses a folder that holds frames.h5, energy.csv, log.txt\n"
          "            or checkpoint.esf)\n"
          "  --checkpoint-every T  write DIR/checkpoint.esf every T seconds of\n"
          "            simulated time (= --set output.checkpoint_every=T); SIGINT or\n"
          "            SIGTERM also writes one, then stops\n"
          "  --resume DIR  continue the run whose checkpoint is in DIR\n\n"
          "integrators (integrator.method):\n");
  for (int k = 0; esf_integrators[k]; k++)
    fprintf(f, "  %-12s %s\n",
            strcmp(esf_integrators[k]->name, "erk") == 0 ? "erk:<TABLE>"
                                                         : esf_integrators[k]->name,
            esf_integrators[k]->summary);
}

static int fail(int code, const char *msg) {
  int rank, size;
  esf_par_world(&rank, &size); /* MPI: every process has the message; rank 0 prints */
  if (rank == 0) fprintf(stderr, "esfera: %s\n", msg);
  return esf_error_exit_status(code);
}

/* The options `run` and `modes` share. */
typedef struct cli_args {
  const char *scene, *out, *resume;
  const char **sets;
  int nsets, quiet, overwrite;
  int threads;       /* --threads, 0 when not given */
  char ckpt_set[96]; /* --checkpoint-every as an override */
} cli_args;

/* Parses the arguments after the command; 0 ok, else the exit status (message given).
 * a->sets is allocated (free it). */
static int parse_args(int argc, char **argv, cli_args *a) {
  memset(a, 0, sizeof *a);
  a->sets = calloc((size_t)argc + 1, sizeof *a->sets);
  if (!a->sets) return fail(ESF_ENOMEM, "out of memory");
  for (int k = 0; k < argc; k++) {
    const char *o = argv[k];
    if (strcmp(o, "--out") == 0 && k + 1 < argc)
      a->out = argv[++k];
    else if (strcmp(o, "--set") == 0 && k + 1 < argc)
      a->sets[a->nsets++] = argv[++k];
    else if (strncmp(o, "--set=", 6) == 0)
      a->sets[a->nsets++] = o + 6;
    else if (strcmp(o, "--threads") == 0 && k + 1 < argc) {
      char *end = NULL;
      long t = strtol(argv[++k], &end, 10);
      if (!end || *end || t < 1 || t > 1024)
        return fail(ESF_EINPUT, "--threads takes a whole number from 1 to 1024");
      a->threads = (int)t;
    } else if (strcmp(o, "--quiet") == 0)
      a->quiet = 1;
    else if (strcmp(o, "--overwrite") == 0)
      a->overwrite = 1;
    else if (strcmp(o, "--resume") == 0 && k + 1 < argc)
      a->resume = argv[++k];
    else if (strcmp(o, "--checkpoint-every") == 0 && k + 1 < argc) {
      snprintf(a->ckpt_set, sizeof a->ckpt_set, "output.checkpoint_every=%s", argv[++k]);
      a->sets[a->nsets++] = a->ckpt_set;
    } else if (o[0] == '-') {
      fprintf(stderr, "esfera: unknown or incomplete option '%s'\n", o);
      usage(stderr);
      return 2;
    } else if (!a->scene)
      a->scene = o;
    else {
      fprintf(stderr, "esfera: more than one scene given ('%s' and '%s')\n", a->scene, o);
      return 2;
    }
  }
  const char *ow = getenv("ESF_OVERWRITE"); /* --overwrite for scripts (usage.md) */
  if (ow && strcmp(ow, "1") == 0 && !a->resume) a->overwrite = 1;
  if (a->resume &&
      (a->scene || a->out || a->overwrite || a->nsets > (a->ckpt_set[0] ? 1 : 0)))
    return fail(ESF_EINPUT, "--resume DIR continues a run as its checkpoint stored it: "
                            "give no scene, --out, --overwrite or --set with it (only "
                            "--checkpoint-every, --threads and --quiet)");
  if (!a->scene && !a->resume) {
    usage(stderr);
    return 2;
  }
  return 0;
}

/* Loads the scene with its overrides and checks the method name. */
static int load_scene(const cli_args *a, const esf_ckpt *ck, esf_sim *s, esf_error *err) {
  memset(s, 0, sizeof *s);
  int rc = ck ? esf_ckpt_load_scene(ck, a->sets, a->nsets, s, err)
              : esf_scene_load(a->scene, a->sets, a->nsets, s, err);
  if (!rc && !esf_integrator_find(s->cfg.method)) {
    char list[512] = "";
    for (int k = 0; esf_integrators[k]; k++) {
      size_t l = strlen(list);
      const char *nm = esf_integrators[k]->name;
      snprintf(list + l, sizeof list - l, "%s%s", k ? ", " : "",
               strcmp(nm, "erk") == 0 ? "erk:<ARKODE table>, rk4" : nm);
    }
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: integrator.method: unknown method '%s' "
                  "(available: %s)",
                  esf_config_where(&s->cfg, "integrator.method"), s->cfg.method, list);
  }
  return rc;
}

/* Diagnostic knobs from the environment (docs/usage.md#environment): ESF_ISA, the
 * fused step's kernels (base, avx2, avx512); ESF_RANGE_WORK, its least work per range
 * (1: one range per thread); ESF_ERK_DRIVER, the fixed-step erk methods' driver (esfera,
 * arkode). Results do not depend on any. */
static int env_knobs(esf_config *c, esf_error *err) {
  const char *isa = getenv("ESF_ISA"), *rw = getenv("ESF_RANGE_WORK");
  if (isa && *isa) {
    if (strlen(isa) >= sizeof c->isa)
      return esf_fail(err, ESF_EINPUT, "ESF_ISA=%s: base, avx2 or avx512", isa);
    snprintf(c->isa, sizeof c->isa, "%s", isa);
  }
  if (rw && *rw) {
    char *end;
    const long v = strtol(rw, &end, 10);
    if (*end || v < 1 || v > 1000000000)
      return esf_fail(err, ESF_EINPUT, "ESF_RANGE_WORK=%s: a whole number from 1", rw);
    c->range_work = (int)v;
  }
  const char *drv = getenv("ESF_ERK_DRIVER");
  if (drv && *drv) {
    if (strcmp(drv, "arkode") && strcmp(drv, "esfera"))
      return esf_fail(err, ESF_EINPUT, "ESF_ERK_DRIVER=%s: esfera or arkode", drv);
    c->erk_arkode = strcmp(drv, "arkode") == 0;
  }
  return ESF_OK;
}

/* Parses the arguments, loads the scene and sets the sim up; 0 ok, else the exit
 * status (the message printed; the sim released). */
static int prepare(int argc, char **argv, cli_args *a, esf_ckpt **ck, esf_sim *s) {
  int status = parse_args(argc, argv, a);
  if (status) {
    free(a->sets);
    return status;
  }
  esf_error err;
  esf_error_clear(&err);
  int rc = a->resume && ck ? esf_ckpt_load(a->resume, ck, &err) : ESF_OK;
  if (rc) {
    free(a->sets);
    return fail(rc, err.msg);
  }
  rc = load_scene(a, ck ? *ck : NULL, s, &err);
  if (!rc && a->threads) s->cfg.threads = a->threads;
  if (!rc) rc = env_knobs(&s->cfg, &err);
  if (!rc) rc = esf_sim_setup(s, &err);
  if (rc) {
    free(a->sets);
    esf_sim_release(s);
    return fail(rc, err.msg);
  }
  return 0;
}

/* An MPI run of more than one process: what it cannot do refused with its reason
 * (docs/mpi.md), then the sim taken onto the processes (par.h). */
static int attach_mpi(esf_sim *s, esf_error *err) {
  int rank, size;
  esf_par_world(&rank, &size);
  if (size < 2) return ESF_OK;
  if (strcmp(s->cfg.method, "leapfrog") == 0) {
    const char *why = esf_fused_refusal(s);
    if (why)
      return esf_fail(err, ESF_EINPUT,
                      "%s: not supported on several MPI processes yet: the leapfrog's "
                      "general path (%s); run it on one process",
                      esf_config_where(&s->cfg, "integrator"), why);
  }
  return esf_par_attach(s, err);
}

/* esfera modes SCENE: the assembled contact system's highest frequency at the scene's
 * initial state against the seeds' critical-step rules (modes.h). */
static int cmd_modes(int argc, char **argv) {
  cli_args a;
  esf_sim s;
  int status = prepare(argc, argv, &a, NULL, &s);
  if (status) return status;
  free(a.sets);
  esf_error err;
  esf_error_clear(&err);
  esf_modes m;
  int rc = esf_modes_compute(&s, &m, &err);
  if (rc) {
    esf_sim_release(&s);
    return fail(rc, err.msg);
  }
  printf("modes: particles=%zu dofs=%zu contacts=%zu omega_max=%.10g xi_max=%.6g "
         "dt_2_over_omega=%.10g dt_damped=%.10g cundall=%.10g hart=%.10g damped=%.10g "
         "argmax_particle=%zu xi_mode=%.6g dt_mode=%.10g dt=%.10g lambda=%.10g "
         "lambda_live=%.10g dt_live=%.10g\n",
         s.p.n, m.dofs, m.contacts, m.omega_max, m.xi_max, m.dt_undamped, m.dt_damped,
         s.dte.crit[ESF_DT_CUNDALL], s.dte.crit[ESF_DT_HART], s.dte.crit[ESF_DT_DAMPED],
         m.dofs ? m.argmax_dof / (m.dofs / s.p.n) : 0, m.xi_mode, m.dt_mode, s.dt,
         m.lambda, m.lambda_live, m.dt_live);
  esf_sim_release(&s);
  return 0;
}

static volatile sig_atomic_t stop_signal = 0;

/* The first SIGINT or SIGTERM asks the run to stop (a checkpoint, then exit); a second
 * one ends the process at once, whatever the run is doing. */
static void on_stop_signal(int sig) {
  if (stop_signal) {
    signal(sig, SIG_DFL);
    raise(sig);
  }
  stop_signal = sig;
}

static void install_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  signal(SIGXFSZ, SIG_IGN);
}

/* The directory a --resume argument names (itself, or a checkpoint file's). */
static void resume_dir(const char *arg, char *dir, size_t size) {
  snprintf(dir, size, "%s", arg);
  size_t l = strlen(dir), k = strlen(ESF_CKPT_NAME);
  if (l >= k && strcmp(dir + l - k, ESF_CKPT_NAME) == 0) {
    dir[l - k] = '\0';
    if (l > k) dir[l - k - 1] = '\0';
    if (!dir[0]) snprintf(dir, size, ".");
  }
}

/* esfera generate SCENE --out CSV: model generation by successive copies. */
static int cmd_generate(int argc, char **argv) {
  cli_args a;
  int status = parse_args(argc, argv, &a);
  if (!status && (a.resume || !a.out))
    status = fail(ESF_EINPUT, "usage: esfera generate SCENE.yaml --out PACKING.csv "
                              "[--set KEY=VALUE]...");
  esf_error err;
  esf_error_clear(&err);
  int rc = status ? ESF_OK
                  : esf_generate_copies(a.scene, a.sets, a.nsets, a.out, stdout, &err);
  free(a.sets);
  return status ? status : rc ? fail(rc, err.msg) : 0;
}

/* Writes word to f as one shell word (quoted when it needs to be). */
static void shell_word(FILE *f, const char *word) {
  if (word[0] && strspn(word, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                              "0123456789_./-+=:,@%") == strlen(word)) {
    fputs(word, f);
    return;
  }
  fputc('\'', f);
  for (const char *c = word; *c; c++)
    if (*c == '\'')
      fputs("'\\''", f);
    else
      fputc(*c, f);
  fputc('\'', f);
}

/* The program's own path, for the commands the messages suggest: /proc/self/exe, else
 * argv[0] made absolute when it names a file, else argv[0]. */
static void program_path(const char *argv0, char *buf, size_t size) {
  ssize_t n = readlink("/proc/self/exe", buf, size - 1);
  if (n > 0) {
    buf[n] = '\0';
    return;
  }
  char real[PATH_MAX];
  snprintf(buf, size, "%s", strchr(argv0, '/') && realpath(argv0, real) ? real : argv0);
}

/* The lines a finished run ends with: the summary (its key=value format is read by
 * scripts: new fields go at the end), then where the output is and how to look at it. */
static void print_summary(const esf_sim *s, const esf_run_stats *st, const char *dir,
                          const char *prog, int status) {
  printf("summary: steps=%ld particles=%.0f contacts_mean=%.2f wall_s=%.4f "
         "particle_steps_per_s=%.6g dt=%.6g rebuilds=%ld rhs_evals=%ld "
         "energy_error=%.6g dissipated=%.6g removed=%ld method=%s rejected=%ld "
         "acc_limited=%ld stab_limited=%ld h_last=%.6g events=%ld restarts=%ld "
         "checkpoints=%ld bonds=%ld bonds_broken=%ld threads=%d resumed_from_step=%ld "
         "stability=%.4g stability_checks=%ld exit=%d inserted=%lld n_end=%zu ranks=%d\n",
         st->steps, st->particles_mean, st->contacts_mean, st->wall_s, st->rate, s->dt,
         s->nb.builds, st->integ.rhs_evals, st->energy_error, st->dissipated, s->removed,
         s->cfg.method, st->integ.rejected, st->integ.acc_limited, st->integ.stab_limited,
         st->integ.h_last, st->integ.events, st->integ.restarts, st->checkpoints_total,
         s->bonds.formed, s->bonds.broken, s->cfg.threads, st->resumed_step,
         s->stab.worst, s->stab.checks, status, esf_inserts_total(s), esf_par_count(s),
         esf_par_size(s));
  if (st->resumed_step)
    printf("resumed at step %ld: wall_s and particle_steps_per_s cover steps %ld to %ld; "
           "checkpoints=%ld counts every checkpoint since the run's start (%ld written "
           "now)\n",
           st->resumed_step, st->resumed_step, st->steps, st->checkpoints_total,
           st->checkpoints);
  fputs("output: ", stdout);
  shell_word(stdout, dir);
  fputs(" (summary: ", stdout);
  shell_word(stdout, prog);
  fputs(" info ", stdout);
  shell_word(stdout, dir);
  fputs("/frames.h5; ParaView: ", stdout);
  shell_word(stdout, dir);
  fputs("/frames.xdmf; log: ", stdout);
  shell_word(stdout, dir);
  fputs("/log.txt)\n", stdout);
}

static int cmd_run(int argc, char **argv, const char *argv0) {
  cli_args a;
  esf_sim s;
  esf_ckpt *ck = NULL;
  int status = prepare(argc, argv, &a, &ck, &s);
  if (status) {
    esf_ckpt_free(&ck);
    return status;
  }
  {
    esf_error e;
    esf_error_clear(&e);
    if (attach_mpi(&s, &e)) {
      free(a.sets);
      esf_ckpt_free(&ck);
      esf_sim_release(&s);
      return fail(e.code, e.msg);
    }
  }
  if (s.cfg.duration <= 0 && s.cfg.steps <= 0) { /* a generate scene has no run */
    free(a.sets);
    esf_ckpt_free(&ck);
    esf_error e;
    esf_fail(&e, ESF_EINPUT,
             "%s: the scene has no 'run' section (a generate scene: use esfera generate "
             "SCENE --out PACKING.csv)",
             esf_config_where(&s.cfg, ""));
    esf_sim_release(&s);
    return fail(ESF_EINPUT, e.msg);
  }
  esf_error err;
  esf_error_clear(&err);
  /* what the checkpoints store: the scene's text and its overrides (a resumed run's
     are the stored ones followed by this command's --checkpoint-every) */
  esf_ckpt_scene sc = {0};
  char *text = NULL, dir[1200], scene_abs[PATH_MAX];
  const char **sets = NULL;
  int rc = ESF_OK;
  if (ck) {
    esf_ckpt_scene stored;
    esf_ckpt_scene_of(ck, &stored);
    sc = stored;
    sc.nsets = 0;
    sets = calloc((size_t)(stored.nsets + a.nsets + 1), sizeof *sets);
    if (!sets) rc = esf_fail(&err, ESF_ENOMEM, "out of memory");
    for (int k = 0; sets && k < stored.nsets; k++) sets[sc.nsets++] = stored.sets[k];
    for (int k = 0; sets && k < a.nsets; k++) sets[sc.nsets++] = a.sets[k];
    sc.sets = sets;
    resume_dir(a.resume, dir, sizeof dir);
  } else {
    rc = esf_read_file(a.scene, &text, &sc.len, &err);
    /* absolute, so that a resume from elsewhere finds the scene's relative files */
    sc.path = realpath(a.scene, scene_abs) ? scene_abs : a.scene;
    sc.text = text;
    sc.sets = a.sets;
    sc.nsets = a.nsets;
    snprintf(dir, sizeof dir, "%s", a.out ? a.out : s.cfg.out_dir);
  }
  install_signals();
  esf_run_opts o = {.out_dir = dir,
                    .quiet = a.quiet,
                    .progress = isatty(STDOUT_FILENO) && esf_par_rank(&s) == 0,
                    .scene = &sc,
                    .resume = ck,
                    .stop = &stop_signal,
                    .overwrite = a.overwrite};
  esf_run_stats st = {0};
  if (!rc) rc = esf_run(&s, &o, &st, &err);
  free(text);
  free(sets);
  free(a.sets);
  esf_ckpt_free(&ck);
  char prog[PATH_MAX];
  program_path(argv0, prog, sizeof prog);
  if (rc) {
    status = fail(rc, err.msg);
    const int root = esf_par_rank(&s) == 0;
    if (st.stepping && root)
      fprintf(stderr, "esfera: output so far is in %s\n", o.out_dir);
    if (st.stepping && status == 1 &&
        root) /* the counts up to the failure, for scripts */
      print_summary(&s, &st, dir, prog, status);
    esf_sim_release(&s);
    return status;
  }
  if (st.interrupted && esf_par_rank(&s) != 0) { /* MPI: rank 0 says it */
    esf_sim_release(&s);
    return 128 + (int)stop_signal;
  }
  if (st.interrupted) {
    fflush(stdout);
    /* on a terminal the message starts its own line: the ^C the terminal echoed and
       any progress are cleared first */
    if (isatty(STDERR_FILENO)) fputs("\r\033[K", stderr);
    fprintf(stderr, "esfera: stopped by signal %d at step %ld, t = %.9g s; ",
            (int)stop_signal, s.step, s.t);
    if (st.stop_checkpoint) {
      fprintf(stderr, "checkpoint written to %s/%s\nesfera: resume with: ", dir,
              ESF_CKPT_NAME);
      shell_word(stderr, prog);
      fputs(" run --resume ", stderr);
      shell_word(stderr, dir);
      fputc('\n', stderr);
    } else {
      fprintf(stderr,
              "%s cannot write checkpoints, so this run cannot be resumed; its output "
              "up to here (the last frame included) is in %s\n",
              s.cfg.method, dir);
    }
    esf_sim_release(&s);
    return 128 + (int)stop_signal;
  }
  if (esf_par_rank(&s) == 0) print_summary(&s, &st, dir, prog, 0);
  esf_sim_release(&s);
  return 0;
}

/* The command, with MPI set up around it in an MPI build (docs/mpi.md): only `run`
 * runs on several processes. */
static int command(int argc, char **argv);

int main(int argc, char **argv) {
#ifdef ESF_MPI
  int provided = 0, size = 1;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int status;
  if (size > 1 && (argc < 2 || strcmp(argv[1], "run") != 0))
    status = fail(ESF_EINPUT, "only `esfera run` runs on several MPI processes");
  else
    status = command(argc, argv);
  MPI_Finalize();
  return status;
#else
  return command(argc, argv);
#endif
}

static int command(int argc, char **argv) {
#ifdef __GLIBC__
  /* Arrays from ESF_MMAP_MIN bytes on get pages of their own, returned when freed:
   * glibc's default raises that bound to the largest array freed so far (up to 32 MB),
   * after which freed arrays stay resident in the heap and the peak memory counts
   * storage already given back (docs/performance.md#memory). */
  mallopt(M_MMAP_THRESHOLD, ESF_MMAP_MIN);
#endif
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
    usage(stdout);
    return 0;
  }
  if (strcmp(argv[1], "--version") == 0) {
    printf("esfera %s\n", ESF_VERSION);
    return 0;
  }
  if (strcmp(argv[1], "run") == 0) return cmd_run(argc - 2, argv + 2, argv[0]);
  if (strcmp(argv[1], "modes") == 0) return cmd_modes(argc - 2, argv + 2);
  if (strcmp(argv[1], "generate") == 0) return cmd_generate(argc - 2, argv + 2);
  if (strcmp(argv[1], "info") == 0) {
    esf_error err;
    esf_error_clear(&err);
    int rc = argc == 3 ? esf_info_print(argv[2], stdout, &err)
                       : esf_fail(&err, ESF_EINPUT, "usage: esfera info FILE.h5");
    return rc ? fail(rc, err.msg) : 0;
  }
  fprintf(stderr, "esfera: unknown command '%s'\n", argv[1]);
  usage(stderr);
  return 2;
}
