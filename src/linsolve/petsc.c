/* petsc.c: the PETSc backend (solver.linear: petsc) and the MPI process
 * layer it needs (ps_parallel_*).
 *
 * The system PETSc solves is over all dofs, in blocks of dim (one block a
 * particle): a free dof's row is its row of the tangent (the full
 * symmetric row ps_csc_expand makes of the upper triangle), a prescribed
 * dof's row is the identity's. Its rows are split over the ranks in whole
 * particles (PETSc's default layout of blocks), and each rank sets only
 * its own rows. The matrix is AIJ (MPIAIJ on several ranks, block size
 * dim), or SBAIJ with -mat_type sbaij (the upper triangle only). The KSP
 * and its PC come from PETSc's options (the case's solver.petsc_options,
 * then the command line's -ksp_* / -pc_* / ...). Without options:
 * -ksp_type preonly -pc_type cholesky with MUMPS, an LDL^T factorisation
 * with pivoting (symmetric, not assumed definite); its negative pivots
 * (MUMPS INFOG(12)) make the factor PS_NOT_POSDEF, as CHOLMOD's LL^T would
 * be. The particles' rigid-body modes are the near-null space (GAMG).
 *
 * The right-hand side and the solution are whole vectors of the free dofs
 * on every rank: each rank copies its rows in and all ranks get all of x
 * back (a VecScatter to all), so the callers, which hold the whole state
 * on every rank, stay identical on all ranks. */
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

int ps_parallel_launched(void) {
  const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", NULL};
  for (int k = 0; vars[k]; k++)
    if (getenv(vars[k])) return 1;
  return 0;
}

int ps_parallel_init(const char *options, ps_ctx *ctx) {
  PetscBool up = PETSC_FALSE;
  PetscInitialized(&up);
  if (up) return PS_OK;
  /* options given to PetscInitialize as arguments, so that those read
   * only there (-log_view, -malloc_debug) take effect */
  char buf[1024], *argv[130], **args = argv;
  int argc = 0;
  snprintf(buf, sizeof buf, "%s", options ? options : "");
  argv[argc++] = "peristatic";
  for (char *t = strtok(buf, " \t"); t && argc < 128; t = strtok(NULL, " \t")) argv[argc++] = t;
  argv[argc] = NULL;
  if (PetscInitialize(&argc, &args, NULL, NULL) != 0)
    return ps_error(ctx, PS_ERR_SOLVER, "PETSc (and MPI) could not be initialised");
  /* peristatic reports PETSc's errors itself (petsc_failed) */
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
  PetscInt N, rstart, rend; /* the system's order (all dofs: full_rows),
                            this rank's rows */
  ps_int n_free;         /* A's order */
  int d;                 /* the block size: dim, or 1 */
  const ps_int *dof;     /* free index -> dof (ls->dof_of_free), or NULL
                            when the system is A's own (identity) */
  ps_int *row_free;      /* this rank's row r: its free index, or -1 */
  ps_int *Ap, *Ai, *map; /* this rank's rows of the whole system (dofs as
                            columns) and where each value is in A->x (-1:
                            a prescribed dof's diagonal, 1) */
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
  PS_CHECK(ps_parallel_init(ls->options, ctx));
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
  free(s->row_free);
  s->row_free = NULL;
  free(s->cols);
  free(s->vals);
  s->Ap = s->Ai = s->map = NULL;
  s->cols = NULL;
  s->vals = NULL;
  s->have_pc = 0;
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

/* the first free index whose dof is >= g */
static ps_int free_from(const petsc_state *s, ps_int g) {
  if (!s->dof) return g < s->n_free ? g : s->n_free;
  ps_int lo = 0, hi = s->n_free;
  while (lo < hi) {
    ps_int mid = lo + (hi - lo) / 2;
    if (s->dof[mid] < g) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/* this rank's rows of the whole system over all dofs: a free dof's row is
 * its row of A (ps_csc_expand) with the columns as dofs; a prescribed
 * dof's row is its diagonal alone (map -1: the value 1). Rows are split
 * in whole particles (blocks of dim dofs). */
static int full_rows(petsc_state *s, const ps_csc *A, ps_ctx *ctx) {
  const ps_int *dof = s->dof;
  ps_int k0 = free_from(s, s->rstart), k1 = free_from(s, s->rend), *fAp, *fAi, *fmap;
  PS_CHECK(ps_csc_expand(A, k0, k1, &fAp, &fAi, &fmap, ctx));
  ps_int m = s->rend - s->rstart, nz = fAp[k1 - k0] + (m - (k1 - k0));
  s->Ap = ps_calloc((size_t)m + 1, sizeof *s->Ap, ctx);
  s->Ai = ps_calloc((size_t)nz + 1, sizeof *s->Ai, ctx);
  s->map = ps_calloc((size_t)nz + 1, sizeof *s->map, ctx);
  s->row_free = ps_calloc((size_t)m + 1, sizeof *s->row_free, ctx);
  if (s->Ap && s->Ai && s->map && s->row_free) {
    ps_int w = 0, k = k0;
    for (ps_int r = 0; r < m; r++) {
      ps_int g = s->rstart + r;
      s->Ap[r] = w;
      s->row_free[r] = -1;
      if (k < k1 && (dof ? dof[k] : k) == g) {
        s->row_free[r] = k;
        for (ps_int e = fAp[k - k0]; e < fAp[k - k0 + 1]; e++, w++) {
          s->Ai[w] = dof ? dof[fAi[e]] : fAi[e];
          s->map[w] = fmap[e];
        }
        k++;
      } else {
        s->Ai[w] = g;
        s->map[w++] = -1;
      }
    }
    s->Ap[m] = w;
  }
  free(fAp);
  free(fAi);
  free(fmap);
  return s->Ap && s->Ai && s->map && s->row_free ? PS_OK : PS_ERR_NOMEM;
}

/* the near-null space of elasticity: PETSc's rigid-body modes of the
 * particles' positions (all dofs, blocks of dim) */
static int rigid_modes(petsc_state *s, ps_ctx *ctx) {
  const ps_linsolve *ls = s->ls;
  Vec xyz;
  PT(VecCreateMPI(PETSC_COMM_WORLD, s->rend - s->rstart, s->N, &xyz), "VecCreateMPI");
  PetscErrorCode ierr = VecSetBlockSize(xyz, ls->dim);
  PetscScalar *a = NULL;
  if (!ierr) ierr = VecGetArray(xyz, &a);
  if (!ierr) {
    /* dof g is component g % dim of particle g / dim: its coordinate is x[g] */
    memcpy(a, ls->x + s->rstart, (size_t)(s->rend - s->rstart) * sizeof *a);
    ierr = VecRestoreArray(xyz, &a);
  }
  MatNullSpace ns = NULL;
  if (!ierr) ierr = MatNullSpaceCreateRigidBody(xyz, &ns);
  if (!ierr) ierr = MatSetNearNullSpace(s->A, ns);
  if (ns) MatNullSpaceDestroy(&ns);
  VecDestroy(&xyz);
  if (ierr) return petsc_failed(ierr, "the rigid-body modes (MatNullSpaceCreateRigidBody)", ctx);
  return PS_OK;
}

/* the pattern: this rank's rows, the matrix, the vectors and the KSP */
static int pt_analyze(void *state, const ps_csc *A, ps_linsolve_stats *st, ps_ctx *ctx) {
  petsc_state *s = state;
  const ps_linsolve *ls = s->ls;
  double t = ps_wtime();
  pt_free_objects(s);
  /* the system over all dofs when the solver object says what they are
   * (blocks of dim for GAMG and the rigid-body modes), else over A's */
  int blocks = ls->dim >= 1 && ls->dof_of_free && ls->x && ls->n_dof >= A->n;
  s->d = blocks ? ls->dim : 1;
  s->dof = blocks ? ls->dof_of_free : NULL;
  s->n_free = A->n;
  ps_int N = blocks ? ls->n_dof : A->n;
  if (N > (ps_int)PETSC_MAX_INT || A->p[A->n] > (ps_int)PETSC_MAX_INT / 2)
    return ps_error(ctx, PS_ERR_INPUT, "the system (%lld unknowns, %lld stored entries) is too "
                    "large for this PETSc's %d-bit indices", (long long)N,
                    (long long)A->p[A->n], (int)(8 * sizeof(PetscInt)));
  s->N = (PetscInt)N;
  PetscInt local = PETSC_DECIDE, end = 0;
  PT(PetscSplitOwnershipBlock(PETSC_COMM_WORLD, s->d, &local, &s->N), "PetscSplitOwnershipBlock");
  MPI_Scan(&local, &end, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD);
  s->rstart = end - local;
  s->rend = end;
  if (ls->options && ls->options[0])
    PT(PetscOptionsInsertString(NULL, ls->options), "PetscOptionsInsertString");
  PT(MatCreate(PETSC_COMM_WORLD, &s->A), "MatCreate");
  PT(MatSetSizes(s->A, local, local, s->N, s->N), "MatSetSizes");
  PT(MatSetType(s->A, MATAIJ), "MatSetType");
  PT(MatSetFromOptions(s->A), "MatSetFromOptions (check -mat_type)");
  PetscBool sbaij = PETSC_FALSE;
  PT(PetscObjectTypeCompareAny((PetscObject)s->A, &sbaij, MATSBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""),
     "PetscObjectTypeCompareAny");
  if (!sbaij && s->d > 1) PT(MatSetBlockSize(s->A, s->d), "MatSetBlockSize");
  PS_CHECK(full_rows(s, A, ctx));
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
  if (blocks && s->d >= 2) PS_CHECK(rigid_modes(s, ctx));
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
      s->vals[q] = s->map[k] >= 0 ? A->x[s->map[k]] : 1.0;
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
    /* any other PC (AMG, incomplete factor, a factor not by MUMPS): its
     * set-up counted as about
     * PS_PETSC_SETUP_ITERATIONS of the CG iterations it preconditions
     * (ps_linsolve_stats: flops_factor / (5 x 4 nnz_factor)) */
    st->nnz_factor = (double)A->p[A->n];
    st->flops_factor = 20.0 * PS_PETSC_SETUP_ITERATIONS * st->nnz_factor;
  }
  return PS_OK;
}

/* x (every free dof, on every rank) from the vector s->x of this rank's
 * rows */
static int gather(petsc_state *s, double *x, ps_ctx *ctx) {
  PT(VecScatterBegin(s->to_all, s->x, s->x_all, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
  PT(VecScatterEnd(s->to_all, s->x, s->x_all, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
  const PetscScalar *a;
  PT(VecGetArrayRead(s->x_all, &a), "VecGetArrayRead");
  for (ps_int k = 0; k < s->n_free; k++) x[k] = a[s->dof ? s->dof[k] : k];
  PT(VecRestoreArrayRead(s->x_all, &a), "VecRestoreArrayRead");
  return PS_OK;
}

/* s->b = this rank's rows of b (0 at prescribed dofs) */
static int scatter(petsc_state *s, const double *b, ps_ctx *ctx) {
  PetscScalar *a;
  PT(VecGetArray(s->b, &a), "VecGetArray");
  for (ps_int r = 0; r < s->rend - s->rstart; r++)
    a[r] = s->row_free[r] >= 0 ? b[s->row_free[r]] : 0.0;
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

int ps_parallel_launched(void) { return 0; }
int ps_parallel_init(const char *options, ps_ctx *ctx) {
  return ps_error(ctx, PS_ERR_INPUT, "this peristatic was built without PETSc: configure "
                  "--with-petsc (scripts/install-deps.sh --with-petsc installs petsc-dev)");
}
int ps_parallel_rank(void) { return 0; }
int ps_parallel_size(void) { return 1; }
void ps_parallel_finalize(void) {}

static int pt_create(void **state, const ps_linsolve *ls, ps_ctx *ctx) {
  *state = NULL;
  return ps_parallel_init(ls->options, ctx);
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
