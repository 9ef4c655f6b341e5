/* ps_report.h: the files a run writes, in one place: summary.txt (the
 * run's record, ps_run_result, as "key: value" lines), history.csv (one
 * row per increment), particles.csv and the VTK files of a state (.vtu
 * grids and the .pvd time series that lists them), and
 * the reading back of summary.txt and history.csv (griffith --resume).
 * The keys of summary.txt and the columns of history.csv are each
 * defined once, in a table in report.c that both the writer and the
 * reader walk. Numbers that are not finite are written as n/a. */
#ifndef PS_REPORT_H
#define PS_REPORT_H

#include "../post/ps_post.h"
#include "../nonlinear/ps_solver_stats.h"
#include "ps_io.h"

/* Outcome of one run along the load path: what summary.txt holds. */
typedef struct ps_run_result {
  /* what was run */
  char case_name[128];
  ps_int particles, arms;
  double delta;             /* elongation limit, m (inf: no breaking) */
  double sigma_y;           /* E eps_y, Pa */
  uint64_t fingerprint;     /* ps_case_fingerprint of the case */
  /* the path */
  double sigma_peak;        /* peak boundary stress, Pa: sigma_failure */
  double lambda_peak;       /* load factor at the peak */
  int fractured;            /* 1: the crack ran (tip or load-drop stop) */
  int stalled;              /* 1: the solve failed before the crack ran
                               (fractured = 0): Newton below path.min_step,
                               or a re-equilibration that failed without
                               the load falling below its peak */
  int interrupted;          /* SIGINT or SIGTERM that ended the run before
                               its end, 0 if none */
  char stop_reason[160];
  ps_int increments, step_cuts;
  ps_int gentle_rounds;     /* breaking rounds retried with fewer arms */
  ps_int arms_broken;
  double crack_tip;         /* of the last converged state, in units of c
                               (disk) */
  /* the cost */
  ps_solver_stats solver;   /* ps_solver_get_stats at the end of the run */
  double wall;              /* wall seconds of the run */
  double t_network;         /* wall seconds of geometry + network */
  int processes;            /* MPI processes of the run (1: one) */
  int distributed;          /* 1: each process held its share of the model
                               (solver.layout), 0: the whole model */
  double peak_memory_mib;   /* ps_peak_mib when the summary was written */
} ps_run_result;

/* v with `digits` significant digits ("%.*g") in buf, or "n/a" when v is
 * not finite (no nan or inf in outputs); returns buf. */
const char *ps_fmt_or_na(double v, int digits, char *buf, size_t len);

/* A state to write or to take the J-integral of: read-only views. */
/* A process's piece of a distributed state (doc/design-distributed.md):
 * its particles (the first n_owned of the state's P are its own, the
 * rest ghosts) and its arms. */
typedef struct ps_report_piece {
  const ps_comm *comm;          /* the run's processes (the writes are
                                   collective) */
  ps_int n_owned;
  const ps_int *global;         /* [P.n] each particle's number in the
                                   whole model */
  const unsigned char *own_arm; /* [net.n_arm] 1: the process's own arm */
} ps_report_piece;

typedef struct ps_report_state {
  const ps_particles *P;
  const ps_network *net;
  const ps_material *mat;   /* with the run's delta */
  const double *u;          /* [n_dof] displacements, m */
  const double *T, *q, *dl; /* arm tensions, unit directions, elongations */
  const ps_arm_state *st;   /* yielding, broken, plastic strains */
  double lambda;            /* the load factor */
  const ps_report_piece *piece; /* NULL: the whole model; else P, net and
                               the arrays above are a process's share */
} ps_report_state;

/* dir/summary.txt from res (through FILE.tmp, renamed): every key of the
 * table in order, then, when cs has output.j_integral rings and the case
 * is 2D, J of `state` per ring (Eq. 39 and Eq. 36, also logged). Of a
 * piece of a distributed state (state->piece) every process calls it
 * (J's sums are collective) and the first writes the file. Returns
 * PS_OK, PS_ERR_IO, PS_ERR_NOMEM. */
int ps_report_write_summary(const char *dir, const ps_run_result *res, const ps_case *cs,
                            const ps_report_state *state, ps_ctx *ctx);

/* Read dir/summary.txt into *res: the keys of the table (the first line
 * of each; unknown keys are skipped). Absent keys leave numbers NAN
 * (-1 for counts), flags 0, strings "" and the fingerprint 0; "n/a"
 * reads as NAN. Returns 0, or -1 when the file cannot be read. */
int ps_report_read_summary(const char *dir, ps_run_result *res);

/* One row of history.csv. */
typedef struct ps_history_row {
  ps_int step;
  double load_factor;
  double boundary_stress;     /* Pa */
  double stress_over_sigma_y;
  ps_int newton_iterations;
  double relative_residual;
  ps_int converged;           /* 1, or 0 for a final failed re-equilibration */
  ps_int arms_yielding, arms_broken;
  double crack_tip;           /* c */
  double wall;                /* s since the start of the run */
  double reaction;            /* boundary stress x the measured length: the
                                 force on the measured particles, N per m of
                                 thickness in 2D, N in 3D */
  double displacement;        /* the measured particles' prescribed
                                 displacement along their direction, m (NAN:
                                 none prescribed) */
  double broken_energy;       /* J (per m of thickness in 2D): the stored
                                 energy of the broken arms when they broke
                                 (NAN: the model's energy does not split
                                 into arms) */
  double stored_energy;       /* J (per m of thickness in 2D): the energy
                                 stored in the arms (ps_solver_stored_energy) */
  double dissipated_energy;   /* J (per m of thickness in 2D): the energy
                                 the arms dissipated (softening, measured
                                 by the model; ps_solver_dissipated), 0
                                 for a model that measures none */
  const double *reactions;    /* [n_reactions * dim]: per named
                                 loading.boundary entry, the reaction
                                 components summed over its particles, N
                                 per m of thickness in 2D, N in 3D (after
                                 the table's columns; NULL when none) */
} ps_history_row;

/* history.csv, written a row at a time (flushed, so tail -f follows). */
typedef struct ps_report_history {
  FILE *f;                    /* NULL: not open, rows are dropped */
  char dir[1300];
  int n_reactions, dim;       /* the reaction columns after the table's */
} ps_report_history;

/* history.csv's header line (newline included): the table's columns,
 * then reaction_<name>_x, _y (, _z in 3D) for each of the n_reactions
 * names, into buf[len] as snprintf would (buf may be NULL with len 0);
 * returns its length. */
size_t ps_report_history_header(char *buf, size_t len, const char *const *reaction_names,
                                int n_reactions, int dim);
/* Create dir/history.csv with its header (ps_report_history_header).
 * Returns PS_OK, PS_ERR_IO or PS_ERR_NOMEM. */
int ps_report_history_open(ps_report_history *h, const char *dir,
                           const char *const *reaction_names, int n_reactions, int dim,
                           ps_ctx *ctx);
void ps_report_history_row(ps_report_history *h, const ps_history_row *row);
/* Close it (nothing when not open). Returns PS_OK, or PS_ERR_IO when a
 * write failed. */
int ps_report_history_close(ps_report_history *h, ps_ctx *ctx);

/* path.gp in dir: a gnuplot script that plots history.csv into path.png
 * (the reaction against displacement_m when with_displacement,
 * else boundary stress / sigma_y and load factor against the increment);
 * name is the case's, in the title. Returns PS_OK or an I/O status. */
int ps_report_write_path_plot(const char *dir, const char *name, int with_displacement,
                              ps_ctx *ctx);

/* name as the inside of a single-quoted gnuplot string into buf (a quote
 * doubled, a control character as '?'); returns buf. */
const char *ps_gnuplot_quoted(const char *name, char *buf, size_t len);

/* Run gnuplot on script in dir (a child changes into dir and executes
 * PS_GNUPLOT with an argument vector, no shell). Returns 0 when gnuplot
 * ran and succeeded, -1 otherwise (none found at configure time too). */
int ps_gnuplot_run(const char *dir, const char *script);

/* Did the run in dir end on an unconverged state (the last row of
 * history.csv has converged = 0)? Then *sigma = its boundary stress, Pa. */
int ps_report_last_attempt_failed(const char *dir, double *sigma);

/* The field files of a run so far: the steps written, in order (what
 * particles.pvd and arms.pvd list). Start it zeroed; free it with
 * ps_report_series_free. */
typedef struct ps_report_series {
  int *step;
  int n, cap;
  int pvtu;   /* 1: the steps' files are .pvtu (a distributed run's) */
} ps_report_series;
void ps_report_series_free(ps_report_series *series);
/* step (not below the series' last) joins the series of the field files
 * already in dir (those a restarted run keeps) and dir/particles.pvd and
 * dir/arms.pvd are rewritten. Returns PS_OK, PS_ERR_IO, PS_ERR_NOMEM or
 * PS_ERR_INTERNAL (a step below the last). */
int ps_report_series_add(const char *dir, ps_report_series *series, int step, ps_ctx *ctx);

/* dir/particles_NNNN.vtu and dir/arms_NNNN.vtu of the state (NNNN = step;
 * the same points and point fields, the arms as lines with their own
 * fields; the load factor and the step as the data set's FieldData); with
 * series (else NULL), step joins it (a step equal to its last one is that
 * entry, written again) and dir/particles.pvd and dir/arms.pvd are
 * rewritten to list every step of the series, time = the step; with
 * final != 0 also dir/particles.csv (doc/peristatic.md, OUTPUT FILES).
 * Each file is written atomically and the .pvd files after the .vtu
 * files, so an interrupted run's folder lists only files that exist.
 * A piece of a distributed state (state->piece; the call is then
 * collective, and a failure on one process fails all): every process
 * writes particles_NNNN_pR.vtu (its own particles) and arms_NNNN_pR.vtu
 * (its own arms, all its particles their ends' points) for its rank R,
 * the first process particles_NNNN.pvtu and arms_NNNN.pvtu, which make
 * them one data set, and the .pvd files listing those; particles.csv is
 * gathered to the first process and written in the whole model's
 * particle order, as a one-process run writes it.
 * Returns PS_OK, PS_ERR_IO, PS_ERR_NOMEM, PS_ERR_INTERNAL (a step below
 * the series' last). */
int ps_report_write_fields(const char *dir, int step, int final, const ps_report_state *state,
                           ps_report_series *series, ps_ctx *ctx);

#endif
