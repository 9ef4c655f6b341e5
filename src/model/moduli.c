/* moduli.c: the per-particle moment matching of ps_moduli.h (issue 19,
 * doc/moduli.md). For each particle a, over its half-arms b (weights w_b,
 * reference directions n_b) and the monomials m_alpha(n) = n^alpha of
 * degree p (alpha the exponents, |alpha| = p), the factors
 *   phi_b = 1 + lambda . m(n_b),   A lambda = t_a c - sum_b w_b m(n_b),
 *   A = sum_b w_b m(n_b) m(n_b)^T,
 * are the least change sum w (phi - 1)^2 with sum_b w_b phi_b m(n_b) = t_a c,
 * c_alpha the component of the isotropic tensor I_p for the exponents
 * alpha: prod_k (alpha_k - 1)!! when every alpha_k is even, else 0 (I_2 =
 * delta: c = 1 on n_k^2; I_4: 3 on n_k^4, 1 on n_j^2 n_k^2). A is solved by
 * Cholesky (at most 15 x 15); a pivot below 1e-12 of the largest diagonal
 * leaves phi = 1 (singular); factors below PS_MODULI_FLOOR scale the whole
 * change lambda . m down until the lowest is the floor (partial). No
 * global state; the factors of one particle depend on its family only. */
#include "ps_moduli.h"

#include "../linsolve/ps_linsolve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAXMONO 15

int ps_moduli_correction_on(const ps_material *mat) { return mat->surface_correction == 1; }

/* the exponents of the monomials of degree p in N variables, into e[k][3];
 * returns their number */
static int monomials(int N, int p, int e[MAXMONO][3]) {
  int n = 0;
  for (int i = p; i >= 0; i--)
    for (int j = p - i; j >= 0; j--) {
      int k = p - i - j;
      if (N == 2 && k != 0) continue;
      e[n][0] = i;
      e[n][1] = j;
      e[n][2] = k;
      n++;
    }
  return n;
}

static double iso_component(const int e[3]) {
  double c = 1.0;
  for (int k = 0; k < 3; k++) {
    if (e[k] % 2) return 0.0;
    for (int f = e[k] - 1; f > 1; f -= 2) c *= f; /* (e_k - 1)!! */
  }
  return c;
}

static void eval_monomials(int N, int nm, int e[MAXMONO][3], const double *n, double *m) {
  double pw[3][5];
  for (int k = 0; k < 3; k++) {
    double v = k < N ? n[k] : 0.0;
    pw[k][0] = 1.0;
    for (int q = 1; q < 5; q++) pw[k][q] = pw[k][q - 1] * v;
  }
  for (int j = 0; j < nm; j++) m[j] = pw[0][e[j][0]] * pw[1][e[j][1]] * pw[2][e[j][2]];
}

/* Cholesky of the nm x nm symmetric A (lower triangle, in place) and the
 * solve of A x = r (r overwritten by x); 0 when a pivot is below tol */
static int cholesky_solve(int nm, double A[MAXMONO][MAXMONO], double *r) {
  double dmax = 0.0;
  for (int i = 0; i < nm; i++) dmax = fmax(dmax, A[i][i]);
  if (!(dmax > 0)) return 0;
  for (int j = 0; j < nm; j++) {
    double s = A[j][j];
    for (int k = 0; k < j; k++) s -= A[j][k] * A[j][k];
    if (!(s > 1e-12 * dmax)) return 0;
    A[j][j] = sqrt(s);
    for (int i = j + 1; i < nm; i++) {
      double t = A[i][j];
      for (int k = 0; k < j; k++) t -= A[i][k] * A[j][k];
      A[i][j] = t / A[j][j];
    }
  }
  for (int i = 0; i < nm; i++) { /* L y = r */
    double t = r[i];
    for (int k = 0; k < i; k++) t -= A[i][k] * r[k];
    r[i] = t / A[i][i];
  }
  for (int i = nm - 1; i >= 0; i--) { /* L^T x = y */
    double t = r[i];
    for (int k = i + 1; k < nm; k++) t -= A[k][i] * r[k];
    r[i] = t / A[i][i];
  }
  return 1;
}

/* the reference direction of arm i seen from its end p, into n */
static void direction(const ps_particles *P, const ps_network *net, ps_int i, ps_int p,
                      double *n) {
  int N = net->dim;
  ps_int q = net->a[i] == p ? net->b[i] : net->a[i];
  for (int k = 0; k < N; k++) n[k] = (P->x[q * N + k] - P->x[p * N + k]) / net->r0[i];
}

/* ps_moduli_factors with, when code != NULL, each particle's outcome in
 * code[a]: 0 no arm of weight > 0, 1 matched, 2 partial, 3 singular */
static int local_factors(const ps_particles *P, const ps_network *net, int order,
                         const double *w, const double *target, double *phi,
                         ps_moduli_stats *stats, unsigned char *code, ps_ctx *ctx) {
  int N = net->dim;
  if ((order != 2 && order != 4) || (N != 2 && N != 3))
    return ps_error(ctx, PS_ERR_INPUT, "moduli correction: order %d in %d dimensions", order,
                    N);
  int e[MAXMONO][3];
  int nm = monomials(N, order, e);
  double c[MAXMONO];
  for (int j = 0; j < nm; j++) c[j] = iso_component(e[j]);
  ps_moduli_stats s = {0, 0, 0, INFINITY, -INFINITY, 0, 0};
  ps_int na = net->n_arm;
  for (ps_int k = 0; k < 2 * na; k++) phi[k] = 1.0;
  for (ps_int a = 0; a < net->n_particle; a++) {
    double A[MAXMONO][MAXMONO], r[MAXMONO], m[MAXMONO], n[3];
    memset(A, 0, sizeof A);
    for (int j = 0; j < nm; j++) r[j] = target[a] * c[j];
    int any = 0;
    for (ps_int f = net->fam_ptr[a]; f < net->fam_ptr[a + 1]; f++) {
      ps_int i = net->fam_arm[f], side = net->a[i] == a ? i : na + i;
      double wb = w[side];
      if (!(wb > 0)) continue;
      any = 1;
      direction(P, net, i, a, n);
      eval_monomials(N, nm, e, n, m);
      for (int j = 0; j < nm; j++) {
        r[j] -= wb * m[j];
        for (int l = 0; l <= j; l++) A[j][l] += wb * m[j] * m[l];
      }
    }
    if (code) code[a] = 0;
    if (!any) continue;
    if (!cholesky_solve(nm, A, r)) {
      s.n_singular++;
      if (code) code[a] = 3;
      continue;
    }
    /* the change per half-arm, and how far it may go above the floor */
    double tau = 1.0;
    for (int pass = 0; pass < 2; pass++)
      for (ps_int f = net->fam_ptr[a]; f < net->fam_ptr[a + 1]; f++) {
        ps_int i = net->fam_arm[f], side = net->a[i] == a ? i : na + i;
        if (!(w[side] > 0)) continue;
        direction(P, net, i, a, n);
        eval_monomials(N, nm, e, n, m);
        double d = 0.0;
        for (int j = 0; j < nm; j++) d += r[j] * m[j];
        if (pass == 0) {
          if (1.0 + d < PS_MODULI_FLOOR) tau = fmin(tau, (1.0 - PS_MODULI_FLOOR) / -d);
        } else {
          phi[side] = 1.0 + tau * d;
          s.phi_min = fmin(s.phi_min, phi[side]);
          s.phi_max = fmax(s.phi_max, phi[side]);
        }
      }
    if (code) code[a] = tau < 1.0 ? 2 : 1;
    if (tau < 1.0)
      s.n_partial++;
    else
      s.n_matched++;
  }
  if (stats) *stats = s;
  return PS_OK;
}

int ps_moduli_factors(const ps_particles *P, const ps_network *net, int order,
                      const double *w, const double *target, double *phi,
                      ps_moduli_stats *stats, ps_ctx *ctx) {
  return local_factors(P, net, order, w, target, phi, stats, NULL, ctx);
}

/* ---- the force balance (ps_moduli_balance) ----
 * Unknowns: the changes d_h = phi_h - 1 of the free half-arms (those of
 * matched particles). Rows per particle p: its energy moment (nE = 5 or
 * 15 monomials of degree 4, when p is matched) and its force moment (nF =
 * 4 or 10 monomials of degree 3, when p is balanced). Half-arm h of
 * particle a on arm (a, b), direction n from a, has the column
 *   E_a: w_h m4(n),  F_a: k_h m3(n),  F_b: -k_h m3(n)
 * (m3(-n) = -m3(n)). The least change sum w_h d_h^2 under C d = r is d =
 * W^-1 C^T lambda with (C W^-1 C^T) lambda = r, a sparse symmetric
 * positive definite system whose blocks follow the arms (particle p's
 * rows next to each other): factored by CHOLMOD. */

typedef struct {
  int N, nE, nF;
  int e4[MAXMONO][3], e3[MAXMONO][3];
  double c4[MAXMONO];
  ps_int *row0;  /* [np + 1] first row of each particle's block */
  ps_int *coff;  /* [2 n_arm + np]: per family entry (upper neighbour) the
                    offset of its block in the columns of the family's
                    particle; [2 n_arm + q] the diagonal block's offset */
} balance_layout;

static inline int rows_of(const unsigned char *matched, const unsigned char *bal, ps_int p,
                          const balance_layout *L) {
  return (matched[p] == 1 ? L->nE : 0) + (bal[p] ? L->nF : 0);
}

/* the column of half-arm side (arm i, particle a, direction n from a)
 * restricted to a's rows (va[nE + nF], the F part zero when a is not
 * balanced) and to b's F rows (vb[nF]) */
static void half_arm_column(const balance_layout *L, const double *n, double w, double k,
                            double *va, double *vb) {
  double m4[MAXMONO], m3[MAXMONO];
  eval_monomials(L->N, L->nE, (int(*)[3])L->e4, n, m4);
  eval_monomials(L->N, L->nF, (int(*)[3])L->e3, n, m3);
  for (int j = 0; j < L->nE; j++) va[j] = w * m4[j];
  for (int j = 0; j < L->nF; j++) {
    va[L->nE + j] = k * m3[j];
    vb[j] = -k * m3[j];
  }
}

/* one solve of the balance system for the rows selected by matched (1)
 * and bal; phi (in: the local factors; out: the balanced ones of the
 * matched particles). PS_OK, PS_NOT_POSDEF (the system is singular: no
 * change made), or a fatal status. */
static int balance_solve(const ps_particles *P, const ps_network *net, const double *w,
                         const double *k, const double *target, const unsigned char *matched,
                         const unsigned char *bal, const unsigned char *pinned, double *phi,
                         balance_layout *L, ps_linsolve *ls, ps_ctx *ctx) {
  int nE = L->nE, nF = L->nF;
  ps_int np = net->n_particle, na = net->n_arm;
  const ps_int *fp = net->fam_ptr, *fa = net->fam_arm;
  /* rows and block offsets */
  ps_int *row0 = L->row0, *coff = L->coff;
  row0[0] = 0;
  for (ps_int p = 0; p < np; p++) row0[p + 1] = row0[p] + rows_of(matched, bal, p, L);
  ps_int n = row0[np];
  if (n == 0) return PS_OK;
  for (ps_int q = 0; q < np; q++) {
    ps_int off = 0, f = fp[q];
    for (; f < fp[q + 1]; f++) {
      ps_int i = fa[f], o = net->a[i] == q ? net->b[i] : net->a[i];
      if (o > q) break;
      coff[f] = off;
      off += rows_of(matched, bal, o, L);
    }
    coff[2 * na + q] = off;
  }
  /* the CSC pattern: column (q, s) holds q's upper neighbours' rows, then
   * q's own rows 0..s */
  ps_csc S = {n, NULL, NULL, NULL};
  double *r = NULL, *lam = NULL;
  int status = PS_ERR_NOMEM;
  S.p = ps_calloc((size_t)n + 1, sizeof *S.p, ctx);
  if (!S.p) goto done;
  for (ps_int q = 0; q < np; q++) {
    ps_int kq = row0[q + 1] - row0[q];
    for (ps_int s = 0; s < kq; s++) S.p[row0[q] + s + 1] = coff[2 * na + q] + s + 1;
  }
  for (ps_int j = 0; j < n; j++) S.p[j + 1] += S.p[j];
  ps_int nnz = S.p[n];
  S.i = ps_calloc((size_t)nnz, sizeof *S.i, ctx);
  S.x = ps_calloc((size_t)nnz, sizeof *S.x, ctx);
  r = ps_calloc((size_t)n, sizeof *r, ctx);
  lam = ps_calloc((size_t)n, sizeof *lam, ctx);
  if (!S.i || !S.x || !r || !lam) goto done;
  for (ps_int q = 0; q < np; q++) {
    ps_int kq = row0[q + 1] - row0[q];
    for (ps_int s = 0; s < kq; s++) {
      ps_int c = S.p[row0[q] + s];
      for (ps_int f = fp[q]; f < fp[q + 1]; f++) {
        ps_int i = fa[f], o = net->a[i] == q ? net->b[i] : net->a[i];
        if (o > q) break;
        for (ps_int t = row0[o]; t < row0[o + 1]; t++) S.i[c++] = t;
      }
      for (ps_int t = 0; t <= s; t++) S.i[c++] = row0[q] + t;
    }
  }
  /* S += v v^T / w over the free half-arms; the right-hand side */
  for (ps_int p = 0; p < np; p++) {
    if (matched[p] == 1)
      for (int j = 0; j < nE; j++) r[row0[p] + j] = target[p] * L->c4[j];
  }
  for (ps_int i = 0; i < na; i++)
    for (int side = 0; side < 2; side++) {
      ps_int h = side * na + i, a = side ? net->b[i] : net->a[i];
      ps_int b = side ? net->a[i] : net->b[i];
      if (!(w[h] > 0)) continue;
      double nv[3], va[2 * MAXMONO], vb[MAXMONO];
      direction(P, net, i, a, nv);
      half_arm_column(L, nv, w[h], k[h], va, vb);
      int ea = matched[a] == 1 ? nE : 0; /* a's rows: va[0..ea) then F */
      double *ua = va + (ea ? 0 : nE);   /* a's rows in order */
      int ka = row0[a + 1] - row0[a], kb = bal[b] ? nF : 0;
      ps_int rb = row0[b] + (matched[b] == 1 ? nE : 0); /* b's F rows */
      /* the right-hand side: minus the current sums (phi of fixed
       * half-arms as they are, free ones at 1) */
      int free_h = matched[a] == 1 && !pinned[h];
      double ph = free_h ? 1.0 : phi[h];
      for (int j = 0; j < ka; j++) r[row0[a] + j] -= ph * ua[j];
      for (int j = 0; j < kb; j++) r[rb + j] -= ph * vb[j];
      if (!free_h) continue; /* a fixed half-arm: no column */
      double iw = 1.0 / w[h];
      /* diagonal blocks */
      for (int s = 0; s < ka; s++) {
        ps_int c = S.p[row0[a] + s] + coff[2 * na + a];
        for (int t = 0; t <= s; t++) S.x[c + t] += ua[t] * ua[s] * iw;
      }
      for (int s = 0; s < kb; s++) {
        ps_int col = rb + s, c = S.p[col] + coff[2 * na + b];
        for (int t = 0; t <= s; t++) S.x[c + (rb - row0[b]) + t] += vb[t] * vb[s] * iw;
      }
      /* the off-diagonal block between a's rows and b's F rows */
      if (kb) {
        ps_int hi = a < b ? b : a, f = fp[hi];
        while (fa[f] != i) f++;
        if (a < b) { /* rows of a in the columns of b's F rows */
          for (int s = 0; s < kb; s++) {
            ps_int c = S.p[rb + s] + coff[f];
            for (int t = 0; t < ka; t++) S.x[c + t] += ua[t] * vb[s] * iw;
          }
        } else { /* rows of b (its F rows) in the columns of a's rows */
          ps_int sh = rb - row0[b];
          for (int s = 0; s < ka; s++) {
            ps_int c = S.p[row0[a] + s] + coff[f] + sh;
            for (int t = 0; t < kb; t++) S.x[c + t] += vb[t] * ua[s] * iw;
          }
        }
      }
    }
  ps_int bad = -1;
  status = ps_linsolve_factor(ls, &S, &bad, ctx);
  if (status == PS_SINGULAR) status = PS_NOT_POSDEF;
  if (status != PS_OK) goto done;
  status = ps_linsolve_solve(ls, r, lam, ctx);
  if (status != PS_OK) goto done;
  /* d_h = (column . lambda) / w_h */
  for (ps_int i = 0; i < na; i++)
    for (int side = 0; side < 2; side++) {
      ps_int h = side * na + i, a = side ? net->b[i] : net->a[i];
      ps_int b = side ? net->a[i] : net->b[i];
      if (!(w[h] > 0) || matched[a] != 1 || pinned[h]) continue;
      double nv[3], va[2 * MAXMONO], vb[MAXMONO], d = 0.0;
      direction(P, net, i, a, nv);
      half_arm_column(L, nv, w[h], k[h], va, vb);
      int ka = row0[a + 1] - row0[a];
      for (int j = 0; j < ka; j++) d += va[j] * lam[row0[a] + j];
      if (bal[b]) {
        ps_int rb = row0[b] + (matched[b] == 1 ? nE : 0);
        for (int j = 0; j < nF; j++) d += vb[j] * lam[rb + j];
      }
      phi[h] = 1.0 + d / w[h];
    }
done:
  free(S.p);
  free(S.i);
  free(S.x);
  free(r);
  free(lam);
  return status;
}

/* The largest residual of the constraints under the factors phi: over the
 * matched particles (code 1) the energy moment's, |sum_b w_b phi_b m4 -
 * t_a c| / t_a, when energy != 0, and over the balanced ones the force
 * moment's, |sum_b s_cb m3| / sum_b |s_cb| */
static double residual(const ps_particles *P, const ps_network *net, const double *w,
                       const double *k, const double *target, const double *phi,
                       const unsigned char *code, const unsigned char *bal, int energy,
                       const balance_layout *L) {
  ps_int na = net->n_arm;
  double worst = 0.0;
  for (ps_int c = 0; c < net->n_particle; c++) {
    int e = energy && code[c] == 1;
    if (!e && !bal[c]) continue;
    double T[MAXMONO] = {0}, M[MAXMONO] = {0}, m[MAXMONO], n[3], sum = 0.0;
    for (ps_int f = net->fam_ptr[c]; f < net->fam_ptr[c + 1]; f++) {
      ps_int i = net->fam_arm[f], h = net->a[i] == c ? i : na + i;
      direction(P, net, i, c, n);
      if (bal[c]) {
        double sc = k[i] * phi[i] + k[na + i] * phi[na + i];
        eval_monomials(L->N, L->nF, (int(*)[3])L->e3, n, m);
        for (int j = 0; j < L->nF; j++) T[j] += sc * m[j];
        sum += fabs(sc);
      }
      if (e && w[h] > 0) {
        eval_monomials(L->N, L->nE, (int(*)[3])L->e4, n, m);
        for (int j = 0; j < L->nE; j++) M[j] += w[h] * phi[h] * m[j];
      }
    }
    for (int j = 0; bal[c] && j < L->nF; j++) worst = fmax(worst, fabs(T[j]) / sum);
    for (int j = 0; e && j < L->nE; j++)
      worst = fmax(worst, fabs(M[j] - target[c] * L->c4[j]) / target[c]);
  }
  return worst;
}

int ps_moduli_balance(const ps_particles *P, const ps_network *net, const double *w,
                      const double *k, const double *target, double *phi,
                      ps_moduli_stats *stats, ps_ctx *ctx) {
  int N = net->dim;
  if (N != 2 && N != 3)
    return ps_error(ctx, PS_ERR_INPUT, "moduli correction: %d dimensions", N);
  ps_int np = net->n_particle, na = net->n_arm;
  balance_layout L;
  L.N = N;
  L.nE = monomials(N, 4, L.e4);
  L.nF = monomials(N, 3, L.e3);
  for (int j = 0; j < L.nE; j++) L.c4[j] = iso_component(L.e4[j]);
  unsigned char *code = ps_calloc((size_t)np, 1, ctx), *bal = ps_calloc((size_t)np, 1, ctx);
  unsigned char *cut = ps_calloc((size_t)np, 1, ctx), *pinned = ps_calloc((size_t)(2 * na), 1, ctx);
  double *local = ps_calloc((size_t)(2 * na), sizeof *local, ctx);
  L.row0 = ps_calloc((size_t)np + 1, sizeof *L.row0, ctx);
  L.coff = ps_calloc((size_t)(2 * na + np), sizeof *L.coff, ctx);
  ps_moduli_stats s;
  ps_linsolve ls;
  int status = PS_ERR_NOMEM, lsok = 0;
  if (!code || !bal || !cut || !pinned || !local || !L.row0 || !L.coff) goto done;
  status = local_factors(P, net, 4, w, target, local, &s, code, ctx);
  if (status != PS_OK) goto done;
  /* surface particles: a family that a free surface, a hole or a crack
   * cuts off has a large first moment. A family is cut when its particle
   * or a neighbour is on the surface (a surface within reach), and a
   * particle is balanced when it is matched and neither its family nor a
   * neighbour's is cut: on a lattice every arm of a balanced particle then
   * joins two complete families, whose local factors balance it already */
  for (ps_int a = 0; a < np; a++) {
    double m0 = 0.0, m1[3] = {0, 0, 0}, n[3];
    for (ps_int f = net->fam_ptr[a]; f < net->fam_ptr[a + 1]; f++) {
      ps_int i = net->fam_arm[f], h = net->a[i] == a ? i : na + i;
      if (!(w[h] > 0)) continue;
      direction(P, net, i, a, n);
      m0 += w[h];
      for (int c = 0; c < N; c++) m1[c] += w[h] * n[c];
    }
    double g = sqrt(m1[0] * m1[0] + m1[1] * m1[1] + m1[2] * m1[2]);
    bal[a] = !(m0 > 0) || g > PS_MODULI_SURFACE * m0; /* on the surface */
  }
  for (ps_int a = 0; a < np; a++) {
    cut[a] = bal[a];
    for (ps_int f = net->fam_ptr[a]; !cut[a] && f < net->fam_ptr[a + 1]; f++) {
      ps_int i = net->fam_arm[f];
      cut[a] = bal[net->a[i] == a ? net->b[i] : net->a[i]];
    }
  }
  for (ps_int a = 0; a < np; a++) {
    bal[a] = code[a] == 1 && !cut[a];
    for (ps_int f = net->fam_ptr[a]; bal[a] && f < net->fam_ptr[a + 1]; f++) {
      ps_int i = net->fam_arm[f];
      if (cut[net->a[i] == a ? net->b[i] : net->a[i]]) bal[a] = 0;
    }
  }
  /* nothing to do where the local factors balance every balanced particle
   * already (a lattice: the same factors, bit for bit) */
  /* in 3D the system's factor is too large (25 rows a particle, ~100
   * neighbours: 212 s and 5.4 GB for a jittered box of 4,500 particles,
   * against 6 s for the whole run without it): 3D clouds keep the local
   * factors, n_balanced = 0 */
  int already = residual(P, net, w, k, target, local, code, bal, 0, &L) <= 1e-12;
  if (already || N == 3) {
    if (!already) memset(bal, 0, (size_t)np);
    memcpy(phi, local, (size_t)(2 * na) * sizeof *phi);
    s.n_balanced = 0;
    for (ps_int a = 0; a < np; a++) s.n_balanced += bal[a];
    s.balance_passes = 0;
    if (stats) *stats = s;
    status = PS_OK;
    goto done;
  }
  /* the bound phi >= floor by an active set: a free half-arm whose factor
   * falls below it is held at the floor and the system solved again (the
   * same pattern: one analysis) */
  status = ps_linsolve_create(&ls, ps_linsolve_cholmod, ctx);
  if (status != PS_OK) goto done;
  lsok = 1;
  for (int pass = 1; pass <= 8; pass++) {
    memcpy(phi, local, (size_t)(2 * na) * sizeof *phi);
    for (ps_int h = 0; h < 2 * na; h++)
      if (pinned[h]) phi[h] = PS_MODULI_FLOOR;
    status = balance_solve(P, net, w, k, target, code, bal, pinned, phi, &L, &ls, ctx);
    int ok = status == PS_OK && residual(P, net, w, k, target, phi, code, bal, 1, &L) <= 1e-8;
    if (status != PS_OK && status != PS_NOT_POSDEF) goto done;
    status = PS_OK;
    int low = 0;
    for (ps_int h = 0; ok && h < 2 * na; h++) {
      ps_int i = h < na ? h : h - na, a = h < na ? net->a[i] : net->b[i];
      if (w[h] > 0 && code[a] == 1 && !pinned[h] && phi[h] < PS_MODULI_FLOOR)
        pinned[h] = 1, low = 1;
    }
    s.balance_passes = pass;
    if (ok && !low) break;
    if (!ok || pass == 8) { /* singular, inaccurate or still below: the local factors */
      memcpy(phi, local, (size_t)(2 * na) * sizeof *phi);
      s.balance_passes = -pass;
      break;
    }
  }
  s.n_balanced = 0;
  for (ps_int a = 0; a < np; a++) s.n_balanced += s.balance_passes > 0 && bal[a];
  s.phi_min = INFINITY;
  s.phi_max = -INFINITY;
  for (ps_int h = 0; h < 2 * na; h++)
    if (w[h] > 0) {
      s.phi_min = fmin(s.phi_min, phi[h]);
      s.phi_max = fmax(s.phi_max, phi[h]);
    }
  if (stats) *stats = s;
done:
  if (lsok) ps_linsolve_destroy(&ls);
  free(code);
  free(bal);
  free(cut);
  free(pinned);
  free(local);
  free(L.row0);
  free(L.coff);
  return status;
}
