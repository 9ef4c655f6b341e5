/* ps_linsolve.h: sparse linear solvers behind one table of operations.
 * Analyse once per pattern, factor per matrix, solve per right-hand side.
 * Backends: "cholmod" (supernodal LL^T, the default: the tangent is
 * symmetric and, in tension-driven runs, positive definite), "umfpack"
 * (unsymmetric LU with pivoting, for indefinite tangents) and, when built
 * with it, "petsc" (a KSP and PC of PETSc's chosen by its options, the
 * matrix distributed by rows over the MPI ranks: petsc.c). */
#ifndef PS_LINSOLVE_H
#define PS_LINSOLVE_H

#include "../util/ps_util.h"

typedef struct ps_linsolve_stats {
  double t_analyze, t_factor, t_solve; /* accumulated wall seconds */
  ps_int n_analyze, n_factor, n_solve;
  ps_int n_iterations;                 /* iterations of the backend's own
                                          iterative solves (PETSc's KSP;
                                          0 for a direct solve) */
  double nnz_factor;                   /* nnz(L) (+ nnz(U) for LU) */
  double flops_factor;                 /* of the last factorisation */
  double serial_share;                 /* of the work of a preconditioner
                                          solve, the share one thread does
                                          while the others wait (the top of
                                          the elimination tree; CHOLMOD,
                                          0 until the first solve) */
} ps_linsolve_stats;

/* default of ps_linsolve.single_after: preconditioner solves with a
 * factor in double before the backend's precondition takes over (making
 * CHOLMOD's single-precision copy is not worth it for fewer) */
#define PS_SINGLE_AFTER 16

struct ps_linsolve;
typedef struct ps_linsolve_type {
  const char *name;
  /* *state for the solver object ls (its address stays fixed; a backend
   * may keep it to read ls's settings when it analyses) */
  int (*create)(void **state, const struct ps_linsolve *ls, ps_ctx *ctx);
  /* symbolic analysis of A's pattern (upper triangle CSC). PS_OK or fatal */
  int (*analyze)(void *state, const ps_csc *A, ps_linsolve_stats *st,
                 ps_ctx *ctx);
  /* numeric factorisation with the analysed pattern. Returns PS_OK,
   * PS_NOT_POSDEF or PS_SINGULAR (recoverable; *bad_col = the failing
   * column, or -1 if unknown), or a fatal status. CHOLMOD calls a factor
   * singular when min L_jj^2 < 1e-13 max L_jj^2 (bad_col: the smallest
   * pivot's column), UMFPACK when its rcond estimate is below 1e-15. */
  int (*factor)(void *state, const ps_csc *A, ps_int *bad_col,
                ps_linsolve_stats *st, ps_ctx *ctx);
  /* x = A \ b with the last factor (x and b may not alias). */
  int (*solve)(void *state, const double *b, double *x, ps_linsolve_stats *st,
               ps_ctx *ctx);
  /* x ~= A \ b with the last factor for preconditioning: a symmetric
   * positive definite approximation cheaper than solve (CHOLMOD: the
   * factor in single precision, made on the first call after a
   * factorisation), in `parts` parts (1 .. PS_PARTS_MAX; the numbers
   * depend on them) on the team's threads (they do not depend on those).
   * NULL: solve is used. */
  int (*precondition)(void *state, const double *b, double *x, ps_team *team, int parts,
                      ps_linsolve_stats *st, ps_ctx *ctx);
  void (*destroy)(void **state);
  int precondition_always; /* 1: CG's preconditioner is always
                              precondition, never solve (PETSc: one
                              application of its PC, where solve is a
                              whole KSP solve) */
} ps_linsolve_type;

extern const ps_linsolve_type *const ps_linsolve_cholmod;
extern const ps_linsolve_type *const ps_linsolve_umfpack;
extern const ps_linsolve_type *const ps_linsolve_cholmod_simplicial;
/* simplicial LDL^T without pivoting, for symmetric indefinite matrices
 * (PS_SINGULAR on a zero or tiny pivot) */
extern const ps_linsolve_type *const ps_linsolve_cholmod_ldl;
/* PETSc (petsc.c): "factor" sets the matrix's rows of this rank and sets
 * up the KSP's preconditioner (a factorisation for -pc_type cholesky/lu,
 * MUMPS by default; an AMG hierarchy for gamg/hypre); "solve" is
 * KSPSolve, "precondition" one application of that preconditioner. b and
 * x are whole vectors on every rank (the same on each). In a build
 * without PETSc its create returns PS_ERR_INPUT saying so. */
extern const ps_linsolve_type *const ps_linsolve_petsc;

/* The MPI process layer of the PETSc backend (petsc.c). MPI and PETSc
 * are process-wide, so these are too; without PETSc the process is rank
 * 0 of 1. */
/* 1 when an MPI launcher (mpiexec) started this process (its environment) */
int ps_parallel_launched(void);
/* Initialise PETSc and MPI once, with PETSc options (NULL: none) as if
 * given on PetscInitialize's command line (later calls: PS_OK at once,
 * the options left to the backend). PS_OK, PS_ERR_SOLVER, or
 * PS_ERR_INPUT in a build without PETSc. */
int ps_parallel_init(const char *options, ps_ctx *ctx);
/* this process's rank and the number of ranks (0 and 1 before init) */
int ps_parallel_rank(void);
int ps_parallel_size(void);
/* *comm = the processes of the MPI launch (PETSC_COMM_WORLD) as a
 * ps_comm (ps_util.h), after ps_parallel_init. PS_OK, PS_ERR_INTERNAL
 * before init, PS_ERR_INPUT in a build without PETSc. */
int ps_parallel_comm(ps_comm *comm, ps_ctx *ctx);
/* PetscFinalize (and MPI's) if init ran; no-op otherwise */
void ps_parallel_finalize(void);

/* 1 when PETSc options select a factorisation as the PC (the last
 * -pc_type is cholesky or lu, or none is given: the backend's default
 * MUMPS Cholesky), 0 for an iterative one (gamg, hypre, icc, bjacobi,
 * ...). Reads the string only; in every build. */
int ps_petsc_options_factor(const char *options);

/* Look a backend up by name; NULL if unknown. */
const ps_linsolve_type *ps_linsolve_type_find(const char *name);

/* A solver object: a backend, its state and its statistics. */
typedef struct ps_linsolve {
  const ps_linsolve_type *type;
  void *state;
  int analysed;
  int reanalyze;            /* 1: symbolic analysis before every factor
                               (for comparison only; default 0) */
  int single_precision;     /* 1: ps_linsolve_precondition uses the
                               backend's precondition (default 0) */
  int single_after;         /* ... after this many solves with a factor
                               (default PS_SINGLE_AFTER) */
  int n_since_factor;       /* preconditioner solves with the last factor */
  ps_team *team;            /* threads precondition may use (not owned;
                               NULL: one; the results do not depend on it) */
  int parts;                /* the parts precondition splits its work into
                               (PS_PARTS_DEFAULT; 1 .. PS_PARTS_MAX): the
                               results depend on it */
  ps_linsolve_stats stats;
  int keep_matrix;          /* 1: ps_linsolve_factor keeps the matrix it
                               factors in `kept` (default 0) */
  int dim;                  /* the rigid-body modes of the unknowns, for
                               backends that build a multigrid (PETSc's
                               near-null space): unknown k is component
                               dof_of_free[k] % dim of particle
                               dof_of_free[k] / dim, at x[dim * particle]
                               (increasing; borrowed; dim 0: not given).
                               PETSc solves over all n_dof dofs, the
                               prescribed ones as rows of the identity */
  const ps_int *dof_of_free;
  const double *x;
  ps_int n_dof;             /* all dofs (dim x particles), 0: not given */
  /* A share of a distributed system (doc/design-distributed.md; PETSc
   * only): the n_dof dofs above are a process's share (owned particles,
   * then ghosts), global_row[n_dof] each one's row in the whole system of
   * n_global dofs, and this process's rows are [row0, row0 + n_rows), the
   * rows of its owned dofs. A's rows of owned free dofs are complete
   * (ghost columns included); its ghost rows are not used. The right-hand
   * side and the solution are the share's free dofs: b's owned entries
   * are read, x comes back at every free dof, ghosts included. NULL: the
   * whole system on every process. */
  const ps_int *global_row;
  ps_int n_global, row0, n_rows;
  double rtol;              /* the relative residual at which an
                               iterative backend's solve may stop (0:
                               its default; direct backends ignore it) */
  const char *options;      /* PETSc options for the backend ("-ksp_type
                               cg -pc_type gamg"; borrowed; NULL: none) */
  ps_csc kept;              /* that matrix (n = 0: none): a copy of its
                               values (x, owned) on the pattern of the
                               matrix factored (p, i borrowed: the caller
                               keeps that pattern alive and unchanged, as
                               the assembly's fixed patterns are); a
                               checkpoint stores it, and factoring it
                               again gives the same factor */
  size_t kept_cap;          /* entries allocated in kept.x */
} ps_linsolve;

/* Create / destroy. Returns PS_OK or a fatal status. */
int ps_linsolve_create(ps_linsolve *ls, const ps_linsolve_type *type,
                       ps_ctx *ctx);
void ps_linsolve_destroy(ps_linsolve *ls);
/* Factor A (analysing its pattern on first use; with ls->keep_matrix A
 * kept in ls->kept first, PS_ERR_NOMEM when it cannot be).
 * Statuses as ->factor. */
int ps_linsolve_factor(ps_linsolve *ls, const ps_csc *A, ps_int *bad_col,
                       ps_ctx *ctx);
/* ls->kept = A: its values copied, its pattern borrowed (ls->kept's
 * rule; made without factoring: for a factor made before keep_matrix was
 * set). Returns PS_OK or PS_ERR_NOMEM. */
int ps_linsolve_keep(ps_linsolve *ls, const ps_csc *A, ps_ctx *ctx);
/* x = A \ b with the last factor. */
int ps_linsolve_solve(ps_linsolve *ls, const double *b, double *x,
                      ps_ctx *ctx);
/* x ~= A \ b for CG: the backend's precondition when it says
 * precondition_always, or when ls->single_precision and ls->single_after
 * solves with the last factor were made; else ps_linsolve_solve.
 * Statuses as ->solve. */
int ps_linsolve_precondition(ps_linsolve *ls, const double *b, double *x, ps_ctx *ctx);

/* Columns c0 .. c1-1 of the full symmetric matrix whose upper triangle
 * is the CSC matrix A (rows sorted in each column): *Ap[c1 - c0 + 1],
 * *Ai (rows, sorted in each column) and *map (for each entry, the index
 * of its value in A->x), all allocated here; for a symmetric matrix
 * column j is also row j. Returns PS_OK or PS_ERR_NOMEM (nothing
 * allocated). */
int ps_csc_expand(const ps_csc *A, ps_int c0, ps_int c1, ps_int **Ap, ps_int **Ai,
                  ps_int **map, ps_ctx *ctx);

/* y = A x for a symmetric A stored as one triangle (upper or lower). */
void ps_csc_symv(const ps_csc *A, const double *x, double *y);

/* A symmetric linear operator on n unknowns: y = A x (x, y do not alias),
 * an assembled matrix or a matrix-free product (ps_system_operator). */
typedef struct ps_operator {
  ps_int n;
  void (*apply)(void *data, const double *x, double *y);
  void *data;
  const unsigned char *owned; /* [n] 1: the entry counts in the dot products
                                 of CG and GMRES (a share's own dofs: its
                                 ghosts' entries are another process's);
                                 NULL: every entry */
} ps_operator;

/* The operator of a symmetric CSC matrix (one triangle; ps_csc_symv). */
ps_operator ps_csc_operator(const ps_csc *A);

/* Conjugate gradients on A x = b (A a symmetric operator), started
 * from x = 0 and preconditioned by the last factor held by M (a factor of
 * a nearby matrix: an earlier tangent; in single precision when
 * M->single_precision and the backend has one). Stops when ||b - A x|| <= rtol
 * ||b||. work: 4 n doubles. *its gets the iterations. Returns PS_OK;
 * PS_NOT_POSDEF when a CG direction p has p.A p <= 0 (A is indefinite):
 * x is then the last iterate before it, or M^-1 b if that was the first
 * direction, so that b.x > 0 (Steihaug's truncated CG: a descent
 * direction for the energy whose gradient is -b); PS_DIVERGED (not
 * converged within maxit, or the preconditioner not positive definite;
 * x is then garbage); or a fatal status from the solve. */
int ps_linsolve_pcg(ps_linsolve *M, const ps_operator *A, const double *b,
                    double *x, double rtol, int maxit, double *work, int *its,
                    ps_ctx *ctx);

/* GMRES on A x = b (A any nonsingular operator: an indefinite tangent),
 * started from x = 0 and preconditioned on the right by the factor held
 * by M in double precision (ps_linsolve_solve: a factor of a nearby
 * matrix, such as the positive definite factor of a shifted indefinite
 * one), without restarts: at most maxit iterations, each one solve with
 * M and one product with A, and one more solve at the end. Stops when
 * ||b - A x|| <= rtol ||b|| (the residual of GMRES's least-squares
 * problem). *its gets the iterations. Returns PS_OK, PS_DIVERGED (not
 * converged within maxit: x is then GMRES's best iterate), PS_ERR_NOMEM,
 * or a fatal status of the solve. */
int ps_linsolve_gmres(ps_linsolve *M, const ps_operator *A, const double *b, double *x,
                      double rtol, int maxit, int *its, ps_ctx *ctx);

#endif
