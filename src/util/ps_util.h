/* ps_util.h: status codes, the run context, error reporting, timers and
 * small memory helpers shared by every peristatic module. */
#ifndef PS_UTIL_H
#define PS_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* 64-bit index for particles, arms, dofs and nonzeros (SuiteSparse_long). */
typedef int64_t ps_int;

/* Status codes. Negative = fatal (climb to main), positive = recoverable
 * (the caller decides: cut the step, try another factorisation). */
enum ps_status {
  PS_OK = 0,
  PS_NOT_POSDEF = 1,  /* Cholesky met a non-positive pivot */
  PS_SINGULAR = 2,    /* the matrix is singular to working precision */
  PS_DIVERGED = 3,    /* a nonlinear iteration failed to converge */
  PS_ERR_NOMEM = -1,  /* out of memory */
  PS_ERR_INPUT = -2,  /* bad input: case file, parameter, point cloud */
  PS_ERR_IO = -3,     /* a file could not be read or written */
  PS_ERR_SOLVER = -4, /* the linear or nonlinear solver failed for good */
  PS_ERR_INTERNAL = -5, /* a bug: an invariant does not hold */
  PS_ERR_INTERRUPTED = -6 /* SIGINT or SIGTERM ended the run early */
};

/* The processes one run is spread over (MPI ranks; doc/design-distributed.md).
 * Every global quantity of a run (a norm, a dot product, an energy, a
 * count of arms, the boundary stress, the crack tip) is a sum, maximum or
 * minimum of each process's share, formed by these operations: each
 * replaces x[0..n) by the sum (maximum, minimum) over the processes of
 * their x[0..n), the same result on every process. A NULL comm is one
 * process: the operations are the identity, so a serial run's numbers do
 * not depend on the hook. The operations must be called by every process
 * of the run in the same order (collective), and must give every process
 * the same bits (Newton's and the line search's decisions follow them on
 * each process: MPI implementations whose reductions are not
 * reproducible across ranks need that setting, e.g. Intel MPI's
 * I_MPI_CBWR). */
typedef struct ps_comm {
  int rank, size; /* this process, the number of processes */
  void *data;     /* the implementation's (an MPI communicator) */
  void (*sum)(void *data, double *x, int n);
  void (*max)(void *data, double *x, int n);
  void (*min)(void *data, double *x, int n);
  /* personalised all-to-all: process q gets send[sdispl[q] .. +
   * scount[q]) bytes of each process into recv at rdispl of its own
   * (MPI_Alltoallv on bytes); the counts of [size] ints each. Used by the
   * halo below; NULL in a comm without one (then no halo). */
  void (*alltoallv)(void *data, const void *send, const int *scount, const int *sdispl,
                    void *recv, const int *rcount, const int *rdispl);
} ps_comm;

/* x[0..n) <- its sum (maximum, minimum) over the processes of comm (NULL:
 * unchanged). Counts go through ps_comm_sum as doubles (exact below 2^53). */
void ps_comm_sum(const ps_comm *comm, double *x, int n);
void ps_comm_max(const ps_comm *comm, double *x, int n);
void ps_comm_min(const ps_comm *comm, double *x, int n);
/* one value: the sum over the processes of x; a count; 1 when flag is
 * nonzero on any process (a decision every process must take alike) */
double ps_comm_sum1(const ps_comm *comm, double x);
int64_t ps_comm_count(const ps_comm *comm, int64_t n);
int ps_comm_any(const ps_comm *comm, int flag);
/* this process's rank (0 for NULL) */
static inline int ps_comm_rank(const ps_comm *comm) { return comm ? comm->rank : 0; }


/* The run context, passed last to every call that can fail: holds the last
 * error message, verbosity, the log stream and the processes of the run.
 * No global state. */
typedef struct ps_ctx {
  char msg[2048];   /* last error message, "" when none */
  int verbosity;    /* 0 quiet, 1 progress lines, 2 Newton detail */
  FILE *log;        /* progress stream (stderr by default) */
  const ps_comm *comm; /* the processes of a distributed run; NULL (the
                          default): one process holds the whole model */
} ps_ctx;

/* A halo (comm.c): how the values of a process's ghosts come from the
 * processes that own them. A process holds n_local items (particles),
 * the first n_owned its own, the rest ghosts, each with its global
 * number; owner[k] is the process owning ghost k (k = 0 .. n_local -
 * n_owned - 1). Built once (collective); each exchange then sends every
 * owned item's values to the processes holding it as a ghost. */
typedef struct ps_halo {
  int size;                 /* processes */
  int *scount, *sdispl;     /* [size] items sent to each process */
  int *rcount, *rdispl;     /* [size] items received from each */
  ps_int *send_item;        /* [sum scount] local owned items to send */
  ps_int *recv_item;        /* [sum rcount] local ghost items received */
  int *bcount, *bdispl, *ccount, *cdispl; /* [size] each: byte counts of
                               one exchange (width set at the last) */
  double *sbuf, *rbuf;      /* packing buffers */
  int width;                /* values per item of the buffers */
} ps_halo;
/* Build the halo of global numbers global[n_local] (owned first) with
 * owners owner[n_local - n_owned] (collective; every process's owned
 * numbers must include those the others ask for). A NULL comm, or one of
 * one process, needs no ghosts: n_local must equal n_owned. PS_OK,
 * PS_ERR_INPUT (a ghost asked of a process that does not own it, a
 * ghost on one process, a comm without alltoallv), PS_ERR_NOMEM. */
int ps_halo_create(ps_halo *h, const ps_comm *comm, ps_int n_local, ps_int n_owned,
                   const ps_int *global, const int *owner, ps_ctx *ctx);
/* x[n_local * width]: every ghost's width values from its owner
 * (collective). PS_OK or PS_ERR_NOMEM. */
int ps_halo_exchange(ps_halo *h, const ps_comm *comm, double *x, int width, ps_ctx *ctx);
void ps_halo_free(ps_halo *h);

/* Rows to the first process (to_all: to every process): every process's
 * n_mine rows of width doubles (mine); on process 0 (to_all: on every
 * process), *all (allocated here, the caller frees it) holds all of them
 * in the order of the processes and *n_all their number; elsewhere *all
 * = NULL and *n_all = 0. A NULL comm (one process): a copy. Collective.
 * PS_OK, PS_ERR_INPUT (more than 2^31 bytes), PS_ERR_NOMEM (here or on
 * another process: every process fails alike). */
int ps_comm_gather(const ps_comm *comm, const double *mine, ps_int n_mine, int width,
                   int to_all, double **all, ps_int *n_all, ps_ctx *ctx);

/* Initialise a context: empty message, verbosity 1, log = stderr, one
 * process (comm NULL). */
void ps_ctx_init(ps_ctx *ctx);

/* Record a formatted error message in ctx->msg; returns status unchanged so
 * callers can write `return ps_error(ctx, PS_ERR_INPUT, "...")`. */
int ps_error(ps_ctx *ctx, int status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Append "(at file:line)" to ctx->msg when ctx->verbosity >= 3; returns
 * status unchanged. Used by the PS_CHECK macros. */
int ps_trace(ps_ctx *ctx, int status, const char *file, int line);

/* Print a progress line to ctx->log when ctx->verbosity >= level. */
void ps_log(const ps_ctx *ctx, int level, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Return on a fatal (negative) status; positive statuses pass through to
 * the caller's own handling. Needs a `ps_ctx *ctx` in scope. */
#define PS_CHECK(call)                                                       \
  do {                                                                       \
    int ps_s_ = (call);                                                      \
    if (ps_s_ < 0) return ps_trace(ctx, ps_s_, __FILE__, __LINE__);          \
  } while (0)

/* Same, but jump to `cleanup` with `status` set (for functions that own
 * resources). Needs `int status` and a `cleanup:` label. */
#define PS_CHECK_GOTO(call)                                                  \
  do {                                                                       \
    status = (call);                                                         \
    if (status < 0) {                                                        \
      ps_trace(ctx, status, __FILE__, __LINE__);                             \
      goto cleanup;                                                          \
    }                                                                        \
  } while (0)

/* The one allocation function of peristatic: calloc that records
 * PS_ERR_NOMEM in ctx and returns NULL on failure (also when count * size
 * overflows size_t). Every allocation of ours goes through ps_calloc or
 * ps_realloc, so that the memory-failure test can make each one fail. */
void *ps_calloc(size_t count, size_t size, ps_ctx *ctx);
/* realloc with the same contract; on failure *p is left untouched.
 * Returns PS_OK or PS_ERR_NOMEM. */
int ps_realloc(void **p, size_t count, size_t size, ps_ctx *ctx);

/* Test hook (in the style of CSparse's Tcov malloc tests): after n more
 * successful allocations by ps_calloc/ps_realloc, every further one fails
 * as if the system had no memory. n < 0 (the default) switches it off.
 * Process-wide: for the memory-failure test program only. Returns the
 * number of allocations made since the previous call. */
long ps_alloc_countdown(long n);
/* The countdown for another library's allocator (the test's SuiteSparse
 * wrappers): counts one allocation; returns 1 when it must fail. */
int ps_alloc_countdown_fails(void);

/* Wall-clock seconds since an arbitrary origin (CLOCK_MONOTONIC). */
double ps_wtime(void);

/* Peak resident memory of this process in MiB (from getrusage). */
double ps_peak_mib(void);

/* Write a file atomically: open `path`.tmp for writing; commit renames it
 * over `path`, abort removes it. A failed run leaves old outputs intact. */
typedef struct ps_outfile {
  FILE *f;
  char path[1024];
  char tmp[1040];
} ps_outfile;
int ps_outfile_open(ps_outfile *o, const char *path, ps_ctx *ctx);
int ps_outfile_commit(ps_outfile *o, ps_ctx *ctx);
void ps_outfile_abort(ps_outfile *o);

/* FNV-1a (64 bit): *h takes the n bytes of data in turn; a hash starts at
 * PS_FNV_START. The case fingerprint and the checkpoint's checksum. */
#define PS_FNV_START 1469598103934665603ULL
void ps_fnv1a(uint64_t *h, const void *data, size_t n);

/* A layer's state for a checkpoint (src/io/checkpoint.c): a list of named
 * items, each the address and size in bytes of an array or scalar the
 * layer owns. A layer lists its items (e.g. ps_solver_state_list); the
 * checkpoint writes their bytes and, into the items of a freshly created
 * layer of the same sizes, reads them back. Names are at most
 * PS_STATE_NAME - 1 characters. */
#define PS_STATE_NAME 40
typedef struct ps_state_item {
  char name[PS_STATE_NAME];
  void *data;
  size_t bytes;
} ps_state_item;
typedef struct ps_state_list {
  ps_state_item *item;
  int n, cap;
} ps_state_list;
/* Append an item (data may be NULL only when bytes is 0). Returns PS_OK,
 * PS_ERR_NOMEM, or PS_ERR_INTERNAL for a name too long or used twice. */
int ps_state_add(ps_state_list *l, const char *name, void *data, size_t bytes, ps_ctx *ctx);
void ps_state_list_free(ps_state_list *l);

/* Output folders (outdir.c). peristatic replaces or removes only a folder
 * it wrote itself: one holding its marker file PS_OUTDIR_MARKER (written
 * into every output folder it creates), or, for folders of earlier
 * versions, one whose summary.txt starts "case: ", whose history.csv
 * starts "step,load_factor," or whose griffith.csv starts "delta_over_c,",
 * or an empty folder; and which holds nothing but names peristatic writes
 * (the marker, summary.txt, history.csv, particles.csv, particles_N.vtu,
 * arms_N.vtu, particles.pvd, arms.pvd, particles_N.vtk and arms_N.vtk of
 * earlier versions, griffith.csv/.gp/.png, path.gp/.png,
 * checkpoint.bin, and a distributed run's particles_N_pR.vtu,
 * arms_N_pR.vtu, particles_N.pvtu, arms_N.pvtu and checkpoint_pR.bin,
 * griffith_fit.txt, job-N.log, any of
 * these + ".tmp", and a sweep's delta_cN folders, with .partial or .old,
 * holding such files, and delta_cN.claim). Anything else (another folder,
 * a file, a symbolic link, a folder of ours holding a file of someone
 * else's) is refused, never moved or deleted. */
#define PS_OUTDIR_MARKER ".peristatic"
/* The longest output folder name the command line takes: room for what
 * peristatic writes inside it, up to a sweep's
 * DIR.partial/delta_cNNNN.partial/particles_NNNN.vtu.tmp, within the
 * 1024 characters of a ps_outfile path. */
#define PS_OUTDIR_MAX 900

/* What is at path: 0 nothing, 1 a folder of ours (rule above), -1
 * anything else, described in why (e.g. "is a file, not a folder", or
 * "holds files peristatic did not write (a, b, c, ...)"). */
int ps_outdir_owned(const char *path, char *why, size_t len);
/* The step of a field file of an output folder: particles_NNNN.vtu,
 * arms_NNNN.vtu, a distributed run's pieces particles_NNNN_pR.vtu and
 * arms_NNNN_pR.vtu and the particles_NNNN.pvtu and arms_NNNN.pvtu that
 * join them; -1 for any other name. With listed, *listed = 1 for the
 * files the .pvd series list (.vtu of one process, .pvtu of several), 0
 * for the pieces. */
long ps_outdir_field_step(const char *name, int *listed);
/* Make the output folder dir ready for a writer (the caller holds its
 * lock): when dir is missing, or an empty folder, and dir.old (ours)
 * holds the previous results, a kill hit the commit's rename window:
 * restore dir.old to dir and say so on ctx->log; otherwise remove a
 * leftover dir.old when dir exists.
 * Refuses (PS_ERR_IO, naming the path and what to do) when dir, dir.old or
 * dir.partial is there and not ours. PS_OK, PS_ERR_IO. */
int ps_outdir_prepare(const char *dir, ps_ctx *ctx);
/* An empty folder at path with our marker: a folder of ours there is
 * removed first, anything else refused; parents are created. PS_OK or
 * PS_ERR_IO. */
int ps_outdir_fresh(const char *path, ps_ctx *ctx);
/* The folder dir, created with our marker when missing (a folder of ours
 * there is kept as it is; anything else refused). PS_OK or PS_ERR_IO. */
int ps_outdir_open(const char *dir, ps_ctx *ctx);
/* Replace the folder `final` by `staging`. When final is there (ours:
 * checked again here), the two are exchanged atomically (renameat2
 * RENAME_EXCHANGE), so final is never missing, and the earlier tree is
 * moved to final.old and removed; on a file system without the exchange,
 * final is moved to final.old and staging renamed to final (a kill -9
 * between the two is repaired by ps_outdir_prepare). Missing final: one
 * rename. SIGINT and SIGTERM are blocked in this thread meanwhile. A
 * failure to remove the earlier tree is a warning on ctx->log. PS_OK or
 * PS_ERR_IO (final untouched). */
int ps_dir_commit(const char *staging, const char *final, ps_ctx *ctx);

/* The writer's lock of an output folder: flock(LOCK_EX | LOCK_NB) on
 * dir.lock beside it (created, with its parents, when missing; it holds
 * "peristatic lock: pid N"). Forked children share the lock (the sweep's
 * workers); the holder removes dir.lock when it lets go. */
typedef struct ps_outdir_lock {
  int fd;          /* -1: not held */
  long pid;        /* the process that took it (the one that removes it) */
  char path[1100]; /* dir.lock */
} ps_outdir_lock;
/* Take the lock; PS_OK, or PS_ERR_IO when another process holds it ("DIR
 * is being written by another peristatic process (pid N)") or when
 * dir.lock is not a peristatic lock file (left untouched). */
int ps_outdir_lock_take(ps_outdir_lock *lk, const char *dir, ps_ctx *ctx);
/* Release it (remove dir.lock when this process took it); a lock with
 * fd -1 is a no-op. */
void ps_outdir_lock_release(ps_outdir_lock *lk);

/* Create directory `path` and its parents (mkdir -p). PS_OK or PS_ERR_IO. */
int ps_mkdir_p(const char *path, ps_ctx *ctx);
/* Remove a directory tree (rm -rf) without following symbolic links or
 * entering another file system mounted inside it; the
 * marker PS_OUTDIR_MARKER of the top folder goes last, so a folder whose
 * removal is interrupted is still ours. PS_OK or PS_ERR_IO. Callers check
 * ownership first (ps_outdir_owned). */
int ps_rm_rf(const char *path, ps_ctx *ctx);

/* A sparse symmetric matrix: the upper triangle (diagonal included) in
 * compressed sparse columns, row indices sorted within each column. */
typedef struct ps_csc {
  ps_int n;    /* order */
  ps_int *p;   /* [n + 1] column pointers */
  ps_int *i;   /* [p[n]] row indices */
  double *x;   /* [p[n]] values */
} ps_csc;

/* A team of threads for the parallel loops of one run (team.c). The
 * caller splits a job into n_parts parts, a number fixed by the data, not
 * by the team, and every part writes only its own outputs (sums across
 * parts are formed afterwards in a fixed order): results do not depend on
 * the number of threads. Part p runs on member p mod size; the calling
 * thread is member 0. A NULL team runs the parts in order on the caller.
 * Create a team only after any fork() (threads do not survive it). */
typedef struct ps_team ps_team;

/* The number of parts a parallel loop of a run is split into (the
 * assembly's shares of the arms and particles, the disjoint subtrees of
 * the preconditioner's triangular solves) is a setting of the run
 * (solver.parts, 1 .. PS_PARTS_MAX; ps_system.parts, ps_linsolve.parts),
 * not of the machine: every sum is formed in the order the parts fix, so
 * a run gives the same numbers on any number of threads, and other
 * numbers (within round-off) with another number of parts. More threads
 * than parts would idle: the solver makes a team of at most `parts`
 * members. PS_PARTS_DEFAULT, the parts of every run before the count
 * became a setting, keeps their results. */
#define PS_PARTS_DEFAULT 2
#define PS_PARTS_MAX 64

/* [*lo, *hi): part `part`'s share of n items in `parts` parts */
static inline void ps_part_range(ps_int n, int part, int parts, ps_int *lo, ps_int *hi) {
  *lo = n * part / parts;
  *hi = n * (part + 1) / parts;
}

/* *team = a team of n_threads members (NULL when n_threads <= 1; fewer
 * members if the system refuses threads). PS_OK or PS_ERR_NOMEM. */
int ps_team_create(ps_team **team, int n_threads, ps_ctx *ctx);
void ps_team_free(ps_team *team);
/* the number of members (1 for NULL) */
int ps_team_size(const ps_team *team);
/* fn(arg, p) for p = 0 .. n_parts - 1; returns when all have run. */
void ps_team_run(ps_team *team, int n_parts, void (*fn)(void *arg, int part), void *arg);

/* The number of CPUs this process may run on (sched_getaffinity; >= 1). */
int ps_cpu_count(void);

/* force inlining (GCC, Clang), so that a dimension passed as a constant
 * unrolls the inner loops */
#if defined(__GNUC__)
#define PS_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define PS_ALWAYS_INLINE inline
#endif

/* Cholesky factor L (A = L L^T) of the m x m symmetric matrix A
 * (row-major; its lower triangle is read and overwritten by L, the
 * upper left as it was). Returns 1, or 0 when a pivot is not above tol
 * times A's largest diagonal entry (tol 0: not positive). For the small
 * dense blocks of a particle or a family (at most a few dozen rows). */
int ps_dense_cholesky(int m, double *A, double tol);

/* x = A^-1 x with the factor L of ps_dense_cholesky */
void ps_dense_cholesky_solve(int m, const double *L, double *x);

/* c = a x b (3-vectors; c must not alias a or b) */
static inline void ps_cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

#endif
