/* ps_app.h: what the command line does, as a library: set a problem up
 * from a case (geometry, sizes, network, material, boundary conditions),
 * run it along the load path with progress lines and outputs, and the
 * Griffith sweep over delta. Tests call these too. */
#ifndef PS_APP_H
#define PS_APP_H

#include "../io/ps_io.h"
#include "../post/ps_post.h"
#include "../solver/ps_solver.h"

typedef struct ps_problem {
  ps_case cs;             /* the case (copy) */
  ps_particles P;
  ps_kernel kernel;
  ps_network net;
  ps_material mat;        /* finished; delta resolved (inf: no breaking) */
  double c;               /* disk: half crack length (m); 0 otherwise */
  unsigned char *fixed;   /* [n_dof] prescribed dofs */
  double *ubar;           /* [n_dof] prescribed displacement at lambda 1 */
  double *measure;        /* [n_dof] boundary-stress weights (normals) */
  double *fext;           /* [n_dof] forces at lambda 1 from tractions (N,
                             per unit thickness in 2D), or NULL if none */
  double measure_length;  /* m (2D) or m^2 (3D) */
  double t_network;       /* wall seconds of geometry + network */
  int threads;            /* threads per run (ps_solver_opts.threads; 0:
                             the CPUs this process may use, shared among
                             griffith's jobs) */
  int stall_is_result;    /* set by the Griffith sweep: a stalled run
                             (ps_run_result.stalled) ends as a result, no
                             fracture, instead of an error
                             (doc/griffith.md) */
} ps_problem;

/* Build the particle cloud, sizes, network and boundary conditions of a
 * case. Errors name the case file and line where one is known. Returns
 * PS_OK, PS_ERR_INPUT, PS_ERR_IO, PS_ERR_NOMEM. */
int ps_problem_setup(ps_problem *pb, const ps_case *cs, ps_ctx *ctx);
/* ps_problem_setup with the size estimate (src/network/estimate.c) checked
 * before the network is built, for `purpose` (enum ps_estimate_purpose:
 * PS_ESTIMATE_INFO or PS_ESTIMATE_RUN; `jobs` runs at once share the
 * particles and network) against cs->max_memory_gib, and printed to
 * `report` (key: value lines) when not NULL. ps_problem_setup is this
 * with PS_ESTIMATE_RUN, 1, NULL. Returns as ps_problem_setup; a case
 * above the limit is PS_ERR_INPUT with the figures. */
int ps_problem_setup_sized(ps_problem *pb, const ps_case *cs, int purpose, int jobs,
                           FILE *report, ps_ctx *ctx);
void ps_problem_free(ps_problem *pb);

/* Outcome of one run along the load path. */
typedef struct ps_run_result {
  double sigma_peak;        /* peak boundary stress, Pa: sigma_failure */
  double lambda_peak;       /* load factor at the peak */
  double sigma_y;           /* E eps_y, Pa */
  int fractured;            /* 1: the crack ran (tip or load-drop stop) */
  int stalled;              /* 1: the solve failed before the crack ran
                               (fractured = 0): Newton below path.min_step,
                               or a re-equilibration that failed without
                               the load falling below its peak */
  int interrupted;          /* SIGINT or SIGTERM that ended the run before
                               its end, 0 if none */
  char stop_reason[160];
  ps_int increments, newton_iterations, factorisations, arms_broken;
  ps_int n_fallback, step_cuts;
  ps_int gentle_rounds;     /* breaking rounds retried with fewer arms */
  ps_int pcg_iterations, pcg_failures, pcg_skipped, solves;
  ps_int majorant_factorisations, majorant_failures; /* solver.majorant */
  ps_int shifted_steps;     /* Newton directions from a shifted tangent */
  ps_int cg_truncated;      /* from CG truncated at negative curvature */
  ps_int stagnated;         /* Newton solves ended as stagnated */
  ps_int handovers;         /* adaptive CG solves that went on with the
                               fixed rule at max_iterations */
  int threads;              /* threads of the run's CG */
  double serial_share;      /* share of a preconditioner solve on one
                               thread alone (the majorant's factor, else
                               the tangent's) */
  ps_int line_search_cuts;  /* backtracking steps of the line search */
  double t_majorant_factor, nnz_majorant_factor;
  double t_cg;              /* wall seconds in CG (products and
                               preconditioner solves) */
  double nnz_tangent;       /* nonzeros of the free tangent (upper) */
  double nnz_factor, flops_factor; /* of the last factorisation */
  double crack_tip;         /* in units of c (disk) */
  double wall, t_assembly, t_analyze, t_factor, t_solve;
} ps_run_result;

/* Run the case's load path with elongation limit delta (m; inf: no
 * breaking). When out_dir is not NULL, first takes out_dir's lock
 * (ps_outdir_lock_take: another writer is refused) and checks the folders
 * (ps_outdir_prepare: only a folder of ours is replaced), then writes
 * through out_dir.partial, renamed to out_dir at the end so a failed run
 * leaves earlier results intact: history.csv, particles.csv, summary.txt
 * and VTK files (particles_NNNN.vtk, arms_NNNN.vtk); non-finite numbers are
 * written as n/a. SIGINT or SIGTERM (ps_signal_received) ends the run
 * after the increment or breaking round under way: the outputs so far
 * stay in out_dir.partial and the status is PS_ERR_INTERRUPTED.
 * Returns PS_OK, or a fatal status (e.g. PS_ERR_SOLVER when Newton fails
 * below the smallest increment; the message says what was seen and what
 * can help). */
int ps_run(ps_problem *pb, double delta, const char *out_dir,
           ps_run_result *res, ps_ctx *ctx);

/* ps_run without the lock, for a caller whose lock covers out_dir (the
 * sweep's runs, in folders inside the sweep's). */
int ps_run_unlocked(ps_problem *pb, double delta, const char *out_dir,
                    ps_run_result *res, ps_ctx *ctx);

/* A re-equilibration that failed after arms broke counts as the crack
 * running only when arms broke and the failed attempt's boundary stress
 * fell below the peak of the settled states. */
int ps_failed_attempt_is_fracture(ps_int broken_total, double sig, double peak);

/* v with `digits` significant digits ("%.*g") in buf, or "n/a" when v is
 * not finite (no nan or inf in outputs); returns buf. */
const char *ps_fmt_or_na(double v, int digits, char *buf, size_t len);

/* Keep the solver of the last ps_run alive for inspection (tests): when
 * keep != NULL, ps_run_keep hands the solver over instead of freeing it. */
int ps_run_keep(ps_problem *pb, double delta, const char *out_dir,
                ps_run_result *res, ps_solver *keep, ps_ctx *ctx);

/* Griffith sweep over the case's delta/c values on one particle cloud:
 * writes griffith.csv, griffith_fit.txt, griffith.gp and (with gnuplot,
 * run without a shell) griffith.png into out_dir, and one folder
 * delta_cNNNN per run. The fit is over the runs that fractured. The sweep
 * holds out_dir's lock throughout (ps_outdir_lock_take) and replaces only
 * a folder of ours (ps_outdir_prepare). A fresh sweep (resume = 0) is
 * staged in out_dir.partial and replaces out_dir at the end; with resume
 * = 1 it continues in out_dir.partial when an interrupted fresh sweep left
 * one there (and replaces out_dir at the end), otherwise works in out_dir
 * itself; either way it reuses every run folder whose summary.txt matches
 * this cloud (particles, arms) and delta, so a long sweep can be
 * continued. SIGINT/SIGTERM end the run under way as in ps_run and the
 * sweep with PS_ERR_INTERRUPTED. Returns PS_OK or a fatal status; fit
 * results in *slope, *intercept, *r2 (NAN when fewer than two runs
 * fractured). */
int ps_griffith(ps_problem *pb, const char *out_dir, int resume, double *slope,
                double *intercept, double *r2, int *n_fractured, ps_ctx *ctx);

/* The same with the runs shared among `jobs` worker processes (fork; each
 * takes the next unclaimed run, largest delta first, and logs to
 * DIR/job-N.log), after which the sweep's tables, fit and plot are written
 * from the finished runs as above. The workers share the parent's lock
 * and die with the parent (ps_signals_worker); the parent passes a
 * SIGINT/SIGTERM on to them as SIGTERM and waits for them. jobs <= 1 is
 * ps_griffith. Returns PS_OK, PS_ERR_SOLVER when a worker failed (its log
 * names the run) or a run is held by another process,
 * PS_ERR_INTERRUPTED, or a fatal status. */
int ps_griffith_jobs(ps_problem *pb, const char *out_dir, int resume, int jobs,
                     double *slope, double *intercept, double *r2, int *n_fractured,
                     ps_ctx *ctx);

/* Install the SIGINT/SIGTERM handlers of the command line: the first
 * signal sets a flag that the load path checks (ps_signal_received) to end
 * the run cleanly; a second one of the same kind ends the process at once
 * (the default action). Call once at the start of main. */
void ps_signals_install(void);
/* The first signal number received since ps_signals_install, 0 if none. */
int ps_signal_received(void);
/* "SIGINT", "SIGTERM" */
const char *ps_signal_name(int sig);
/* In a worker forked by the process `parent` (the sweep's jobs): the
 * worker is killed when its parent dies (PR_SET_PDEATHSIG, SIGKILL: a
 * parent killed outright cannot stop it any other way), and every SIGINT
 * or SIGTERM only sets the flag (the parent passes its signal on and
 * waits). Returns 0, or -1 when the parent is already gone. */
int ps_signals_worker(long parent);

#endif
