/* run.c: one run of a case at the app level: the solver created from the
 * problem, the output folder (lock, staging, commit: src/util/outdir.c),
 * the load path (src/path) with a progress line, a history row and the
 * fields per increment, and the reports at the end (src/io/report.c). */
#include "ps_app.h"

#include "config.h"

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* One run: what its parts share. */
typedef struct run_state {
  ps_problem *pb;
  ps_material mat;          /* pb->mat with this run's delta */
  ps_solver *s;             /* NULL until created */
  ps_run_result *res;
  const char *out_dir;      /* NULL: no outputs */
  char staging[1200];       /* out_dir.partial, "" without outputs */
  ps_report_history hist;   /* staging/history.csv */
  ps_report_series series;  /* the field files in staging (the .pvd lists) */
  char stall_msg[2048];     /* the path's message of a stall */
  double *reactions;        /* [pb->n_groups * dim] of the history row */
  double t0;                /* wall seconds at the start */
} run_state;

/* 1 when path is a folder (earlier results to speak of) */
static int is_dir(const char *path) {
  struct stat sb;
  return path && lstat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

/* the path's interruption: SIGINT or SIGTERM received */
static int signal_received(void *data, char *why, size_t len) {
  (void)data;
  int sig = ps_signal_received();
  if (sig && why) snprintf(why, len, "interrupted by %s", ps_signal_name(sig));
  return sig;
}

/* the solver's current state, for the field files and J */
static ps_report_state report_state(const run_state *r) {
  ps_report_state st = {.P = &r->pb->P,
                        .net = &r->pb->net,
                        .mat = &r->mat,
                        .u = ps_solver_u(r->s),
                        .T = ps_solver_arm_tension(r->s),
                        .q = ps_solver_arm_direction(r->s),
                        .dl = ps_solver_arm_elongation(r->s),
                        .st = ps_solver_arm_state(r->s),
                        .lambda = ps_solver_lambda(r->s)};
  return st;
}

/* Stage the outputs: an empty out_dir.partial (ps_outdir_prepare has
 * checked it is ours) with history.csv's header. */
static int open_outputs(run_state *r, ps_ctx *ctx) {
  char why[512];
  ps_run_result *old = NULL;
  snprintf(r->staging, sizeof r->staging, "%s.partial", r->out_dir);
  /* a complete result there (not stalled, not interrupted) was on its
   * way to out_dir when a kill stopped the commit: say what goes */
  if (ps_outdir_owned(r->staging, why, sizeof why) == 1 && (old = malloc(sizeof *old)) &&
      ps_report_read_summary(r->staging, old) == 0 && !old->stalled &&
      strncmp(old->stop_reason, "interrupted", 11) != 0)
    ps_log(ctx, 0, "peristatic: replacing %s, the output of an earlier run that did not "
                   "complete its commit\n", r->staging);
  free(old);
  PS_CHECK(ps_outdir_fresh(r->staging, ctx));
  const ps_problem *pb = r->pb;
  const char **names = NULL;
  if (pb->n_groups > 0 && !(names = ps_calloc((size_t)pb->n_groups, sizeof *names, ctx)))
    return PS_ERR_NOMEM;
  for (int g = 0; g < pb->n_groups; g++) names[g] = pb->cs.bc[pb->group_bc[g]].name;
  int status = ps_report_history_open(&r->hist, r->staging, names, pb->n_groups, pb->P.dim,
                                      ctx);
  free(names);
  return status;
}

/* The prescribed displacement at load factor 1 of the first measured dof
 * along its measured direction (loading.boundary), or NAN when no
 * measured dof has one (and for the disk's Eq. 116 field). */
static double measured_displacement(const ps_problem *pb) {
  ps_int nd = pb->P.n * pb->P.dim;
  if (pb->cs.load_type == PS_LOAD_EQ116) return NAN;
  for (ps_int j = 0; j < nd; j++)
    if (pb->measure[j] != 0 && pb->fixed[j]) return pb->ubar[j] * pb->measure[j];
  return NAN;
}

/* The displacement of the history row: the measured particles'
 * prescribed displacement (lambda x measured_displacement), or, under
 * tractions, the loaded particles' mean displacement along their forces,
 * fext . u / sum |fext| (NAN for neither). */
static double row_displacement(const run_state *r, double lambda) {
  const ps_problem *pb = r->pb;
  double d = measured_displacement(pb);
  if (!isnan(d) || !pb->fext) return lambda * d;
  const double *u = ps_solver_u(r->s);
  double w = 0, a = 0;
  for (ps_int j = 0; j < pb->P.n * pb->P.dim; j++) {
    w += pb->fext[j] * u[j];
    a += fabs(pb->fext[j]);
  }
  return a > 0 ? w / a : NAN;
}

/* The reactions of the named loading.boundary entries into
 * r->reactions: per entry and component, the sum over its particles of
 * the reactions at their prescribed dofs (free dofs carry none). */
static void group_reactions(run_state *r) {
  const ps_problem *pb = r->pb;
  const double *f = ps_solver_force(r->s);
  int d = pb->P.dim;
  for (int g = 0; g < pb->n_groups; g++)
    for (int k = 0; k < d; k++) {
      double sum = 0.0;
      for (ps_int i = pb->group_ptr[g]; i < pb->group_ptr[g + 1]; i++) {
        ps_int j = pb->group_particle[i] * d + k;
        if (pb->fixed[j]) sum += f[j];
      }
      r->reactions[g * d + k] = sum;
    }
}

/* The progress line, history row and (every output.vtk_every) fields of
 * the increment the path just made. */
static int record_increment(run_state *r, const ps_path *p, ps_ctx *ctx) {
  const ps_path_increment *inc = &p->last;
  int step = (int)inc->step;
  ps_log(ctx, 1, "  %4d %9.5f %10.5f %6d %9.2e %8lld %7lld %6.2f\n", step, inc->lambda,
         inc->sigma / r->mat.sigma_y, inc->newton_iterations, inc->residual,
         (long long)inc->yielding, (long long)p->broken_total, inc->tip);
  ps_history_row row = {.step = inc->step,
                        .load_factor = inc->lambda,
                        .boundary_stress = inc->sigma,
                        .stress_over_sigma_y = inc->sigma / r->mat.sigma_y,
                        .newton_iterations = inc->newton_iterations,
                        .relative_residual = inc->residual,
                        .converged = inc->converged,
                        .arms_yielding = inc->yielding,
                        .arms_broken = p->broken_total,
                        .crack_tip = inc->tip,
                        .wall = ps_wtime() - r->t0,
                        .reaction = inc->sigma * r->pb->measure_length,
                        .displacement = row_displacement(r, inc->lambda),
                        .broken_energy = ps_solver_arm_state(r->s)->broken_energy,
                        .stored_energy = ps_solver_stored_energy(r->s),
                        .dissipated_energy = ps_solver_dissipated(r->s),
                        .reactions = r->reactions};
  if (r->reactions) group_reactions(r);
  ps_report_history_row(&r->hist, &row);
  const ps_output_opts *out = &r->pb->cs.output;
  if (r->out_dir && out->fields && out->vtk_every > 0 && step % out->vtk_every == 0) {
    ps_report_state st = report_state(r);
    PS_CHECK(ps_report_write_fields(r->staging, step, 0, &st, &r->series, ctx));
  }
  return PS_OK;
}

/* the path's outcome into res */
static void result_from_path(ps_run_result *res, const ps_path *p) {
  res->sigma_peak = p->peak;
  res->lambda_peak = p->lambda_peak;
  res->fractured = p->end == PS_PATH_FRACTURED;
  res->stalled = p->end == PS_PATH_STALLED;
  res->interrupted = p->interrupted;
  snprintf(res->stop_reason, sizeof res->stop_reason, "%s", p->stop_reason);
  res->increments = p->increments;
  res->step_cuts = p->step_cuts;
  res->gentle_rounds = p->gentle_rounds;
  res->arms_broken = p->broken_total;
  res->crack_tip = p->crack_tip;
}

/* The load path under the case's step controller, an increment at a time, recorded as
 * it goes. Returns PS_OK (the outcome is in res) or a fatal status. */
static int follow_path(run_state *r, ps_ctx *ctx) {
  ps_problem *pb = r->pb;
  ps_path_problem pp = {.P = &pb->P,
                        .net = &pb->net,
                        .model = ps_model_type_find(pb->cs.model),
                        .mat = &r->mat,
                        .measure = pb->measure,
                        .measure_length = pb->measure_length,
                        .c = pb->c,
                        .name = pb->cs.file,
                        .interrupted = signal_received};
  ps_path p;
  int status = ps_path_init(&p, r->s, &pp, &pb->cs.path,
                             ps_step_control_find(pb->cs.path.control), ctx);
  while (status >= 0 && ps_path_test(&p) == PS_PATH_CONTINUE) {
    ps_int before = p.increments;
    status = ps_path_iterate(&p, ctx);
    if (status >= 0 && p.increments > before) status = record_increment(r, &p, ctx);
  }
  if (status >= 0) {
    result_from_path(r->res, &p);
    snprintf(r->stall_msg, sizeof r->stall_msg, "%s", p.message);
  }
  ps_path_free(&p);
  return status;
}

static void log_end(const run_state *r, const ps_ctx *ctx) {
  const ps_run_result *res = r->res;
  char b[32];
  if (r->pb->measure_length > 0)
    ps_log(ctx, 1, "# end: %s\n# sigma_failure = %s Pa = %.5f sigma_y (peak at load "
                   "factor %.5g)%s; %lld increments, %lld Newton iterations, %.2f s\n",
           res->stop_reason, ps_fmt_or_na(res->sigma_peak, 6, b, sizeof b),
           res->sigma_peak / r->mat.sigma_y, res->lambda_peak,
           res->fractured ? "" : " [no fracture]", (long long)res->increments,
           (long long)res->solver.newton_iterations, res->wall);
  else /* no measure: loaded by tractions or unmeasured displacements */
    ps_log(ctx, 1, "# end: %s\n# no boundary-stress measure (loading.boundary has no "
                   "measure: true): the stress column is 0; %lld increments, %lld Newton "
                   "iterations, %.2f s\n",
           res->stop_reason, (long long)res->increments,
           (long long)res->solver.newton_iterations, res->wall);
}

/* The final state, history.csv and summary.txt into staging; then staging
 * replaces out_dir when commit is set. */
static int finish_outputs(run_state *r, int commit, ps_ctx *ctx) {
  ps_report_state st = report_state(r);
  if (r->pb->cs.output.fields)
    PS_CHECK(ps_report_write_fields(r->staging, (int)r->res->increments, 1, &st, &r->series,
                                    ctx));
  PS_CHECK(ps_report_history_close(&r->hist, ctx));
  /* the path's plot: with no gnuplot (or a failed one) the script stays */
  PS_CHECK(ps_report_write_path_plot(r->staging, r->pb->cs.name,
                                     !isnan(row_displacement(r, 1.0)), ctx));
  if (PS_GNUPLOT[0] && ps_gnuplot_run(r->staging, "path.gp") != 0)
    ps_log(ctx, 2, "# gnuplot failed on %s/path.gp\n", r->staging);
  r->res->peak_memory_mib = ps_peak_mib();
  PS_CHECK(ps_report_write_summary(r->staging, r->res, &r->pb->cs, &st, ctx));
  if (commit) PS_CHECK(ps_dir_commit(r->staging, r->out_dir, ctx));
  return PS_OK;
}

/* The solver, created with SIGINT and SIGTERM blocked: its threads
 * inherit the mask, so the signals go to the thread that runs the load
 * path and ps_dir_commit's blocking holds them off. */
static int create_solver(run_state *r, ps_ctx *ctx) {
  ps_problem *pb = r->pb;
  const ps_case *cs = &pb->cs;
  ps_solver_opts opts = cs->solver; /* the case's, with the run's threads */
  sigset_t block, saved;
  opts.threads = pb->threads;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &block, &saved);
  int status = ps_solver_create(&r->s, &pb->P, &pb->net, ps_model_type_find(cs->model),
                                &r->mat, pb->fixed, pb->ubar, &opts, ctx);
  pthread_sigmask(SIG_SETMASK, &saved, NULL);
  if (status == PS_ERR_INPUT && strncmp(ctx->msg, cs->file, strlen(cs->file)) != 0) {
    char m[sizeof ctx->msg];
    snprintf(m, sizeof m, "%s", ctx->msg);
    ps_error(ctx, PS_ERR_INPUT, "%s: %s", cs->file, m); /* name the case file */
  }
  return status;
}

/* what was run, into res */
static void describe_run(const run_state *r, double delta) {
  const ps_problem *pb = r->pb;
  ps_run_result *res = r->res;
  snprintf(res->case_name, sizeof res->case_name, "%s", pb->cs.name);
  res->particles = pb->P.n;
  res->arms = pb->net.n_arm;
  res->delta = delta;
  res->sigma_y = r->mat.sigma_y;
  res->fingerprint = ps_case_fingerprint(&pb->cs);
  res->t_network = pb->t_network;
}

/* the breaking criterion in words, for the first progress line */
static void describe_breaking(const ps_material *m, double delta, char *buf, size_t len) {
  if (m->fracture != PS_FRACTURE_NONE && m->fracture_energy > 0)
    snprintf(buf, len, "G_c %.4g J/m^2 (%s criterion)", m->fracture_energy,
             m->fracture == PS_FRACTURE_STRETCH ? "stretch" : "energy");
  else if (m->fracture == PS_FRACTURE_STRETCH)
    snprintf(buf, len, "critical stretch %.4g", m->critical_stretch);
  else if (m->fracture == PS_FRACTURE_ENERGY)
    snprintf(buf, len, "critical micropotential %.4g", m->critical_micropotential);
  else if (isfinite(delta))
    snprintf(buf, len, "delta %.4g m", delta);
  else
    snprintf(buf, len, "no breaking");
}

static void log_start(const run_state *r, double delta, const ps_ctx *ctx) {
  const ps_problem *pb = r->pb;
  ps_solver_stats st;
  ps_solver_get_stats(r->s, &st);
  char breaking[96];
  describe_breaking(&r->mat, delta, breaking, sizeof breaking);
  ps_log(ctx, 1, "# %s: %lld particles, %lld arms, %lld free dofs, %s, %d thread%s\n",
         pb->cs.name, (long long)pb->P.n, (long long)pb->net.n_arm, (long long)st.n_free,
         breaking, st.threads, st.threads > 1 ? "s" : "");
  ps_log(ctx, 1, "# %4s %9s %10s %6s %9s %8s %7s %6s\n", "step", "lambda", "sig/sig_y",
         "newton", "residual", "yielding", "broken", "tip/c");
}

static int run_case(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                    ps_solver **keep, ps_ctx *ctx) {
  int status = PS_OK;
  run_state r;
  memset(&r, 0, sizeof r);
  memset(res, 0, sizeof *res);
  r.pb = pb;
  r.res = res;
  r.out_dir = out_dir;
  r.t0 = ps_wtime();
  r.mat = pb->mat;
  r.mat.delta = delta;
  describe_run(&r, delta);
  /* the folders are checked before anything is computed: only a folder
   * of ours is replaced, a result lost in a commit's rename is restored */
  if (out_dir) PS_CHECK_GOTO(ps_outdir_prepare(out_dir, ctx));
  PS_CHECK_GOTO(create_solver(&r, ctx));
  if (ps_signal_received()) { /* before the first increment: nothing to keep */
    status = ps_error(ctx, PS_ERR_INTERRUPTED, "%s: interrupted by %s before the first "
                      "increment; nothing was written", pb->cs.file,
                      ps_signal_name(ps_signal_received()));
    goto cleanup;
  }
  if (pb->n_groups > 0 &&
      !(r.reactions = ps_calloc((size_t)pb->n_groups * pb->P.dim, sizeof *r.reactions, ctx))) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  if (out_dir) PS_CHECK_GOTO(open_outputs(&r, ctx));
  ps_solver_set_forces(r.s, pb->fext);
  log_start(&r, delta, ctx);
  PS_CHECK_GOTO(follow_path(&r, ctx));
  ps_solver_get_stats(r.s, &res->solver);
  res->wall = ps_wtime() - r.t0;
  log_end(&r, ctx);
  /* a stalled or interrupted run stays in staging: the caller decides */
  if (out_dir) PS_CHECK_GOTO(finish_outputs(&r, !res->stalled && !res->interrupted, ctx));
  if (res->interrupted) {
    char where[2600] = "";
    if (out_dir)
      snprintf(where, sizeof where, "; the partial output is in %s%s%s%s", r.staging,
               is_dir(out_dir) ? ", earlier results in " : "", is_dir(out_dir) ? out_dir : "",
               is_dir(out_dir) ? " are untouched" : "");
    status = ps_error(ctx, PS_ERR_INTERRUPTED, "%s: %s%s", pb->cs.file, res->stop_reason,
                      where);
    r.staging[0] = '\0'; /* the message says it all */
  } else if (res->stalled) {
    status = ps_error(ctx, PS_RUN_STALLED, "%s", r.stall_msg);
  }
cleanup:
  free(r.reactions);
  ps_report_history_close(&r.hist, ctx);
  ps_report_series_free(&r.series);
  if (status < 0 && r.staging[0]) {
    size_t n = strlen(ctx->msg);
    if (is_dir(out_dir))
      snprintf(ctx->msg + n, sizeof ctx->msg - n,
               "\n(earlier results in %s are untouched; this run's partial output is in "
               "%s)",
               out_dir, r.staging);
    else
      snprintf(ctx->msg + n, sizeof ctx->msg - n, "\n(this run's partial output is in %s)",
               r.staging);
  }
  if (keep && status >= 0)
    *keep = r.s;
  else
    ps_solver_free(r.s);
  return status < 0 ? status : status == PS_RUN_STALLED ? PS_RUN_STALLED : PS_OK;
}

int ps_run_keep(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                ps_solver **keep, ps_ctx *ctx) {
  ps_outdir_lock lk = {.fd = -1};
  if (keep) *keep = NULL;
  if (out_dir) PS_CHECK(ps_outdir_lock_take(&lk, out_dir, ctx));
  int status = run_case(pb, delta, out_dir, res, keep, ctx);
  ps_outdir_lock_release(&lk);
  return status;
}

int ps_run(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
           ps_ctx *ctx) {
  return ps_run_keep(pb, delta, out_dir, res, NULL, ctx);
}

int ps_run_unlocked(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                    ps_ctx *ctx) {
  return run_case(pb, delta, out_dir, res, NULL, ctx);
}

int ps_run_stalled_error(const char *out_dir, ps_ctx *ctx) {
  size_t n = strlen(ctx->msg);
  if (out_dir && is_dir(out_dir))
    snprintf(ctx->msg + n, sizeof ctx->msg - n,
             "\n(earlier results in %s are untouched; this run's partial output is in "
             "%s.partial)",
             out_dir, out_dir);
  else if (out_dir)
    snprintf(ctx->msg + n, sizeof ctx->msg - n, "\n(this run's partial output is in %s.partial)",
             out_dir);
  return PS_ERR_SOLVER;
}

int ps_run_commit(const char *out_dir, ps_ctx *ctx) {
  char staging[1300];
  snprintf(staging, sizeof staging, "%s.partial", out_dir);
  return ps_dir_commit(staging, out_dir, ctx);
}
