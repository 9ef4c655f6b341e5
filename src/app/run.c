/* run.c: one run of a case at the app level: the solver created from the
 * problem, the output folder (lock, staging, commit: src/util/outdir.c),
 * the load path (src/path) with a progress line, a history row and the
 * fields per increment, and the reports at the end (src/io/report.c). */
#include "ps_app.h"

#include "../io/ps_checkpoint.h"
#include "config.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* One run: what its parts share. */
typedef struct run_state {
  ps_problem *pb;           /* the problem the solver holds: the whole, or
                               in a distributed run this process's part
                               (part.local) */
  const ps_problem *whole;  /* the whole problem (pb but in a distributed
                               run) */
  const ps_comm *comm;      /* a distributed run's processes, else NULL */
  int writer;               /* 1: this process writes history.csv, the
                               summary and the plot, and commits (the
                               first of a distributed run's) */
  ps_problem_part part;     /* a distributed run's part of whole */
  ps_material mat;          /* pb->mat with this run's delta */
  ps_solver *s;             /* NULL until created */
  ps_run_result *res;
  const char *out_dir;      /* NULL: no outputs */
  char staging[1200];       /* out_dir.partial, "" without outputs */
  ps_report_history hist;   /* staging/history.csv */
  ps_report_series series;  /* the field files in staging (the .pvd lists) */
  char stall_msg[2048];     /* the path's message of a stall */
  double *reactions;        /* [pb->n_groups * dim] of the history row */
  double t0;                /* wall seconds at the start (a restarted
                               run's: less the wall of the run it
                               continues) */
  /* a restart (pb->restart): the checkpoint, the folder it is in, and
   * its history.csv's rows up to the checkpoint's increment */
  ps_checkpoint ck;
  int restarting;
  char from[1200];
  char *rows;               /* those rows, header first (owned) */
  int64_t last_checkpoint;  /* increment of the last checkpoint written */
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
                        .lambda = ps_solver_lambda(r->s),
                        .piece = r->comm ? &r->part.piece : NULL};
  return st;
}

/* the names of the named loading entries, whose reactions history.csv
 * has (*names NULL when none). Returns PS_OK or PS_ERR_NOMEM. */
static int reaction_names(const run_state *r, const char ***names, ps_ctx *ctx) {
  const ps_problem *pb = r->pb;
  *names = NULL;
  if (pb->n_groups > 0 && !(*names = ps_calloc((size_t)pb->n_groups, sizeof **names, ctx)))
    return PS_ERR_NOMEM;
  for (int g = 0; g < pb->n_groups; g++) (*names)[g] = pb->cs.bc[pb->group_bc[g]].name;
  return PS_OK;
}

/* staging/history.csv with its header */
static int history_open(run_state *r, ps_ctx *ctx) {
  const char **names;
  PS_CHECK(reaction_names(r, &names, ctx));
  int status = ps_report_history_open(&r->hist, r->staging, names, r->pb->n_groups,
                                      r->pb->P.dim, ctx);
  free(names);
  return status;
}

static int step_order(const void *a, const void *b) {
  long x = *(const long *)a, y = *(const long *)b;
  return x < y ? -1 : x > y;
}

/* dst = a copy of src (a hard link where the file system allows) */
static int copy_file(const char *src, const char *dst, ps_ctx *ctx) {
  if (link(src, dst) == 0) return PS_OK;
  FILE *in = fopen(src, "rb"), *out = in ? fopen(dst, "wb") : NULL;
  char buf[65536];
  size_t n;
  int bad = !in || !out;
  while (!bad && (n = fread(buf, 1, sizeof buf, in)) > 0) bad = fwrite(buf, 1, n, out) != n;
  if (in && ferror(in)) bad = 1;
  if (in) fclose(in);
  if (out && fclose(out) != 0) bad = 1;
  if (bad) return ps_error(ctx, PS_ERR_IO, "%s: cannot copy to %s", src, dst);
  return PS_OK;
}

/* 1 when the field files of `step` are among those the uninterrupted run
 * writes up to the checkpoint's increment (every output.vtk_every, not
 * the final state of a run that ended at the checkpoint) */
static int keeps_fields(const run_state *r, long step) {
  const ps_output_opts *o = &r->pb->cs.output;
  return o->fields && o->vtk_every > 0 && step <= r->ck.head.increment &&
         step % o->vtk_every == 0;
}

/* The field files of the restart's folder: those the uninterrupted run
 * has (keeps_fields) into staging (from a completed run's folder), or,
 * when the checkpoint is in staging itself, the others and the reports
 * of the end removed there; the kept steps make the series of the .pvd
 * files. */
static int restart_fields(run_state *r, int in_place, ps_ctx *ctx) {
  static const char *const ends[] = {"summary.txt", "particles.csv", "path.gp", "path.png",
                                     "particles.pvd", "arms.pvd"};
  char src[2600], dst[2600];
  long *kept = NULL;
  size_t n_kept = 0, cap = 0;
  DIR *d = opendir(r->from);
  struct dirent *e;
  int status = PS_OK;
  if (!d) return ps_error(ctx, PS_ERR_IO, "%s: cannot list: %s", r->from, strerror(errno));
  r->series.pvtu = r->comm != NULL;
  while (status == PS_OK && (e = readdir(d))) {
    int listed;
    long step = ps_outdir_field_step(e->d_name, &listed);
    if (step < 0) continue;
    snprintf(src, sizeof src, "%s/%s", r->from, e->d_name);
    snprintf(dst, sizeof dst, "%s/%s", r->staging, e->d_name);
    if (in_place && !keeps_fields(r, step) && unlink(src) != 0)
      status = ps_error(ctx, PS_ERR_IO, "%s: cannot remove: %s", src, strerror(errno));
    else if (!in_place && keeps_fields(r, step))
      status = copy_file(src, dst, ctx);
    if (status == PS_OK && keeps_fields(r, step) && listed &&
        !strncmp(e->d_name, "particles_", 10)) {
      if (n_kept == cap) {
        void *q = kept;
        cap = cap ? 2 * cap : 16;
        status = ps_realloc(&q, cap, sizeof *kept, ctx);
        kept = q;
      }
      if (status == PS_OK) kept[n_kept++] = step;
    }
  }
  closedir(d);
  for (size_t k = 0; in_place && status == PS_OK && k < sizeof ends / sizeof ends[0]; k++) {
    snprintf(src, sizeof src, "%s/%s", r->from, ends[k]);
    if (unlink(src) != 0 && errno != ENOENT)
      status = ps_error(ctx, PS_ERR_IO, "%s: cannot remove: %s", src, strerror(errno));
  }
  if (n_kept) qsort(kept, n_kept, sizeof *kept, step_order);
  for (size_t k = 0; status == PS_OK && k < n_kept; k++)
    status = ps_report_series_add(r->staging, &r->series, (int)kept[k], ctx);
  free(kept);
  return status;
}

/* A restart's outputs: staging is the checkpoint's folder (continued in
 * place) or a fresh one with its field files; history.csv holds its
 * rows up to the checkpoint. */
static int open_restart_outputs(run_state *r, ps_ctx *ctx) {
  struct stat a, b;
  int in_place = stat(r->from, &a) == 0 && stat(r->staging, &b) == 0 && a.st_dev == b.st_dev &&
                 a.st_ino == b.st_ino;
  if (!in_place) PS_CHECK(ps_outdir_fresh(r->staging, ctx));
  PS_CHECK(restart_fields(r, in_place, ctx));
  PS_CHECK(history_open(r, ctx));
  const char *rows = strchr(r->rows, '\n') + 1; /* after the header (restart_rows) */
  if (fputs(rows, r->hist.f) < 0 || fflush(r->hist.f) != 0)
    return ps_error(ctx, PS_ERR_IO, "%s/history.csv: cannot write", r->staging);
  return PS_OK;
}

/* Stage the outputs: an empty out_dir.partial (ps_outdir_prepare has
 * checked it is ours) with history.csv's header; for a restart,
 * open_restart_outputs. */
static int open_outputs(run_state *r, ps_ctx *ctx) {
  char why[512];
  ps_run_result *old = NULL;
  snprintf(r->staging, sizeof r->staging, "%s.partial", r->out_dir);
  if (r->restarting) return open_restart_outputs(r, ctx);
  /* a complete result there (not stalled, not interrupted) was on its
   * way to out_dir when a kill stopped the commit: say what goes */
  if (ps_outdir_owned(r->staging, why, sizeof why) == 1 && (old = malloc(sizeof *old)) &&
      ps_report_read_summary(r->staging, old) == 0 && !old->stalled &&
      strncmp(old->stop_reason, "interrupted", 11) != 0)
    ps_log(ctx, 0, "peristatic: replacing %s, the output of an earlier run that did not "
                   "complete its commit\n", r->staging);
  free(old);
  PS_CHECK(ps_outdir_fresh(r->staging, ctx));
  return history_open(r, ctx);
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
  double d = measured_displacement(r->whole);
  if (!isnan(d) || !pb->fext) return lambda * d;
  const double *u = ps_solver_u(r->s);
  double wa[2] = {0, 0}; /* fext . u, sum |fext| */
  for (ps_int j = 0; j < pb->P.n * pb->P.dim; j++) {
    wa[0] += pb->fext[j] * u[j];
    wa[1] += fabs(pb->fext[j]);
  }
  ps_comm_sum(ps_solver_comm(r->s), wa, 2);
  return wa[1] > 0 ? wa[0] / wa[1] : NAN;
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
  ps_comm_sum(ps_solver_comm(r->s), r->reactions, pb->n_groups * d);
}

/* The progress line, history row and (every output.vtk_every) fields of
 * the increment the path just made. */
static int record_increment(run_state *r, const ps_path *p, ps_ctx *ctx) {
  const ps_path_increment *inc = &p->last;
  int step = (int)inc->step;
  ps_log(ctx, 1, "  %4d %9.5f %10.5f %6d %9.2e %8lld %7lld %6.2f\n", step, inc->lambda,
         inc->sigma / r->mat.sigma_y, inc->newton_iterations, inc->residual,
         (long long)inc->yielding, (long long)p->broken_total, inc->tip);
  /* the sums over the run's processes, in one order on every process
   * (an initialiser list's order is unspecified) */
  const double displacement = row_displacement(r, inc->lambda);
  const double broken_energy =
      ps_comm_sum1(ps_solver_comm(r->s), ps_solver_arm_state(r->s)->broken_energy);
  const double stored_energy = ps_solver_stored_energy(r->s);
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
                        .displacement = displacement,
                        .broken_energy = broken_energy,
                        .stored_energy = stored_energy,
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

/* status as the processes of a distributed run agree on it: a failure
 * on one fails all (the others would wait in a collective); the first
 * process's message says what failed when it did */
static int agree(const run_state *r, int status, ps_ctx *ctx) {
  if (r->comm && ps_comm_any(r->comm, status < 0) && status >= 0)
    return ps_error(ctx, PS_ERR_IO, "%s: another process of the run failed (its files or "
                    "memory)", r->pb->cs.file);
  return status;
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

/* what identifies this run in a checkpoint (increment and wall: now) */
static ps_checkpoint_head checkpoint_head(const run_state *r, int64_t increment) {
  const ps_problem *pb = r->pb;
  ps_int nd = pb->P.n * pb->P.dim, nfree = 0;
  for (ps_int j = 0; j < nd; j++) nfree += !pb->fixed[j];
  ps_checkpoint_head h = {.algorithm = ps_algorithm_version(),
                          .fingerprint = ps_case_restart_fingerprint(&pb->cs),
                          .delta = r->mat.delta,
                          .particles = pb->P.n,
                          .arms = pb->net.n_arm,
                          .dofs = nd,
                          .free_dofs = nfree,
                          .increment = increment,
                          .wall = ps_wtime() - r->t0,
                          .processes = r->comm ? r->comm->size : 0,
                          .rank = r->comm ? r->comm->rank : 0};
  ps_case_restart_part_fingerprints(&pb->cs, h.parts);
  return h;
}

/* the state of the solver and of the path, as one list */
static int state_list(run_state *r, ps_path *p, ps_state_list *l, ps_ctx *ctx) {
  PS_CHECK(ps_solver_state_list(r->s, l, ctx));
  return ps_path_state_list(p, l, ctx);
}

/* staging/checkpoint.bin of the state after p's last increment */
static int write_checkpoint(run_state *r, ps_path *p, ps_ctx *ctx) {
  ps_state_list l = {0};
  const ps_csc *A;
  int which, status = PS_OK;
  PS_CHECK_GOTO(ps_solver_factor_matrix(r->s, &which, &A, ctx));
  PS_CHECK_GOTO(state_list(r, p, &l, ctx));
  ps_checkpoint_head h = checkpoint_head(r, p->increments);
  PS_CHECK_GOTO(ps_checkpoint_write(r->staging, &h, which, A, &l, ctx));
  r->last_checkpoint = p->increments;
  char name[64];
  ps_checkpoint_name(h.processes, h.rank, name, sizeof name);
  ps_log(ctx, 2, "# checkpoint at increment %lld: %s/%s%s\n", (long long)p->increments,
         r->staging, name, r->comm ? " (and the other processes')" : "");
cleanup:
  ps_state_list_free(&l);
  return status;
}

/* the checkpoint's state into the solver and the path */
static int restore_checkpoint(run_state *r, ps_path *p, ps_ctx *ctx) {
  ps_state_list l = {0};
  int status = PS_OK;
  PS_CHECK_GOTO(state_list(r, p, &l, ctx));
  PS_CHECK_GOTO(ps_checkpoint_load_items(&r->ck, &l, ctx));
  PS_CHECK_GOTO(ps_solver_state_restored(r->s, r->ck.which, r->ck.which ? &r->ck.A : NULL, ctx));
  ps_log(ctx, 1, "# restarted from %s at increment %lld (load factor %.6g)\n", r->ck.path,
         (long long)p->increments, ps_solver_lambda(r->s));
cleanup:
  ps_state_list_free(&l);
  return status;
}

/* The load path under the case's step controller, an increment at a time, recorded as
 * it goes; with pb->checkpoint, checkpoints every output.checkpoint_every
 * increments and at a resumable end. Returns PS_OK (the outcome is in
 * res) or a fatal status. */
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
  const int every = pb->cs.output.checkpoint_every, ckpt = pb->checkpoint && r->out_dir;
  if (status >= 0 && r->restarting) status = restore_checkpoint(r, &p, ctx);
  /* the restart's own checkpoint first: the folder it came from may go */
  if (status >= 0 && r->restarting && ckpt) status = write_checkpoint(r, &p, ctx);
  while (status >= 0 && ps_path_test(&p) == PS_PATH_CONTINUE) {
    ps_int before = p.increments;
    status = ps_path_iterate(&p, ctx);
    if (status >= 0 && p.increments > before) status = record_increment(r, &p, ctx);
    if (status >= 0 && ckpt && every > 0 && p.increments > before && p.resumable &&
        p.increments % every == 0)
      status = write_checkpoint(r, &p, ctx);
  }
  if (status >= 0 && ckpt && p.resumable && p.increments != r->last_checkpoint)
    status = write_checkpoint(r, &p, ctx);
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
  int with_displacement = !isnan(row_displacement(r, 1.0)); /* (collective) */
  double peak = ps_peak_mib(); /* (the largest process's) */
  ps_comm_max(r->comm, &peak, 1);
  r->res->peak_memory_mib = peak;
  int status = PS_OK;
  if (r->writer) {
    status = ps_report_history_close(&r->hist, ctx);
    /* the path's plot: with no gnuplot (or a failed one) the script stays */
    if (status == PS_OK)
      status = ps_report_write_path_plot(r->staging, r->pb->cs.name, with_displacement, ctx);
    if (status == PS_OK && PS_GNUPLOT[0] && ps_gnuplot_run(r->staging, "path.gp") != 0)
      ps_log(ctx, 2, "# gnuplot failed on %s/path.gp\n", r->staging);
  }
  PS_CHECK(agree(r, status, ctx));
  /* (every process of a distributed run: J's sums are collective) */
  status = ps_report_write_summary(r->staging, r->res, &r->pb->cs, &st, ctx);
  /* (every process's files are written before the folder is committed) */
  PS_CHECK(agree(r, status, ctx));
  if (commit && r->writer) status = ps_dir_commit(r->staging, r->out_dir, ctx);
  return agree(r, status, ctx);
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
  if (r->comm) opts.majorant = 0; /* (not on a share: ps_solver_create_share) */
  int status = ps_solver_create_share(&r->s, &pb->P, &pb->net, ps_model_type_find(cs->model),
                                      &r->mat, pb->fixed, pb->ubar, &opts,
                                      r->comm ? &r->part.solver_share : NULL, ctx);
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
  const ps_problem *pb = r->whole;
  ps_run_result *res = r->res;
  snprintf(res->case_name, sizeof res->case_name, "%s", pb->cs.name);
  res->particles = pb->P.n;
  res->arms = r->comm ? r->part.arms : pb->net.n_arm;
  res->delta = delta;
  res->sigma_y = r->mat.sigma_y;
  res->fingerprint = ps_case_fingerprint(&pb->cs);
  res->t_network = pb->t_network;
  res->processes = ps_parallel_size();
  res->distributed = r->comm != NULL;
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
  const ps_problem *pb = r->whole;
  ps_solver_stats st;
  ps_solver_get_stats(r->s, &st);
  char breaking[96];
  describe_breaking(&r->mat, delta, breaking, sizeof breaking);
  ps_int nd = pb->P.n * pb->P.dim, n_free = 0;
  for (ps_int j = 0; j < nd; j++) n_free += !pb->fixed[j];
  ps_log(ctx, 1, "# %s: %lld particles, %lld arms, %lld free dofs, %s, %d thread%s\n",
         pb->cs.name, (long long)pb->P.n, (long long)r->res->arms, (long long)n_free,
         breaking, st.threads, st.threads > 1 ? "s" : "");
  if (r->comm)
    ps_log(ctx, 1, "# distributed over %d processes (solver.layout): %lld particles and "
                   "%lld ghosts here\n",
           r->comm->size, (long long)r->part.sh.n_owned,
           (long long)(r->part.sh.P.n - r->part.sh.n_owned));
  ps_log(ctx, 1, "# %4s %9s %10s %6s %9s %8s %7s %6s\n", "step", "lambda", "sig/sig_y",
         "newton", "residual", "yielding", "broken", "tip/c");
}

/* 1 when dir/name is a regular file */
static int has_file(const char *dir, const char *name) {
  char path[1400];
  struct stat sb;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

/* r->rows = the header and the first k rows of r->from's history.csv
 * (the rows a later part of the run wrote after the checkpoint go) */
static int restart_rows(run_state *r, ps_ctx *ctx) {
  char path[1400], line[4096];
  int64_t k = r->ck.head.increment, n = -1;
  size_t len = 0, cap = 0;
  snprintf(path, sizeof path, "%s/history.csv", r->from);
  FILE *f = fopen(path, "r");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
  int status = PS_OK;
  while (n < k && fgets(line, sizeof line, f)) {
    size_t l = strlen(line);
    if (!l || line[l - 1] != '\n') break; /* a row cut short */
    if (n >= 0 && strtoll(line, NULL, 10) != n + 1) break;
    if (len + l + 1 > cap) {
      void *q = r->rows;
      cap = 2 * (len + l + 1);
      if ((status = ps_realloc(&q, cap, 1, ctx)) < 0) break;
      r->rows = q;
    }
    memcpy(r->rows + len, line, l + 1);
    len += l;
    n++;
  }
  fclose(f);
  if (status == PS_OK && n >= 0) { /* the columns: this run's (named entries' reactions) */
    const char **names;
    PS_CHECK(reaction_names(r, &names, ctx));
    const ps_problem *pb = r->pb;
    size_t need = ps_report_history_header(NULL, 0, names, pb->n_groups, pb->P.dim) + 1;
    char *head = ps_calloc(need, 1, ctx);
    if (head) ps_report_history_header(head, need, names, pb->n_groups, pb->P.dim);
    size_t l0 = strcspn(r->rows, "\n") + 1;
    if (!head)
      status = PS_ERR_NOMEM;
    else if (strlen(head) != l0 || strncmp(head, r->rows, l0) != 0)
      status = ps_error(ctx, PS_ERR_INPUT, "%s has other columns than %s's history.csv would "
                        "(its named loading entries differ): not this case's run", path,
                        r->pb->cs.file);
    free(head);
    free(names);
  }
  if (status == PS_OK && n < k)
    status = ps_error(ctx, PS_ERR_INPUT, "%s has %lld complete rows, fewer than the %lld "
                      "increments of its checkpoint %s: restart from the checkpoint's own "
                      "folder", path, (long long)(n < 0 ? 0 : n), (long long)k, r->ck.path);
  return status;
}

/* The checkpoint of pb->restart (DIR.partial's when it has one, else
 * DIR's), checked against this run, and its history rows; in a
 * distributed run each process's own checkpoint_pR.bin, all from the
 * same folder and of the same increment. Nothing is changed on disk.
 * Returns PS_OK or fatal (collective: a failure on one process fails
 * all). */
static int load_restart(run_state *r, ps_ctx *ctx) {
  const char *dir = r->pb->restart;
  char path[1400], name[64];
  const int processes = r->comm ? r->comm->size : 0, rank = r->comm ? r->comm->rank : 0;
  ps_checkpoint_name(processes, rank, name, sizeof name);
  snprintf(r->from, sizeof r->from, "%s.partial", dir);
  int partial = has_file(r->from, name), status = PS_OK;
  ps_int in_partial = ps_comm_count(r->comm, partial);
  if (in_partial > 0 && in_partial < (r->comm ? r->comm->size : 1))
    return ps_error(ctx, PS_ERR_INPUT, "%s.partial holds the checkpoints of %lld of the %d "
                    "processes: restart with the run's number of processes", dir,
                    (long long)in_partial, r->comm->size);
  if (!partial) snprintf(r->from, sizeof r->from, "%s", dir);
  snprintf(path, sizeof path, "%s/%s", r->from, name);
  status = ps_checkpoint_read(path, &r->ck, ctx);
  if (status == PS_ERR_INPUT && !has_file(r->from, name)) { /* another layout's? */
    char other[64];
    ps_checkpoint_name(processes ? 0 : 1, 0, other, sizeof other);
    if (has_file(r->from, other))
      status = ps_error(ctx, PS_ERR_INPUT, "%s has no %s but %s: the checkpoint of a run %s; "
                        "restart it %s", r->from, name, other,
                        processes ? "that held the whole model" : "distributed over several "
                        "processes", processes ? "with solver.layout: replicated or on one "
                        "process" : "with mpiexec -n P, P its processes");
  }
  ps_checkpoint_head want = checkpoint_head(r, 0);
  if (status >= 0) status = ps_checkpoint_check(&r->ck, &want, r->pb->cs.file, ctx);
  if (status >= 0) status = restart_rows(r, ctx);
  PS_CHECK(agree(r, status, ctx));
  double inc[2] = {(double)r->ck.head.increment, -(double)r->ck.head.increment};
  ps_comm_max(r->comm, inc, 2);
  if (inc[0] != -inc[1])
    return ps_error(ctx, PS_ERR_INPUT, "the checkpoints of %s's processes are of different "
                    "increments (%.0f to %.0f: a run stopped while writing them); run the "
                    "case afresh", r->from, -inc[1], inc[0]);
  r->restarting = 1;
  r->last_checkpoint = r->ck.head.increment;
  r->t0 -= r->ck.head.wall; /* the wall column goes on from the checkpoint's */
  return PS_OK;
}

/* The run of the case, or of this process's part of it when pb->comm is
 * set (a distributed run: every call collective, the first process the
 * writer of the run's files, every process its own field pieces). */
static int run_case(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                    ps_solver **keep, ps_ctx *ctx) {
  int status = PS_OK;
  run_state r;
  memset(&r, 0, sizeof r);
  memset(res, 0, sizeof *res);
  const ps_comm *saved_comm = ctx->comm;
  r.pb = pb;
  r.whole = pb;
  r.comm = pb->comm;
  r.writer = ps_comm_rank(r.comm) == 0;
  r.res = res;
  r.out_dir = out_dir;
  r.t0 = ps_wtime();
  r.mat = pb->mat;
  r.mat.delta = delta;
  r.last_checkpoint = -1;
  if (r.comm) { /* the part's problem; every reduction over the processes */
    ctx->comm = r.comm;
    PS_CHECK_GOTO(ps_problem_part_create(&r.part, pb, r.comm, ctx));
    r.pb = &r.part.local;
  }
  describe_run(&r, delta);
  /* the folders are checked before anything is computed: only a folder
   * of ours is replaced, a result lost in a commit's rename is restored */
  if (out_dir && r.writer) status = ps_outdir_prepare(out_dir, ctx);
  PS_CHECK_GOTO(agree(&r, status, ctx));
  if (pb->restart) PS_CHECK_GOTO(load_restart(&r, ctx));
  PS_CHECK_GOTO(create_solver(&r, ctx));
  if ((r.pb->checkpoint && out_dir) || r.restarting) /* (a part: its share's) */
    PS_CHECK_GOTO(ps_solver_keep_factors(r.s, ctx));
  if (ps_comm_any(r.comm, ps_signal_received() != 0)) { /* before the first increment:
                                                           nothing to keep */
    int sig = ps_signal_received() ? ps_signal_received() : SIGTERM;
    status = ps_error(ctx, PS_ERR_INTERRUPTED, "%s: interrupted by %s before the first "
                      "increment; nothing was written", pb->cs.file, ps_signal_name(sig));
    goto cleanup;
  }
  if (pb->n_groups > 0 &&
      !(r.reactions = ps_calloc((size_t)pb->n_groups * pb->P.dim, sizeof *r.reactions, ctx)))
    status = PS_ERR_NOMEM;
  if (status == PS_OK && out_dir) {
    snprintf(r.staging, sizeof r.staging, "%s.partial", out_dir);
    if (r.writer) status = open_outputs(&r, ctx);
  }
  PS_CHECK_GOTO(agree(&r, status, ctx));
  ps_solver_set_forces(r.s, r.pb->fext);
  log_start(&r, delta, ctx);
  PS_CHECK_GOTO(follow_path(&r, ctx));
  ps_solver_get_stats(r.s, &res->solver);
  if (r.comm) { /* the whole model's free dofs, not the share's */
    ps_int nd = pb->P.n * pb->P.dim;
    res->solver.n_free = 0;
    for (ps_int j = 0; j < nd; j++) res->solver.n_free += !pb->fixed[j];
  }
  res->wall = ps_wtime() - r.t0;
  log_end(&r, ctx);
  /* a stalled or interrupted run stays in staging: the caller decides */
  if (out_dir) PS_CHECK_GOTO(finish_outputs(&r, !res->stalled && !res->interrupted, ctx));
  if (res->interrupted) {
    char where[2600] = "", more[1600] = "";
    if (out_dir && r.last_checkpoint >= 0)
      snprintf(more, sizeof more, "; peristatic run --restart %s continues it from its "
               "checkpoint at increment %lld", out_dir, (long long)r.last_checkpoint);
    if (out_dir)
      snprintf(where, sizeof where, "; the partial output is in %s%s%s%s%s", r.staging,
               is_dir(out_dir) ? ", earlier results in " : "", is_dir(out_dir) ? out_dir : "",
               is_dir(out_dir) ? " are untouched" : "", more);
    status = ps_error(ctx, PS_ERR_INTERRUPTED, "%s: %s%s", pb->cs.file, res->stop_reason,
                      where);
    r.staging[0] = '\0'; /* the message says it all */
  } else if (res->stalled) {
    status = ps_error(ctx, PS_RUN_STALLED, "%s", r.stall_msg);
  }
cleanup:
  free(r.reactions);
  ps_checkpoint_free(&r.ck);
  free(r.rows);
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
  if (keep && status >= 0 && !r.comm) /* (a part's solver holds a share) */
    *keep = r.s;
  else
    ps_solver_free(r.s);
  ps_problem_part_free(&r.part);
  ctx->comm = saved_comm;
  return status < 0 ? status : status == PS_RUN_STALLED ? PS_RUN_STALLED : PS_OK;
}

int ps_run_keep(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                ps_solver **keep, ps_ctx *ctx) {
  ps_outdir_lock lk = {.fd = -1};
  int status = PS_OK;
  if (keep) *keep = NULL;
  /* (a distributed run's first process holds the lock for all) */
  if (out_dir && ps_comm_rank(pb->comm) == 0) status = ps_outdir_lock_take(&lk, out_dir, ctx);
  if (pb->comm && ps_comm_any(pb->comm, status < 0) && status >= 0)
    status = ps_error(ctx, PS_ERR_IO, "%s: the first process could not lock %s", pb->cs.file,
                      out_dir);
  if (status < 0) return status;
  status = run_case(pb, delta, out_dir, res, keep, ctx);
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
