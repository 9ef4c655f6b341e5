/* linsolve.c: the generic solver object over a backend table. */
#include "ps_linsolve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const ps_linsolve_type *ps_linsolve_type_find(const char *name) {
  const ps_linsolve_type *const all[] = {ps_linsolve_cholmod, ps_linsolve_umfpack,
                                         ps_linsolve_cholmod_simplicial, ps_linsolve_petsc};
  for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
    if (strcmp(all[i]->name, name) == 0) return all[i];
  return NULL;
}

int ps_linsolve_create(ps_linsolve *ls, const ps_linsolve_type *type,
                       ps_ctx *ctx) {
  memset(ls, 0, sizeof *ls);
  ls->type = type;
  ls->single_after = PS_SINGLE_AFTER;
  ls->parts = PS_PARTS_DEFAULT;
  return type->create(&ls->state, ls, ctx);
}

void ps_linsolve_destroy(ps_linsolve *ls) {
  if (ls->type && ls->state) ls->type->destroy(&ls->state);
  free(ls->kept.x);
  memset(ls, 0, sizeof *ls);
}

int ps_linsolve_keep(ps_linsolve *ls, const ps_csc *A, ps_ctx *ctx) {
  ps_csc *K = &ls->kept;
  size_t nnz = (size_t)A->p[A->n];
  if (nnz > ls->kept_cap) {
    void *x = K->x;
    PS_CHECK(ps_realloc(&x, nnz, sizeof *K->x, ctx));
    K->x = x;
    ls->kept_cap = nnz;
  }
  memcpy(K->x, A->x, nnz * sizeof *K->x);
  K->p = A->p;
  K->i = A->i;
  K->n = A->n;
  return PS_OK;
}

int ps_linsolve_factor(ps_linsolve *ls, const ps_csc *A, ps_int *bad_col,
                       ps_ctx *ctx) {
  if (ls->keep_matrix) PS_CHECK(ps_linsolve_keep(ls, A, ctx));
  if (!ls->analysed || ls->reanalyze) {
    PS_CHECK(ls->type->analyze(ls->state, A, &ls->stats, ctx));
    ls->analysed = 1;
  }
  ls->n_since_factor = 0;
  return ls->type->factor(ls->state, A, bad_col, &ls->stats, ctx);
}

int ps_linsolve_solve(ps_linsolve *ls, const double *b, double *x,
                      ps_ctx *ctx) {
  return ls->type->solve(ls->state, b, x, &ls->stats, ctx);
}

int ps_csc_expand(const ps_csc *A, ps_int c0, ps_int c1, ps_int **Ap_out, ps_int **Ai_out,
                  ps_int **map_out, ps_ctx *ctx) {
  ps_int n = A->n, m = c1 - c0;
  ps_int *Ap = ps_calloc((size_t)m + 1, sizeof *Ap, ctx), *cnt = ps_calloc((size_t)m + 1, sizeof *cnt, ctx);
  ps_int *Ai = NULL, *map = NULL;
  if (!Ap || !cnt) goto nomem;
  /* column counts: upper entries of the columns + the transposes of
   * entries (i, j), i < j, whose row i is one of the columns */
  for (ps_int j = 0; j < n; j++)
    for (ps_int k = A->p[j]; k < A->p[j + 1]; k++) {
      ps_int i = A->i[k];
      if (j >= c0 && j < c1) Ap[j - c0 + 1]++;
      if (i != j && i >= c0 && i < c1) Ap[i - c0 + 1]++;
    }
  for (ps_int c = 0; c < m; c++) Ap[c + 1] += Ap[c];
  Ai = ps_calloc((size_t)Ap[m] + 1, sizeof *Ai, ctx);
  map = ps_calloc((size_t)Ap[m] + 1, sizeof *map, ctx);
  if (!Ai || !map) goto nomem;
  for (ps_int c = 0; c < m; c++) cnt[c] = Ap[c];
  /* column j: its own upper entries (rows <= j, sorted) first, then the
   * transposes of row j's entries in later columns r > j (rows r, in
   * increasing order): rows stay sorted */
  for (ps_int j = c0; j < c1; j++)
    for (ps_int k = A->p[j]; k < A->p[j + 1]; k++) {
      Ai[cnt[j - c0]] = A->i[k];
      map[cnt[j - c0]++] = k;
    }
  for (ps_int r = 0; r < n; r++)
    for (ps_int k = A->p[r]; k < A->p[r + 1]; k++) {
      ps_int i = A->i[k];
      if (i == r || i < c0 || i >= c1) continue;
      /* entry (i, r), i < r; its transpose (r, i) goes into column i */
      Ai[cnt[i - c0]] = r;
      map[cnt[i - c0]++] = k;
    }
  free(cnt);
  *Ap_out = Ap;
  *Ai_out = Ai;
  *map_out = map;
  return PS_OK;
nomem:
  free(Ap);
  free(cnt);
  free(Ai);
  free(map);
  return PS_ERR_NOMEM;
}

void ps_csc_symv(const ps_csc *A, const double *x, double *y) {
  memset(y, 0, (size_t)A->n * sizeof *y);
  for (ps_int j = 0; j < A->n; j++) {
    double xj = x[j], acc = 0.0;
    for (ps_int k = A->p[j]; k < A->p[j + 1]; k++) {
      ps_int i = A->i[k];
      double a = A->x[k];
      y[i] += a * xj;
      if (i != j) acc += a * x[i];
    }
    y[j] += acc;
  }
}

static void csc_apply(void *A, const double *x, double *y) {
  ps_csc_symv((const ps_csc *)A, x, y);
}

ps_operator ps_csc_operator(const ps_csc *A) {
  ps_operator op = {A->n, csc_apply, (void *)A, NULL};
  return op;
}

int ps_linsolve_precondition(ps_linsolve *M, const double *r, double *z, ps_ctx *ctx) {
  if (M->type->precondition &&
      (M->type->precondition_always ||
       (M->single_precision && ++M->n_since_factor > M->single_after)))
    return M->type->precondition(M->state, r, z, M->team, M->parts, &M->stats, ctx);
  return ps_linsolve_solve(M, r, z, ctx);
}

/* a . b over A's own entries (A->owned) and the run's processes
 * (ctx->comm) */
static double dot(const ps_operator *A, const double *a, const double *b, const ps_ctx *ctx) {
  double s = 0.0;
  if (A->owned) {
    for (ps_int k = 0; k < A->n; k++)
      if (A->owned[k]) s += a[k] * b[k];
  } else {
    for (ps_int k = 0; k < A->n; k++) s += a[k] * b[k];
  }
  return ps_comm_sum1(ctx->comm, s);
}

int ps_linsolve_pcg(ps_linsolve *M, const ps_operator *A, const double *b,
                    double *x, double rtol, int maxit, double *work, int *its,
                    ps_ctx *ctx) {
  ps_int n = A->n;
  double *r = work, *z = work + n, *p = work + 2 * n, *Ap = work + 3 * n;
  double bnorm = sqrt(dot(A, b, b, ctx));
  *its = 0;
  memset(x, 0, (size_t)n * sizeof *x);
  if (bnorm == 0.0) return PS_OK;
  memcpy(r, b, (size_t)n * sizeof *r);
  PS_CHECK(ps_linsolve_precondition(M, r, z, ctx)); /* z = M^-1 r */
  memcpy(p, z, (size_t)n * sizeof *p);
  double rz = dot(A, r, z, ctx);
  for (int it = 1; it <= maxit; it++) {
    A->apply(A->data, p, Ap);
    double pAp = dot(A, p, Ap, ctx);
    if (!(rz > 0)) return PS_DIVERGED; /* the preconditioner is not SPD */
    if (!(pAp > 0)) { /* A is not positive definite along p */
      if (it == 1) memcpy(x, p, (size_t)n * sizeof *x); /* p = M^-1 b */
      return PS_NOT_POSDEF;
    }
    double alpha = rz / pAp;
    for (ps_int k = 0; k < n; k++) {
      x[k] += alpha * p[k];
      r[k] -= alpha * Ap[k];
    }
    *its = it;
    if (sqrt(dot(A, r, r, ctx)) <= rtol * bnorm) return PS_OK;
    PS_CHECK(ps_linsolve_precondition(M, r, z, ctx));
    double rz1 = dot(A, r, z, ctx), beta = rz1 / rz;
    rz = rz1;
    for (ps_int k = 0; k < n; k++) p[k] = z[k] + beta * p[k];
  }
  return PS_DIVERGED;
}

int ps_linsolve_gmres(ps_linsolve *M, const ps_operator *A, const double *b, double *x,
                      double rtol, int maxit, int *its, ps_ctx *ctx) {
  const ps_int n = A->n;
  const int m = maxit > 0 ? maxit : 1;
  *its = 0;
  memset(x, 0, (size_t)n * sizeof *x);
  double beta = sqrt(dot(A, b, b, ctx));
  if (beta == 0.0) return PS_OK;
  /* V: the Krylov basis (m + 1 columns of n); H: the Hessenberg matrix,
   * column j at H + j (m + 1), made upper triangular by the rotations
   * (c, sn); g: the rotated right-hand side beta e1 */
  double *V = malloc((size_t)(m + 1) * (size_t)n * sizeof *V);
  double *z = malloc((size_t)n * sizeof *z);
  double *H = calloc((size_t)(m + 1) * (size_t)m, sizeof *H);
  double *rot = calloc((size_t)(3 * m + 1), sizeof *rot);
  if (!V || !z || !H || !rot) {
    free(V), free(z), free(H), free(rot);
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory for GMRES (%d vectors of %lld)", m + 1,
                    (long long)n);
  }
  double *c = rot, *sn = rot + m, *g = rot + 2 * m;
  int status = PS_DIVERGED, k = 0;
  for (ps_int i = 0; i < n; i++) V[i] = b[i] / beta;
  g[0] = beta;
  for (int j = 0; j < m; j++) {
    double *v = V + (size_t)j * n, *w = V + (size_t)(j + 1) * n, *h = H + (size_t)j * (m + 1);
    int st = ps_linsolve_solve(M, v, z, ctx); /* z = M^-1 v_j */
    if (st < 0) {
      status = st;
      goto cleanup;
    }
    A->apply(A->data, z, w); /* w = A z, orthogonalised (modified Gram-Schmidt) */
    for (int i = 0; i <= j; i++) {
      const double *vi = V + (size_t)i * n;
      h[i] = dot(A, w, vi, ctx);
      for (ps_int q = 0; q < n; q++) w[q] -= h[i] * vi[q];
    }
    double hn = h[j + 1] = sqrt(dot(A, w, w, ctx));
    if (hn > 0)
      for (ps_int q = 0; q < n; q++) w[q] /= hn;
    for (int i = 0; i < j; i++) { /* the earlier rotations on column j */
      double t = c[i] * h[i] + sn[i] * h[i + 1];
      h[i + 1] = -sn[i] * h[i] + c[i] * h[i + 1];
      h[i] = t;
    }
    double d = hypot(h[j], h[j + 1]);
    if (!(d > 0)) break; /* A M^-1 singular on the basis */
    c[j] = h[j] / d;
    sn[j] = h[j + 1] / d;
    h[j] = d;
    h[j + 1] = 0.0;
    g[j + 1] = -sn[j] * g[j];
    g[j] *= c[j];
    k = *its = j + 1;
    if (fabs(g[j + 1]) <= rtol * beta || hn == 0.0) { /* hn = 0: exact in the span */
      status = PS_OK;
      break;
    }
  }
  /* y = H^-1 g (back substitution, into g), x = M^-1 V y */
  for (int i = k - 1; i >= 0; i--) {
    for (int l = i + 1; l < k; l++) g[i] -= H[(size_t)l * (m + 1) + i] * g[l];
    g[i] /= H[(size_t)i * (m + 1) + i];
  }
  memset(z, 0, (size_t)n * sizeof *z);
  for (int i = 0; i < k; i++)
    for (ps_int q = 0; q < n; q++) z[q] += g[i] * V[(size_t)i * n + q];
  if (k > 0) {
    int st = ps_linsolve_solve(M, z, x, ctx);
    if (st < 0) status = st;
  }
cleanup:
  free(V), free(z), free(H), free(rot);
  return status;
}
