/* petsc.c: the PETSc backend (solver.linear: petsc) and the MPI process
 * layer it needs (ps_parallel_*).
 *
 * The system PETSc solves is over all dofs, in blocks of dim (one block a
 * particle): a free dof's row is its row of the symmetric tangent whose
 * upper triangle the caller's A is, a prescribed dof's row is the
 * identity's. Its rows are split over the ranks in whole particles: on
 * several ranks numbered along the space-filling curve of
 * ps_partition_curve, so that a rank's rows are a compact part of the
 * body (numbering), and each rank sets only its own rows. The matrix is AIJ (MPIAIJ on several ranks, block size dim), or
 * SBAIJ with -mat_type sbaij (the upper triangle only), or BAIJ; its
 * pattern is set once per analysis, and each factorisation writes A's
 * values straight into the value arrays of the matrix's local pieces,
 * slot by slot (value_slots finds which entry each slot holds). The KSP
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

#include "../geom/ps_geom.h"

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

/* ps_comm's operations on PETSC_COMM_WORLD (MPI_Allreduce in place) */
static void world_sum(void *data, double *x, int n) {
  (void)data;
  MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
}
static void world_max(void *data, double *x, int n) {
  (void)data;
  MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
}
static void world_min(void *data, double *x, int n) {
  (void)data;
  MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_MIN, PETSC_COMM_WORLD);
}

static void world_alltoallv(void *data, const void *send, const int *scount,
                            const int *sdispl, void *recv, const int *rcount,
                            const int *rdispl) {
  (void)data;
  (void)MPI_Alltoallv(send, scount, sdispl, MPI_BYTE, recv, rcount, rdispl, MPI_BYTE,
                PETSC_COMM_WORLD);
}

int ps_parallel_comm(ps_comm *comm, ps_ctx *ctx) {
  PetscBool up = PETSC_FALSE;
  PetscInitialized(&up);
  if (!up) return ps_error(ctx, PS_ERR_INTERNAL, "ps_parallel_comm before ps_parallel_init");
  *comm = (ps_comm){ps_parallel_rank(), ps_parallel_size(), NULL, world_sum, world_max,
                    world_min, world_alltoallv};
  return PS_OK;
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
  PetscInt N, rstart, rend; /* the system's order (all dofs: this_rows),
                            this rank's rows */
  ps_int n_free;         /* A's order */
  int d;                 /* the block size: dim, or 1 */
  const ps_int *dof;     /* free index -> dof (ls->dof_of_free), or NULL
                            when the system is A's own (identity) */
  ps_int *row_free;      /* this rank's row r: its free index, or -1 */
  /* the numbering of the system's rows (all dofs): particle by particle
   * along the space-filling curve of ps_partition_curve when there are
   * several ranks (each rank's rows a compact part of the body), else the
   * dofs' own order */
  ps_int *row_dof;       /* [this rank's rows] the dof of each */
  ps_int *row_of_dof;    /* [N] the row of each dof */
  ps_int *free_of;       /* [N] the free index of each dof, or -1 */
  int curve;             /* 1: rows along the curve; 0: the dofs' order */
  /* where the values go (fill_values): the local pieces of the matrix
   * (the matrix itself, or an MPI matrix's diagonal and off-diagonal
   * blocks) whose value arrays are written directly, slot by slot from
   * A->x (piece_src[p][slot]: the position in A->x, PS_ONE for a
   * prescribed dof's diagonal, PS_ZERO for a slot outside the pattern);
   * and the entries no piece holds (MatSetValues, row by row: rest_ia,
   * rest_ja, rest_src) */
  Mat piece[2];
  ps_int piece_len[2];
  ps_int *piece_src[2];
  PetscInt *rest_ia, *rest_ja;
  ps_int *rest_src;
  double *vals;          /* one row's values */
  ps_int max_row;        /* the longest row */
  int direct;            /* the PC is a factorisation by MUMPS */
  PetscReal rtol;        /* the KSP's tolerance from the options (default
                            1e-10), for solves without ls->rtol */
  int have_pc;           /* the PC was set up */
} petsc_state;

/* piece_src and rest_src values that are not positions in A->x */
#define PS_ONE ((ps_int)-1)
#define PS_ZERO ((ps_int)-2)

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
  free(s->row_free);
  free(s->row_dof);
  free(s->row_of_dof);
  free(s->free_of);
  s->row_free = s->row_dof = s->row_of_dof = s->free_of = NULL;
  for (int p = 0; p < 2; p++) {
    free(s->piece_src[p]);
    s->piece_src[p] = NULL;
    s->piece[p] = NULL;
    s->piece_len[p] = 0;
  }
  free(s->rest_ia);
  free(s->rest_ja);
  free(s->rest_src);
  free(s->vals);
  s->rest_ia = s->rest_ja = NULL;
  s->rest_src = NULL;
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

typedef struct {
  PetscInt col;
  ps_int src;
} entry;

static int by_col(const void *x, const void *y) {
  PetscInt a = ((const entry *)x)->col, b = ((const entry *)y)->col;
  return (a > b) - (a < b);
}

/* 1 when the entry (row, col) of the system (rows and columns in its own
 * numbering) is stored: always for a full row (upper_bs 0); for SBAIJ of
 * block size upper_bs when col's block is not left of row's */
static inline int stored(PetscInt row, PetscInt col, int upper_bs) {
  return upper_bs <= 0 || col / upper_bs >= row / upper_bs;
}

/* This rank's rows of the system over all dofs (A's own when s->dof is
 * NULL) in CSR, columns in the system's numbering (row_of_dof), sorted:
 * *ia[m + 1], *ja, and *src, for each entry the position of its value in
 * A->x (PS_ONE: a prescribed dof's diagonal, the value 1). A free dof k's
 * row is row k of the symmetric matrix whose upper triangle A is: the
 * entries of A's column k (rows i <= k) and the entries (k, c) of the
 * columns c > k; with upper_bs > 0 (SBAIJ of that block size) only those
 * whose column's block is not left of the row's. Returns PS_OK or
 * PS_ERR_NOMEM. */
static int this_rows(const petsc_state *s, const ps_csc *A, int upper_bs, PetscInt **ia_out,
                     PetscInt **ja_out, ps_int **src_out, ps_ctx *ctx) {
  const ps_int *dof = s->dof, *row = s->row_of_dof;
  ps_int m = s->rend - s->rstart, n = A->n;
  PetscInt *ia = ps_calloc((size_t)m + 1, sizeof *ia, ctx), *ja = NULL;
  ps_int *src = NULL, *fill = ps_calloc((size_t)m + 1, sizeof *fill, ctx);
  ps_int *owner = ps_calloc((size_t)n + 1, sizeof *owner, ctx); /* free index -> local row */
  entry *tmp = NULL;
  if (!ia || !fill || !owner) goto nomem;
#define ROW(k) ((PetscInt)row[dof ? dof[k] : (k)])
  for (ps_int k = 0; k < n; k++) owner[k] = -1;
  for (ps_int r = 0; r < m; r++)
    if (s->row_free[r] >= 0) owner[s->row_free[r]] = r;
  /* each row's length: a prescribed dof 1; a free dof its stored entries
   * of A's column k, then of the later columns */
  for (ps_int r = 0; r < m; r++) {
    ps_int k = s->row_free[r];
    if (k < 0) {
      ia[r + 1] = 1;
      continue;
    }
    for (ps_int e = A->p[k]; e < A->p[k + 1]; e++) ia[r + 1] += stored(ROW(k), ROW(A->i[e]), upper_bs);
  }
  for (ps_int c = 0; c < n; c++)
    for (ps_int e = A->p[c]; e < A->p[c + 1]; e++) {
      ps_int i = A->i[e];
      if (i != c && owner[i] >= 0 && stored(ROW(i), ROW(c), upper_bs)) ia[owner[i] + 1]++;
    }
  for (ps_int r = 0; r < m; r++) ia[r + 1] += ia[r];
  ja = ps_calloc((size_t)ia[m] + 1, sizeof *ja, ctx);
  src = ps_calloc((size_t)ia[m] + 1, sizeof *src, ctx);
  if (!ja || !src) goto nomem;
  for (ps_int r = 0; r < m; r++) {
    ps_int k = s->row_free[r], w = ia[r];
    if (k < 0) {
      ja[w] = (PetscInt)(s->rstart + r);
      src[w] = PS_ONE;
      continue;
    }
    for (ps_int e = A->p[k]; e < A->p[k + 1]; e++)
      if (stored(ROW(k), ROW(A->i[e]), upper_bs)) {
        ja[w] = ROW(A->i[e]);
        src[w++] = e;
      }
    fill[r] = w;
  }
  for (ps_int c = 0; c < n; c++)
    for (ps_int e = A->p[c]; e < A->p[c + 1]; e++) {
      ps_int i = A->i[e];
      if (i == c || owner[i] < 0 || !stored(ROW(i), ROW(c), upper_bs)) continue;
      ps_int w = fill[owner[i]]++;
      ja[w] = ROW(c);
      src[w] = e;
    }
#undef ROW
  /* in the dofs' own numbering the rows come out sorted; along the curve
   * they are sorted here */
  if (s->curve) {
    ps_int longest = 0;
    for (ps_int r = 0; r < m; r++)
      if (ia[r + 1] - ia[r] > longest) longest = ia[r + 1] - ia[r];
    tmp = ps_calloc((size_t)longest + 1, sizeof *tmp, ctx);
    if (!tmp) goto nomem;
    for (ps_int r = 0; r < m; r++) {
      ps_int len = ia[r + 1] - ia[r];
      for (ps_int q = 0; q < len; q++) tmp[q] = (entry){ja[ia[r] + q], src[ia[r] + q]};
      qsort(tmp, (size_t)len, sizeof *tmp, by_col);
      for (ps_int q = 0; q < len; q++) {
        ja[ia[r] + q] = tmp[q].col;
        src[ia[r] + q] = tmp[q].src;
      }
    }
  }
  free(tmp);
  free(fill);
  free(owner);
  *ia_out = ia;
  *ja_out = ja;
  *src_out = src;
  return PS_OK;
nomem:
  free(ia);
  free(ja);
  free(src);
  free(fill);
  free(owner);
  free(tmp);
  return PS_ERR_NOMEM;
}

/* The local pieces of the matrix whose value arrays can be written
 * directly: a sequential AIJ, BAIJ or SBAIJ matrix itself; an MPI AIJ or
 * BAIJ matrix's diagonal and off-diagonal blocks; an MPI SBAIJ matrix's
 * diagonal block (its off-diagonal block is not public). Other types: no
 * piece (every value through MatSetValues). */
static int local_pieces(petsc_state *s, ps_ctx *ctx) {
  PetscBool seq = PETSC_FALSE, maij = PETSC_FALSE, mbaij = PETSC_FALSE, msbaij = PETSC_FALSE;
  const PetscInt *colmap;
  s->piece[0] = s->piece[1] = NULL;
  PT(PetscObjectTypeCompareAny((PetscObject)s->A, &seq, MATSEQAIJ, MATSEQBAIJ, MATSEQSBAIJ, ""),
     "PetscObjectTypeCompareAny");
  PT(PetscObjectTypeCompare((PetscObject)s->A, MATMPIAIJ, &maij), "PetscObjectTypeCompare");
  PT(PetscObjectTypeCompare((PetscObject)s->A, MATMPIBAIJ, &mbaij), "PetscObjectTypeCompare");
  PT(PetscObjectTypeCompare((PetscObject)s->A, MATMPISBAIJ, &msbaij), "PetscObjectTypeCompare");
  if (seq) s->piece[0] = s->A;
  else if (maij)
    PT(MatMPIAIJGetSeqAIJ(s->A, &s->piece[0], &s->piece[1], &colmap), "MatMPIAIJGetSeqAIJ");
  else if (mbaij)
    PT(MatMPIBAIJGetSeqBAIJ(s->A, &s->piece[0], &s->piece[1], &colmap), "MatMPIBAIJGetSeqBAIJ");
  else if (msbaij) PT(MatGetDiagonalBlock(s->A, &s->piece[0]), "MatGetDiagonalBlock");
  return PS_OK;
}

/* a sequential piece's value array (its stored entries, padding of
 * blocks included) */
static PetscErrorCode piece_array(Mat P, PetscScalar **a, int get) {
  PetscBool aij = PETSC_FALSE, baij = PETSC_FALSE;
  PetscErrorCode ierr = PetscObjectTypeCompare((PetscObject)P, MATSEQAIJ, &aij);
  if (!ierr) ierr = PetscObjectTypeCompare((PetscObject)P, MATSEQBAIJ, &baij);
  if (ierr) return ierr;
  if (aij) return get ? MatSeqAIJGetArray(P, a) : MatSeqAIJRestoreArray(P, a);
  if (baij) return get ? MatSeqBAIJGetArray(P, a) : MatSeqBAIJRestoreArray(P, a);
  return get ? MatSeqSBAIJGetArray(P, a) : MatSeqSBAIJRestoreArray(P, a);
}

/* The preallocation of a block matrix (BAIJ) of block size s->d from the
 * numbers of blocks each block row of this rank's rows (ia, ja) has in
 * the diagonal part (columns among this rank's rows) and outside it.
 * Returns PS_OK or PS_ERR_NOMEM; PETSc's error in *ierr. */
static int block_preallocation(const petsc_state *s, const PetscInt *ia, const PetscInt *ja,
                               PetscErrorCode *ierr, ps_ctx *ctx) {
  int d = s->d;
  ps_int mb = (s->rend - s->rstart) / d, nb = s->N / d;
  PetscInt *dn = ps_calloc((size_t)mb + 1, sizeof *dn, ctx);
  PetscInt *on = ps_calloc((size_t)mb + 1, sizeof *on, ctx);
  ps_int *seen = ps_calloc((size_t)nb + 1, sizeof *seen, ctx);
  if (!dn || !on || !seen) {
    free(dn), free(on), free(seen);
    return PS_ERR_NOMEM;
  }
  for (ps_int c = 0; c < nb; c++) seen[c] = -1;
  for (ps_int R = 0; R < mb; R++)
    for (ps_int r = R * d; r < (R + 1) * d; r++)
      for (PetscInt e = ia[r]; e < ia[r + 1]; e++) {
        ps_int c = ja[e] / d;
        if (seen[c] == R) continue;
        seen[c] = R;
        if (c >= s->rstart / d && c < s->rend / d) dn[R]++;
        else on[R]++;
      }
  *ierr = MatXAIJSetPreallocation(s->A, d, dn, on, dn, on); /* (SBAIJ: rows of upper blocks) */
  free(dn), free(on), free(seen);
  return PS_OK;
}

/* 1 when the matrix is a sequential AIJ (any block size) or SBAIJ (block
 * size 1) matrix that stores exactly this rank's rows ia, ja (the CSR
 * preallocation, which leaves it assembled) in that order: then slot k of
 * its value array is entry k, with no need to find out (value_slots) */
static int same_layout(petsc_state *s, const PetscInt *ia, const PetscInt *ja) {
  PetscBool aij = PETSC_FALSE, sbaij = PETSC_FALSE, done = PETSC_FALSE;
  PetscInt n = 0, bs = 1;
  const PetscInt *mi = NULL, *mj = NULL;
  /* (AIJ stores scalar rows whatever its block size) */
  if (PetscObjectTypeCompare((PetscObject)s->A, MATSEQAIJ, &aij) ||
      PetscObjectTypeCompare((PetscObject)s->A, MATSEQSBAIJ, &sbaij) || !(aij || sbaij) ||
      MatGetBlockSize(s->A, &bs) || (sbaij && bs != 1) ||
      MatGetRowIJ(s->A, 0, PETSC_FALSE, PETSC_FALSE, &n, &mi, &mj, &done))
    return 0;
  ps_int m = s->rend - s->rstart;
  int same = done && n == (PetscInt)m && !memcmp(mi, ia, (size_t)(m + 1) * sizeof *ia) &&
             !memcmp(mj, ja, (size_t)ia[m] * sizeof *ja);
  if (done) MatRestoreRowIJ(s->A, 0, PETSC_FALSE, PETSC_FALSE, &n, &mi, &mj, &done);
  return same;
}

/* Where each value goes. The matrix, preallocated with this rank's rows,
 * is filled once with the number of each entry plus one and assembled;
 * reading the pieces' arrays back then says which entry every slot
 * holds (numbers are exact in double up to 2^53; a slot left 0 is block
 * padding; two slots may hold one entry: SBAIJ keeps its diagonal blocks
 * whole and sets both halves). A matrix of the same layout as ia, ja
 * (same_layout) needs no such pass and takes *src_io as its slots'
 * sources (*src_io = NULL). Entries found in no piece stay for
 * MatSetValues (rest_*).
 * Returns PS_OK, PS_ERR_NOMEM or a PETSc error. */
static int value_slots(petsc_state *s, const PetscInt *ia, const PetscInt *ja, ps_int **src_io,
                       ps_ctx *ctx) {
  ps_int m = s->rend - s->rstart, nz = (ps_int)ia[m];
  const ps_int *src = *src_io;
  if (same_layout(s, ia, ja)) { /* the slots are the entries */
    s->piece[0] = s->A;
    s->piece_len[0] = nz;
    s->rest_ia = ps_calloc((size_t)m + 1, sizeof *s->rest_ia, ctx);
    s->rest_ja = ps_calloc(1, sizeof *s->rest_ja, ctx);
    s->rest_src = ps_calloc(1, sizeof *s->rest_src, ctx);
    if (!s->rest_ia || !s->rest_ja || !s->rest_src) return PS_ERR_NOMEM;
    s->piece_src[0] = *src_io; /* taken */
    *src_io = NULL;
    return PS_OK;
  }
  unsigned char *found = ps_calloc((size_t)nz + 1, 1, ctx);
  if (!found) return PS_ERR_NOMEM;
  int status = PS_OK;
  for (ps_int r = 0; r < m && status == PS_OK; r++) {
    PetscInt row = s->rstart + (PetscInt)r, len = ia[r + 1] - ia[r];
    for (PetscInt q = 0; q < len; q++) s->vals[q] = (double)(ia[r] + q + 1);
    PetscErrorCode ierr = MatSetValues(s->A, 1, &row, len, ja + ia[r], s->vals, INSERT_VALUES);
    if (ierr) status = petsc_failed(ierr, "MatSetValues", ctx);
  }
  if (status == PS_OK) {
    PetscErrorCode ierr = MatAssemblyBegin(s->A, MAT_FINAL_ASSEMBLY);
    if (!ierr) ierr = MatAssemblyEnd(s->A, MAT_FINAL_ASSEMBLY);
    if (ierr) status = petsc_failed(ierr, "matrix assembly", ctx);
  }
  if (status == PS_OK) status = local_pieces(s, ctx);
  for (int p = 0; p < 2 && status == PS_OK && s->piece[p]; p++) {
    MatInfo info;
    PetscScalar *a = NULL;
    PetscErrorCode ierr = MatGetInfo(s->piece[p], MAT_LOCAL, &info);
    if (!ierr) ierr = piece_array(s->piece[p], &a, 1);
    if (ierr) {
      status = petsc_failed(ierr, "MatGetInfo / the value array", ctx);
      break;
    }
    s->piece_len[p] = (ps_int)info.nz_used;
    s->piece_src[p] = ps_calloc((size_t)s->piece_len[p] + 1, sizeof *s->piece_src[p], ctx);
    if (!s->piece_src[p]) status = PS_ERR_NOMEM;
    for (ps_int slot = 0; status == PS_OK && slot < s->piece_len[p]; slot++) {
      double v = a[slot];
      ps_int e = (ps_int)v - 1;
      if (v == 0.0) s->piece_src[p][slot] = PS_ZERO;
      else if (v != (double)(e + 1) || e < 0 || e >= nz)
        status = ps_error(ctx, PS_ERR_INTERNAL, "PETSc's matrix holds a value peristatic did not "
                          "set (slot %lld of piece %d: %g)", (long long)slot, p, v);
      else {
        found[e] = 1;
        s->piece_src[p][slot] = src[e];
      }
    }
    ierr = piece_array(s->piece[p], &a, 0);
    if (ierr && status == PS_OK) status = petsc_failed(ierr, "the value array", ctx);
  }
  /* the rest, row by row */
  ps_int n_rest = 0;
  for (ps_int e = 0; e < nz; e++) n_rest += !found[e];
  if (status == PS_OK) {
    s->rest_ia = ps_calloc((size_t)m + 1, sizeof *s->rest_ia, ctx);
    s->rest_ja = ps_calloc((size_t)n_rest + 1, sizeof *s->rest_ja, ctx);
    s->rest_src = ps_calloc((size_t)n_rest + 1, sizeof *s->rest_src, ctx);
    if (!s->rest_ia || !s->rest_ja || !s->rest_src) status = PS_ERR_NOMEM;
  }
  if (status == PS_OK) {
    ps_int w = 0;
    for (ps_int r = 0; r < m; r++) {
      s->rest_ia[r] = (PetscInt)w;
      for (PetscInt e = ia[r]; e < ia[r + 1]; e++)
        if (!found[e]) {
          s->rest_ja[w] = ja[e];
          s->rest_src[w++] = src[e];
        }
    }
    s->rest_ia[m] = (PetscInt)w;
  }
  free(found);
  return status;
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
    for (ps_int r = 0; r < s->rend - s->rstart; r++) a[r] = ls->x[s->row_dof[r]];
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

/* The system's numbering and this rank's rows (*local of them): with
 * several ranks and the particles' positions, the particles in the order
 * of ps_partition_curve, rank r's rows those of its part (compact
 * subdomains: block Jacobi and the off-rank entries see less boundary
 * than slabs of particle numbers would, doc/design-distributed.md);
 * else (or with the PETSc option -peristatic_rows natural) the dofs' own
 * order split by PETSc (blocks of dim). Sets N's
 * maps row_of_dof and free_of and the rows' row_dof and row_free.
 * Returns PS_OK, PS_ERR_NOMEM or a PETSc error. */
static int numbering(petsc_state *s, PetscInt *local, ps_ctx *ctx) {
  PetscMPIInt rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const ps_linsolve *ls = s->ls;
  ps_int N = s->N, d = s->d, np = N / d;
  ps_int nl = ls->global_row ? ls->n_dof : N; /* the dofs this rank holds */
  s->row_of_dof = ps_calloc((size_t)nl + 1, sizeof *s->row_of_dof, ctx);
  s->free_of = ps_calloc((size_t)nl + 1, sizeof *s->free_of, ctx);
  if (!s->row_of_dof || !s->free_of) return PS_ERR_NOMEM;
  for (ps_int g = 0; g < nl; g++) s->free_of[g] = -1;
  for (ps_int k = 0; k < s->n_free; k++) s->free_of[s->dof ? s->dof[k] : k] = k;
  /* -peristatic_rows natural keeps the dofs' order (for comparisons) */
  char rows[32] = "curve";
  PetscBool given = PETSC_FALSE;
  PT(PetscOptionsGetString(NULL, NULL, "-peristatic_rows", rows, sizeof rows, &given),
     "PetscOptionsGetString");
  if (strcmp(rows, "curve") && strcmp(rows, "natural"))
    return ps_error(ctx, PS_ERR_INPUT, "-peristatic_rows must be curve or natural (got '%s')",
                    rows);
  s->curve = s->dof && size > 1 && np >= size && !strcmp(rows, "curve");
  if (ls->global_row) { /* a share: its rows and their numbers are given */
    s->curve = 1;       /* (rows sorted in this_rows) */
    for (ps_int g = 0; g < nl; g++) s->row_of_dof[g] = ls->global_row[g];
    s->rstart = (PetscInt)ls->row0;
    s->rend = (PetscInt)(ls->row0 + ls->n_rows);
  } else if (s->curve) {
    ps_particles P = {.dim = (int)d, .n = np, .x = (double *)s->ls->x};
    ps_partition pt;
    PS_CHECK(ps_partition_curve(&pt, &P, size, ctx));
    for (ps_int j = 0; j < np; j++)
      for (ps_int c = 0; c < d; c++) s->row_of_dof[pt.order[j] * d + c] = j * d + c;
    s->rstart = (PetscInt)(pt.start[rank] * d);
    s->rend = (PetscInt)(pt.start[rank + 1] * d);
    ps_partition_free(&pt);
  } else {
    PetscInt m = PETSC_DECIDE, end = 0;
    PT(PetscSplitOwnershipBlock(PETSC_COMM_WORLD, (PetscInt)d, &m, &s->N),
       "PetscSplitOwnershipBlock");
    MPI_Scan(&m, &end, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD);
    s->rstart = end - m;
    s->rend = end;
    for (ps_int g = 0; g < N; g++) s->row_of_dof[g] = g;
  }
  ps_int m = s->rend - s->rstart;
  s->row_dof = ps_calloc((size_t)m + 1, sizeof *s->row_dof, ctx);
  s->row_free = ps_calloc((size_t)m + 1, sizeof *s->row_free, ctx);
  if (!s->row_dof || !s->row_free) return PS_ERR_NOMEM;
  for (ps_int g = 0; g < nl; g++) {
    ps_int r = s->row_of_dof[g] - s->rstart;
    if (r >= 0 && r < m) s->row_dof[r] = g;
  }
  for (ps_int r = 0; r < m; r++) s->row_free[r] = s->free_of[s->row_dof[r]];
  *local = (PetscInt)m;
  return PS_OK;
}

/* a share's solution at its free dofs (owned and ghosts) from the rows
 * of the whole system's: the scatter of those rows into s->x_all */
static int share_scatter(petsc_state *s, ps_ctx *ctx) {
  PetscInt *rows = ps_calloc((size_t)s->n_free + 1, sizeof *rows, ctx);
  if (!rows) return PS_ERR_NOMEM;
  for (ps_int k = 0; k < s->n_free; k++) rows[k] = (PetscInt)s->row_of_dof[s->dof[k]];
  IS is = NULL;
  PetscErrorCode ierr =
      ISCreateGeneral(PETSC_COMM_SELF, (PetscInt)s->n_free, rows, PETSC_COPY_VALUES, &is);
  free(rows);
  if (!ierr) ierr = VecCreateSeq(PETSC_COMM_SELF, (PetscInt)s->n_free, &s->x_all);
  if (!ierr) ierr = VecScatterCreate(s->x, is, s->x_all, NULL, &s->to_all);
  if (is) ISDestroy(&is);
  if (ierr) return petsc_failed(ierr, "the share's scatter (VecScatterCreate)", ctx);
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
  if (ls->global_row && !blocks)
    return ps_error(ctx, PS_ERR_INTERNAL, "a share of a system without its dofs");
  s->d = blocks ? ls->dim : 1;
  s->dof = blocks ? ls->dof_of_free : NULL;
  s->n_free = A->n;
  ps_int N = ls->global_row ? ls->n_global : blocks ? ls->n_dof : A->n;
  int too_big = N > (ps_int)PETSC_MAX_INT || A->p[A->n] > (ps_int)PETSC_MAX_INT / 2;
  if (ls->global_row) /* a share's own A: every rank stops alike */
    MPI_Allreduce(MPI_IN_PLACE, &too_big, 1, MPI_INT, MPI_LOR, PETSC_COMM_WORLD);
  if (too_big)
    return ps_error(ctx, PS_ERR_INPUT, "the system (%lld unknowns, %lld stored entries) is too "
                    "large for this PETSc's %d-bit indices", (long long)N,
                    (long long)A->p[A->n], (int)(8 * sizeof(PetscInt)));
  s->N = (PetscInt)N;
  if (ls->options && ls->options[0])
    PT(PetscOptionsInsertString(NULL, ls->options), "PetscOptionsInsertString");
  PetscInt local = 0;
  PS_CHECK(numbering(s, &local, ctx));
  PT(MatCreate(PETSC_COMM_WORLD, &s->A), "MatCreate");
  PT(MatSetSizes(s->A, local, local, s->N, s->N), "MatSetSizes");
  PT(MatSetType(s->A, MATAIJ), "MatSetType");
  PT(MatSetFromOptions(s->A), "MatSetFromOptions (check -mat_type)");
  PetscBool sbaij = PETSC_FALSE;
  PT(PetscObjectTypeCompareAny((PetscObject)s->A, &sbaij, MATSBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""),
     "PetscObjectTypeCompareAny");
  if (!sbaij && s->d > 1) PT(MatSetBlockSize(s->A, s->d), "MatSetBlockSize");
  /* SBAIJ in blocks of dim (a particle's dofs): the upper triangle of
   * blocks, the diagonal blocks whole */
  int sbs = sbaij ? s->d : 0;
  ps_int m = s->rend - s->rstart;
  PetscInt *ia = NULL, *ja = NULL;
  ps_int *src = NULL;
  PS_CHECK(this_rows(s, A, sbs, &ia, &ja, &src, ctx));
  s->max_row = 0;
  for (ps_int r = 0; r < m; r++)
    if (ia[r + 1] - ia[r] > s->max_row) s->max_row = ia[r + 1] - ia[r];
  s->vals = ps_calloc((size_t)s->max_row + 1, sizeof *s->vals, ctx);
  PetscErrorCode ierr = 0;
  int status = s->vals ? PS_OK : PS_ERR_NOMEM;
  if (status == PS_OK) {
    /* the exact pattern for AIJ and scalar SBAIJ (the preallocation of
     * the matrix's type; the other calls do nothing); block types (BAIJ,
     * SBAIJ in blocks of dim) from counts of blocks */
    PetscBool aij = PETSC_FALSE;
    ierr = PetscObjectTypeCompareAny((PetscObject)s->A, &aij, MATSEQAIJ, MATMPIAIJ, "");
    if (ierr) {
    } else if (sbaij && sbs == 1) {
      ierr = MatSeqSBAIJSetPreallocationCSR(s->A, 1, ia, ja, NULL);
      if (!ierr) ierr = MatMPISBAIJSetPreallocationCSR(s->A, 1, ia, ja, NULL);
    } else if (aij) {
      ierr = MatSeqAIJSetPreallocationCSR(s->A, ia, ja, NULL);
      if (!ierr) ierr = MatMPIAIJSetPreallocationCSR(s->A, ia, ja, NULL);
    } else {
      status = block_preallocation(s, ia, ja, &ierr, ctx);
    }
    if (!ierr && status == PS_OK)
      ierr = MatSetOption(s->A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE);
    if (ierr) status = petsc_failed(ierr, "matrix preallocation", ctx);
  }
  if (status == PS_OK && !ierr) status = value_slots(s, ia, ja, &src, ctx);
  free(ia);
  free(ja);
  free(src);
  PS_CHECK(status);
  PT(MatSetOption(s->A, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
  PT(MatSetOption(s->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
  PT(MatCreateVecs(s->A, &s->x, &s->b), "MatCreateVecs");
  if (ls->global_row)
    PS_CHECK(share_scatter(s, ctx));
  else
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

/* the value of a slot or rest entry whose source is src: A->x[src], or 1
 * (a prescribed dof's diagonal, PS_ONE) or 0 (block padding, PS_ZERO) */
static inline double source_value(const ps_csc *A, ps_int src) {
  return src >= 0 ? A->x[src] : src == PS_ONE ? 1.0 : 0.0;
}

/* A's values into the matrix: the pieces' arrays slot by slot, the rest
 * by MatSetValues (assembled by the caller) */
static int fill_values(petsc_state *s, const ps_csc *A, ps_ctx *ctx) {
  for (int p = 0; p < 2 && s->piece[p]; p++) {
    PetscScalar *a;
    const ps_int *src = s->piece_src[p];
    PT(piece_array(s->piece[p], &a, 1), "the value array");
    for (ps_int slot = 0; slot < s->piece_len[p]; slot++)
      a[slot] = source_value(A, src[slot]);
    PT(piece_array(s->piece[p], &a, 0), "the value array");
  }
  ps_int m = s->rend - s->rstart;
  for (ps_int r = 0; r < m; r++) {
    PetscInt row = s->rstart + (PetscInt)r, len = s->rest_ia[r + 1] - s->rest_ia[r];
    if (len == 0) continue;
    const ps_int *src = s->rest_src + s->rest_ia[r];
    for (PetscInt q = 0; q < len; q++) s->vals[q] = source_value(A, src[q]);
    PT(MatSetValues(s->A, 1, &row, len, s->rest_ja + s->rest_ia[r], s->vals, INSERT_VALUES),
       "MatSetValues");
  }
  return PS_OK;
}

/* this rank's rows of A into the matrix, then the PC's set-up */
static int pt_factor(void *state, const ps_csc *A, ps_int *bad_col, ps_linsolve_stats *st,
                     ps_ctx *ctx) {
  petsc_state *s = state;
  double t = ps_wtime();
  *bad_col = -1;
  PS_CHECK(fill_values(s, A, ctx));
  PT(MatAssemblyBegin(s->A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  PT(MatAssemblyEnd(s->A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  /* (the assembly raises the matrix's state, which tells the PC that the
   * values written into the pieces' arrays changed) */
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
  if (s->ls->global_row) /* a share's free dofs, in order */
    for (ps_int k = 0; k < s->n_free; k++) x[k] = a[k];
  else
    for (ps_int k = 0; k < s->n_free; k++) x[k] = a[s->row_of_dof[s->dof ? s->dof[k] : k]];
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
  PetscInt its = 0;
  PT(KSPGetIterationNumber(s->ksp, &its), "KSPGetIterationNumber");
  st->n_iterations += its;
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
int ps_parallel_comm(ps_comm *comm, ps_ctx *ctx) {
  *comm = (ps_comm){0, 1, NULL, NULL, NULL, NULL, NULL};
  return ps_parallel_init(NULL, ctx);
}
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
