/* petsc.c: the PETSc backend (solver.linear: petsc) and the MPI process
 * layer it needs (ps_parallel_*).
 *
 * The matrix is PETSc's AIJ (MPIAIJ on several ranks), rows split in
 * contiguous blocks over the ranks (PETSc's default layout: n / P rows
 * each, the first n % P ranks one more); each rank sets only its own rows,
 * from the full symmetric rows ps_csc_expand makes of the upper triangle.
 * The KSP and its PC come from PETSc's options (the case's
 * solver.petsc_options, then the command line's -ksp_* / -pc_* / ...).
 * Without options: -ksp_type preonly -pc_type cholesky with MUMPS, an
 * LDL^T factorisation with pivoting (symmetric, not assumed definite);
 * its negative pivots (MUMPS INFOG(12)) make the factor PS_NOT_POSDEF,
 * as CHOLMOD's LL^T would be. A multigrid PC gets the rigid-body modes of
 * the unknowns as its near-null space.
 *
 * The right-hand side and the solution are whole vectors on every rank:
 * each rank copies its rows in and all ranks get all of x back (a
 * VecScatter to all), so the callers, which hold the whole state on every
 * rank, stay identical on all ranks. */
#include <config.h>

#include "ps_linsolve.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef HAVE_PETSC
#include <petscksp.h>

/* An AMG or incomplete-factor set-up is counted as this many CG
 * iterations with it (direction.c's rule for when refactoring pays, which
 * reads flops_factor / (5 x 4 nnz_factor)): a rule of thumb, not a
 * measurement (doc/performance.md) */
#define PS_PETSC_SETUP_ITERATIONS 50.0

int ps_parallel_available(void) { return 1; }

int ps_parallel_launched(void) {
  const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", NULL};
  for (int k = 0; vars[k]; k++)
    if (getenv(vars[k])) return 1;
  return 0;
}

int ps_parallel_init(ps_ctx *ctx) {
  PetscBool up = PETSC_FALSE;
  PetscInitialized(&up);
  if (up) return PS_OK;
  /* peristatic reports PETSc's errors itself (petsc_failed) */
  if (PetscInitializeNoArguments() != 0)
    return ps_error(ctx, PS_ERR_SOLVER, "PETSc (and MPI) could not be initialised");
  PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
  return PS_OK;
}

int ps_parallel_rank(void) {
  PetscBool up = PETSC_FALSE;
  PetscInitialized(&up);
  if (!up) return 0;
  PetscMPIInt r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

int ps_parallel_size(void) {
  PetscBool up = PETSC_FALSE;
  PetscInitialized(&up);
  if (!up) return 1;
  PetscMPIInt n = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &n);
  return n;
}

int ps_parallel_all_agree(int flag) {
  if (ps_parallel_size() == 1) return flag;
  int lo = flag, hi = flag;
  MPI_Allreduce(&flag, &lo, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
  MPI_Allreduce(&flag, &hi, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  return lo == hi;
}

void ps_parallel_finalize(void) {
  PetscBool up = PETSC_FALSE, down = PETSC_FALSE;
  PetscInitialized(&up);
  PetscFinalized(&down);
  if (up && !down) PetscFinalize();
}

typedef struct {
  const ps_linsolve *ls; /* the object this is the state of: its options
                            and rigid-body modes */
  Mat A;
  KSP ksp;
  Vec b, x, x_all;      /* b, x: this rank's rows; x_all: all rows */
  VecScatter to_all;
  PetscInt n, rstart, rend;
  ps_int *Ap, *Ai, *map; /* this rank's rows of the full matrix (global
                            columns) and where each value is in A->x */
  PetscInt *cols;        /* one row's columns as PetscInt */
  double *vals;          /* one row's values */
  ps_int max_row;        /* the longest row */
  int direct;            /* the PC is a factorisation by MUMPS */
  PetscReal rtol;        /* the KSP's tolerance from the options (default
                            1e-10), for solves without ls->rtol */
  int have_pc;           /* the PC was set up */
} petsc_state;

/* PS_ERR_SOLVER with PETSc's own text for error ierr of call `what` */
static int petsc_failed(PetscErrorCode ierr, const char *what, ps_ctx *ctx) {
  const char *text = NULL;
  char *specific = NULL; /* the message of the error's origin */
  PetscErrorMessage(ierr, &text, &specific);
  if (ierr == PETSC_ERR_MEM)
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory in PETSc's %s", what);
  return ps_error(ctx, PS_ERR_SOLVER, "PETSc's %s failed (error %d: %s%s%s)", what, (int)ierr,
                  specific && specific[0] ? specific : "", specific && specific[0] ? "; " : "",
                  text ? text : "no message");
}

#define PT(call, what)                                                       \
  do {                                                                       \
    PetscErrorCode ps_ierr_ = (call);                                        \
    if (ps_ierr_) return petsc_failed(ps_ierr_, what, ctx);                  \
  } while (0)

static int pt_create(void **state, const ps_linsolve *ls, ps_ctx *ctx) {
  PS_CHECK(ps_parallel_init(ctx));
  petsc_state *s = ps_calloc(1, sizeof *s, ctx);
  if (!s) return PS_ERR_NOMEM;
  s->ls = ls;
  *state = s;
  return PS_OK;
}

static void pt_free_objects(petsc_state *s) {
  if (s->ksp) KSPDestroy(&s->ksp);
  if (s->A) MatDestroy(&s->A);
  if (s->b) VecDestroy(&s->b);
  if (s->x) VecDestroy(&s->x);
  if (s->x_all) VecDestroy(&s->x_all);
  if (s->to_all) VecScatterDestroy(&s->to_all);
  free(s->Ap);
  free(s->Ai);
  free(s->map);
  free(s->cols);
  free(s->vals);
  s->Ap = s->Ai = s->map = NULL;
  s->cols = NULL;
  s->vals = NULL;
  s->have_pc = 0;
}

/* the near-null space of elasticity on the unknowns: the translations
 * and rotations of the particles (about the mean position of the free
 * dofs) restricted to
 * the free dofs, orthonormalised (modified Gram-Schmidt, twice) as PETSc
 * requires; a mode that the supports leave no part of (its norm falls
 * below 1e-10 of its own) is dropped */
static int rigid_modes(petsc_state *s, const ps_linsolve *ls, ps_ctx *ctx) {
  int d = ls->dim, nm = d == 2 ? 3 : 6, kept = 0;
  double c[3] = {0, 0, 0};
  ps_int np = 0;
  for (PetscInt r = 0; r < s->n; r++, np++) { /* the mean position of the free dofs */
    const double *x = ls->x + (size_t)d * (ls->dof_of_free[r] / d);
    for (int k = 0; k < d; k++) c[k] += x[k];
  }
  for (int k = 0; k < d; k++) c[k] /= np > 0 ? (double)np : 1.0;
  Vec v[6];
  int status = PS_OK;
  for (int m = 0; m < nm && status == PS_OK; m++) {
    PetscScalar *a;
    PetscReal n0 = 0.0, norm = 0.0;
    PetscErrorCode ierr = VecDuplicate(s->x, &v[kept]);
    if (!ierr) ierr = VecGetArray(v[kept], &a);
    if (ierr) {
      status = petsc_failed(ierr, "VecDuplicate", ctx);
      break;
    }
    for (PetscInt r = s->rstart; r < s->rend; r++) {
      ps_int dof = ls->dof_of_free[r];
      int k = (int)(dof % d);
      const double *x = ls->x + (size_t)d * (dof / d);
      double val;
      if (m < d) val = k == m ? 1.0 : 0.0;
      else if (d == 2) val = k == 0 ? -(x[1] - c[1]) : x[0] - c[0]; /* e_z x r */
      else { /* rotation about axis ax: (e_ax x r)_k */
        int ax = m - 3, i1 = (ax + 1) % 3, i2 = (ax + 2) % 3;
        val = k == i1 ? -(x[i2] - c[i2]) : k == i2 ? x[i1] - c[i1] : 0.0;
      }
      a[r - s->rstart] = val;
    }
    ierr = VecRestoreArray(v[kept], &a);
    if (!ierr) ierr = VecNorm(v[kept], NORM_2, &n0);
    for (int pass = 0; pass < 2 && !ierr; pass++)
      for (int j = 0; j < kept && !ierr; j++) {
        PetscScalar dot;
        ierr = VecDot(v[kept], v[j], &dot);
        if (!ierr) ierr = VecAXPY(v[kept], -dot, v[j]);
      }
    if (!ierr) ierr = VecNorm(v[kept], NORM_2, &norm);
    if (!ierr && norm > 1e-10 * n0) ierr = VecScale(v[kept], 1.0 / norm);
    if (ierr) {
      VecDestroy(&v[kept]);
      status = petsc_failed(ierr, "the rigid-body modes", ctx);
    } else if (norm > 1e-10 * n0) {
      kept++;
    } else {
      VecDestroy(&v[kept]);
    }
  }
  if (status == PS_OK && kept > 0) {
    MatNullSpace ns;
    PetscErrorCode ierr = MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, kept, v, &ns);
    if (!ierr) {
      ierr = MatSetNearNullSpace(s->A, ns);
      MatNullSpaceDestroy(&ns);
    }
    if (ierr) status = petsc_failed(ierr, "MatSetNearNullSpace", ctx);
  }
  for (int k = 0; k < kept; k++) VecDestroy(&v[k]);
  return status;
}

/* the KSP and PC from the options: preonly + MUMPS Cholesky unless the
 * options say otherwise; an iterative KSP's default tolerance 1e-10 */
static int make_ksp(petsc_state *s, ps_ctx *ctx) {
  PT(KSPCreate(PETSC_COMM_WORLD, &s->ksp), "KSPCreate");
  PT(KSPSetType(s->ksp, KSPPREONLY), "KSPSetType");
  PC pc;
  PT(KSPGetPC(s->ksp, &pc), "KSPGetPC");
  PT(PCSetType(pc, PCCHOLESKY), "PCSetType");
  PT(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  PT(KSPSetTolerances(s->ksp, 1e-10, 1e-300, PETSC_DEFAULT, 10000), "KSPSetTolerances");
  PT(KSPSetFromOptions(s->ksp), "KSPSetFromOptions (check the PETSc options)");
  PT(KSPGetTolerances(s->ksp, &s->rtol, NULL, NULL, NULL), "KSPGetTolerances");
  return PS_OK;
}

/* the pattern: this rank's rows, the matrix, the vectors and the KSP */
static int pt_analyze(void *state, const ps_csc *A, ps_linsolve_stats *st, ps_ctx *ctx) {
  petsc_state *s = state;
  const ps_linsolve *ls = s->ls;
  double t = ps_wtime();
  pt_free_objects(s);
  if (A->n > (ps_int)PETSC_MAX_INT || A->p[A->n] > (ps_int)PETSC_MAX_INT / 2)
    return ps_error(ctx, PS_ERR_INPUT, "the system (%lld unknowns, %lld stored entries) is too "
                    "large for this PETSc's %d-bit indices", (long long)A->n,
                    (long long)A->p[A->n], (int)(8 * sizeof(PetscInt)));
  s->n = (PetscInt)A->n;
  PetscInt local = PETSC_DECIDE, end = 0;
  PT(PetscSplitOwnership(PETSC_COMM_WORLD, &local, &s->n), "PetscSplitOwnership");
  MPI_Scan(&local, &end, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD);
  s->rstart = end - local;
  s->rend = end;
  if (ls->options && ls->options[0])
    PT(PetscOptionsInsertString(NULL, ls->options), "PetscOptionsInsertString");
  PT(MatCreate(PETSC_COMM_WORLD, &s->A), "MatCreate");
  PT(MatSetSizes(s->A, local, local, s->n, s->n), "MatSetSizes");
  PT(MatSetType(s->A, MATAIJ), "MatSetType");
  PT(MatSetFromOptions(s->A), "MatSetFromOptions (check -mat_type)");
  PetscBool sbaij = PETSC_FALSE;
  PT(PetscObjectTypeCompareAny((PetscObject)s->A, &sbaij, MATSBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""),
     "PetscObjectTypeCompareAny");
  PS_CHECK(ps_csc_expand(A, s->rstart, s->rend, &s->Ap, &s->Ai, &s->map, ctx));
  ps_int m = s->rend - s->rstart;
  if (sbaij) { /* symmetric storage: each row's entries on and right of
                  the diagonal only (a suffix of the sorted row) */
    ps_int w = 0;
    for (ps_int r = 0; r < m; r++) {
      ps_int k = s->Ap[r];
      while (k < s->Ap[r + 1] && s->Ai[k] < s->rstart + r) k++;
      s->Ap[r] = w;
      for (; k < s->Ap[r + 1]; k++, w++) {
        s->Ai[w] = s->Ai[k];
        s->map[w] = s->map[k];
      }
    }
    s->Ap[m] = w; /* (row r's old end, Ap[r + 1], was read before it moved) */
  }
  PetscInt *ia = ps_calloc((size_t)m + 1, sizeof *ia, ctx);
  PetscInt *ja = ps_calloc((size_t)s->Ap[m] + 1, sizeof *ja, ctx);
  s->max_row = 0;
  for (ps_int r = 0; r < m; r++)
    if (s->Ap[r + 1] - s->Ap[r] > s->max_row) s->max_row = s->Ap[r + 1] - s->Ap[r];
  s->cols = ps_calloc((size_t)s->max_row + 1, sizeof *s->cols, ctx);
  s->vals = ps_calloc((size_t)s->max_row + 1, sizeof *s->vals, ctx);
  PetscErrorCode ierr = 0;
  if (ia && ja && s->cols && s->vals) {
    for (ps_int r = 0; r <= m; r++) ia[r] = (PetscInt)s->Ap[r];
    for (ps_int k = 0; k < s->Ap[m]; k++) ja[k] = (PetscInt)s->Ai[k];
    /* the preallocation of the matrix's type; the others do nothing */
    if (sbaij) {
      ierr = MatSeqSBAIJSetPreallocationCSR(s->A, 1, ia, ja, NULL);
      if (!ierr) ierr = MatMPISBAIJSetPreallocationCSR(s->A, 1, ia, ja, NULL);
    } else {
      ierr = MatSeqAIJSetPreallocationCSR(s->A, ia, ja, NULL);
      if (!ierr) ierr = MatMPIAIJSetPreallocationCSR(s->A, ia, ja, NULL);
    }
  }
  int nomem = !ia || !ja || !s->cols || !s->vals;
  free(ia);
  free(ja);
  if (nomem) return PS_ERR_NOMEM;
  if (ierr) return petsc_failed(ierr, "matrix preallocation", ctx);
  PT(MatSetOption(s->A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  PT(MatSetOption(s->A, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
  PT(MatSetOption(s->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
  PT(MatCreateVecs(s->A, &s->x, &s->b), "MatCreateVecs");
  PT(VecScatterCreateToAll(s->x, &s->to_all, &s->x_all), "VecScatterCreateToAll");
  if (ls->dim >= 2 && ls->dof_of_free && ls->x) PS_CHECK(rigid_modes(s, ls, ctx));
  PS_CHECK(make_ksp(s, ctx));
  PC pc;
  PT(KSPGetPC(s->ksp, &pc), "KSPGetPC");
  PetscBool chol = PETSC_FALSE, lu = PETSC_FALSE;
  PT(PetscObjectTypeCompare((PetscObject)pc, PCCHOLESKY, &chol), "PetscObjectTypeCompare");
  PT(PetscObjectTypeCompare((PetscObject)pc, PCLU, &lu), "PetscObjectTypeCompare");
  MatSolverType type = NULL;
  if (chol || lu) PT(PCFactorGetMatSolverType(pc, &type), "PCFactorGetMatSolverType");
  s->direct = type && !strcmp(type, MATSOLVERMUMPS);
  st->t_analyze += ps_wtime() - t;
  st->n_analyze++;
  return PS_OK;
}

/* this rank's rows of A into the matrix, then the PC's set-up */
static int pt_factor(void *state, const ps_csc *A, ps_int *bad_col, ps_linsolve_stats *st,
                     ps_ctx *ctx) {
  petsc_state *s = state;
  double t = ps_wtime();
  *bad_col = -1;
  ps_int m = s->rend - s->rstart;
  for (ps_int r = 0; r < m; r++) {
    PetscInt row = s->rstart + (PetscInt)r, len = (PetscInt)(s->Ap[r + 1] - s->Ap[r]);
    for (ps_int k = s->Ap[r], q = 0; k < s->Ap[r + 1]; k++, q++) {
      s->cols[q] = (PetscInt)s->Ai[k];
      s->vals[q] = A->x[s->map[k]];
    }
    PT(MatSetValues(s->A, 1, &row, len, s->cols, s->vals, INSERT_VALUES), "MatSetValues");
  }
  PT(MatAssemblyBegin(s->A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  PT(MatAssemblyEnd(s->A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  PT(KSPSetOperators(s->ksp, s->A, s->A), "KSPSetOperators");
  PetscErrorCode ierr = KSPSetUp(s->ksp);
  PC pc;
  PT(KSPGetPC(s->ksp, &pc), "KSPGetPC");
  PCFailedReason why = PC_NOERROR;
  PT(PCGetFailedReason(pc, &why), "PCGetFailedReason");
  st->t_factor += ps_wtime() - t;
  st->n_factor++;
  s->have_pc = 0;
  if (why == PC_FACTOR_STRUCT_ZEROPIVOT || why == PC_FACTOR_NUMERIC_ZEROPIVOT) return PS_SINGULAR;
  if (ierr || why != PC_NOERROR) return petsc_failed(ierr ? ierr : PETSC_ERR_LIB,
                                                    "preconditioner set-up (KSPSetUp)", ctx);
  s->have_pc = 1;
  if (s->direct) {
    Mat F;
    PetscInt neg = 0, info3 = 0;
    PetscReal flops = 0.0;
    PT(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
    PT(MatMumpsGetInfog(F, 12, &neg), "MatMumpsGetInfog");   /* negative pivots */
    PT(MatMumpsGetInfog(F, 3, &info3), "MatMumpsGetInfog");  /* factor entries */
    PT(MatMumpsGetRinfog(F, 3, &flops), "MatMumpsGetRinfog"); /* elimination flops */
    st->nnz_factor = info3 < 0 ? -1e6 * info3 : (double)info3;
    st->flops_factor = flops;
    if (neg > 0) return PS_NOT_POSDEF;
  } else {
    /* an AMG or incomplete factor: its set-up counted as about
     * PS_PETSC_SETUP_ITERATIONS of the CG iterations it preconditions
     * (ps_linsolve_stats: flops_factor / (5 x 4 nnz_factor)) */
    st->nnz_factor = (double)A->p[A->n];
    st->flops_factor = 20.0 * PS_PETSC_SETUP_ITERATIONS * st->nnz_factor;
  }
  return PS_OK;
}

/* x (all rows, every rank) from the vector s->x of this rank's rows */
static int gather(petsc_state *s, double *x, ps_ctx *ctx) {
  PT(VecScatterBegin(s->to_all, s->x, s->x_all, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
  PT(VecScatterEnd(s->to_all, s->x, s->x_all, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
  const PetscScalar *a;
  PT(VecGetArrayRead(s->x_all, &a), "VecGetArrayRead");
  memcpy(x, a, (size_t)s->n * sizeof *x);
  PT(VecRestoreArrayRead(s->x_all, &a), "VecRestoreArrayRead");
  return PS_OK;
}

/* s->b = this rank's rows of b */
static int scatter(petsc_state *s, const double *b, ps_ctx *ctx) {
  PetscScalar *a;
  PT(VecGetArray(s->b, &a), "VecGetArray");
  memcpy(a, b + s->rstart, (size_t)(s->rend - s->rstart) * sizeof *a);
  PT(VecRestoreArray(s->b, &a), "VecRestoreArray");
  return PS_OK;
}

static int pt_solve(void *state, const double *b, double *x, ps_linsolve_stats *st,
                    ps_ctx *ctx) {
  petsc_state *s = state;
  double t = ps_wtime();
  if (!s->have_pc) return ps_error(ctx, PS_ERR_INTERNAL, "PETSc solve without a set-up");
  PS_CHECK(scatter(s, b, ctx));
  double rtol = s->ls->rtol > 0 ? s->ls->rtol : s->rtol;
  PT(KSPSetTolerances(s->ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT),
     "KSPSetTolerances");
  PT(KSPSolve(s->ksp, s->b, s->x), "KSPSolve");
  KSPConvergedReason why;
  PT(KSPGetConvergedReason(s->ksp, &why), "KSPGetConvergedReason");
  if (why < 0) {
    PetscInt its = 0;
    KSPGetIterationNumber(s->ksp, &its);
    return ps_error(ctx, PS_ERR_SOLVER, "PETSc's KSP did not solve the Newton system: %s after "
                    "%d iterations (choose another -ksp_type/-pc_type, or raise -ksp_max_it, in "
                    "solver.petsc_options or on the command line)",
                    KSPConvergedReasons[why], (int)its);
  }
  PS_CHECK(gather(s, x, ctx));
  st->t_solve += ps_wtime() - t;
  st->n_solve++;
  return PS_OK;
}

/* one application of the PC (CG's preconditioner, ps_linsolve_pcg) */
static int pt_precondition(void *state, const double *b, double *x, ps_team *team, int parts,
                           ps_linsolve_stats *st, ps_ctx *ctx) {
  petsc_state *s = state;
  double t = ps_wtime();
  if (!s->have_pc) return ps_error(ctx, PS_ERR_INTERNAL, "PETSc solve without a set-up");
  PS_CHECK(scatter(s, b, ctx));
  PC pc;
  PT(KSPGetPC(s->ksp, &pc), "KSPGetPC");
  PT(PCApply(pc, s->b, s->x), "PCApply");
  PS_CHECK(gather(s, x, ctx));
  st->t_solve += ps_wtime() - t;
  st->n_solve++;
  return PS_OK;
}

static void pt_destroy(void **state) {
  petsc_state *s = *state;
  if (!s) return;
  pt_free_objects(s);
  free(s);
  *state = NULL;
}

#else /* without PETSc: rank 0 of 1, and a backend that says how to get one */

int ps_parallel_available(void) { return 0; }
int ps_parallel_launched(void) { return 0; }
int ps_parallel_init(ps_ctx *ctx) {
  return ps_error(ctx, PS_ERR_INPUT, "this peristatic was built without PETSc: configure "
                  "--with-petsc (scripts/install-deps.sh --with-petsc installs petsc-dev)");
}
int ps_parallel_rank(void) { return 0; }
int ps_parallel_size(void) { return 1; }
int ps_parallel_all_agree(int flag) { return flag; }
void ps_parallel_finalize(void) {}

static int pt_create(void **state, const ps_linsolve *ls, ps_ctx *ctx) {
  *state = NULL;
  return ps_parallel_init(ctx);
}
static void pt_destroy(void **state) { *state = NULL; }
#define pt_analyze NULL
#define pt_factor NULL
#define pt_solve NULL
#define pt_precondition NULL
#endif

int ps_petsc_options_factor(const char *options) {
  const char *p = options, *pc = NULL;
  while (p && (p = strstr(p, "-pc_type")) != NULL) {
    p += strlen("-pc_type");
    if (*p == ' ' || *p == '\t') pc = p;
  }
  if (!pc) return 1;
  while (*pc == ' ' || *pc == '\t') pc++;
  return !strncmp(pc, "cholesky", 8) || !strncmp(pc, "lu", 2);
}

static const ps_linsolve_type pt_type = {"petsc", pt_create, pt_analyze, pt_factor, pt_solve,
                                         pt_precondition, pt_destroy, 1};
const ps_linsolve_type *const ps_linsolve_petsc = &pt_type;
