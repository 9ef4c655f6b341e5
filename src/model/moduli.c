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

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_math.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAXMONO 15
#define MAXE 21 /* energy rows of a particle: 15, or 3 x 7 (restricted_energy) */

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
  ps_moduli_stats s = {0, 0, 0, INFINITY, -INFINITY, 0, 0, 0, 0};
  ps_int na = net->n_arm;
  for (ps_int k = 0; k < 2 * na; k++) phi[k] = 1.0;
  for (ps_int a = 0; a < net->n_particle; a++) {
    double A[MAXMONO * MAXMONO], r[MAXMONO], m[MAXMONO], n[3];
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
        for (int l = 0; l <= j; l++) A[j * nm + l] += wb * m[j] * m[l];
      }
    }
    if (code) code[a] = 0;
    if (!any) continue;
    if (!ps_dense_cholesky(nm, A, 1e-12)) {
      s.n_singular++;
      if (code) code[a] = 3;
      continue;
    }
    ps_dense_cholesky_solve(nm, A, r);
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
 * matched particles). Rows per particle p: its energy moment (nE
 * monomials mE of degree p = order: 5 or 15 for p = 4, 3 or 6 for p = 2;
 * when p is matched) and its force moment (nF monomials mF of degree p - 1:
 * 4 or 10, 2 or 3; when p is balanced). Half-arm h of particle a on arm
 * (a, b), direction n from a, has the column
 *   E_a: w_h mE(n),  F_a: k_h mF(n),  F_b: -k_h mF(n)
 * (mF(-n) = -mF(n), the degree being odd). The least change sum w_h
 * d_h^2 under C d = r is d = W^-1 C^T lambda with (C W^-1 C^T) lambda =
 * r, a sparse symmetric positive definite system whose blocks follow the
 * arms (particle p's rows next to each other): factored by CHOLMOD in 2D,
 * solved by CG in 3D. */

typedef struct {
  int N, nE, nF;
  int eE[MAXMONO][3], eF[MAXMONO][3];
  double cE[MAXMONO];
  const unsigned char *type; /* [np] force rows: 0 none, 1 the moment mF,
                                2 the surface states (below) */
  unsigned char *ns;         /* [np] surface states of a type-2 particle */
  double *seps;              /* [np][3][9] their strains, times 2G */
  int order;                 /* of the energy moment: 2 or 4 */
  double beta;               /* the arm force is s (n.eps.n + beta tr eps) n */
  double lam_over_G;         /* (K - 2G/N) / G */
  const double *kfix;        /* surf->kfix, scaled by kscale (NULL: none) */
  double kscale;             /* the force rows' scale (ps_moduli_balance) */
  ps_int *row0;  /* [np + 1] first row of each particle's block */
  ps_int *coff;  /* [2 n_arm + np]: per family entry of a neighbour with a
                    lower number, the offset of its block in the columns
                    of the family's particle; [2 n_arm + q] the diagonal
                    block's offset */
} balance_layout;

/* the number of force rows of particle p */
static inline int force_rows(const balance_layout *L, ps_int p) {
  return L->type[p] == 1 ? L->nF : L->type[p] == 2 ? L->N * L->ns[p] : 0;
}

/* the rows per surface state of a particle matched under those states
 * only (restricted_energy): order 2, 1; order 4, N (N + 1)/2, and 1 more
 * without kfix */
static inline int restricted_rows(const balance_layout *L) {
  return L->order == 2 ? 1 : L->N * (L->N + 1) / 2 + (L->kfix ? 0 : 1);
}

/* the number of energy rows of particle p: the moment's nE when p is
 * matched (code 1); when its energy is matched under its surface states
 * only (code 5), ns restricted_rows (restricted_energy) */
static inline int energy_rows(const unsigned char *matched, ps_int p, const balance_layout *L) {
  return matched[p] == 1 ? L->nE : matched[p] == 5 ? L->ns[p] * restricted_rows(L) : 0;
}

static inline int rows_of(const unsigned char *matched, ps_int p, const balance_layout *L) {
  return energy_rows(matched, p, L) + force_rows(L, p);
}

/* the trace of surface state q of particle p */
static double state_trace(const balance_layout *L, ps_int p, int q) {
  const double *e = &L->seps[(p * 3 + q) * 9];
  double tr = 0.0;
  for (int i = 0; i < L->N; i++) tr += e[i * L->N + i];
  return tr;
}

/* the strain n.e.n of direction n under surface state q of particle p */
static double state_strain(const balance_layout *L, ps_int p, int q, const double *n) {
  const double *e = &L->seps[(p * 3 + q) * 9];
  double g = 0.0;
  for (int i = 0; i < L->N; i++)
    for (int j = 0; j < L->N; j++) g += n[i] * e[i * L->N + j] * n[j];
  return g;
}

/* The energy rows of a particle p matched under its surface states e_q
 * only (code 5: one whose family cannot carry the isotropic moment with
 * factors above the floor, such as a 3D edge, where the continuum carries
 * only the stress along the edge). Of the moment's conditions sum_b w_b
 * phi_b n^(x)p = t I_p it keeps those its states see, per state e:
 * - order 2 (the state model's dilatation): sum_b w_b phi_b n.e.n = t tr e;
 * - order 4: the half-arm virial stress, sum_b w_b phi_b (n.e.n + beta tr
 *   e) n n (+ the fixed part with kfix, fixed_energy) = t (2 e + (lambda
 *   / G) tr e I), lambda = K - 2G/N (the moment's, traced: G (N + 2)
 *   times it is the continuum's stress times V_a), and, without kfix (the
 *   fibre model), first the mean strain, sum_b w_b phi_b (n.e.n - tr e /
 *   N) = 0 (the state model's dilatation has its own factors: order 2).
 * Then under every combination of its states the particle's mean strain,
 * stress and energy are the continuum's. (Its energy alone is not enough:
 * along a 3D bar the factors that match it leave stresses that vary from
 * one cross-section to the next, and a bar 5 widths long came out 4%
 * stiff.) Coefficients of direction n into m, the targets over t into c
 * (either may be NULL). */
static void restricted_energy(const balance_layout *L, ps_int p, const double *n, double *m,
                              double *c) {
  int N = L->N, ns = L->ns[p], j = 0;
  for (int q = 0; q < ns; q++) {
    const double *e = &L->seps[(p * 3 + q) * 9];
    double tr = state_trace(L, p, q), g = n ? state_strain(L, p, q, n) : 0.0;
    if (L->order == 2) {
      if (m) m[j] = g;
      if (c) c[j] = tr;
      j++;
      continue;
    }
    if (!L->kfix) {
      if (m) m[j] = g - tr / N;
      if (c) c[j] = 0.0;
      j++;
    }
    for (int a = 0; a < N; a++)
      for (int b = a; b < N; b++, j++) {
        if (m) m[j] = (g + L->beta * tr) * n[a] * n[b];
        if (c) c[j] = 2.0 * e[a * N + b] + (a == b ? L->lam_over_G * tr : 0.0);
      }
  }
}

/* 1 when the restricted rows of particle p (restricted_energy) are
 * linearly independent as functions of the direction and fewer than the
 * moment's nE, so that p's block of the multipliers' system is regular
 * and p is not asked for the moment it could not carry. The rows are
 * forms of degree order on the unit sphere, told apart by their values at
 * 64 fixed directions spread over it (2D: 24 on the circle); Gram-Schmidt
 * in order, a row dependent when less than 1e-6 of its norm is left. In
 * 3D an edge's rows (one state) are independent, and a face's (three
 * states: 21 rows of the fibre model, 18 of the state model, quartic
 * forms in a space of 15 dimensions) span the whole moment: a partly
 * matched particle at a face stays out of the stage. */
static int rows_independent(const balance_layout *L, ps_int p) {
  enum { NS = 64 };
  int nr = L->ns[p] * restricted_rows(L), ns = L->N == 2 ? 24 : NS;
  if (nr >= L->nE) return 0;
  double F[MAXE][NS], Q[MAXE][NS];
  for (int s = 0; s < ns; s++) {
    double n[3] = {0, 0, 0}, m[MAXE];
    if (L->N == 2) {
      n[0] = cos(M_PI * (s + 0.5) / ns), n[1] = sin(M_PI * (s + 0.5) / ns);
    } else { /* a Fibonacci lattice on the sphere */
      double z = 1.0 - (2.0 * s + 1.0) / ns, r = sqrt(1.0 - z * z), a = 2.399963229728653 * s;
      n[0] = r * cos(a), n[1] = r * sin(a), n[2] = z;
    }
    restricted_energy(L, p, n, m, NULL);
    for (int j = 0; j < nr; j++) F[j][s] = m[j];
  }
  for (int j = 0; j < nr; j++) {
    double norm0 = 0.0, norm = 0.0;
    for (int s = 0; s < ns; s++) norm0 += F[j][s] * F[j][s];
    for (int k = 0; k < j; k++) {
      double d = 0.0;
      for (int s = 0; s < ns; s++) d += Q[k][s] * F[j][s];
      for (int s = 0; s < ns; s++) F[j][s] -= d * Q[k][s];
    }
    for (int s = 0; s < ns; s++) norm += F[j][s] * F[j][s];
    if (!(norm > 1e-12 * norm0)) return 0;
    for (int s = 0; s < ns; s++) Q[j][s] = F[j][s] / sqrt(norm);
  }
  return 1;
}

/* the fixed part of the restricted rows (code 5, order 4, with kfix) from
 * p's half-arm h of length r0 in direction n: kfix_h r0 tr e_q n n per
 * state q (the state model's dilatation force in its half-arm virial
 * stress), added to M */
static void fixed_energy(const balance_layout *L, const unsigned char *matched, ps_int p,
                         ps_int h, double r0, const double *n, double *M) {
  if (!L->kfix || L->order != 4 || matched[p] != 5) return;
  int N = L->N, j = 0;
  for (int q = 0; q < L->ns[p]; q++) {
    double s = L->kfix[h] * r0 * state_trace(L, p, q);
    for (int a = 0; a < N; a++)
      for (int b = a; b < N; b++, j++) M[j] += s * n[a] * n[b];
  }
}

/* the energy rows' coefficients of an arm of particle p with direction n
 * (before the weight) and, when c != NULL, their targets over t */
static void energy_coefficients(const balance_layout *L, const unsigned char *matched, ps_int p,
                                const double *n, double *m, double *c) {
  if (matched[p] == 5) {
    restricted_energy(L, p, n, m, c);
    return;
  }
  if (m) eval_monomials(L->N, L->nE, (int(*)[3])L->eE, n, m);
  if (c) memcpy(c, L->cE, (size_t)L->nE * sizeof *c);
}

/* the force rows' coefficients of an arm of particle p with direction n
 * (odd in n): type 1, the monomials mF(n); type 2, per surface state e
 * and component i, (n.e.n + beta tr e) n_i */
static void force_coefficients(const balance_layout *L, ps_int p, const double *n, double *f) {
  int N = L->N;
  if (L->type[p] == 1) {
    eval_monomials(N, L->nF, (int(*)[3])L->eF, n, f);
    return;
  }
  for (int q = 0; q < L->ns[p]; q++) {
    double g = state_strain(L, p, q, n) + L->beta * state_trace(L, p, q);
    for (int i = 0; i < N; i++) f[q * N + i] = g * n[i];
  }
}

/* the fixed part of the force rows of particle p (type 2) from arm i in
 * direction n: (kfix_ab + kfix_ba) tr e_q n per state q, added to f
 * (N ns entries); returns its |stiffness| (0 without kfix) */
static double fixed_force(const balance_layout *L, ps_int p, ps_int i, ps_int na,
                          const double *n, double *f) {
  if (!L->kfix || L->type[p] != 2) return 0.0;
  int N = L->N;
  double sf = (L->kfix[i] + L->kfix[na + i]) * L->kscale;
  for (int q = 0; q < L->ns[p]; q++) {
    double tr = state_trace(L, p, q);
    for (int k = 0; k < N; k++) f[q * N + k] += sf * tr * n[k];
  }
  return fabs(sf);
}

/* the column of half-arm side (arm i, particle a, direction n from a)
 * restricted to a's rows (va: a's energy rows, then its force rows) and
 * to b's force rows (vb) */
static void half_arm_column(const balance_layout *L, const unsigned char *matched, ps_int a,
                            ps_int b, const double *n, double w, double k, double *va,
                            double *vb) {
  double mE[MAXE], f[MAXMONO];
  int ne = energy_rows(matched, a, L);
  if (ne) energy_coefficients(L, matched, a, n, mE, NULL);
  for (int j = 0; j < ne; j++) va[j] = w * mE[j];
  force_coefficients(L, a, n, f);
  for (int j = 0; j < force_rows(L, a); j++) va[ne + j] = k * f[j];
  force_coefficients(L, b, n, f);
  for (int j = 0; j < force_rows(L, b); j++) vb[j] = -k * f[j];
}

/* half-arm h's column, restricted to its particle a's rows (ua[ka], at
 * row ra) and to the other end b's F rows (vb[kb], at row rb); free: a
 * column of the system (a matched, h not pinned) */
typedef struct {
  ps_int a, b, ra, rb;
  int ka, kb, free;
  double va[MAXE + MAXMONO], vb[MAXMONO], *ua;
} half_arm;

static void half_arm_get(const ps_particles *P, const ps_network *net, const double *w,
                         const double *k, const unsigned char *matched,
                         const unsigned char *pinned, const balance_layout *L, ps_int h,
                         half_arm *c) {
  ps_int na = net->n_arm, i = h < na ? h : h - na;
  double nv[3];
  c->a = h < na ? net->a[i] : net->b[i];
  c->b = h < na ? net->b[i] : net->a[i];
  direction(P, net, i, c->a, nv);
  half_arm_column(L, matched, c->a, c->b, nv, w[h], k[h], c->va, c->vb);
  c->ua = c->va; /* a's rows in order */
  c->ra = L->row0[c->a];
  c->ka = (int)(L->row0[c->a + 1] - c->ra);
  c->kb = force_rows(L, c->b);
  c->rb = L->row0[c->b] + energy_rows(matched, c->b, L);
  c->free = (matched[c->a] == 1 || matched[c->a] == 5) && !pinned[h];
}

/* the column of half-arm c dotted with x (a vector over the rows) */
static double column_dot(const half_arm *c, const double *x) {
  double t = 0.0;
  for (int j = 0; j < c->ka; j++) t += c->ua[j] * x[c->ra + j];
  for (int j = 0; j < c->kb; j++) t += c->vb[j] * x[c->rb + j];
  return t;
}

/* The free half-arms' columns scaled by w^-1/2, gathered once for the
 * CG iterations: column c, of particle pa[c] and other end pb[c], has its
 * rows ra[c] .. ra[c] + ka[c] - 1 (its particle's) and rb[c] .. rb[c] +
 * kb[c] - 1 (the other end's force rows), values val[off[c] ..] in that
 * order. */
typedef struct {
  ps_int n, *pa, *pb, *ra, *rb, *off;
  unsigned char *ka, *kb;
  double *val;
} column_cache;

static void cache_free(column_cache *cc) {
  free(cc->pa);
  free(cc->pb);
  free(cc->ra);
  free(cc->rb);
  free(cc->off);
  free(cc->ka);
  free(cc->kb);
  free(cc->val);
}

/* PS_OK or PS_ERR_NOMEM (cc then freed) */
static int cache_build(const ps_particles *P, const ps_network *net, const double *w,
                       const double *k, const unsigned char *matched,
                       const unsigned char *pinned, const balance_layout *L, column_cache *cc,
                       ps_ctx *ctx) {
  ps_int nh = 2 * net->n_arm, n = 0, nv = 0;
  for (int pass = 0; pass < 2; pass++) {
    n = nv = 0;
    for (ps_int h = 0; h < nh; h++) {
      if (!(w[h] > 0)) continue;
      half_arm c;
      half_arm_get(P, net, w, k, matched, pinned, L, h, &c);
      if (!c.free) continue;
      if (pass) {
        double sw = 1.0 / sqrt(w[h]);
        cc->pa[n] = c.a, cc->pb[n] = c.b;
        cc->ra[n] = c.ra, cc->rb[n] = c.rb, cc->off[n] = nv;
        cc->ka[n] = (unsigned char)c.ka, cc->kb[n] = (unsigned char)c.kb;
        for (int j = 0; j < c.ka; j++) cc->val[nv + j] = c.ua[j] * sw;
        for (int j = 0; j < c.kb; j++) cc->val[nv + c.ka + j] = c.vb[j] * sw;
      }
      n++;
      nv += c.ka + c.kb;
    }
    if (pass) break;
    cc->n = n;
    cc->pa = ps_calloc((size_t)n + 1, sizeof *cc->pa, ctx);
    cc->pb = ps_calloc((size_t)n + 1, sizeof *cc->pb, ctx);
    cc->ra = ps_calloc((size_t)n + 1, sizeof *cc->ra, ctx);
    cc->rb = ps_calloc((size_t)n + 1, sizeof *cc->rb, ctx);
    cc->off = ps_calloc((size_t)n + 1, sizeof *cc->off, ctx);
    cc->ka = ps_calloc((size_t)n + 1, 1, ctx);
    cc->kb = ps_calloc((size_t)n + 1, 1, ctx);
    cc->val = ps_calloc((size_t)nv + 1, sizeof *cc->val, ctx);
    if (!cc->pa || !cc->pb || !cc->ra || !cc->rb || !cc->off || !cc->ka || !cc->kb ||
        !cc->val) {
      cache_free(cc);
      return PS_ERR_NOMEM;
    }
  }
  return PS_OK;
}

/* y = S x = C W^-1 C^T x over the free half-arms (matrix-free) */
static void balance_apply(const column_cache *cc, ps_int nrow, const double *x, double *y) {
  memset(y, 0, (size_t)nrow * sizeof *y);
  for (ps_int c = 0; c < cc->n; c++) {
    const double *v = cc->val + cc->off[c];
    const double *xa = x + cc->ra[c], *xb = x + cc->rb[c];
    int ka = cc->ka[c], kb = cc->kb[c];
    double t = 0.0;
    for (int j = 0; j < ka; j++) t += v[j] * xa[j];
    for (int j = 0; j < kb; j++) t += v[ka + j] * xb[j];
    double *ya = y + cc->ra[c], *yb = y + cc->rb[c];
    for (int j = 0; j < ka; j++) ya[j] += t * v[j];
    for (int j = 0; j < kb; j++) yb[j] += t * v[ka + j];
  }
}

/* S lambda = r by conjugate gradients preconditioned by S's diagonal
 * blocks (one a particle), to ||r - S lambda|| <= 1e-13 ||r||, from the
 * lambda given when warm (the last active-set pass's), else from 0. PS_OK,
 * PS_NOT_POSDEF (a block or the operator is not positive definite, or no
 * convergence in 20,000 iterations), PS_ERR_NOMEM. */
static int balance_pcg(const ps_particles *P, const ps_network *net, const double *w,
                       const double *k, const unsigned char *matched,
                       const unsigned char *pinned, const balance_layout *L, const double *r,
                       double *lam, int warm, int *its, ps_ctx *ctx) {
  ps_int np = net->n_particle, n = L->row0[np];
  column_cache cc = {0, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL};
  ps_int *boff = ps_calloc((size_t)np + 1, sizeof *boff, ctx);
  double *D = NULL, *res = NULL, *z = NULL, *pv = NULL, *q = NULL;
  int status = PS_ERR_NOMEM;
  if (!boff || cache_build(P, net, w, k, matched, pinned, L, &cc, ctx) != PS_OK) goto done;
  for (ps_int p = 0; p < np; p++) {
    ps_int kp = L->row0[p + 1] - L->row0[p];
    boff[p + 1] = boff[p] + kp * kp;
  }
  D = ps_calloc((size_t)boff[np] + 1, sizeof *D, ctx);
  res = ps_calloc((size_t)n, sizeof *res, ctx);
  z = ps_calloc((size_t)n, sizeof *z, ctx);
  pv = ps_calloc((size_t)n, sizeof *pv, ctx);
  q = ps_calloc((size_t)n, sizeof *q, ctx);
  if (!D || !res || !z || !pv || !q) goto done;
  /* the diagonal blocks, from the cached columns: a's rows with
   * themselves, b's F rows likewise */
  for (ps_int c = 0; c < cc.n; c++) {
    ps_int b = cc.pb[c];
    const double *va = cc.val + cc.off[c], *vb = va + cc.ka[c];
    double *Da = D + boff[cc.pa[c]], *Db = D + boff[b];
    int ka = cc.ka[c], kb = cc.kb[c];
    int kb_all = (int)(L->row0[b + 1] - L->row0[b]), sh = (int)(cc.rb[c] - L->row0[b]);
    for (int s = 0; s < ka; s++)
      for (int t = 0; t < ka; t++) Da[s * ka + t] += va[s] * va[t];
    for (int s = 0; s < kb; s++)
      for (int t = 0; t < kb; t++) Db[(sh + s) * kb_all + sh + t] += vb[s] * vb[t];
  }
  status = PS_NOT_POSDEF;
  for (ps_int p = 0; p < np; p++)
    if (!ps_dense_cholesky((int)(L->row0[p + 1] - L->row0[p]), D + boff[p], 0.0)) goto done;
  double rr0 = 0.0, rz = 0.0;
  if (warm) /* res = r - S lambda (res is zero from the allocation) */
    balance_apply(&cc, n, lam, res);
  else
    memset(lam, 0, (size_t)n * sizeof *lam);
  for (ps_int j = 0; j < n; j++) {
    res[j] = r[j] - res[j];
    rr0 += r[j] * r[j];
  }
  *its = 0;
  status = PS_OK;
  if (rr0 == 0.0) goto done;
  for (int it = 0;; it++) {
    memcpy(z, res, (size_t)n * sizeof *z);
    for (ps_int p = 0; p < np; p++)
      ps_dense_cholesky_solve((int)(L->row0[p + 1] - L->row0[p]), D + boff[p], z + L->row0[p]);
    double rz_new = 0.0;
    for (ps_int j = 0; j < n; j++) rz_new += res[j] * z[j];
    double beta = it ? rz_new / rz : 0.0;
    rz = rz_new;
    for (ps_int j = 0; j < n; j++) pv[j] = z[j] + beta * pv[j];
    balance_apply(&cc, n, pv, q);
    double pq = 0.0, rr = 0.0;
    for (ps_int j = 0; j < n; j++) pq += pv[j] * q[j];
    if (!(pq > 0)) {
      status = PS_NOT_POSDEF;
      goto done;
    }
    double alpha = rz / pq;
    for (ps_int j = 0; j < n; j++) {
      lam[j] += alpha * pv[j];
      res[j] -= alpha * q[j];
      rr += res[j] * res[j];
    }
    *its = it + 1;
    if (rr <= 1e-26 * rr0) break;
    if (it >= 20000) {
      status = PS_NOT_POSDEF;
      goto done;
    }
  }
done:
  cache_free(&cc);
  free(boff);
  free(D);
  free(res);
  free(z);
  free(pv);
  free(q);
  return status;
}

/* one solve of the balance system for the rows selected by matched (1)
 * and L->type, by CHOLMOD (ls) or, when ls is NULL, by balance_pcg; phi (in:
 * the local factors, pinned ones at the floor; out: the balanced ones of
 * the free half-arms). keep (CG only; NULL: none): the multipliers, kept
 * for the next call, which starts from them when warm. PS_OK,
 * PS_NOT_POSDEF (the system is singular: no change made), or a fatal
 * status. */
static int balance_solve(const ps_particles *P, const ps_network *net, const double *w,
                         const double *k, const double *target, const unsigned char *matched,
                         const unsigned char *pinned, double *phi, balance_layout *L,
                         ps_linsolve *ls, double *keep, int warm, int *its, ps_ctx *ctx) {
  ps_int np = net->n_particle, na = net->n_arm;
  const ps_int *fp = net->fam_ptr, *fa = net->fam_arm;
  /* rows and block offsets */
  ps_int *row0 = L->row0, *coff = L->coff;
  row0[0] = 0;
  for (ps_int p = 0; p < np; p++) row0[p + 1] = row0[p] + rows_of(matched, p, L);
  ps_int n = row0[np];
  if (n == 0) return PS_OK;
  ps_csc S = {n, NULL, NULL, NULL};
  double *r = ps_calloc((size_t)n, sizeof *r, ctx);
  double *lam = keep ? keep : ps_calloc((size_t)n, sizeof *lam, ctx);
  int status = PS_ERR_NOMEM;
  if (!r || !lam) goto done;
  /* the right-hand side: the targets less the current sums (fixed
   * half-arms at their phi, free ones at 1) */
  for (ps_int p = 0; p < np; p++) {
    int ne = energy_rows(matched, p, L);
    double cE[MAXE];
    if (ne) energy_coefficients(L, matched, p, NULL, NULL, cE);
    for (int j = 0; j < ne; j++) r[row0[p] + j] = target[p] * cE[j];
  }
  if (L->kfix) /* the fixed part (surf->kfix): of the restricted rows
                 (fixed_energy) and of the surface force rows (fixed_force) */
    for (ps_int p = 0; p < np; p++) {
      int ne = energy_rows(matched, p, L), nf = force_rows(L, p);
      if (matched[p] != 5 && (L->type[p] != 2 || !nf)) continue;
      double M[MAXE] = {0}, f[MAXMONO] = {0}, nv[3];
      for (ps_int q = fp[p]; q < fp[p + 1]; q++) {
        ps_int i = fa[q];
        direction(P, net, i, p, nv);
        fixed_energy(L, matched, p, net->a[i] == p ? i : na + i, net->r0[i], nv, M);
        fixed_force(L, p, i, na, nv, f);
      }
      for (int j = 0; j < ne; j++) r[row0[p] + j] -= M[j]; /* 0 unless code 5 */
      for (int j = 0; j < nf; j++) r[row0[p] + ne + j] -= f[j];
    }
  for (ps_int h = 0; h < 2 * na; h++) {
    if (!(w[h] > 0)) continue;
    half_arm c;
    half_arm_get(P, net, w, k, matched, pinned, L, h, &c);
    double ph = c.free ? 1.0 : phi[h];
    for (int j = 0; j < c.ka; j++) r[c.ra + j] -= ph * c.ua[j];
    for (int j = 0; j < c.kb; j++) r[c.rb + j] -= ph * c.vb[j];
  }
  if (!ls) {
    status = balance_pcg(P, net, w, k, matched, pinned, L, r, lam, warm && keep, its, ctx);
    if (status != PS_OK) goto done;
  } else {
    for (ps_int q = 0; q < np; q++) {
      ps_int off = 0, f = fp[q];
      for (; f < fp[q + 1]; f++) {
        ps_int i = fa[f], o = net->a[i] == q ? net->b[i] : net->a[i];
        if (o > q) break;
        coff[f] = off;
        off += rows_of(matched, o, L);
      }
      coff[2 * na + q] = off;
    }
    /* the CSC pattern: column (q, s) holds the rows of q's neighbours
     * with lower numbers, then q's own rows 0..s */
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
    if (!S.i || !S.x) goto done;
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
    /* S += v v^T / w over the free half-arms */
    for (ps_int h = 0; h < 2 * na; h++) {
      if (!(w[h] > 0)) continue;
      half_arm c;
      half_arm_get(P, net, w, k, matched, pinned, L, h, &c);
      if (!c.free) continue;
      ps_int a = c.a, b = c.b, i = h < na ? h : h - na;
      double iw = 1.0 / w[h];
      for (int s = 0; s < c.ka; s++) { /* a's rows */
        ps_int col = S.p[c.ra + s] + coff[2 * na + a];
        for (int t = 0; t <= s; t++) S.x[col + t] += c.ua[t] * c.ua[s] * iw;
      }
      ps_int sh = c.rb - row0[b]; /* b's F rows within b's block */
      for (int s = 0; s < c.kb; s++) {
        ps_int col = S.p[c.rb + s] + coff[2 * na + b] + sh;
        for (int t = 0; t <= s; t++) S.x[col + t] += c.vb[t] * c.vb[s] * iw;
      }
      if (!c.kb) continue;
      /* the block between a's rows and b's F rows, in the column block of
       * the higher particle, at the lower one's offset coff[f] */
      ps_int hi = a < b ? b : a, f = fp[hi];
      while (fa[f] != i) f++;
      if (a < b)
        for (int s = 0; s < c.kb; s++) {
          ps_int col = S.p[c.rb + s] + coff[f];
          for (int t = 0; t < c.ka; t++) S.x[col + t] += c.ua[t] * c.vb[s] * iw;
        }
      else
        for (int s = 0; s < c.ka; s++) {
          ps_int col = S.p[c.ra + s] + coff[f] + sh;
          for (int t = 0; t < c.kb; t++) S.x[col + t] += c.vb[t] * c.ua[s] * iw;
        }
    }
    ps_int bad = -1;
    status = ps_linsolve_factor(ls, &S, &bad, ctx);
    if (status == PS_SINGULAR) status = PS_NOT_POSDEF;
    if (status != PS_OK) goto done;
    status = ps_linsolve_solve(ls, r, lam, ctx);
    if (status != PS_OK) goto done;
  }
  /* d_h = (column . lambda) / w_h */
  for (ps_int h = 0; h < 2 * na; h++) {
    if (!(w[h] > 0)) continue;
    half_arm c;
    half_arm_get(P, net, w, k, matched, pinned, L, h, &c);
    if (!c.free) continue;
    phi[h] = 1.0 + column_dot(&c, lam) / w[h];
  }
done:
  free(S.p);
  free(S.i);
  free(S.x);
  free(r);
  if (lam != keep) free(lam);
  return status;
}

/* The largest residual of the constraints under the factors phi: over the
 * matched particles (code 1, or 5: restricted_energy) the energy rows',
 * |sum_b w_b phi_b mE - t_a c| / t_a, when energy != 0, and over those with force rows
 * (L->type) the force rows', |sum_b s_cb f(n)| / sum_b |s_cb| */
static double residual(const ps_particles *P, const ps_network *net, const double *w,
                       const double *k, const double *target, const double *phi,
                       const unsigned char *code, int energy, const balance_layout *L) {
  ps_int na = net->n_arm;
  double worst = 0.0;
  for (ps_int c = 0; c < net->n_particle; c++) {
    int e = energy ? energy_rows(code, c, L) : 0, nf = force_rows(L, c);
    if (!e && !nf) continue;
    double T[MAXMONO] = {0}, M[MAXE] = {0}, m[MAXE], n[3], sum = 0.0, cE[MAXE];
    for (ps_int f = net->fam_ptr[c]; f < net->fam_ptr[c + 1]; f++) {
      ps_int i = net->fam_arm[f], h = net->a[i] == c ? i : na + i;
      direction(P, net, i, c, n);
      if (nf) {
        double sc = k[i] * phi[i] + k[na + i] * phi[na + i];
        force_coefficients(L, c, n, m);
        for (int j = 0; j < nf; j++) T[j] += sc * m[j];
        sum += fabs(sc) + fixed_force(L, c, i, na, n, T);
      }
      if (e && w[h] > 0) {
        energy_coefficients(L, code, c, n, m, NULL);
        for (int j = 0; j < e; j++) M[j] += w[h] * phi[h] * m[j];
      }
      if (e) fixed_energy(L, code, c, h, net->r0[i], n, M);
    }
    for (int j = 0; j < nf; j++) worst = fmax(worst, fabs(T[j]) / sum);
    if (e) energy_coefficients(L, code, c, NULL, NULL, cE);
    for (int j = 0; j < e; j++) worst = fmax(worst, fabs(M[j] - target[c] * cE[j]) / target[c]);
  }
  return worst;
}

/* The least change under the rows of L (force rows by L->type) with the bound
 * phi >= floor by an active set: a free half-arm whose factor falls below
 * it is held at the floor (pinned 1) and the system solved again (the
 * same pattern: one analysis); pinned 2: held at base. In 2D by CHOLMOD;
 * in 3D (25 rows a particle, ~100 neighbours) its factor is too large (a
 * jittered box of 4,500 particles: 212 s and 5.4 GB), so by CG
 * (balance_pcg: 10 s, 0.9 GB). phi: the result, or base when the system
 * is singular, does not fit in memory, its solution is inaccurate or 8
 * solves leave a factor below the floor (then returns 1). Adds its solves
 * and CG iterations to *s. PS_OK, 1, or a fatal status. */
static int active_set(const ps_particles *P, const ps_network *net, const double *w,
                      const double *ks, const double *target, const unsigned char *code,
                      unsigned char *pinned, const double *base, double *phi, balance_layout *L,
                      ps_moduli_stats *s, ps_ctx *ctx) {
  ps_int na = net->n_arm;
  ps_linsolve ls;
  int status = ps_linsolve_create(&ls, ps_linsolve_cholmod, ctx);
  if (status != PS_OK) return status;
  /* CG's multipliers, each pass starting from the last one's */
  ps_int nrow = 0;
  for (ps_int p = 0; p < net->n_particle; p++) nrow += rows_of(code, p, L);
  double *keep = net->dim == 2 ? NULL : ps_calloc((size_t)nrow + 1, sizeof *keep, ctx);
  int warm = 0;
  for (int pass = 1; pass <= 8; pass++) {
    memcpy(phi, base, (size_t)(2 * na) * sizeof *phi);
    for (ps_int h = 0; h < 2 * na; h++)
      if (pinned[h] == 1) phi[h] = PS_MODULI_FLOOR;
    int its = 0;
    status = balance_solve(P, net, w, ks, target, code, pinned, phi, L,
                           net->dim == 2 ? &ls : NULL, keep, warm, &its, ctx);
    warm = status == PS_OK;
    s->balance_iterations += its;
    s->balance_passes++;
    int ok = status == PS_OK && residual(P, net, w, ks, target, phi, code, 1, L) <= 1e-8;
    if (status != PS_OK && status != PS_NOT_POSDEF && status != PS_ERR_NOMEM) break;
    status = PS_OK;
    int low = 0;
    for (ps_int h = 0; ok && h < 2 * na; h++) {
      ps_int i = h < na ? h : h - na, a = h < na ? net->a[i] : net->b[i];
      if (w[h] > 0 && (code[a] == 1 || code[a] == 5) && !pinned[h] && phi[h] < PS_MODULI_FLOOR)
        pinned[h] = 1, low = 1;
    }
    if (ok && !low) break;
    if (!ok || pass == 8) {
      memcpy(phi, base, (size_t)(2 * na) * sizeof *phi);
      status = 1;
      break;
    }
  }
  ps_linsolve_destroy(&ls);
  free(keep);
  return status;
}

/* the surface states of particle c: the outward normals of the surface
 * particles among c and its neighbours (u[3 p], unit first moments; 0
 * for others) span the normal space (eigenvectors of sum u u^T above a
 * quarter of its largest eigenvalue or a tenth of its trace: near a
 * corner of a body a few horizons wide the surface particles' normals
 * lean towards the diagonal, and the largest eigenvalue alone made the
 * faces' normals look like tangents); the tangents t the rest, and the
 * stresses with no traction on those faces are the symmetrised t_i t_j;
 * their strains in the model's elasticity (K, G), times 2G, into
 * L->seps. Returns their number (0: a corner, or no surface near). */
static int surface_states(const ps_network *net, const double *u, ps_int c,
                          const ps_moduli_surface *sf, balance_layout *L) {
  int N = L->N;
  double M[9] = {0};
  int any = 0;
  for (ps_int f = net->fam_ptr[c] - 1; f < net->fam_ptr[c + 1]; f++) {
    ps_int o = c;
    if (f >= net->fam_ptr[c]) {
      ps_int i = net->fam_arm[f];
      o = net->a[i] == c ? net->b[i] : net->a[i];
    }
    const double *uo = &u[3 * o];
    if (uo[0] == 0 && uo[1] == 0 && uo[2] == 0) continue;
    any = 1;
    for (int i = 0; i < N; i++)
      for (int j = 0; j < N; j++) M[i * N + j] += uo[i] * uo[j];
  }
  if (!any) return 0;
  double lam[3], vec[9];
  gsl_matrix_view Mv = gsl_matrix_view_array(M, (size_t)N, (size_t)N);
  gsl_vector_view lv = gsl_vector_view_array(lam, (size_t)N);
  gsl_matrix_view Vv = gsl_matrix_view_array(vec, (size_t)N, (size_t)N);
  gsl_eigen_symmv_workspace *ws = gsl_eigen_symmv_alloc((size_t)N);
  if (!ws) return 0;
  gsl_eigen_symmv(&Mv.matrix, &lv.vector, &Vv.matrix, ws);
  gsl_eigen_symmv_free(ws);
  double big = 0.0, trM = 0.0;
  for (int e = 0; e < N; e++) big = fmax(big, lam[e]), trM += lam[e];
  double t[3][3];
  int nt = 0;
  for (int e = 0; e < N; e++)
    if (lam[e] <= 0.25 * big && lam[e] <= 0.1 * trM) {
      for (int i = 0; i < N; i++) t[nt][i] = vec[i * N + e]; /* column e */
      nt++;
    }
  int ns = 0;
  for (int p = 0; p < nt; p++)
    for (int q = p; q < nt; q++, ns++) {
      double sg[9], tr = 0.0, *e = &L->seps[(c * 3 + ns) * 9];
      for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) sg[i * N + j] = 0.5 * (t[p][i] * t[q][j] + t[q][i] * t[p][j]);
      for (int i = 0; i < N; i++) tr += sg[i * N + i];
      for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++)
          e[i * N + j] = sg[i * N + j] +
                         (i == j ? (2.0 * sf->G / (N * N * sf->K) - 1.0 / N) * tr : 0.0);
    }
  return ns;
}

int ps_moduli_balance(const ps_particles *P, const ps_network *net, int order,
                      const double *w, const double *k, const double *target,
                      const ps_moduli_surface *surf, double *phi, ps_moduli_stats *stats,
                      ps_ctx *ctx) {
  int N = net->dim;
  if ((order != 2 && order != 4) || (N != 2 && N != 3))
    return ps_error(ctx, PS_ERR_INPUT, "moduli correction: order %d in %d dimensions", order,
                    N);
  ps_int np = net->n_particle, na = net->n_arm;
  balance_layout L;
  L.N = N;
  L.nE = monomials(N, order, L.eE);
  L.nF = monomials(N, order - 1, L.eF);
  for (int j = 0; j < L.nE; j++) L.cE[j] = iso_component(L.eE[j]);
  unsigned char *code = ps_calloc((size_t)np, 1, ctx), *bal = ps_calloc((size_t)np, 1, ctx);
  unsigned char *cut = ps_calloc((size_t)np, 1, ctx), *pinned = ps_calloc((size_t)(2 * na), 1, ctx);
  double *ks = ps_calloc((size_t)(2 * na), sizeof *ks, ctx);
  double *u = ps_calloc((size_t)(3 * np), sizeof *u, ctx);
  unsigned char *code2 = ps_calloc((size_t)np, 1, ctx), *bal2 = ps_calloc((size_t)np, 1, ctx);
  L.ns = ps_calloc((size_t)np, 1, ctx);
  L.seps = surf ? ps_calloc((size_t)(27 * np), sizeof *L.seps, ctx) : NULL;
  L.type = bal;
  L.order = order;
  L.beta = surf ? surf->beta : 0.0;
  L.kfix = surf ? surf->kfix : NULL;
  L.lam_over_G = surf ? (surf->K - 2.0 * surf->G / N) / surf->G : 0.0;
  double *local = ps_calloc((size_t)(2 * na), sizeof *local, ctx);
  L.row0 = ps_calloc((size_t)np + 1, sizeof *L.row0, ctx);
  L.coff = ps_calloc((size_t)(2 * na + np), sizeof *L.coff, ctx);
  ps_moduli_stats s;
  int status = PS_ERR_NOMEM;
  if (!code || !bal || !cut || !pinned || !ks || !u || !code2 || !bal2 || !L.ns ||
      (surf && !L.seps) || !local || !L.row0 || !L.coff)
    goto done;
  status = local_factors(P, net, order, w, target, local, &s, code, ctx);
  if (status != PS_OK) goto done;
  /* the force rows scaled by the mean arm length rounded to a power of
   * two, so that they carry the energy rows' unit (w = k r0): the
   * multipliers' system is then as well conditioned in micrometres as in
   * metres, and the scaling is exact (the solution is the same) */
  double lbar = 0.0;
  for (ps_int i = 0; i < na; i++) lbar += net->r0[i] / (double)na;
  lbar = lbar > 0 ? exp2(round(log2(lbar))) : 1.0;
  for (ps_int h = 0; h < 2 * na; h++) ks[h] = k[h] * lbar;
  L.kscale = lbar;
  /* surface particles: a family that a free surface, a hole or a crack
   * cuts off has a large first moment. A family is cut when its particle
   * or a neighbour is on the surface (a surface within reach), and a
   * particle is balanced when it is matched and neither its family nor a
   * neighbour's is cut: on a lattice every arm of a balanced particle then
   * joins two complete families, whose local factors balance it already.
   * (A neighbour only partly matched, at the floor, has a mean strain
   * near but not equal to tr eps / N: there the balance of the arm forces
   * is exact and that of the family term approximate. Requiring matched
   * neighbours would leave much of a 3D cloud's interior unbalanced.) */
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
    if (bal[a] && g > 0)
      for (int c = 0; c < N; c++) u[3 * a + c] = m1[c] / g;
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
      ps_int i = net->fam_arm[f], o = net->a[i] == a ? net->b[i] : net->a[i];
      if (cut[o]) bal[a] = 0;
    }
  }
  /* stage 1, the interior: nothing to do where the local factors balance
   * every balanced particle already (a lattice: the same factors, bit
   * for bit) */
  int failed = 0;
  memcpy(phi, local, (size_t)(2 * na) * sizeof *phi);
  if (residual(P, net, w, ks, target, local, code, 0, &L) > 1e-12) {
    status = active_set(P, net, w, ks, target, code, pinned, local, phi, &L, &s, ctx);
    if (status < 0) goto done;
    failed |= status > 0;
  }
  /* stage 2, with surf: the matched particles near a surface get its
   * states (force rows; not with energy_only), and so do the partly
   * matched ones, whose energy is then matched under those states only
   * (restricted_energy); the factors of the interior (type 1) stay as
   * stage 1 left them. (With the state model's two factor sets the
   * surface particles and normals come from each set's own weights, ks xi
   * and ks xi^2: on a lattice they agree by symmetry, on a cloud the
   * deviatoric stage's states may differ slightly from those the
   * dilatation was matched under.) */
  int any = 0, eonly = surf && surf->energy_only;
  for (ps_int a = 0; surf && a < np; a++)
    if (!bal[a] && cut[a] && (code[a] == 2 || (code[a] == 1 && !eonly))) {
      L.ns[a] = (unsigned char)surface_states(net, u, a, surf, &L);
      /* a partly matched particle joins only with independent rows that
       * do not span the whole moment (not at a 3D face: rows_independent) */
      if (L.ns[a] && code[a] == 2 && !rows_independent(&L, a)) L.ns[a] = 0;
      if (L.ns[a]) bal[a] = 2, any = 1;
    }
  if (any) {
    /* the stage's rows: the deep interior (balanced particles with
     * balanced neighbours only) keeps its factors, and so do the arms that
     * reach it (pinned 2): its rows are dropped (code2 4, bal2 0) */
    memcpy(local, phi, (size_t)(2 * na) * sizeof *phi); /* the stage's base */
    for (ps_int a = 0; a < np; a++) { /* bal2: 3 marks the deep interior */
      int deep = bal[a] == 1;
      for (ps_int f = net->fam_ptr[a]; deep && f < net->fam_ptr[a + 1]; f++) {
        ps_int i = net->fam_arm[f];
        deep = bal[net->a[i] == a ? net->b[i] : net->a[i]] == 1;
      }
      bal2[a] = deep ? 3 : bal[a];
    }
    for (ps_int h = 0; h < 2 * na; h++) {
      ps_int i = h < na ? h : h - na;
      if (bal2[net->a[i]] == 3 || bal2[net->b[i]] == 3) pinned[h] = 2;
    }
    for (ps_int a = 0; a < np; a++) {
      code2[a] = bal2[a] == 3 ? 4 : code[a] == 2 && bal[a] == 2 ? 5 : code[a];
      if (bal2[a] == 3 || eonly) bal2[a] = 0;
      if (eonly && code2[a] != 5) code2[a] = 4; /* only the restricted rows */
    }
    L.type = bal2;
    status = active_set(P, net, w, ks, target, code2, pinned, local, phi, &L, &s, ctx);
    L.type = bal;
    if (status < 0) goto done;
    failed |= status > 0;
  }
  status = PS_OK;
  if (failed) {
    s.balance_passes = -s.balance_passes;
    ps_log(ctx, 1,
           "# warning: material.surface_correction: the %s could not be balanced on "
           "this cloud (order %d, %d solves); each particle keeps its own energy match "
           "and the moduli may be up to ~1.5%% soft (doc/moduli.md)\n",
           eonly ? "factors at the surface" : "arm forces", order, -s.balance_passes);
  }
  s.n_balanced = s.n_surface = 0;
  for (ps_int a = 0; !failed && a < np; a++) {
    s.n_balanced += bal[a] == 1;
    s.n_surface += bal[a] == 2;
  }
  s.phi_min = INFINITY;
  s.phi_max = -INFINITY;
  for (ps_int h = 0; h < 2 * na; h++)
    if (w[h] > 0) {
      s.phi_min = fmin(s.phi_min, phi[h]);
      s.phi_max = fmax(s.phi_max, phi[h]);
    }
  if (stats) *stats = s;
done:
  free(code);
  free(bal);
  free(cut);
  free(pinned);
  free(ks);
  free(u);
  free(code2);
  free(bal2);
  free(L.ns);
  free(L.seps);
  free(local);
  free(L.row0);
  free(L.coff);
  return status;
}
