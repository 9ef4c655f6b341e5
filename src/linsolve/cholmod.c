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
#include <string.h>

typedef struct {
  cholmod_common c;
  cholmod_factor *L;
  cholmod_sparse Ah; /* header over the caller's arrays (no copy) */
  cholmod_dense *X, *Y, *E; /* cholmod_l_solve2's solution and workspace,
                               kept between solves (CG solves thousands of
                               times: no allocation per solve) */
  ps_int n;
  /* the supernodal factor's blocks with their diagonal blocks inverted
   * (make_single), in single precision, for chol_precondition: made on its
   * first call after a factorisation (ps_linsolve_precondition calls it
   * once the factor has served ps_linsolve.single_after solves: making
   * the copy costs a few of the factor's solves, which a short CG, e.g.
   * an elastic solve's 3 iterations, never earns back) */
  float *Lf;
  size_t Lf_size;
  int Lf_current; /* 1: Lf is of the current factor; 0: not made yet; -1:
                    not usable (make_single) */
  double *y; /* the permuted vector (n) */
  float *t, *u; /* one supernode's rows of it and its columns (<= n) */
  /* the parts of the elimination tree for chol_precondition (make_parts),
   * n_parts subtrees below a top: part_list[part_ptr[p] .. part_ptr[p +
   * 1]) the supernodes of part p (p < n_parts: whole subtrees; p =
   * n_parts, the top: the supernodes above them) in increasing order;
   * top_pos[k] = the place of column k among the n_top columns of the top
   * part, -1 for a column below it */
  ps_int *part_list, *part_ptr;
  ps_int *top_pos, n_top;
  int n_parts;
  int parts_current; /* 1: made for the current analysis and n_parts */
  ps_int rows_max;   /* the most rows of a supernode */
  float *t_parts, *u_parts; /* parts 1 .. n_parts - 1's t and u
                               (rows_max each; part 0 has t and u) */
  double *z; /* parts 1 .. n_parts - 1's updates of the top rows (n_top
               each, at top_pos; zero between solves) */
  double *w; /* one supernode's block while make_single inverts it */
  size_t w_size;
  size_t n_size; /* the length of y, t, u */
  int ldl;       /* 1: simplicial LDL^T (chol_create_ldl) */
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

static int chol_create(void **state, const struct ps_linsolve *ls, ps_ctx *ctx) {
  (void)ls;
  return create(state, 1, ctx);
}
/* simplicial LDL^T without pivoting, for symmetric indefinite tangents
 * (softening or perfectly plastic arms past a peak): negative pivots are
 * taken, a zero or tiny one is reported singular */
static int chol_create_ldl(void **state, const struct ps_linsolve *ls, ps_ctx *ctx) {
  (void)ls;
  PS_CHECK(create(state, 0, ctx));
  chol_state *s = *state;
  s->c.final_ll = 0;
  s->c.quick_return_if_not_posdef = 0;
  s->ldl = 1;
  return PS_OK;
}
static int chol_create_simplicial(void **state, const struct ps_linsolve *ls, ps_ctx *ctx) {
  (void)ls;
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

/* The status for a failed CHOLMOD call `what`: PS_ERR_NOMEM when CHOLMOD
 * ran out of memory (or the problem is too large for its integers),
 * PS_ERR_SOLVER otherwise; the message names the call. */
static int chol_failed(const chol_state *s, const char *what, ps_ctx *ctx) {
  if (s->c.status == CHOLMOD_OUT_OF_MEMORY || s->c.status == CHOLMOD_TOO_LARGE)
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory in CHOLMOD's %s (status %d)", what,
                    s->c.status);
  return ps_error(ctx, PS_ERR_SOLVER, "CHOLMOD %s failed (status %d)", what, s->c.status);
}

static int chol_analyze(void *state, const ps_csc *A, ps_linsolve_stats *st,
                        ps_ctx *ctx) {
  chol_state *s = state;
  double t = ps_wtime();
  set_header(s, A);
  if (s->L) cholmod_l_free_factor(&s->L, &s->c);
  s->L = cholmod_l_analyze(&s->Ah, &s->c);
  if (!s->L || s->c.status < CHOLMOD_OK)
    return chol_failed(s, "analysis", ctx);
  s->n = A->n;
  s->parts_current = 0;
  s->Lf_current = 0;
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
  st->t_factor += ps_wtime() - t;
  st->n_factor++;
  st->flops_factor = s->c.fl;
  st->nnz_factor = s->c.lnz;
  if (s->c.status == CHOLMOD_NOT_POSDEF && !(s->ldl && s->L->minor == s->L->n)) {
    /* L->minor is a column of the permuted matrix */
    ps_int minor = (ps_int)s->L->minor;
    const ps_int *perm = s->L->Perm;
    *bad_col = perm && minor < (ps_int)s->L->n ? perm[minor] : minor;
    return PS_NOT_POSDEF;
  }
  if (!ok || s->c.status < CHOLMOD_OK)
    return chol_failed(s, "factorisation", ctx);
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
    return chol_failed(s, "solve", ctx);
  const double *xx = s->X->x;
  for (ps_int k = 0; k < s->n; k++) x[k] = xx[k];
  st->t_solve += ps_wtime() - t;
  st->n_solve++;
  return PS_OK;
}

/* supernodes of at most this many columns have their diagonal block
 * inverted for the single-precision solve (make_single); wider ones, few
 * and large, keep L: strsv is blocked and efficient there, and inverting
 * them would double the cost of making the float copy for no faster CG */
#define PS_INVERT_MAX_COLUMNS 64

/* BLAS and LAPACK (OpenBLAS; 32-bit integers, as CHOLMOD's own calls) */
void sgemv_(const char *trans, const int *m, const int *n, const float *alpha,
            const float *a, const int *lda, const float *x, const int *incx,
            const float *beta, float *y, const int *incy);
void strsv_(const char *uplo, const char *trans, const char *diag, const int *n,
            const float *a, const int *lda, float *x, const int *incx);
void dtrsm_(const char *side, const char *uplo, const char *transa, const char *diag,
            const int *m, const int *n, const double *alpha, const double *a,
            const int *lda, double *b, const int *ldb);
void dtrtri_(const char *uplo, const char *diag, const int *n, double *a, const int *lda,
             int *info);

/* Makes s->Lf, s->y, s->t, s->u for the current supernodal factor: the
 * block [L_d; L_b] of each supernode of at most PS_INVERT_MAX_COLUMNS
 * columns (nr x nc, column-major, its diagonal block L_d first) becomes
 * W = [L_d^-1; L_b L_d^-1] (computed in double, the upper triangle of the
 * top block zero), rounded to float; wider blocks are L rounded. PS_OK,
 * PS_ERR_NOMEM, or PS_SINGULAR (a diagonal block is singular: the
 * factor's solves stay in double). */
static int make_single(chol_state *s, ps_ctx *ctx) {
  const cholmod_factor *L = s->L;
  const ps_int *super = L->super, *pi = L->pi, *px = L->px;
  size_t wmax = 0; /* the largest supernode block */
  for (size_t sn = 0; sn < L->nsuper; sn++)
    if ((size_t)(px[sn + 1] - px[sn]) > wmax) wmax = (size_t)(px[sn + 1] - px[sn]);
  if (L->xsize > s->Lf_size || wmax > s->w_size || (size_t)s->n > s->n_size || !s->y) {
    free(s->Lf);
    free(s->y);
    free(s->t);
    free(s->u);
    free(s->w);
    s->Lf_size = s->w_size = 0;
    s->Lf = ps_calloc(L->xsize, sizeof *s->Lf, ctx);
    s->y = ps_calloc((size_t)s->n, sizeof *s->y, ctx);
    s->t = ps_calloc((size_t)s->n, sizeof *s->t, ctx); /* >= any supernode's rows */
    s->u = ps_calloc((size_t)s->n, sizeof *s->u, ctx);
    s->w = ps_calloc(wmax, sizeof *s->w, ctx);
    if (!s->Lf || !s->y || !s->t || !s->u || !s->w) return PS_ERR_NOMEM;
    s->Lf_size = L->xsize;
    s->w_size = wmax;
    s->n_size = (size_t)s->n;
  }
  const double *Lx = L->x;
  const double d_one = 1.0;
  for (size_t sn = 0; sn < L->nsuper; sn++) {
    int nc = (int)(super[sn + 1] - super[sn]), nr = (int)(pi[sn + 1] - pi[sn]), m = nr - nc;
    float *f = s->Lf + px[sn];
    if (nc > PS_INVERT_MAX_COLUMNS) { /* wide: kept as L, solved by strsv */
      const double *l = Lx + px[sn];
      for (size_t k = 0; k < (size_t)nr * (size_t)nc; k++) f[k] = (float)l[k];
      continue;
    }
    double *w = s->w;
    memcpy(w, Lx + px[sn], (size_t)nr * (size_t)nc * sizeof *w);
    for (int j = 1; j < nc; j++) /* CHOLMOD leaves the upper triangle unused */
      for (int i = 0; i < j; i++) w[(size_t)j * nr + i] = 0.0;
    /* W_b = L_b L_d^-1 first (it needs L_d), then L_d^-1 in place */
    if (m > 0) dtrsm_("R", "L", "N", "N", &m, &nc, &d_one, w, &nr, w + nc, &nr);
    int info = 0;
    dtrtri_("L", "N", &nc, w, &nr, &info);
    if (info != 0) { /* not after a successful factorisation (L_jj > 0) */
      s->Lf_current = -1;
      return PS_SINGULAR;
    }
    for (size_t k = 0; k < (size_t)nr * (size_t)nc; k++) f[k] = (float)w[k];
  }
  s->Lf_current = 1;
  return PS_OK;
}

/* The parts of the supernodal elimination tree for the preconditioner's
 * solves (ps_linsolve.parts of them, on the team's threads): the subtrees
 * of disjoint sets of supernodes (parts 0 .. P - 1) have no column in
 * common, so their forward and backward solves can run at the same time;
 * what lies above them (the top, part P; with nested dissection the top
 * separators) is solved by one thread between them. Forward, the
 * subtrees update rows of the top part too; part 0 writes those into y,
 * part p >= 1 into its own z_p, added to y in the order of the parts
 * afterwards, so the sums are the same on any number of threads (and
 * depend on P). */

/* the top is grown from the roots down, a heaviest subtree at a time,
 * at most this many times, and the cheapest split seen is kept */
#define PS_PART_EXPANSIONS 256

typedef struct {
  double w;  /* the subtree's work */
  ps_int sn; /* its root */
} part_cand;

static int cand_heavier(const void *p, const void *q) {
  const part_cand *a = p, *b = q;
  if (a->w != b->w) return a->w > b->w ? -1 : 1;
  return a->sn < b->sn ? -1 : a->sn > b->sn;
}

/* cands sorted heaviest first, each to the lightest of n_bins bins (the
 * first of equally light ones; LPT): the heaviest bin's work (bins[c] =
 * its bin when bins is not NULL; load: n_bins doubles of work space) */
static double split_cands(part_cand *cand, ps_int n, int n_bins, double *load,
                          unsigned char *bins) {
  qsort(cand, (size_t)n, sizeof *cand, cand_heavier);
  for (int b = 0; b < n_bins; b++) load[b] = 0.0;
  for (ps_int c = 0; c < n; c++) {
    int b = 0;
    for (int k = 1; k < n_bins; k++)
      if (load[k] < load[b]) b = k;
    load[b] += cand[c].w;
    if (bins) bins[c] = (unsigned char)b;
  }
  double most = load[0];
  for (int b = 1; b < n_bins; b++) most = fmax(most, load[b]);
  return most;
}

/* Makes s->part_list, part_ptr, top_pos and the parts' work space for
 * the current analysis in n_parts parts (1 .. PS_PARTS_MAX). The work of
 * a supernode is the entries of its block (read once each way) plus its
 * rows. Supernodes whose parent does not follow them (CHOLMOD orders them
 * so; checked) leave everything in the top part: one thread. PS_OK or
 * PS_ERR_NOMEM. */
static int make_parts(chol_state *s, int n_parts, ps_linsolve_stats *st, ps_ctx *ctx) {
  const cholmod_factor *L = s->L;
  ps_int ns = (ps_int)L->nsuper, n = s->n;
  const ps_int *super = L->super, *pi = L->pi, *Ls = L->s;
  const int top_part = n_parts; /* the top's number in part[] */
  free(s->part_list);
  free(s->part_ptr);
  free(s->top_pos);
  free(s->t_parts);
  free(s->u_parts);
  free(s->z);
  s->t_parts = s->u_parts = NULL;
  s->z = NULL;
  s->parts_current = 0;
  s->part_list = ps_calloc((size_t)ns + 1, sizeof *s->part_list, ctx);
  s->part_ptr = ps_calloc((size_t)n_parts + 2, sizeof *s->part_ptr, ctx);
  s->top_pos = ps_calloc((size_t)n + 1, sizeof *s->top_pos, ctx);
  double *load = ps_calloc((size_t)n_parts, sizeof *load, ctx);
  ps_int *parent = ps_calloc((size_t)ns + 1, sizeof *parent, ctx);
  ps_int *col_sn = ps_calloc((size_t)n + 1, sizeof *col_sn, ctx);
  ps_int *child = ps_calloc((size_t)ns + 1, sizeof *child, ctx); /* first child */
  ps_int *sibling = ps_calloc((size_t)ns + 1, sizeof *sibling, ctx);
  ps_int *expanded = ps_calloc(PS_PART_EXPANSIONS, sizeof *expanded, ctx);
  double *w_self = ps_calloc((size_t)ns + 1, sizeof *w_self, ctx);
  double *w_tree = ps_calloc((size_t)ns + 1, sizeof *w_tree, ctx);
  part_cand *cand = ps_calloc((size_t)ns + 1, sizeof *cand, ctx);
  unsigned char *part = ps_calloc((size_t)ns + 1, 1, ctx);
  unsigned char *bins = ps_calloc((size_t)ns + 1, 1, ctx);
  int status = PS_OK;
  if (!s->part_list || !s->part_ptr || !s->top_pos || !load || !parent || !col_sn || !child ||
      !sibling || !expanded || !w_self || !w_tree || !cand || !part || !bins) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  int tree_ok = 1;
  for (ps_int sn = 0; sn < ns; sn++)
    for (ps_int k = super[sn]; k < super[sn + 1]; k++) col_sn[k] = sn;
  for (ps_int sn = 0; sn < ns; sn++) {
    ps_int nc = super[sn + 1] - super[sn], nr = pi[sn + 1] - pi[sn];
    parent[sn] = nr > nc ? col_sn[Ls[pi[sn] + nc]] : -1;
    if (parent[sn] >= 0 && parent[sn] <= sn) tree_ok = 0;
    for (ps_int r = pi[sn] + nc + 1; r < pi[sn + 1]; r++) /* rows sorted: the */
      if (Ls[r] <= Ls[r - 1]) tree_ok = 0;                /* first is the parent */
    w_self[sn] = w_tree[sn] = (double)nr * (double)nc + (double)nr;
    child[sn] = sibling[sn] = -1;
  }
  ps_int n_exp = 0, best_exp = 0, n_cand = 0;
  double w_all = 0.0, w_top_best = 0.0;
  for (ps_int sn = 0; sn < ns; sn++) w_all += w_self[sn];
  st->serial_share = 1.0;
  if (tree_ok) {
    for (ps_int sn = 0; sn < ns; sn++)
      if (parent[sn] >= 0) w_tree[parent[sn]] += w_tree[sn];
    for (ps_int sn = ns - 1; sn >= 0; sn--)
      if (parent[sn] >= 0) {
        sibling[sn] = child[parent[sn]];
        child[parent[sn]] = sn;
      }
    for (ps_int sn = 0; sn < ns; sn++)
      if (parent[sn] < 0) cand[n_cand++] = (part_cand){w_tree[sn], sn};
    double w_top = 0.0, best = split_cands(cand, n_cand, n_parts, load, NULL);
    while (n_parts > 1 && n_exp < PS_PART_EXPANSIONS && n_cand > 0) { /* one: no top */
      ps_int h = cand[0].sn; /* the heaviest (split_cands sorted them) */
      expanded[n_exp++] = h;
      w_top += w_self[h];
      cand[0] = cand[--n_cand];
      for (ps_int c = child[h]; c >= 0; c = sibling[c]) cand[n_cand++] = (part_cand){w_tree[c], c};
      double cost = split_cands(cand, n_cand, n_parts, load, NULL) + w_top;
      if (cost < best) {
        best = cost;
        best_exp = n_exp;
        w_top_best = w_top;
      }
    }
  }
  /* the best split: the first best_exp expansions are the top, the
   * subtrees below them go to the bins; without a tree, all is top */
  for (ps_int sn = 0; sn < ns; sn++) part[sn] = tree_ok ? 255 : (unsigned char)top_part;
  if (tree_ok) {
    for (ps_int e = 0; e < best_exp; e++) part[expanded[e]] = (unsigned char)top_part;
    n_cand = 0;
    for (ps_int sn = 0; sn < ns; sn++)
      if (part[sn] != top_part && (parent[sn] < 0 || part[parent[sn]] == top_part))
        cand[n_cand++] = (part_cand){w_tree[sn], sn};
    split_cands(cand, n_cand, n_parts, load, bins);
    for (ps_int c = 0; c < n_cand; c++) part[cand[c].sn] = bins[c];
    for (ps_int sn = ns - 1; sn >= 0; sn--) /* parents before children */
      if (part[sn] == 255) part[sn] = part[parent[sn]];
    st->serial_share = w_all > 0 && n_parts > 1 ? w_top_best / w_all : 1.0;
  }
  ps_int m = 0;
  for (int p = 0; p <= top_part; p++) {
    s->part_ptr[p] = m;
    for (ps_int sn = 0; sn < ns; sn++)
      if (part[sn] == p) s->part_list[m++] = sn;
  }
  s->part_ptr[top_part + 1] = m;
  s->n_top = 0;
  for (ps_int k = 0; k < n; k++) s->top_pos[k] = part[col_sn[k]] == top_part ? s->n_top++ : -1;
  s->rows_max = 1;
  for (ps_int sn = 0; sn < ns; sn++)
    if (pi[sn + 1] - pi[sn] > s->rows_max) s->rows_max = pi[sn + 1] - pi[sn];
  if (n_parts > 1) { /* one entry at least, so that no size is 0 */
    size_t others = (size_t)n_parts - 1;
    s->t_parts = ps_calloc(others * (size_t)s->rows_max, sizeof *s->t_parts, ctx);
    s->u_parts = ps_calloc(others * (size_t)s->rows_max, sizeof *s->u_parts, ctx);
    s->z = ps_calloc(others * (size_t)(s->n_top > 0 ? s->n_top : 1), sizeof *s->z, ctx);
    if (!s->t_parts || !s->u_parts || !s->z) {
      status = PS_ERR_NOMEM;
      goto cleanup;
    }
  }
  s->n_parts = n_parts;
  s->parts_current = 1;
cleanup:
  free(parent);
  free(col_sn);
  free(child);
  free(sibling);
  free(expanded);
  free(w_self);
  free(w_tree);
  free(cand);
  free(part);
  free(bins);
  free(load);
  return status;
}

/* supernode sn of the float factor: its first column k1, nc columns, nr
 * rows (indices rows) and block W (make_single) */
typedef struct {
  ps_int k1;
  int nc, nr;
  const ps_int *rows;
  const float *W;
} float_block;

static float_block block_of(const chol_state *s, ps_int sn) {
  const cholmod_factor *L = s->L;
  const ps_int *super = L->super, *pi = L->pi, *px = L->px;
  float_block b = {super[sn], (int)(super[sn + 1] - super[sn]), (int)(pi[sn + 1] - pi[sn]),
                   (const ps_int *)L->s + pi[sn], s->Lf + px[sn]};
  return b;
}

/* Forward step of supernode sn of L y = P b: y_c = L_d^-1 y_c and
 * y_b -= L_b y_c, with the updates of the rows of the top part into
 * z[top_pos[row]] instead when z is not NULL (parts 1 ..) */
static void forward_supernode(const chol_state *s, ps_int sn, float *t, float *u, double *y,
                              double *z) {
  const int one = 1;
  const float f_one = 1.0f, f_zero = 0.0f;
  float_block B = block_of(s, sn);
  int nc = B.nc, nr = B.nr;
  if (nc > PS_INVERT_MAX_COLUMNS) { /* t_c = L_d^-1 y_c (strsv), t_b = L_b t_c */
    int m = nr - nc;
    for (int i = 0; i < nc; i++) t[i] = (float)y[B.k1 + i];
    strsv_("L", "N", "N", &nc, B.W, &nr, t, &one);
    if (m > 0) sgemv_("N", &m, &nc, &f_one, B.W + nc, &nr, t, &one, &f_zero, t + nc, &one);
  } else { /* t = W y_c */
    for (int i = 0; i < nc; i++) u[i] = (float)y[B.k1 + i];
    sgemv_("N", &nr, &nc, &f_one, B.W, &nr, u, &one, &f_zero, t, &one);
  }
  for (int i = 0; i < nc; i++) y[B.k1 + i] = t[i];
  if (!z)
    for (int i = nc; i < nr; i++) y[B.rows[i]] -= t[i];
  else
    for (int i = nc; i < nr; i++) {
      ps_int r = B.rows[i], tp = s->top_pos[r];
      if (tp >= 0)
        z[tp] -= t[i];
      else
        y[r] -= t[i];
    }
}

/* Backward step of supernode sn of L^T x = y (x in y) */
static void backward_supernode(const chol_state *s, ps_int sn, float *t, float *u, double *y) {
  const int one = 1;
  const float f_one = 1.0f, f_zero = 0.0f;
  float_block B = block_of(s, sn);
  int nc = B.nc, nr = B.nr;
  for (int i = 0; i < nc; i++) t[i] = (float)y[B.k1 + i];
  for (int i = nc; i < nr; i++) t[i] = -(float)y[B.rows[i]];
  if (nc > PS_INVERT_MAX_COLUMNS) { /* L_d^T x_c = y_c - L_b^T x_b */
    int m = nr - nc;
    if (m > 0) sgemv_("T", &m, &nc, &f_one, B.W + nc, &nr, t + nc, &one, &f_one, t, &one);
    strsv_("L", "T", "N", &nc, B.W, &nr, t, &one);
    for (int i = 0; i < nc; i++) y[B.k1 + i] = t[i];
  } else { /* x_c = W^T [y_c; -x_b] */
    sgemv_("T", &nr, &nc, &f_one, B.W, &nr, t, &one, &f_zero, u, &one);
    for (int i = 0; i < nc; i++) y[B.k1 + i] = u[i];
  }
}

typedef struct {
  chol_state *s;
  int backward;
} solve_job;

/* the forward or backward steps of one part below the top */
static void solve_part(void *arg, int part) {
  const solve_job *j = arg;
  chol_state *s = j->s;
  size_t other = part > 0 ? (size_t)(part - 1) : 0;
  float *t = part > 0 ? s->t_parts + other * (size_t)s->rows_max : s->t;
  float *u = part > 0 ? s->u_parts + other * (size_t)s->rows_max : s->u;
  const ps_int *list = s->part_list;
  ps_int p0 = s->part_ptr[part], p1 = s->part_ptr[part + 1];
  if (!j->backward) {
    double *z = part > 0 ? s->z + other * (size_t)s->n_top : NULL;
    for (ps_int k = p0; k < p1; k++) forward_supernode(s, list[k], t, u, s->y, z);
  } else {
    for (ps_int k = p1 - 1; k >= p0; k--) backward_supernode(s, list[k], t, u, s->y);
  }
}

/* x ~= A \ b in single precision: x = P^T L^-T L^-1 P b, supernode by
 * supernode as CHOLMOD's own solve (each supernode a dense column-major
 * block of nr rows, its nc columns first), with the blocks of make_single,
 * W = [L_d^-1; L_b L_d^-1] in float, so that each narrow supernode is one
 * matrix-vector product forward (t = W y_c: the solved y_c and the update
 * of the rows below) and one backward (x_c = W^T [y_c; -x_below]) instead
 * of a triangular solve and a product (OpenBLAS's strsv of a few columns
 * goes column by column in BLAS-1 calls: slower than the product with the
 * whole block); wide supernodes use strsv and sgemv with L. The
 * permuted vector itself is kept in double. The triangular solves of a CG
 * preconditioner are bound by memory bandwidth (L is read twice per
 * iteration), so halving the bytes read is what makes them faster. The
 * `parts` parts of the elimination tree (make_parts) run on the team's
 * threads, the top part between them on one. The preconditioner is
 * symmetric positive definite up to float round-off (the same W forward
 * and, transposed, backward), which CG tolerates. Simplicial factors use
 * chol_solve. */
static int chol_precondition(void *state, const double *b, double *x, ps_team *team,
                             int parts, ps_linsolve_stats *st, ps_ctx *ctx) {
  chol_state *s = state;
  const cholmod_factor *L = s->L;
  if (!L->is_super || s->Lf_current < 0) return chol_solve(state, b, x, st, ctx);
  double t0 = ps_wtime();
  if (!s->Lf_current) {
    int status = make_single(s, ctx);
    if (status < 0) return status;
    if (status > 0) return chol_solve(state, b, x, st, ctx);
  }
  if (parts < 1 || parts > PS_PARTS_MAX)
    return ps_error(ctx, PS_ERR_INPUT, "parts must be 1 to %d (got %d)", PS_PARTS_MAX, parts);
  if (!s->parts_current || s->n_parts != parts) PS_CHECK(make_parts(s, parts, st, ctx));
  const ps_int *super = L->super, *perm = L->Perm;
  ps_int n = s->n;
  double *y = s->y, *z = s->z;
  const ps_int *top = s->part_list + s->part_ptr[parts];
  ps_int n_top = s->part_ptr[parts + 1] - s->part_ptr[parts];
  size_t zn = (size_t)s->n_top;
  for (ps_int k = 0; k < n; k++) y[k] = b[perm ? perm[k] : k];
  solve_job job = {s, 0};
  ps_team_run(team, parts, solve_part, &job); /* L y = P b below the top */
  for (ps_int e = 0; e < n_top && parts > 1; e++) /* y_k += z_1 + z_2 + ..., in order */
    for (ps_int k = super[top[e]]; k < super[top[e] + 1]; k++) {
      ps_int tp = s->top_pos[k];
      for (int p = 1; p < parts; p++) {
        double *zp = z + (size_t)(p - 1) * zn + (size_t)tp;
        y[k] += *zp;
        *zp = 0.0;
      }
    }
  for (ps_int e = 0; e < n_top; e++) forward_supernode(s, top[e], s->t, s->u, y, NULL);
  for (ps_int e = n_top - 1; e >= 0; e--) backward_supernode(s, top[e], s->t, s->u, y);
  job.backward = 1;
  ps_team_run(team, parts, solve_part, &job); /* L^T x = y below the top */
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
  free(s->u);
  free(s->w);
  free(s->t_parts);
  free(s->u_parts);
  free(s->z);
  free(s->part_list);
  free(s->part_ptr);
  free(s->top_pos);
  free(s);
  *state = NULL;
}

static const ps_linsolve_type chol_type = {"cholmod",   chol_create, chol_analyze,
                                           chol_factor, chol_solve,  chol_precondition,
                                           chol_destroy, 0};
const ps_linsolve_type *const ps_linsolve_cholmod = &chol_type;
/* simplicial LL^T (for comparison: much slower on the two-horizon tangent) */
static const ps_linsolve_type chol_simp_type = {
    "cholmod-simplicial", chol_create_simplicial, chol_analyze, chol_factor, chol_solve,
    NULL, chol_destroy, 0};
const ps_linsolve_type *const ps_linsolve_cholmod_simplicial = &chol_simp_type;
static const ps_linsolve_type chol_ldl_type = {
    "cholmod-ldl", chol_create_ldl, chol_analyze, chol_factor, chol_solve, NULL, chol_destroy, 0};
const ps_linsolve_type *const ps_linsolve_cholmod_ldl = &chol_ldl_type;
