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

#include <math.h>
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

int ps_moduli_factors(const ps_particles *P, const ps_network *net, int order,
                      const double *w, const double *target, double *phi,
                      ps_moduli_stats *stats, ps_ctx *ctx) {
  int N = net->dim;
  if ((order != 2 && order != 4) || (N != 2 && N != 3))
    return ps_error(ctx, PS_ERR_INPUT, "moduli correction: order %d in %d dimensions", order,
                    N);
  int e[MAXMONO][3];
  int nm = monomials(N, order, e);
  double c[MAXMONO];
  for (int j = 0; j < nm; j++) c[j] = iso_component(e[j]);
  ps_moduli_stats s = {0, 0, 0, INFINITY, -INFINITY};
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
    if (!any) continue;
    if (!cholesky_solve(nm, A, r)) {
      s.n_singular++;
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
    if (tau < 1.0)
      s.n_partial++;
    else
      s.n_matched++;
  }
  if (stats) *stats = s;
  return PS_OK;
}
