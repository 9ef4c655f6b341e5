/* api.c: the public interface (peristatic.h) over the internal layers: a
 * handle holds the case, the caller's particles, the problem built from
 * them (app/setup.c) and the last run's solver, kept for the getters. */
#include "peristatic.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "app/ps_app.h"
#include "config.h"

_Static_assert((int)PERISTATIC_ERR_NOMEM == (int)PS_ERR_NOMEM &&
                   (int)PERISTATIC_ERR_INPUT == (int)PS_ERR_INPUT &&
                   (int)PERISTATIC_ERR_IO == (int)PS_ERR_IO &&
                   (int)PERISTATIC_ERR_SOLVER == (int)PS_ERR_SOLVER &&
                   (int)PERISTATIC_ERR_INTERNAL == (int)PS_ERR_INTERNAL &&
                   (int)PERISTATIC_ERR_INTERRUPTED == (int)PS_ERR_INTERRUPTED &&
                   (int)PERISTATIC_STALLED == (int)PS_RUN_STALLED,
               "public status codes are the internal ones");
_Static_assert(PERISTATIC_MAX_MEMORY_GIB == PS_MAX_MEMORY_GIB, "one memory cap");

struct peristatic {
  ps_ctx *ctx;           /* messages and verbosity (a pointer, so that the
                            const getters can record a usage error) */
  ps_case *cs;           /* the loaded case, NULL before */
  ps_particles given;    /* the caller's particles (n = 0: none) */
  ps_problem *pb;        /* the problem, NULL before set-up */
  int threads;           /* per run, 0: the CPUs */
  int verbosity;         /* -1: the case's output.verbosity */
  double max_memory;     /* GiB, 0: the case's */
  const char *max_memory_source;
  ps_solver *solver;     /* the last run's final state, or NULL */
  ps_run_result res;     /* the last run */
  int ran;               /* 1 after a run, 2 after a sweep */
  double fit[3];         /* the sweep's slope, intercept, R^2 */
  int n_fractured;
  char restart[1100];    /* peristatic_set_restart's folder, "" for none */
  char petsc[1024];      /* peristatic_set_petsc_options, "" for none */
  char case_petsc[1024]; /* the loaded case's own solver.petsc_options */
  ps_comm comm;          /* a distributed run's processes (pb->comm) */
};

#ifdef HAVE_OPENBLAS_SET_NUM_THREADS
void openblas_set_num_threads(int n);
#endif

const char *peristatic_version(void) { return PACKAGE_VERSION; }

peristatic *peristatic_new(void) {
  peristatic *ps = calloc(1, sizeof *ps);
  if (!ps) return NULL;
  ps->ctx = calloc(1, sizeof *ps->ctx);
  if (!ps->ctx) {
    free(ps);
    return NULL;
  }
  ps_ctx_init(ps->ctx);
  ps->verbosity = -1;
  return ps;
}

/* Drop the problem and the last run (the case stays). */
static void drop_problem(peristatic *ps) {
  if (ps->solver) ps_solver_free(ps->solver);
  ps->solver = NULL;
  if (ps->pb) {
    ps_problem_free(ps->pb);
    free(ps->pb);
  }
  ps->pb = NULL;
  ps->ran = 0;
}

void peristatic_free(peristatic *ps) {
  if (!ps) return;
  drop_problem(ps);
  if (ps->cs) ps_case_free(ps->cs);
  free(ps->cs);
  ps_particles_free(&ps->given);
  free(ps->ctx);
  free(ps);
}

const char *peristatic_error(const peristatic *ps) { return ps ? ps->ctx->msg : "no handle"; }

void peristatic_init_process(void) {
  gsl_set_error_handler_off();
#ifdef HAVE_OPENBLAS_SET_NUM_THREADS
  if (!getenv("OPENBLAS_NUM_THREADS")) openblas_set_num_threads(1);
#endif
}

void peristatic_install_signal_handlers(void) { ps_signals_install(); }

int peristatic_parallel_init(peristatic *ps) {
  /* the case's and the handle's PETSc options (-log_view must be there
   * when PETSc starts) */
  const char *o = ps->petsc;
  char both[2100];
  if (ps->cs) {
    snprintf(both, sizeof both, "%s %s", ps->case_petsc, ps->petsc);
    o = both;
  }
  return ps_parallel_init(o, ps->ctx);
}
int peristatic_parallel_launched(void) { return ps_parallel_launched(); }
int peristatic_parallel_rank(void) { return ps_parallel_rank(); }
int peristatic_parallel_size(void) { return ps_parallel_size(); }
void peristatic_parallel_finalize(void) { ps_parallel_finalize(); }

int peristatic_set_petsc_options(peristatic *ps, const char *options) {
  if (!options) options = "";
  if (strlen(options) >= sizeof ps->petsc || (options[0] && options[0] != '-'))
    return ps_error(ps->ctx, PS_ERR_INPUT, "PETSc options must start with '-' and be at most "
                    "%zu characters (got \"%.40s%s\")", sizeof ps->petsc - 1, options,
                    strlen(options) > 40 ? "..." : "");
  snprintf(ps->petsc, sizeof ps->petsc, "%s", options);
  drop_problem(ps); /* the set-up's estimate depends on them */
  return PERISTATIC_OK;
}

/* the case's PETSc options: its own, then the handle's. PS_OK or
 * PS_ERR_INPUT (too long together) */
static int apply_petsc_options(peristatic *ps) {
  char *o = ps->cs->solver.petsc_options;
  const char *c = ps->case_petsc;
  size_t cap = sizeof ps->cs->solver.petsc_options;
  int w = snprintf(o, cap, "%s%s%s", c, c[0] && ps->petsc[0] ? " " : "", ps->petsc);
  if (w < 0 || (size_t)w >= cap)
    return ps_error(ps->ctx, PS_ERR_INPUT, "solver.petsc_options and the command line's PETSc "
                    "options are together longer than %zu characters", cap - 1);
  return PS_OK;
}

/* On ranks other than 0 of an MPI run: no outputs, no progress lines */
static const char *rank_output(peristatic *ps, const char *out_dir) {
  if (ps_parallel_rank() == 0) return out_dir;
  ps->ctx->verbosity = 0;
  return NULL;
}

int peristatic_exit_status(int status) {
  switch (status) {
  case PERISTATIC_OK: return 0;
  case PS_ERR_INPUT:
  case PERISTATIC_ERR_USAGE: return 1;
  case PS_ERR_IO: return 3;
  case PS_ERR_INTERRUPTED: /* the shell's 128 + signal number */
    return 128 + (ps_signal_received() ? ps_signal_received() : SIGINT);
  default: return 2;
  }
}

/* PERISTATIC_ERR_USAGE with "peristatic: what" in the handle's message. */
static int usage(const peristatic *ps, const char *what) {
  return ps_error(ps->ctx, PERISTATIC_ERR_USAGE, "%s", what);
}

int peristatic_set_particles(peristatic *ps, int dim, long n, const double *x,
                             const double *volume, const int *block) {
  ps_ctx *ctx = ps->ctx;
  if (ps->cs) return usage(ps, "peristatic_set_particles: call it before loading the case");
  if ((dim != 2 && dim != 3) || n < 1 || !x || !volume)
    return ps_error(ps->ctx, PS_ERR_INPUT, "particles: need dim 2 or 3, n >= 1, positions "
                    "and volumes (got dim %d, n %ld)", dim, n);
  for (long a = 0; a < n; a++) {
    for (int k = 0; k < dim; k++)
      if (!isfinite(x[a * dim + k]))
        return ps_error(ps->ctx, PS_ERR_INPUT, "particles: particle %ld has a non-finite "
                        "coordinate", a);
    if (!(volume[a] > 0) || !isfinite(volume[a]))
      return ps_error(ps->ctx, PS_ERR_INPUT, "particles: particle %ld has volume %g (must be "
                      "> 0)", a, volume[a]);
    if (block && block[a] < 0)
      return ps_error(ps->ctx, PS_ERR_INPUT, "particles: particle %ld has block %d (must be "
                      ">= 0)", a, block[a]);
  }
  ps_particles_free(&ps->given);
  PS_CHECK(ps_particles_alloc(&ps->given, dim, (ps_int)n, ps->ctx));
  memcpy(ps->given.x, x, sizeof *x * (size_t)dim * (size_t)n);
  memcpy(ps->given.volume, volume, sizeof *volume * (size_t)n);
  if (block) memcpy(ps->given.block, block, sizeof *block * (size_t)n);
  return PERISTATIC_OK;
}

/* Load a case (from the file `path`, or from `text` named `path`) into a
 * fresh case over the defaults; the caller's particles make it a cloud. */
static int load(peristatic *ps, const char *path, const char *text) {
  ps_case *cs = ps_calloc(1, sizeof *cs, ps->ctx);
  if (!cs) return PS_ERR_NOMEM;
  ps_case_defaults(cs);
  if (ps->given.n > 0) {
    cs->geometry = PS_GEOM_CLOUD;
    cs->dim = ps->given.dim;
    cs->given_particles = &ps->given;
  }
  int status = text ? ps_case_load_text(cs, text, strlen(text), path, ps->ctx)
                    : ps_case_load(cs, path, ps->ctx);
  if (status == PS_OK && ps->given.n > 0 &&
      (cs->geometry != PS_GEOM_CLOUD || cs->cloud_file[0] || cs->dim != ps->given.dim))
    status = ps_error(ps->ctx, PS_ERR_INPUT, "%s: particles were given (%dD): the case's "
                      "geometry must be a cloud without a file, of that dimension", path,
                      ps->given.dim);
  if (status != PS_OK) {
    ps_case_free(cs);
    free(cs);
    return status;
  }
  drop_problem(ps);
  if (ps->cs) ps_case_free(ps->cs);
  free(ps->cs);
  ps->cs = cs;
  snprintf(ps->case_petsc, sizeof ps->case_petsc, "%s", cs->solver.petsc_options);
  ps->ctx->verbosity = ps->verbosity >= 0 ? ps->verbosity : cs->output.verbosity;
  return PERISTATIC_OK;
}

int peristatic_load_file(peristatic *ps, const char *path) { return load(ps, path, NULL); }

int peristatic_load_text(peristatic *ps, const char *yaml, const char *name) {
  return load(ps, name && name[0] ? name : "case", yaml);
}

int peristatic_set_verbosity(peristatic *ps, int verbosity) {
  if (verbosity < 0 || verbosity > 3)
    return ps_error(ps->ctx, PS_ERR_INPUT, "verbosity must be 0 to 3 (got %d)", verbosity);
  ps->verbosity = verbosity;
  ps->ctx->verbosity = verbosity;
  return PERISTATIC_OK;
}

int peristatic_set_threads(peristatic *ps, int threads) {
  if (threads < 0 || threads > 64)
    return ps_error(ps->ctx, PS_ERR_INPUT, "threads must be 0 to 64 (got %d)", threads);
  ps->threads = threads;
  if (ps->pb) ps->pb->threads = threads;
  return PERISTATIC_OK;
}

int peristatic_set_restart(peristatic *ps, const char *dir) {
  if (dir && strlen(dir) >= sizeof ps->restart)
    return ps_error(ps->ctx, PS_ERR_INPUT, "--restart %.60s...: folder name too long", dir);
  snprintf(ps->restart, sizeof ps->restart, "%s", dir ? dir : "");
  return PERISTATIC_OK;
}

int peristatic_set_max_memory(peristatic *ps, double gib, const char *source) {
  if (!(gib >= 0) || !(gib <= PS_MAX_MEMORY_GIB))
    return ps_error(ps->ctx, PS_ERR_INPUT, "the memory limit must be > 0 GiB (at most %g; "
                    "got %g)", PS_MAX_MEMORY_GIB, gib);
  ps->max_memory = gib;
  ps->max_memory_source = source ? source : "peristatic_set_max_memory";
  drop_problem(ps); /* the limit is checked at set-up */
  return PERISTATIC_OK;
}

const char *peristatic_case_name(const peristatic *ps) { return ps->cs ? ps->cs->name : ""; }

int peristatic_output_dir(const peristatic *ps, const char *given, char *buf, size_t len) {
  if (!ps->cs) return usage(ps, "peristatic_output_dir: no case loaded");
  const ps_case *cs = ps->cs;
  if (!given && cs->output.dir[0]) given = cs->output.dir;
  size_t gl = given ? strlen(given) : 4 + strlen(cs->name);
  while (given && gl > 1 && given[gl - 1] == '/') gl--;
  if (gl > PS_OUTDIR_MAX || gl >= len)
    return ps_error(ps->ctx, PS_ERR_INPUT, "output directory '%.60s...' is too long (%zu "
                    "characters; at most %d, to leave room for the files peristatic writes "
                    "inside it)", given ? given : "out/", gl, PS_OUTDIR_MAX);
  if (given)
    snprintf(buf, len, "%.*s", (int)gl, given);
  else
    snprintf(buf, len, "out/%s", cs->name);
  const char *base = strrchr(buf, '/');
  base = base ? base + 1 : buf;
  if (!strcmp(base, ".") || !strcmp(base, "..") || !strcmp(buf, "/") || !buf[0])
    return ps_error(ps->ctx, PS_ERR_INPUT, "output directory '%s' must name a folder of its "
                    "own", buf);
  return PERISTATIC_OK;
}

/* The layout of a run on several MPI processes (solver.layout): the
 * distributed model where the case allows it (pb->comm set: its network
 * is then each process's share, built by the run), else every process
 * holding the whole model. PS_OK, or PS_ERR_INPUT for a case that asks
 * for the distributed layout and cannot have it. */
static int layout(peristatic *ps, ps_problem *pb, int info) {
  const int ranks = ps_parallel_size(), want = pb->cs.solver.layout;
  char why[200];
  if (info || ranks < 2 || want == PS_LAYOUT_REPLICATED) return PS_OK;
  if (!ps_problem_distributable(pb, ranks, why, sizeof why)) {
    if (want == PS_LAYOUT_DISTRIBUTED)
      return ps_error(ps->ctx, PS_ERR_INPUT, "%s: solver.layout: distributed, but %s (or "
                      "solver.layout: replicated)", pb->cs.file, why);
    if (ps_parallel_rank() == 0)
      ps_log(ps->ctx, 1, "# every process holds the whole model (solver.layout: auto): %s\n",
             why);
    return PS_OK;
  }
  ps_ctx *ctx = ps->ctx;
  PS_CHECK(ps_parallel_comm(&ps->comm, ctx));
  pb->comm = &ps->comm;
  return PS_OK;
}

int peristatic_setup(peristatic *ps, int purpose, int jobs, FILE *report) {
  if (!ps->cs) return usage(ps, "peristatic_setup: no case loaded");
  drop_problem(ps);
  ps_case *cs = ps->cs;
  ps_ctx *ctx = ps->ctx;
  PS_CHECK(apply_petsc_options(ps));
  if (ps->max_memory > 0) {
    cs->max_memory_gib = ps->max_memory;
    cs->max_memory_key = ps->max_memory_source;
  }
  ps_problem *pb = ps_calloc(1, sizeof *pb, ps->ctx);
  if (!pb) return PS_ERR_NOMEM;
  int info = purpose == PERISTATIC_FOR_INFO;
  int status = ps_problem_setup_cloud(pb, cs, info ? PS_ESTIMATE_INFO : PS_ESTIMATE_RUN,
                                      jobs > 0 ? jobs : 1, report, ps->ctx);
  if (status < 0) {
    free(pb);
    return status;
  }
  status = layout(ps, pb, info);
  if (status >= 0 && !pb->comm) status = ps_problem_setup_network(pb, ps->ctx);
  if (status < 0) {
    ps_problem_free(pb);
    free(pb);
    return status;
  }
  pb->threads = ps->threads;
  ps->pb = pb;
  if (!info && ps_signal_received()) { /* during the set-up: nothing written */
    drop_problem(ps);
    return ps_error(ps->ctx, PS_ERR_INTERRUPTED, "%s: interrupted by %s during the set-up; "
                    "nothing was written", cs->file, ps_signal_name(ps_signal_received()));
  }
  return PERISTATIC_OK;
}

int peristatic_info(peristatic *ps, FILE *out) {
  ps_ctx *ctx = ps->ctx;
  if (!ps->cs) return usage(ps, "peristatic_info: no case loaded");
  double t0 = ps_wtime();
  if (!ps->pb) {
    fprintf(out, "case: %s\n", ps->cs->name);
    fflush(out);
    PS_CHECK(peristatic_setup(ps, PERISTATIC_FOR_INFO, 1, out));
  }
  const ps_problem *pb = ps->pb;
  const ps_case *cs = &pb->cs;
  ps_int nfree = 0, nd = (ps_int)pb->P.dim * pb->P.n;
  for (ps_int j = 0; j < nd; j++) nfree += !pb->fixed[j];
  fprintf(out, "particles: %lld\narms: %lld\narms_per_particle: %.2f\n"
          "size_ratio_max_over_min: %.1f\nfree_dofs: %lld\ncase_fingerprint: %016llx\n"
          "setup_s: %.3f\n",
          (long long)pb->P.n, (long long)pb->net.n_arm, 2.0 * pb->net.n_arm / pb->P.n,
          pb->net.max_h_ratio, (long long)nfree,
          (unsigned long long)ps_case_fingerprint(cs), ps_wtime() - t0);
  /* the tangent's pattern over two horizons unless the model has no
   * family terms: what a factorisation will face */
  ps_system sys;
  double t1 = ps_wtime();
  const ps_model_type *type = ps_model_type_find(cs->model);
  PS_CHECK(ps_system_create_pattern(&sys, &pb->net, pb->fixed,
                                    type ? type->family_coupling : 1, ps->ctx));
  ps_int d2 = (ps_int)pb->P.dim * pb->P.dim;
  double mib = ((double)d2 * sys.bptr[pb->P.n] * 8 + (double)sys.fam_slot_ptr[pb->P.n] * 8 +
                (double)sys.A.p[sys.n_free] * 24) / 1048576.0;
  fprintf(out, "tangent_nnz_upper: %lld\ntangent_nnz_per_row: %.1f\n"
          "particle_pairs_coupled: %lld\nassembly_memory_MiB: %.0f\npattern_s: %.3f\n",
          (long long)sys.A.p[sys.n_free],
          2.0 * sys.A.p[sys.n_free] / (double)(sys.n_free > 0 ? sys.n_free : 1),
          (long long)sys.bptr[pb->P.n], mib, ps_wtime() - t1);
  ps_system_free(&sys);
  return PERISTATIC_OK;
}

int peristatic_run(peristatic *ps, const char *out_dir) {
  ps_ctx *ctx = ps->ctx;
  if (!ps->cs) return usage(ps, "peristatic_run: no case loaded");
  if (!ps->pb) PS_CHECK(peristatic_setup(ps, PERISTATIC_FOR_RUN, 1, NULL));
  if (ps->solver) ps_solver_free(ps->solver);
  ps->solver = NULL;
  ps->ran = 0;
  ps->pb->threads = ps->threads;
  ps->pb->checkpoint = ps->pb->cs.output.checkpoint;
  ps->pb->restart = ps->restart[0] ? ps->restart : NULL;
  if (!ps->pb->comm)
    out_dir = rank_output(ps, out_dir);
  else if (ps_parallel_rank() > 0) /* (every process writes its field pieces) */
    ps->ctx->verbosity = 0;
  int status = ps_run_keep(ps->pb, ps->pb->mat.delta, out_dir, &ps->res, &ps->solver, ps->ctx);
  if (status >= 0) {
    ps->ran = 1;
    if (out_dir)
      ps_log(ps->ctx, 1, "# results in %s/ (summary.txt, history.csv, particles.pvd, arms.pvd)\n",
             out_dir);
  }
  return status;
}

int peristatic_stalled_error(peristatic *ps, const char *out_dir) {
  return ps_run_stalled_error(out_dir, ps->ctx);
}

int peristatic_griffith(peristatic *ps, const char *out_dir, int resume, int jobs) {
  ps_ctx *ctx = ps->ctx;
  if (!ps->cs) return usage(ps, "peristatic_griffith: no case loaded");
  if (!out_dir) return usage(ps, "peristatic_griffith: a sweep needs an output folder");
  if (ps_parallel_size() > 1)
    return ps_error(ctx, PS_ERR_INPUT, "griffith runs in one process: its runs are shared "
                    "among processes by -j, not by MPI (run it without mpiexec)");
  if (jobs < 1) jobs = 1;
  /* the runs a sweep holds at once: at most one per delta */
  int held = ps->cs->sweep.n > 0 && ps->cs->sweep.n < jobs ? ps->cs->sweep.n : jobs;
  if (!ps->pb) PS_CHECK(peristatic_setup(ps, PERISTATIC_FOR_RUN, held, NULL));
  if (ps->solver) ps_solver_free(ps->solver);
  ps->solver = NULL;
  ps->ran = 0;
  ps->pb->threads = ps->threads;
  ps->pb->checkpoint = 0; /* a sweep's runs write no checkpoints */
  ps->pb->restart = NULL;
  int status = ps_griffith_jobs(ps->pb, out_dir, resume, jobs, &ps->fit[0], &ps->fit[1],
                                &ps->fit[2], &ps->n_fractured, ps->ctx);
  if (status >= 0) {
    ps->ran = 2;
    ps_log(ps->ctx, 1, "# results in %s/ (griffith.csv, griffith.png)\n", out_dir);
  }
  return status;
}

long peristatic_particle_count(const peristatic *ps) { return ps->pb ? (long)ps->pb->P.n : 0; }

int peristatic_dim(const peristatic *ps) { return ps->pb ? ps->pb->P.dim : 0; }

int peristatic_get_positions(const peristatic *ps, double *out) {
  if (!ps->pb) return usage(ps, "peristatic_get_positions: the problem is not set up");
  memcpy(out, ps->pb->P.x, sizeof *out * (size_t)ps->pb->P.dim * (size_t)ps->pb->P.n);
  return PERISTATIC_OK;
}

int peristatic_get_volumes(const peristatic *ps, double *out) {
  if (!ps->pb) return usage(ps, "peristatic_get_volumes: the problem is not set up");
  memcpy(out, ps->pb->P.volume, sizeof *out * (size_t)ps->pb->P.n);
  return PERISTATIC_OK;
}

int peristatic_get_displacements(const peristatic *ps, double *out) {
  if (!ps->solver) return usage(ps, "peristatic_get_displacements: no run to read");
  memcpy(out, ps_solver_u(ps->solver),
         sizeof *out * (size_t)ps->pb->P.dim * (size_t)ps->pb->P.n);
  return PERISTATIC_OK;
}

int peristatic_get_damage(const peristatic *ps, double *out) {
  if (!ps->solver) return usage(ps, "peristatic_get_damage: no run to read");
  ps_post_damage(&ps->pb->net, ps_solver_arm_state(ps->solver), out);
  return PERISTATIC_OK;
}

/* A named number of the last run: offset into ps_run_result and type. */
typedef struct result_key {
  const char *name;
  char kind; /* d double, i int, n ps_int, s ps_int of the statistics */
  size_t off;
} result_key;

#define R(name, kind, field) {name, kind, offsetof(ps_run_result, field)}
#define S(name, kind, field) {name, kind, offsetof(ps_solver_stats, field)}
static const result_key RUN_KEYS[] = {
    R("sigma_failure", 'd', sigma_peak), R("lambda_peak", 'd', lambda_peak),
    R("sigma_y", 'd', sigma_y),          R("delta", 'd', delta),
    R("fractured", 'i', fractured),      R("stalled", 'i', stalled),
    R("interrupted", 'i', interrupted),  R("increments", 'n', increments),
    R("step_cuts", 'n', step_cuts),      R("arms", 'n', arms),
    R("arms_broken", 'n', arms_broken),  R("crack_tip", 'd', crack_tip),
    R("wall", 'd', wall),                R("peak_memory_mib", 'd', peak_memory_mib),
    S("newton_iterations", 's', newton_iterations), S("factorisations", 's', factorisations),
    S("solves", 's', solves),            S("pcg_iterations", 's', pcg_iterations),
    S("free_dofs", 's', n_free)};
#undef R
#undef S

int peristatic_get_result(const peristatic *ps, const char *name, double *value) {
  if (!ps->ran) return usage(ps, "peristatic_get_result: nothing has run");
  if (ps->ran == 2) {
    static const char *const fit[] = {"griffith_slope", "griffith_intercept", "griffith_r2"};
    for (int i = 0; i < 3; i++)
      if (!strcmp(name, fit[i])) return *value = ps->fit[i], PERISTATIC_OK;
    if (!strcmp(name, "griffith_fractured")) return *value = ps->n_fractured, PERISTATIC_OK;
    return ps_error(ps->ctx, PS_ERR_INPUT, "no result '%s' after a sweep (griffith_slope, "
                    "griffith_intercept, griffith_r2, griffith_fractured)", name);
  }
  for (size_t i = 0; i < sizeof RUN_KEYS / sizeof RUN_KEYS[0]; i++) {
    const result_key *k = &RUN_KEYS[i];
    if (strcmp(name, k->name)) continue;
    const char *r = (const char *)&ps->res + k->off;
    const char *st = (const char *)&ps->res.solver + k->off;
    switch (k->kind) {
    case 'd': *value = *(const double *)r; break;
    case 'i': *value = *(const int *)r; break;
    case 'n': *value = (double)*(const ps_int *)r; break;
    default: *value = (double)*(const ps_int *)st; break;
    }
    return PERISTATIC_OK;
  }
  char names[600] = "";
  for (size_t i = 0; i < sizeof RUN_KEYS / sizeof RUN_KEYS[0]; i++)
    snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "",
             RUN_KEYS[i].name);
  return ps_error(ps->ctx, PS_ERR_INPUT, "no result '%s' (names: %s)", name, names);
}

const char *peristatic_stop_reason(const peristatic *ps) {
  return ps->ran == 1 ? ps->res.stop_reason : "";
}
