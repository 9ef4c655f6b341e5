/* cholmod.c: CHOLMOD backend (supernodal LL^T, 64-bit indices). The
 * symbolic analysis (fill-reducing ordering, supernodes) runs once per
 * pattern; each factor call reuses it. A matrix that is not positive
 * definite is reported with its failing column (L->minor) as a recoverable
 * status. The global error handler is left NULL and c.print = 0: statuses
 * are read from c.status after each call. */
#include "ps_linsolve.h"

#include <cholmod.h>
#include <math.h>
#include <stdlib.h>

typedef struct {
  cholmod_common c;
  cholmod_factor *L;
  cholmod_sparse Ah; /* header over the caller's arrays (no copy) */
  cholmod_dense *X, *Y, *E; /* cholmod_l_solve2's solution and workspace,
                               kept between solves (CG solves thousands of
                               times: no allocation per solve) */
  ps_int n;
  /* the supernodal factor's values rounded to single precision, for
   * chol_precondition: made once a factor has served PS_SINGLE_AFTER
   * preconditioner solves (copying a factor costs a few of its solves,
   * which a short CG, e.g. an elastic solve's 3 iterations, never earns
   * back: at 80k particles 2.5 s against 0.5 s of CG) */
  float *Lf;
  size_t Lf_size;
  int Lf_current;
  int n_precond; /* preconditioner solves with the current factor */
  double *y; /* the permuted vector (n) */
  float *t;  /* one supernode's rows of it (<= n) */
} chol_state;

static int create(void **state, int supernodal, ps_ctx *ctx) {
  chol_state *s = ps_calloc(1, sizeof *s, ctx);
  if (!s) return PS_ERR_NOMEM;
  cholmod_l_start(&s->c);
  s->c.print = 0;
  s->c.error_handler = NULL;
  s->c.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  s->c.final_ll = 1;
  s->c.quick_return_if_not_posdef = 1;
  *state = s;
  return PS_OK;
}

static int chol_create(void **state, ps_ctx *ctx) { return create(state, 1, ctx); }
static int chol_create_simplicial(void **state, ps_ctx *ctx) {
  return create(state, 0, ctx);
}

static void set_header(chol_state *s, const ps_csc *A) {
  cholmod_sparse *h = &s->Ah;
  h->nrow = h->ncol = (size_t)A->n;
  h->nzmax = (size_t)A->p[A->n];
  h->p = A->p;
  h->i = A->i;
  h->nz = NULL;
  h->x = A->x;
  h->z = NULL;
  h->stype = 1; /* upper triangle stored: CHOLMOD factors it without a
                   transposed copy */
  h->itype = CHOLMOD_LONG;
  h->xtype = CHOLMOD_REAL;
  h->dtype = CHOLMOD_DOUBLE;
  h->sorted = 1;
  h->packed = 1;
}

static int chol_analyze(void *state, const ps_csc *A, ps_linsolve_stats *st,
                        ps_ctx *ctx) {
  chol_state *s = state;
  double t = ps_wtime();
  set_header(s, A);
  if (s->L) cholmod_l_free_factor(&s->L, &s->c);
  s->L = cholmod_l_analyze(&s->Ah, &s->c);
  if (!s->L || s->c.status < CHOLMOD_OK)
    return ps_error(ctx, PS_ERR_SOLVER, "CHOLMOD analysis failed (status %d)",
                    s->c.status);
  s->n = A->n;
  st->t_analyze += ps_wtime() - t;
  st->n_analyze++;
  return PS_OK;
}

static int chol_factor(void *state, const ps_csc *A, ps_int *bad_col,
                       ps_linsolve_stats *st, ps_ctx *ctx) {
  chol_state *s = state;
  double t = ps_wtime();
  set_header(s, A);
  *bad_col = -1;
  int ok = cholmod_l_factorize(&s->Ah, s->L, &s->c);
  s->Lf_current = 0;
  s->n_precond = 0;
  st->t_factor += ps_wtime() - t;
  st->n_factor++;
  st->flops_factor = s->c.fl;
  st->nnz_factor = s->c.lnz;
  if (s->c.status == CHOLMOD_NOT_POSDEF) {
    /* L->minor is a column of the permuted matrix */
    ps_int minor = (ps_int)s->L->minor;
    const ps_int *perm = s->L->Perm;
    *bad_col = perm && minor < (ps_int)s->L->n ? perm[minor] : minor;
    return PS_NOT_POSDEF;
  }
  if (!ok || s->c.status < CHOLMOD_OK)
    return ps_error(ctx, PS_ERR_SOLVER, "CHOLMOD factorisation failed (status %d)",
                    s->c.status);
  /* CHOLMOD flags only pivots <= 0; a mechanism usually leaves a tiny
   * positive one. Singular when min L_jj^2 / max L_jj^2 < 1e-13. */
  double dmin = INFINITY, dmax = 0.0;
  ps_int jmin = -1;
  const ps_int *super = s->L->super, *pi = s->L->pi, *px = s->L->px;
  const double *Lx = s->L->x;
  for (size_t sn = 0; s->L->is_super && sn < s->L->nsuper; sn++) {
    ps_int k1 = super[sn], k2 = super[sn + 1], nr = pi[sn + 1] - pi[sn];
    for (ps_int j = k1; j < k2; j++) {
      double d = Lx[px[sn] + (j - k1) * nr + (j - k1)];
      d *= d;
      if (d < dmin) {
        dmin = d;
        jmin = j;
      }
      if (d > dmax) dmax = d;
    }
  }
  if (!s->L->is_super) { /* simplicial: the diagonal leads each column */
    const ps_int *Lp = s->L->p;
    for (ps_int j = 0; j < (ps_int)s->L->n; j++) {
      double d = Lx[Lp[j]];
      d *= d;
      if (d < dmin) {
        dmin = d;
        jmin = j;
      }
      if (d > dmax) dmax = d;
    }
  }
  if (jmin >= 0 && dmin < 1e-13 * dmax) {
    const ps_int *perm = s->L->Perm;
    *bad_col = perm ? perm[jmin] : jmin;
    return PS_SINGULAR;
  }
  return PS_OK;
}

static int chol_solve(void *state, const double *b, double *x,
                      ps_linsolve_stats *st, ps_ctx *ctx) {
  chol_state *s = state;
  double t = ps_wtime();
  cholmod_dense B = {0};
  B.nrow = B.ncol = 1;
  B.nrow = (size_t)s->n;
  B.d = B.nzmax = (size_t)s->n;
  B.x = (void *)b;
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  int ok = cholmod_l_solve2(CHOLMOD_A, s->L, &B, NULL, &s->X, NULL, &s->Y, &s->E, &s->c);
  if (!ok || !s->X || s->c.status < CHOLMOD_OK)
    return ps_error(ctx, PS_ERR_SOLVER, "CHOLMOD solve failed (status %d)",
                    s->c.status);
  const double *xx = s->X->x;
  for (ps_int k = 0; k < s->n; k++) x[k] = xx[k];
  st->t_solve += ps_wtime() - t;
  st->n_solve++;
  return PS_OK;
}

/* Makes s->Lf, s->y, s->t for the current supernodal factor. PS_OK or
 * PS_ERR_NOMEM. */
static int make_single(chol_state *s, ps_ctx *ctx) {
  const cholmod_factor *L = s->L;
  if (L->xsize > s->Lf_size || !s->y) {
    free(s->Lf);
    free(s->y);
    free(s->t);
    s->Lf_size = 0;
    s->Lf = ps_calloc(L->xsize, sizeof *s->Lf, ctx);
    s->y = ps_calloc((size_t)s->n, sizeof *s->y, ctx);
    s->t = ps_calloc((size_t)s->n, sizeof *s->t, ctx); /* >= any supernode's rows */
    if (!s->Lf || !s->y || !s->t) return PS_ERR_NOMEM;
    s->Lf_size = L->xsize;
  }
  const double *Lx = L->x;
  for (size_t k = 0; k < L->xsize; k++) s->Lf[k] = (float)Lx[k];
  s->Lf_current = 1;
  return PS_OK;
}

/* Fortran BLAS in single precision (OpenBLAS; 32-bit integers, as
 * CHOLMOD's own calls) */
void strsv_(const char *uplo, const char *trans, const char *diag, const int *n,
            const float *a, const int *lda, float *x, const int *incx);
void sgemv_(const char *trans, const int *m, const int *n, const float *alpha,
            const float *a, const int *lda, const float *x, const int *incx,
            const float *beta, float *y, const int *incy);

/* x ~= A \ b in single precision: x = P^T L^-T L^-1 P b, supernode by
 * supernode as CHOLMOD's own solve (each supernode a dense column-major
 * block of nr rows, its nc columns first: a triangular solve with the
 * diagonal block and a product with the rows below), with the factor's
 * values and each supernode's part of the vector rounded to float; the
 * permuted vector itself is kept in double. The triangular solves of a CG
 * preconditioner are bound by memory bandwidth (L is read twice per
 * iteration), so halving the bytes read is what makes them faster. The
 * preconditioner stays symmetric positive definite up to float round-off
 * (the same rounded L forward and backward), which CG tolerates.
 * Simplicial factors, and the first PS_SINGLE_AFTER solves with a factor,
 * use chol_solve. */
static int chol_precondition(void *state, const double *b, double *x,
                             ps_linsolve_stats *st, ps_ctx *ctx) {
  chol_state *s = state;
  const cholmod_factor *L = s->L;
  if (!L->is_super || (!s->Lf_current && ++s->n_precond <= PS_SINGLE_AFTER))
    return chol_solve(state, b, x, st, ctx);
  double t0 = ps_wtime();
  if (!s->Lf_current) PS_CHECK(make_single(s, ctx));
  const ps_int *super = L->super, *pi = L->pi, *px = L->px, *Ls = L->s, *perm = L->Perm;
  ps_int nsuper = (ps_int)L->nsuper, n = s->n;
  double *y = s->y;
  float *t = s->t;
  const int one = 1;
  const float f_one = 1.0f, f_zero = 0.0f, f_minus_one = -1.0f;
  for (ps_int k = 0; k < n; k++) y[k] = b[perm ? perm[k] : k];
  for (ps_int sn = 0; sn < nsuper; sn++) { /* L y = P b */
    ps_int k1 = super[sn];
    int nc = (int)(super[sn + 1] - k1), nr = (int)(pi[sn + 1] - pi[sn]), m = nr - nc;
    const float *Lx = s->Lf + px[sn];
    const ps_int *rows = Ls + pi[sn];
    for (int i = 0; i < nc; i++) t[i] = (float)y[k1 + i];
    strsv_("L", "N", "N", &nc, Lx, &nr, t, &one);
    if (m > 0) sgemv_("N", &m, &nc, &f_minus_one, Lx + nc, &nr, t, &one, &f_zero, t + nc, &one);
    for (int i = 0; i < nc; i++) y[k1 + i] = t[i];
    for (int i = nc; i < nr; i++) y[rows[i]] += t[i];
  }
  for (ps_int sn = nsuper - 1; sn >= 0; sn--) { /* L^T x = y */
    ps_int k1 = super[sn];
    int nc = (int)(super[sn + 1] - k1), nr = (int)(pi[sn + 1] - pi[sn]), m = nr - nc;
    const float *Lx = s->Lf + px[sn];
    const ps_int *rows = Ls + pi[sn];
    for (int i = 0; i < nc; i++) t[i] = (float)y[k1 + i];
    for (int i = nc; i < nr; i++) t[i] = (float)y[rows[i]];
    if (m > 0) sgemv_("T", &m, &nc, &f_minus_one, Lx + nc, &nr, t + nc, &one, &f_one, t, &one);
    strsv_("L", "T", "N", &nc, Lx, &nr, t, &one);
    for (int i = 0; i < nc; i++) y[k1 + i] = t[i];
  }
  for (ps_int k = 0; k < n; k++) x[perm ? perm[k] : k] = y[k];
  st->t_solve += ps_wtime() - t0;
  st->n_solve++;
  return PS_OK;
}

static void chol_destroy(void **state) {
  chol_state *s = *state;
  if (!s) return;
  if (s->L) cholmod_l_free_factor(&s->L, &s->c);
  cholmod_l_free_dense(&s->X, &s->c);
  cholmod_l_free_dense(&s->Y, &s->c);
  cholmod_l_free_dense(&s->E, &s->c);
  cholmod_l_finish(&s->c);
  free(s->Lf);
  free(s->y);
  free(s->t);
  free(s);
  *state = NULL;
}

static const ps_linsolve_type chol_type = {"cholmod",   chol_create, chol_analyze,
                                           chol_factor, chol_solve,  chol_precondition,
                                           chol_destroy};
const ps_linsolve_type *const ps_linsolve_cholmod = &chol_type;
/* simplicial LL^T (for comparison: much slower on the two-horizon tangent) */
static const ps_linsolve_type chol_simp_type = {
    "cholmod-simplicial", chol_create_simplicial, chol_analyze, chol_factor, chol_solve,
    NULL, chol_destroy};
const ps_linsolve_type *const ps_linsolve_cholmod_simplicial = &chol_simp_type;
