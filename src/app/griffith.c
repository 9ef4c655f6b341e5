/* griffith.c: the Griffith sweep: one run per delta/c on one particle
 * cloud, shared among forked worker processes (claims, signals, parent
 * death), reuse of finished runs (--resume), the table, the fit and the
 * plot (gnuplot run without a shell). */
#include "ps_app.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "config.h"

void ps_sweep_opts_default(ps_sweep_opts *o) {
  memset(o, 0, sizeof *o);
  o->n = 12; /* delta/c = 1/500, 1/750, ..., 1/3250 */
  for (int i = 0; i < o->n; i++) o->delta_over_c[i] = 1.0 / (500.0 + 250.0 * i);
}

/* A finished run of this sweep in dir (same case fingerprint, particles,
 * arms and delta)? Then *r is its record, read back from its summary.txt
 * (ps_report_read_summary). */
static int reuse_run(const ps_problem *pb, const char *dir, double delta,
                     ps_run_result *r) {
  double sig_last = NAN;
  if (ps_report_read_summary(dir, r) != 0) return 0;
  if (r->fingerprint != ps_case_fingerprint(&pb->cs) || r->particles != pb->P.n ||
      r->arms != pb->net.n_arm || !(fabs(r->delta - delta) <= 1e-9 * delta))
    return 0; /* written so that a NaN (delta_m: n/a) matches nothing */
  if (r->fractured && ps_report_last_attempt_failed(dir, &sig_last) &&
      !ps_path_failed_attempt_is_fracture(1, sig_last, r->sigma_peak)) {
    r->fractured = 0; /* an older run labelled by the former rule */
    r->stalled = 1;
  }
  return isfinite(r->sigma_peak) && isfinite(r->sigma_y) && r->sigma_y > 0;
}

/* Run i of the sweep in staging/delta_cNNNN, or reuse it there when
 * try_reuse and it matches (reuse_run). With may_run = 0 (another process
 * holds the run) only a finished run will do. job > 0 labels a worker's
 * log. A stalled run is kept as a result when it has a peak, else it is
 * the error `run` would report. Returns PS_OK, ps_run's fatal status, or
 * PS_ERR_SOLVER when the run stalled before any peak or may not be run
 * here and is not finished. */
static int sweep_run(ps_problem *pb, const char *staging, int i, int try_reuse, int may_run,
                     int job, ps_run_result *res, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  double dc = cs->sweep.delta_over_c[i];
  char path[1300], label[32] = "";
  snprintf(path, sizeof path, "%s/delta_c%.6g", staging, 1.0 / dc);
  if (job > 0) snprintf(label, sizeof label, " (job %d)", job);
  if (try_reuse && reuse_run(pb, path, dc * pb->c, res)) {
    ps_log(ctx, 1, "## griffith run %d/%d%s: delta = c/%.6g: reusing %s\n", i + 1,
           cs->sweep.n, label, 1.0 / dc, path);
    return PS_OK;
  }
  if (!may_run) /* a claim of this sweep's own workers that outlived them */
    return ps_error(ctx, PS_ERR_IO,
                    "%s is claimed by another process (pid in %s.claim)", path, path);
  ps_log(ctx, 1, "## griffith run %d/%d%s: delta = c/%.6g\n", i + 1, cs->sweep.n, label,
         1.0 / dc);
  int status = ps_run_unlocked(pb, dc * pb->c, path, res, ctx); /* the sweep holds the lock */
  /* a run whose Newton solve stalls before the crack runs (the paper's
   * delta = c/500: the plate yields) is a row of the table, not an error,
   * once a settled state set a peak */
  if (status == PS_RUN_STALLED)
    status = isfinite(res->sigma_peak) ? ps_run_commit(path, ctx)
                                       : ps_run_stalled_error(path, ctx);
  return status;
}

static void claim_path(const ps_problem *pb, const char *staging, int i, char *path,
                       size_t len) {
  snprintf(path, len, "%s/delta_c%.6g.claim", staging, 1.0 / pb->cs.sweep.delta_over_c[i]);
}

/* Claim run i for this process: create staging/delta_cNNNN.claim
 * exclusively (O_EXCL is atomic, so two workers never take the same run)
 * holding our pid. A claim whose process is gone (a worker killed with
 * its sweep) is taken over. Returns 1 when
 * this process got it; release_run removes it when the run is done. */
static int claim_run(const ps_problem *pb, const char *staging, int i) {
  char path[1300];
  claim_path(pb, staging, i, path, sizeof path);
  for (int attempt = 0; attempt < 2; attempt++) {
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
      char buf[32];
      int n = snprintf(buf, sizeof buf, "%ld\n", (long)getpid());
      int ok = write(fd, buf, (size_t)n) == n;
      close(fd);
      return ok;
    }
    FILE *f = fopen(path, "r");
    long pid = 0;
    if (f) {
      if (fscanf(f, "%ld", &pid) != 1) pid = 0;
      fclose(f);
    }
    if (pid <= 0 || (kill((pid_t)pid, 0) == 0 || errno != ESRCH)) return 0; /* alive */
    unlink(path); /* stale: its process is gone */
  }
  return 0;
}

static void release_run(const ps_problem *pb, const char *staging, int i) {
  char path[1300];
  claim_path(pb, staging, i, path, sizeof path);
  unlink(path);
}

/* Remove every delta_c*.claim in staging. The sweep holds the folder's
 * lock, so no other process can be running one of its runs: a claim there
 * now is a leftover of a killed sweep (possibly empty, or naming a pid
 * that another process has since been given) and would block --resume. */
static void remove_stale_claims(const char *staging, ps_ctx *ctx) {
  DIR *d = opendir(staging);
  struct dirent *e;
  char path[1300];
  if (!d) return;
  while ((e = readdir(d))) {
    size_t n = strlen(e->d_name);
    if (strncmp(e->d_name, "delta_c", 7) || n < 14 || strcmp(e->d_name + n - 6, ".claim"))
      continue;
    snprintf(path, sizeof path, "%s/%s", staging, e->d_name);
    if (unlink(path) == 0) ps_log(ctx, 2, "# removed the stale claim %s\n", path);
  }
  closedir(d);
}


/* The runs in the order the workers take them: largest delta first (the
 * most increments), so the longest runs start first and the short ones
 * fill the gaps (longest-processing-time-first scheduling). */
static void longest_first(const ps_case *cs, int *order) {
  int n = cs->sweep.n;
  for (int k = 0; k < n; k++) order[k] = k;
  for (int k = 1; k < n; k++) /* insertion sort by delta, descending */
    for (int j = k; j > 0 && cs->sweep.delta_over_c[order[j]] >
                               cs->sweep.delta_over_c[order[j - 1]]; j--) {
      int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
}

/* The body of worker w (1-based) of `jobs`, in the forked child: dies with
 * the parent (ps_signals_worker), logs to staging/job-w.log, takes the
 * next unclaimed run until none is left or a signal came. Exit status 0,
 * 1 when a run failed, 2 when interrupted. */
_Noreturn static void worker(ps_problem *pb, const char *staging, int w, int jobs, long parent,
                   const int *order, ps_ctx *ctx) {
  if (ps_signals_worker(parent) != 0) _exit(2); /* the parent is gone */
  char logpath[1300];
  snprintf(logpath, sizeof logpath, "%s/job-%d.log", staging, w);
  FILE *log = fopen(logpath, "w");
  ctx->log = log;
  /* the CPUs are shared among the jobs */
  if (pb->threads <= 0) {
    int per_job = ps_cpu_count() / jobs;
    pb->threads = per_job > 1 ? per_job : 1;
  }
  int bad = 0;
  for (int k = 0; k < pb->cs.sweep.n && !ps_signal_received(); k++) {
    ps_run_result r; /* after a failed run, go on with the others */
    if (!claim_run(pb, staging, order[k])) continue;
    if (sweep_run(pb, staging, order[k], 1, 1, w, &r, ctx) < 0) {
      if (log) fprintf(log, "peristatic: %s\n", ctx->msg);
      bad = 1;
    }
    release_run(pb, staging, order[k]); /* done: later claims just reuse it */
  }
  if (log) fclose(log);
  _exit(ps_signal_received() ? 2 : bad ? 1 : 0);
}

/* Wait for the workers; the first SIGINT/SIGTERM of this process is
 * passed on to them as SIGTERM (each ends its run as `run` does) and they
 * are waited for. *failed = the last job that did not exit 0. */
static void wait_workers(const pid_t *pids, int jobs, int *failed, ps_ctx *ctx) {
  int done[64] = {0}, left = jobs, forwarded = 0;
  *failed = 0;
  while (left > 0) {
    if (ps_signal_received() && !forwarded) {
      for (int w = 0; w < jobs; w++)
        if (!done[w]) kill(pids[w], SIGTERM);
      forwarded = 1;
      ps_log(ctx, 1, "## griffith: %s: stopping the jobs\n",
             ps_signal_name(ps_signal_received()));
    }
    for (int w = 0; w < jobs; w++) {
      int st = 0;
      if (done[w]) continue;
      pid_t r = waitpid(pids[w], &st, WNOHANG);
      if (r == 0 || (r < 0 && errno == EINTR)) continue;
      done[w] = 1;
      left--;
      if (r < 0 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) *failed = w + 1;
      else ps_log(ctx, 1, "## griffith: job %d finished\n", w + 1);
    }
    if (left > 0) { /* poll: the signal flag is not a file descriptor */
      struct timespec t = {0, 50000000L};
      nanosleep(&t, NULL);
    }
  }
}

/* Share the sweep's runs among `jobs` forked workers writing into staging
 * and wait for them (see worker). The table does not depend on which
 * worker ran what. Returns PS_OK, PS_ERR_INTERRUPTED after a signal,
 * or PS_ERR_SOLVER / PS_ERR_IO naming the job. */
static int run_workers(ps_problem *pb, const char *staging, int jobs, ps_ctx *ctx) {
  int order[PS_MAX_SWEEP], failed = 0;
  pid_t pids[64];
  long parent = (long)getpid();
  longest_first(&pb->cs, order);
  fflush(NULL);
  for (int w = 0; w < jobs; w++) {
    pid_t pid = fork();
    if (pid < 0) {
      for (int k = 0; k < w; k++) kill(pids[k], SIGTERM);
      wait_workers(pids, w, &failed, ctx);
      return ps_error(ctx, PS_ERR_IO, "griffith --jobs: cannot fork a worker: %s",
                      strerror(errno));
    }
    if (pid == 0) worker(pb, staging, w + 1, jobs, parent, order, ctx);
    pids[w] = pid;
    ps_log(ctx, 1, "## griffith: job %d started (log %s/job-%d.log)\n", w + 1, staging,
           w + 1);
  }
  wait_workers(pids, jobs, &failed, ctx);
  if (ps_signal_received())
    return ps_error(ctx, PS_ERR_INTERRUPTED, "griffith interrupted by %s: the jobs "
                    "ended their runs", ps_signal_name(ps_signal_received()));
  if (failed)
    return ps_error(ctx, PS_ERR_SOLVER, "griffith --jobs: job %d failed (see %s/job-%d.log)",
                    failed, staging, failed);
  return PS_OK;
}

/* griffith.csv, griffith_fit.txt and griffith.gp in dir */
static int write_tables(const ps_problem *pb, const char *dir, const ps_run_result *res,
                        int nf, double slope, double intercept, double r2, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  int n = cs->sweep.n;
  char path[1300], b1[32], b2[32], b3[32], title[300];
  double nominal = sqrt(2.0 / (M_PI * pb->mat.yield_strain));
  ps_outfile o;
  snprintf(path, sizeof path, "%s/griffith.csv", dir);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f, "delta_over_c,sqrt_delta_over_c,sigma_failure_over_sigma_y,fractured,"
               "increments,newton_iterations,arms_broken,wall_s\n");
  for (int i = 0; i < n; i++) {
    double dc = cs->sweep.delta_over_c[i];
    fprintf(o.f, "%.8g,%.8g,%s,%s,%lld,%lld,%lld,%.3f\n", dc, sqrt(dc),
            ps_fmt_or_na(res[i].sigma_peak / res[i].sigma_y, 8, b1, sizeof b1),
            res[i].fractured ? "yes" : res[i].stalled ? "stalled" : "no",
            (long long)res[i].increments, (long long)res[i].solver.newton_iterations,
            (long long)res[i].arms_broken, res[i].wall);
  }
  PS_CHECK(ps_outfile_commit(&o, ctx));
  snprintf(path, sizeof path, "%s/griffith_fit.txt", dir);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f,
          "# least-squares line sigma_failure/sigma_y = intercept + slope "
          "sqrt(delta/c)\n# over the runs that fractured (n/a: fewer than two)\n"
          "runs: %d\nfractured: %d\nslope: %s\nintercept: %s\nr2: %s\n"
          "nominal_griffith_slope: %.8g\n"
          "# nominal slope sqrt(2/(pi eps_y)) of Eq. 106/109; see doc/griffith.md\n",
          n, nf, ps_fmt_or_na(slope, 8, b1, sizeof b1),
          ps_fmt_or_na(intercept, 8, b2, sizeof b2), ps_fmt_or_na(r2, 8, b3, sizeof b3),
          nominal);
  PS_CHECK(ps_outfile_commit(&o, ctx));
  snprintf(path, sizeof path, "%s/griffith.gp", dir);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f,
          "# gnuplot script: sigma_failure/sigma_y against sqrt(delta/c)\n"
          "set terminal pngcairo size 800,600 noenhanced\nset output 'griffith.png'\n"
          "set datafile separator ','\nset key top left\n"
          "set xlabel 'sqrt(delta / c)'\nset ylabel 'sigma_failure / sigma_yield'\n"
          "set title 'Griffith check: %s (slope %s, intercept %s, R^2 %s)'\n"
          "set xrange [0:*]\nset yrange [0:*]\n"
          "plot 'griffith.csv' every ::1 using (strcol(4) eq \"yes\" ? $2 : 1/0):3 with points "
          "pt 7 ps 1.5 title 'fractured', \\\n"
          "     'griffith.csv' every ::1 using (strcol(4) eq \"no\" ? $2 : 1/0):3 with points "
          "pt 6 ps 1.5 title 'no fracture (peak load)', \\\n"
          "     'griffith.csv' every ::1 using (strcol(4) eq \"stalled\" ? $2 : 1/0):3 with "
          "points pt 4 ps 1.5 title 'no fracture: solve stalled (last settled load)', \\\n"
          "     %.10g + %.10g*x title 'least-squares fit' lw 2, \\\n"
          "     %.10g*x title 'nominal Griffith sqrt(2/(pi eps_y)) x' dt 2\n",
          ps_gnuplot_quoted(cs->name, title, sizeof title), ps_fmt_or_na(slope, 8, b1, sizeof b1),
          ps_fmt_or_na(intercept, 8, b2, sizeof b2), ps_fmt_or_na(r2, 8, b3, sizeof b3),
          isfinite(intercept) ? intercept : 0.0, isfinite(slope) ? slope : 0.0, nominal);
  return ps_outfile_commit(&o, ctx);
}

/* Where the sweep writes (*staging) and whether it is renamed to out_dir
 * at the end (*commit): a fresh sweep stages in out_dir.partial; a resumed
 * one continues in out_dir.partial when an interrupted fresh sweep left
 * one there (a folder of ours without a run's summary.txt), otherwise in
 * out_dir itself, one atomic folder per run. */
static int sweep_folder(const char *out_dir, int resume, char *staging, size_t len,
                        int *commit, ps_ctx *ctx) {
  char why[512], path[1300], table[1300];
  struct stat sb;
  snprintf(staging, len, "%s.partial", out_dir);
  snprintf(path, sizeof path, "%s/summary.txt", staging);
  snprintf(table, sizeof table, "%s/griffith.csv", staging);
  *commit = 1;
  int owned = ps_outdir_owned(staging, why, sizeof why) == 1;
  /* a staging folder with the table is a finished sweep whose commit did
   * not complete, or (beside out_dir) the earlier results a commit had
   * swapped out when it was stopped: never continued over out_dir */
  int finished = owned && lstat(table, &sb) == 0;
  if (!resume) {
    if (finished)
      ps_log(ctx, 0, "peristatic: replacing %s, the output of an earlier sweep that did not "
                     "complete its commit\n", staging);
    return ps_outdir_fresh(staging, ctx);
  }
  if (owned && lstat(path, &sb) != 0 && (!finished || lstat(out_dir, &sb) != 0)) {
    ps_log(ctx, 1, "## griffith: continuing the interrupted sweep in %s\n", staging);
    return PS_OK;
  }
  snprintf(staging, len, "%s", out_dir);
  *commit = 0;
  return ps_outdir_open(staging, ctx);
}

static int griffith_sweep(ps_problem *pb, const char *out_dir, int resume, int jobs,
                          double *slope, double *intercept, double *r2, int *n_fractured,
                          ps_ctx *ctx);

int ps_griffith(ps_problem *pb, const char *out_dir, int resume, double *slope,
                double *intercept, double *r2, int *n_fractured, ps_ctx *ctx) {
  return ps_griffith_jobs(pb, out_dir, resume, 1, slope, intercept, r2, n_fractured, ctx);
}

int ps_griffith_jobs(ps_problem *pb, const char *out_dir, int resume, int jobs,
                     double *slope, double *intercept, double *r2, int *n_fractured,
                     ps_ctx *ctx) {
  ps_outdir_lock lk;
  *slope = *intercept = *r2 = NAN;
  *n_fractured = 0;
  if (!(pb->c > 0))
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: the Griffith sweep needs the elliptic disk (geometry.type "
                    "disk): delta is swept as a fraction of c",
                    pb->cs.file);
  if (pb->cs.sweep.n < 1)
    return ps_error(ctx, PS_ERR_INPUT, "%s: griffith sweep is empty", pb->cs.file);
  /* the lock covers the whole sweep, its workers (which share it) and
   * the runs' folders inside it */
  PS_CHECK(ps_outdir_lock_take(&lk, out_dir, ctx));
  int status = griffith_sweep(pb, out_dir, resume, jobs, slope, intercept, r2, n_fractured,
                              ctx);
  ps_outdir_lock_release(&lk);
  return status;
}

static int griffith_sweep(ps_problem *pb, const char *out_dir, int resume, int jobs,
                          double *slope, double *intercept, double *r2, int *n_fractured,
                          ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  int n = cs->sweep.n, status = PS_OK, nf = 0, commit;
  double xs[PS_MAX_SWEEP], ys[PS_MAX_SWEEP];
  ps_run_result res[PS_MAX_SWEEP];
  char staging[1200], b1[32], b2[32], b3[32];
  PS_CHECK(ps_outdir_prepare(out_dir, ctx));
  PS_CHECK(sweep_folder(out_dir, resume, staging, sizeof staging, &commit, ctx));
  remove_stale_claims(staging, ctx); /* before any worker claims a run */
  if (jobs > n) jobs = n;
  if (jobs > 64) jobs = 64;
  if (jobs > 1) status = run_workers(pb, staging, jobs, ctx); /* then all reused */
  for (int i = 0; i < n && status >= 0; i++) {
    double dc = cs->sweep.delta_over_c[i];
    if (ps_signal_received()) { /* between runs (a run checks its increments) */
      status = ps_error(ctx, PS_ERR_INTERRUPTED, "griffith interrupted by %s between runs",
                        ps_signal_name(ps_signal_received()));
      break;
    }
    /* a run another process holds: only its result will do */
    int mine = claim_run(pb, staging, i);
    status = sweep_run(pb, staging, i, resume || jobs > 1, mine, 0, &res[i], ctx);
    if (mine) release_run(pb, staging, i);
    if (status >= 0 && res[i].fractured) {
      xs[nf] = sqrt(dc);
      ys[nf] = res[i].sigma_peak / res[i].sigma_y;
      nf++;
    }
  }
  if (status < 0) {
    size_t l = strlen(ctx->msg);
    snprintf(ctx->msg + l, sizeof ctx->msg - l,
             "\n(the runs finished so far are in %s; `peristatic griffith --resume -o %s "
             "CASE` continues the sweep)",
             staging, out_dir);
    return status;
  }
  *n_fractured = nf;
  if (nf >= 2) PS_CHECK(ps_post_line_fit(xs, ys, nf, slope, intercept, r2, ctx));
  PS_CHECK(write_tables(pb, staging, res, nf, *slope, *intercept, *r2, ctx));
  if (commit) PS_CHECK(ps_dir_commit(staging, out_dir, ctx));
  if (PS_GNUPLOT[0] && ps_gnuplot_run(out_dir, "griffith.gp") != 0)
    ps_log(ctx, 1, "# warning: gnuplot failed; the plot script is %s/griffith.gp\n", out_dir);
  ps_log(ctx, 1, "## griffith: %d of %d runs fractured; slope %s, intercept %s, R^2 %s "
                 "(nominal slope %.5g)\n",
         nf, n, ps_fmt_or_na(*slope, 8, b1, sizeof b1),
         ps_fmt_or_na(*intercept, 8, b2, sizeof b2), ps_fmt_or_na(*r2, 8, b3, sizeof b3),
         sqrt(2.0 / (M_PI * pb->mat.yield_strain)));
  return status;
}
