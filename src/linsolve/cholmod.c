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

static void chol_destroy(void **state) {
  chol_state *s = *state;
  if (!s) return;
  if (s->L) cholmod_l_free_factor(&s->L, &s->c);
  cholmod_l_free_dense(&s->X, &s->c);
  cholmod_l_free_dense(&s->Y, &s->c);
  cholmod_l_free_dense(&s->E, &s->c);
  cholmod_l_finish(&s->c);
  free(s);
  *state = NULL;
}

static const ps_linsolve_type chol_type = {"cholmod", chol_create, chol_analyze,
                                           chol_factor, chol_solve, chol_destroy};
const ps_linsolve_type *const ps_linsolve_cholmod = &chol_type;
/* simplicial LL^T (for comparison: much slower on the two-horizon tangent) */
static const ps_linsolve_type chol_simp_type = {
    "cholmod-simplicial", chol_create_simplicial, chol_analyze, chol_factor, chol_solve,
    chol_destroy};
const ps_linsolve_type *const ps_linsolve_cholmod_simplicial = &chol_simp_type;
