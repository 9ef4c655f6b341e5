/* ps_app.h: what the command line does, as a library: set a problem up
 * from a case (geometry, sizes, network, material, boundary conditions),
 * run it along the load path with progress lines and outputs, and the
 * Griffith sweep over delta. Tests call these too. */
#ifndef PS_APP_H
#define PS_APP_H

#include "../io/ps_io.h"
#include "../io/ps_report.h"
#include "../nonlinear/ps_solver.h"
#include "../path/ps_path.h"
#include "../post/ps_post.h"

typedef struct ps_problem {
  ps_case cs;             /* the case: pb's own copy (ps_case_copy, freed
                             by ps_problem_free); its option structs go
                             to the layers as they are (cs.solver,
                             cs.path) */
  ps_particles P;
  ps_kernel kernel;
  ps_network net;
  ps_crack *cracks;       /* [n_cracks] what keeps arms from crossing: the
                             case's cracks, the disk's and the holes' sides
                             (a share's network needs them again) */
  int n_cracks;
  ps_material mat;        /* finished; delta resolved (inf: no breaking) */
  double c;               /* disk: half crack length (m); 0 otherwise */
  unsigned char *fixed;   /* [n_dof] prescribed dofs */
  double *ubar;           /* [n_dof] prescribed displacement at lambda 1 */
  double *measure;        /* [n_dof] boundary-stress weights (normals) */
  double *fext;           /* [n_dof] forces at lambda 1 from tractions (N,
                             per unit thickness in 2D), or NULL if none */
  double measure_length;  /* m (2D) or m^2 (3D) */
  int n_groups;           /* named loading.boundary entries: their
                             reactions go to history.csv */
  int *group_bc;          /* [n_groups] each one's index in cs.bc */
  ps_int *group_ptr;      /* [n_groups + 1] group g's particles are
                             group_particle[group_ptr[g] .. group_ptr[g+1]) */
  ps_int *group_particle; /* the particles each named entry selects */
  double t_network;       /* wall seconds of geometry + network */
  int threads;            /* threads per run (ps_solver_opts.threads; 0:
                             the CPUs this process may use, shared among
                             griffith's jobs) */
  int checkpoint;         /* 1: ps_run writes checkpoint.bin into its
                             output (output.checkpoint_every, doc/
                             peristatic.md RESTART); 0 (ps_problem_setup's
                             default, the sweep's runs): none */
  const char *restart;    /* a folder whose checkpoint ps_run continues
                             from (run --restart; NULL: from the start) */
  const ps_comm *comm;    /* NULL (set-up's default): ps_run holds the
                             whole model; else the processes of a
                             distributed run (net then empty:
                             ps_problem_setup_cloud), and ps_run runs this
                             process's part (ps_problem_part) */
} ps_problem;

/* Can the set-up problem pb run as a distributed model on `ranks` MPI
 * processes? Today that needs solver.linear petsc and at least a
 * particle per process. Returns 1, or 0 with the first reason it
 * cannot in why[len] (for the progress line or the error of a case that
 * asks for solver.layout: distributed). */
int ps_problem_distributable(const ps_problem *pb, int ranks, char *why, size_t len);

/* A process's part of a distributed problem: the partition (space-filling
 * curve, ps_partition_curve), its share (ps_problem_share), the rows of
 * the whole system of its dofs, and `local`, the share as a problem:
 * pb's case, material and measure lengths, the share's particles and
 * network (borrowed from sh), its fixed, ubar and measure (own and
 * ghost particles), its forces (own particles only: each applied once),
 * and its named groups' own particles. */
typedef struct ps_problem_part {
  ps_partition pt;
  ps_share sh;
  ps_int *rows, row0;           /* ps_share_global_rows */
  int *owner;                   /* [sh.P.n] the process of each particle */
  ps_problem local;
  ps_solver_share solver_share; /* for ps_solver_create_share */
  ps_report_piece piece;        /* for the field files */
  ps_int arms;                  /* the whole model's arms (the sum of the
                                   processes' own) */
  double *given_k, *given_side; /* the whole model's constants for the
                                   share's arms (ps_model_whole_constants;
                                   NULL: none) */
  ps_model_given given;         /* them, for solver_share */
} ps_problem_part;

/* This process's part of pb (set up by ps_problem_setup_cloud) on the
 * processes of comm. Collective: a failure on one process fails all.
 * Returns PS_OK, PS_ERR_INPUT (ps_problem_share's, or another process
 * failed), PS_ERR_NOMEM (*pa then empty). */
int ps_problem_part_create(ps_problem_part *pa, const ps_problem *pb, const ps_comm *comm,
                           ps_ctx *ctx);
void ps_problem_part_free(ps_problem_part *pa);

/* The share of part `part` of pt (ps_share, doc/design-distributed.md)
 * of the set-up problem pb: ghosts out to ps_model_share_horizons of
 * its model (at least two with output.j_integral), the network with pb's
 * kernel and cracks. PS_OK, PS_ERR_INPUT (the network's), PS_ERR_NOMEM. */
int ps_problem_share(const ps_problem *pb, const ps_partition *pt, int part, ps_share *sh,
                     ps_ctx *ctx);

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
/* ps_problem_setup_sized in two halves: everything but the network
 * (pb->net empty: a distributed run builds only its share's), then the
 * network of pb's particles, kernel and cracks. ps_problem_setup_cloud
 * returns as ps_problem_setup_sized (pb freed on failure);
 * ps_problem_setup_network PS_OK or the network's errors, naming the case
 * file (pb is then the caller's to free). */
int ps_problem_setup_cloud(ps_problem *pb, const ps_case *cs, int purpose, int jobs,
                           FILE *report, ps_ctx *ctx);
int ps_problem_setup_network(ps_problem *pb, ps_ctx *ctx);
void ps_problem_free(ps_problem *pb);

/* ps_run's status for a run whose solve stalled before the crack ran
 * (res->stalled = 1: Newton below path.min_step, or a re-equilibration
 * that failed with the load not below its peak). Positive: the run ended
 * as a result, and the caller decides whether it is an error. ctx->msg
 * says what was seen and what can help; the outputs, summary.txt
 * included, are complete but left in out_dir.partial: ps_run_commit
 * keeps them as the result (the sweep's "stalled" rows),
 * ps_run_stalled_error makes the stall the error `peristatic run`
 * reports (exit 2). */
#define PS_RUN_STALLED PS_DIVERGED

/* Run the case's load path (src/path) with elongation limit delta (m;
 * inf: no breaking), the solver's options pb->cs.solver with pb->threads,
 * the path's pb->cs.path, the outputs' pb->cs.output; the record of the run in *res (ps_run_result,
 * src/io/ps_report.h). When out_dir is not NULL, first takes out_dir's
 * lock (ps_outdir_lock_take: another writer is refused) and checks the
 * folders (ps_outdir_prepare: only a folder of ours is replaced), then
 * writes through out_dir.partial, renamed to out_dir at the end so a
 * failed run leaves earlier results intact: history.csv, particles.csv,
 * summary.txt and VTK files (particles_NNNN.vtu, arms_NNNN.vtu and their
 * time series particles.pvd, arms.pvd); non-finite
 * numbers are written as n/a. SIGINT or SIGTERM (ps_signal_received) ends
 * the run after the increment or breaking round under way: the outputs so
 * far stay in out_dir.partial and the status is PS_ERR_INTERRUPTED (one
 * received by the time the solver is created: nothing is written).
 * Returns PS_OK, PS_RUN_STALLED (above), or a fatal status (e.g.
 * PS_ERR_SOLVER when arms still break after path.max_break_rounds). */
int ps_run(ps_problem *pb, double delta, const char *out_dir,
           ps_run_result *res, ps_ctx *ctx);

/* With pb->checkpoint, ps_run writes out_dir.partial/checkpoint.bin
 * (src/io/ps_checkpoint.h) every cs.output.checkpoint_every increments
 * and when the path ends where it can go on from (ps_path.resumable: at
 * its end or at an interruption between increments). With pb->restart =
 * DIR it continues from DIR.partial/checkpoint.bin when there is one
 * (an interrupted or stalled run), else from DIR/checkpoint.bin (one
 * that completed): the checkpoint must be of this case
 * (ps_checkpoint_check: algorithm version, ps_case_restart_fingerprint,
 * delta, sizes; else PS_ERR_INPUT before any folder is changed); the
 * first k rows of that folder's history.csv (k = the checkpoint's
 * increment) and its VTK files of steps up to k are kept, the rest is
 * dropped, and the run goes on as the uninterrupted run would have:
 * history.csv and particles.csv are the same to the last bit (but the
 * wall column). A distributed run (pb->comm) writes and reads one
 * checkpoint per process (checkpoint_pR.bin: its share's state), to be
 * restarted on as many processes. */

/* ps_run without the lock, for a caller whose lock covers out_dir (the
 * sweep's runs, in folders inside the sweep's). */
int ps_run_unlocked(ps_problem *pb, double delta, const char *out_dir,
                    ps_run_result *res, ps_ctx *ctx);

/* ps_run that keeps the run's solver alive for inspection (tests): when
 * keep != NULL and the status is not fatal, *keep is the solver at the end
 * of the run (the caller frees it with ps_solver_free), else NULL. */
int ps_run_keep(ps_problem *pb, double delta, const char *out_dir,
                ps_run_result *res, ps_solver **keep, ps_ctx *ctx);

/* After PS_RUN_STALLED: the error PS_ERR_SOLVER with ctx->msg's stall
 * message and, when out_dir is not NULL, where the outputs are (out_dir
 * untouched, the partial output in out_dir.partial). */
int ps_run_stalled_error(const char *out_dir, ps_ctx *ctx);

/* After PS_RUN_STALLED: keep the run as a result, its outputs renamed from
 * out_dir.partial to out_dir (ps_dir_commit; the caller holds out_dir's
 * lock). Returns PS_OK or a fatal status of ps_dir_commit. */
int ps_run_commit(const char *out_dir, ps_ctx *ctx);

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
 * continued. A run that stalls (PS_RUN_STALLED) after a settled peak is
 * kept as a row marked stalled (ps_run_commit), one that stalls before
 * any peak ends the sweep with ps_run_stalled_error's message.
 * SIGINT/SIGTERM end the run under way as in ps_run and the sweep with
 * PS_ERR_INTERRUPTED. Returns PS_OK or a fatal status; fit
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
 * ps_griffith. Claims left in the folder (delta_cNNNN.claim) are removed
 * before the workers start: the sweep holds the lock, so they are stale.
 * Returns PS_OK, PS_ERR_SOLVER when a worker failed (its log names the
 * run), PS_ERR_IO when a run is still claimed by another process,
 * PS_ERR_INTERRUPTED, or a fatal status. */
int ps_griffith_jobs(ps_problem *pb, const char *out_dir, int resume, int jobs,
                     double *slope, double *intercept, double *r2, int *n_fractured,
                     ps_ctx *ctx);

/* Install the SIGINT/SIGTERM handlers of the command line: the first
 * signal sets a flag that the load path checks (ps_signal_received) to end
 * the run cleanly; a second one of the same kind ends the process at once
 * (the default action). main calls it once, for run and griffith only
 * (info takes the default action: it ends at once). */
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
