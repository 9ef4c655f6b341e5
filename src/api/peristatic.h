/* peristatic.h: the public interface of libperistatic, an implicit,
 * sparse-direct Newton solver for static peridynamic problems.
 *
 * One opaque handle holds a case (read from a YAML case file or text, see
 * doc/peristatic.md for the format), optionally particles given as arrays,
 * the problem built from them (particles, arm network, material, supports)
 * and the state of its last run. Typical use:
 *
 *     peristatic *ps = peristatic_new();
 *     if (peristatic_load_file(ps, "case.yaml") < 0 ||
 *         peristatic_run(ps, "out/case") < 0)
 *       fprintf(stderr, "%s\n", peristatic_error(ps));
 *     double sigma_f;
 *     peristatic_get_result(ps, "sigma_failure", &sigma_f);
 *     peristatic_free(ps);
 *
 * Status codes: PERISTATIC_OK (0); positive values are results the caller
 * may accept (PERISTATIC_STALLED); negative values are errors, with a
 * message from peristatic_error. Units are SI throughout (m, Pa, N; in 2D
 * forces and energies per metre of thickness). The library keeps no global
 * state except the flag set by the signal handlers that
 * peristatic_install_signal_handlers installs (and, in a build with
 * PETSc, MPI's and PETSc's own, once peristatic_parallel_init or a run
 * with solver.linear: petsc starts them). Handles are not shared
 * between threads; distinct handles may be used from distinct threads.
 *
 * Interface version PERISTATIC_API_VERSION; the shared library's soname
 * changes when a function here changes incompatibly. */
#ifndef PERISTATIC_H
#define PERISTATIC_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PERISTATIC_API_VERSION 1

/* The largest memory limit peristatic_set_max_memory takes, GiB. */
#define PERISTATIC_MAX_MEMORY_GIB 1e6

/* Status codes (the values of the library's internal codes). */
enum peristatic_status {
  PERISTATIC_OK = 0,
  PERISTATIC_STALLED = 3,      /* the run's solve stalled before the crack
                                  ran; its outputs are complete in
                                  OUT_DIR.partial (peristatic_run) */
  PERISTATIC_ERR_NOMEM = -1,   /* out of memory */
  PERISTATIC_ERR_INPUT = -2,   /* bad input: case, parameter, particles */
  PERISTATIC_ERR_IO = -3,      /* a file could not be read or written */
  PERISTATIC_ERR_SOLVER = -4,  /* the linear or nonlinear solver failed */
  PERISTATIC_ERR_INTERNAL = -5,/* a bug: please report it */
  PERISTATIC_ERR_INTERRUPTED = -6, /* SIGINT/SIGTERM ended the run */
  PERISTATIC_ERR_USAGE = -7    /* functions called in the wrong order or
                                  with invalid arguments */
};

/* What peristatic_setup prepares the problem for (the size estimate and
 * the memory limit it is checked against differ). */
enum peristatic_purpose {
  PERISTATIC_FOR_RUN = 0,  /* run or griffith: refuse a case whose
                              estimated memory exceeds the limit */
  PERISTATIC_FOR_INFO = 1  /* info: refuse only what cannot be built */
};

typedef struct peristatic peristatic;

/* The library's version, "MAJOR.MINOR.PATCH". */
const char *peristatic_version(void);

/* A new, empty handle (verbosity 1: progress lines on stderr). Returns
 * NULL only when out of memory. */
peristatic *peristatic_new(void);

/* Free the handle and everything it holds; NULL is allowed. */
void peristatic_free(peristatic *ps);

/* The message of the last error on this handle ("" when none), naming the
 * file, line and key where one is known. Valid until the next call. */
const char *peristatic_error(const peristatic *ps);

/* For a program (not needed by a library user who sets these itself): GSL
 * reports errors by status instead of aborting, and OpenBLAS runs one
 * thread unless OPENBLAS_NUM_THREADS is set (doc/peristatic.md
 * ENVIRONMENT). Process-wide. */
void peristatic_init_process(void);

/* MPI and the PETSc backend (solver.linear: petsc; a library built with
 * configure --with-petsc). A program started by mpiexec calls
 * peristatic_parallel_init before its first run and
 * peristatic_parallel_finalize before it exits; then every rank runs the
 * same case, the linear algebra is shared among the ranks, and only rank
 * 0 writes outputs and progress lines (the other ranks' runs write
 * nothing). A serial run with solver.linear: petsc starts PETSc itself;
 * finalize is still needed then. Process-wide.
 * peristatic_parallel_init returns PERISTATIC_OK, or
 * PERISTATIC_ERR_INPUT (built without PETSc) or PERISTATIC_ERR_SOLVER
 * with the handle's message. The others cannot fail: launched is 1 when
 * an MPI launcher started this process (its environment says so); rank
 * and size are 0 and 1 before init and without PETSc; finalize does
 * nothing unless PETSc was started. */
int peristatic_parallel_init(peristatic *ps);
int peristatic_parallel_launched(void);
int peristatic_parallel_rank(void);
int peristatic_parallel_size(void);
void peristatic_parallel_finalize(void);

/* PETSc options for the runs of this handle, after the case's
 * solver.petsc_options (these win where both set one), e.g. "-ksp_type
 * cg -pc_type gamg" (NULL or "": none). Returns PERISTATIC_OK or
 * PERISTATIC_ERR_INPUT (longer than 1023 characters, or not options). */
int peristatic_set_petsc_options(peristatic *ps, const char *options);

/* Install SIGINT/SIGTERM handlers that make a run end after the increment
 * under way (status PERISTATIC_ERR_INTERRUPTED, outputs in
 * OUT_DIR.partial). Process-wide; optional. */
void peristatic_install_signal_handlers(void);

/* The exit status the peristatic program gives for a status: 0 for
 * PERISTATIC_OK, 1 bad input (and usage), 2 solver failure or out of
 * memory, 3 I/O, 128 + signal when interrupted. */
int peristatic_exit_status(int status);

/* Particles given by the caller: n particles in dim (2 or 3) dimensions,
 * reference positions x[a*dim + k] (m), volumes volume[a] (m^dim; in 2D an
 * area per metre of thickness) and optional block ids (NULL: all 0). The
 * arrays are copied. Call before peristatic_load_*: the case then needs no
 * geometry section (or `geometry: {type: cloud, dim: DIM}` with no file,
 * plus `cracks` if any), and its particles are these, treated as a point
 * cloud (doc/peristatic.md, geometry type cloud). Returns PERISTATIC_OK,
 * PERISTATIC_ERR_INPUT (dim, n < 1, a non-finite coordinate, a volume not
 * > 0, a negative block; the message names the particle),
 * PERISTATIC_ERR_NOMEM, or PERISTATIC_ERR_USAGE after a case was loaded. */
int peristatic_set_particles(peristatic *ps, int dim, long n, const double *x,
                             const double *volume, const int *block);

/* Read a case file (YAML). Relative paths inside it (geometry.file)
 * resolve against the file's folder. Replaces any case loaded before and
 * the problem built from it. Returns PERISTATIC_OK, PERISTATIC_ERR_INPUT
 * (the message names file, line and key), PERISTATIC_ERR_IO,
 * PERISTATIC_ERR_NOMEM. */
int peristatic_load_file(peristatic *ps, const char *path);

/* Read a case from text (YAML, at most 1 MiB). `name` stands for the file
 * in messages and is the case's default name; relative paths inside the
 * text resolve against the current folder. Returns as
 * peristatic_load_file. */
int peristatic_load_text(peristatic *ps, const char *yaml, const char *name);

/* Options of the handle, overriding the case's (call after loading):
 * verbosity 0 (quiet), 1 (progress lines), 2 (Newton iterations), 3 (also
 * source locations in errors) - the case's output.verbosity otherwise;
 * threads per run (0: the CPUs; at most the case's solver.parts are used;
 * results depend on solver.parts, not on the threads); the memory
 * limit in GiB checked before the network is built (0: the case's
 * solver.max_memory_gib, else 80% of the RAM; at most
 * PERISTATIC_MAX_MEMORY_GIB), `source` naming where it came from in
 * messages (NULL: "peristatic_set_max_memory"; the program passes
 * "--max-memory"; a string that must outlive the handle). Each returns PERISTATIC_OK,
 * PERISTATIC_ERR_INPUT for a value out of range, PERISTATIC_ERR_USAGE
 * when no case is loaded. */
int peristatic_set_verbosity(peristatic *ps, int verbosity);
int peristatic_set_threads(peristatic *ps, int threads);
int peristatic_set_max_memory(peristatic *ps, double gib, const char *source);

/* The next peristatic_run continues the run whose output folder is dir
 * from its checkpoint (dir.partial/checkpoint.bin when there is one, else
 * dir/checkpoint.bin; doc/peristatic.md RESTART) instead of starting
 * afresh; NULL: from the start again. dir is copied. A checkpoint of
 * another case, another algorithm version, or a damaged one makes that
 * run fail with PERISTATIC_ERR_INPUT before any folder is changed.
 * Returns PERISTATIC_OK, PERISTATIC_ERR_INPUT (dir too long). */
int peristatic_set_restart(peristatic *ps, const char *dir);

/* The case's name (case `name`, else the file name without .yaml); ""
 * when none is loaded. */
const char *peristatic_case_name(const peristatic *ps);

/* The output folder of a run into buf[len]: `given` when not NULL, else
 * the case's output.dir, else out/<case name>; trailing slashes removed.
 * Returns PERISTATIC_OK, PERISTATIC_ERR_INPUT when it names no folder of
 * its own ("/", ".", "..") or is too long for what a run writes inside it,
 * PERISTATIC_ERR_USAGE when no case is loaded. */
int peristatic_output_dir(const peristatic *ps, const char *given, char *buf, size_t len);

/* Build the problem: particles, the size estimate checked against the
 * memory limit for `purpose` with `jobs` runs at once (griffith -j), the
 * arm network, material and supports. `report`, when not NULL, receives
 * the estimate as "key: value" lines before anything large is built.
 * peristatic_run/griffith/info call it when it has not been called.
 * Returns PERISTATIC_OK, PERISTATIC_ERR_INPUT (including a case above the
 * memory limit, with the figures), PERISTATIC_ERR_IO, PERISTATIC_ERR_NOMEM,
 * PERISTATIC_ERR_INTERRUPTED (a signal during the set-up),
 * PERISTATIC_ERR_USAGE when no case is loaded. */
int peristatic_setup(peristatic *ps, int purpose, int jobs, FILE *report);

/* Print the sizes of the problem (set up for PERISTATIC_FOR_INFO if not
 * yet set up, the estimate then printed first) to `out` as "key: value"
 * lines: particles, arms, free dofs, the case fingerprint, the tangent's
 * nonzeros and memory (what `peristatic info` prints). Returns as
 * peristatic_setup. */
int peristatic_info(peristatic *ps, FILE *out);

/* Run the case along its load path with its own delta. out_dir NULL: no
 * files; else outputs are written to out_dir.partial and renamed to
 * out_dir when the run completes (a folder that is not peristatic's is
 * refused; doc/peristatic.md OUTPUT FILES), checkpoint.bin among them
 * (output.checkpoint_every; peristatic_set_restart continues from it). The final state stays in the
 * handle for the getters below. Returns PERISTATIC_OK, PERISTATIC_STALLED
 * (the solve stalled before the crack ran: a result with outputs in
 * out_dir.partial; peristatic_stalled_error makes it the error the
 * program reports), or an error. */
int peristatic_run(peristatic *ps, const char *out_dir);

/* After PERISTATIC_STALLED from peristatic_run: the error
 * PERISTATIC_ERR_SOLVER with the stall message (what was seen, what can
 * help, where the partial outputs are). */
int peristatic_stalled_error(peristatic *ps, const char *out_dir);

/* The Griffith sweep over the case's griffith.delta_over_c values
 * (doc/griffith.md) into out_dir with `jobs` worker processes; resume = 1
 * continues a sweep in out_dir. Results: peristatic_get_result's
 * "griffith_slope", "griffith_intercept", "griffith_r2",
 * "griffith_fractured". Returns PERISTATIC_OK or an error. */
int peristatic_griffith(peristatic *ps, const char *out_dir, int resume, int jobs);

/* Sizes of the problem (after set-up; 0 before). */
long peristatic_particle_count(const peristatic *ps);
int peristatic_dim(const peristatic *ps);

/* Per-particle arrays of the problem after set-up (positions: x[a*dim+k],
 * m; volumes, m^dim; blocks) or of the last run's final state
 * (displacements: u[a*dim+k], m; damage: the fraction of a particle's arms
 * broken, Eq. 119). `out` holds particle_count (times dim) values.
 * Returns PERISTATIC_OK or PERISTATIC_ERR_USAGE (not set up / not run). */
int peristatic_get_positions(const peristatic *ps, double *out);
int peristatic_get_volumes(const peristatic *ps, double *out);
int peristatic_get_displacements(const peristatic *ps, double *out);
int peristatic_get_damage(const peristatic *ps, double *out);

/* One number of the last run (or sweep) by name:
 *   sigma_failure (Pa, the peak boundary stress), lambda_peak,
 *   sigma_y (Pa), delta (m), fractured, stalled, interrupted (0/1 or the
 *   signal), increments, step_cuts, arms, arms_broken, crack_tip (units of
 *   c), newton_iterations, factorisations, solves, pcg_iterations,
 *   free_dofs, wall (s), peak_memory_mib;
 *   after a sweep: griffith_slope, griffith_intercept, griffith_r2,
 *   griffith_fractured.
 * Returns PERISTATIC_OK, PERISTATIC_ERR_INPUT for an unknown name (the
 * message lists the names), PERISTATIC_ERR_USAGE when nothing has run. */
int peristatic_get_result(const peristatic *ps, const char *name, double *value);

/* The reason the last run stopped ("" before a run). */
const char *peristatic_stop_reason(const peristatic *ps);

#ifdef __cplusplus
}
#endif
#endif
