/* t100_network.c: the geometry and the arm network, checked against
 * independent computations:
 *  1. kernel: GSL normalisation = closed form (k = 2); Eq. 54 by our own
 *     Simpson rule (k = 3); f' = central difference of f; support [0, alpha).
 *  2. k-d tree: radius and k-nearest queries = brute force, exactly.
 *  3. Eq. 115 sizes on the square and hexagonal lattices.
 *  4. network = O(n^2) brute force (arm set, weights of Eq. 70, families,
 *     n_arm0) on jittered variable-size boxes, 2D and 3D.
 *  5. pre-cracks: no arm crosses a crack; every other arm is present; the
 *     crack-tip rule (an arm through a tip is kept, to 1e-13 m shifts);
 *     networks that cannot be built (no arms, coincident particles, a
 *     coordinate not finite) and their messages; the size estimate.
 *  6. the elliptic disk of Eq. 114: exact total area, the paper's Table 1
 *     arm count and size ratio, boundary zone flags, Eq. 116 against its
 *     limits (far field, Griffith opening, symmetry) and against the
 *     Westergaard solution, the ellipse perimeter.
 * Run "t100_network small" for a reduced disk (for valgrind): the paper-size
 * checks of 6(b) are then skipped. */
#include <complex.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "network/ps_network.h"

static int small_mode = 0;

/* ------------------------------------------------------------------ */
/* helpers                                                             */

static int cmp_int(const void *u, const void *v) {
  ps_int a = *(const ps_int *)u, b = *(const ps_int *)v;
  return a < b ? -1 : a > b;
}

typedef struct {
  ps_int a, b;
} pr;

static int cmp_pr(const void *u, const void *v) {
  const pr *p = u, *q = v;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return 0;
}

static double d2_of(const double *x, const double *y, int dim) {
  double s = 0.0;
  for (int k = 0; k < dim; k++) s += (x[k] - y[k]) * (x[k] - y[k]);
  return s;
}

/* Our own segment test (parametric, not orientation signs as in src/):
 * does the open segment x-y cross the open segment p-q? */
static int seg_cross(const double *x, const double *y, const double *p,
                     const double *q) {
  double ex = y[0] - x[0], ey = y[1] - x[1];
  double fx = q[0] - p[0], fy = q[1] - p[1];
  double den = ex * fy - ey * fx;
  if (den == 0.0) return 0; /* parallel (never met with jittered points) */
  double gx = p[0] - x[0], gy = p[1] - x[1];
  double t = (gx * fy - gy * fx) / den; /* along x-y */
  double s = (gx * ey - gy * ex) / den; /* along p-q */
  return t > 0 && t < 1 && s > 0 && s < 1;
}

static void die(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t100_network: %s failed: %s\n", what, ctx->msg);
  exit(2);
}

/* ------------------------------------------------------------------ */
/* 1. kernel                                                           */

static void test_kernel(ps_ctx *ctx) {
  const double alpha = 5.1;
  for (int dim = 2; dim <= 3; dim++) {
    ps_kernel K;
    if (ps_kernel_init(&K, dim, 2, alpha, ctx)) die("ps_kernel_init", ctx);
    /* tol 1e-12: qag with GAUSS61 integrates a polynomial of degree <= 6
     * exactly; what is left is round-off (~1e-15) */
    char what[128];
    snprintf(what, sizeof what, "kernel %dD k=2: GSL Z = closed form Z", dim);
    ps_check_rel(K.Z, ps_kernel_Z_k2(dim, alpha), 1e-12, what);
  }
  for (int dim = 2; dim <= 3; dim++) {
    ps_kernel K;
    if (ps_kernel_init(&K, dim, 3, alpha, ctx)) die("ps_kernel_init", ctx);
    /* Eq. 54 by our own composite Simpson rule, 200000 intervals: the
     * integrand is a polynomial of degree 6 (2D) or 8 (3D) on [0, alpha],
     * truncation error ~ h^4 f''''/180 ~ 1e-20 relative; tol 1e-8 is
     * the brief's, leaves room for accumulated round-off (~1e-13). */
    int m = 200000;
    double hs = alpha / m;
    long double s = 0.0L;
    for (int i = 0; i <= m; i++) {
      double u = i * hs;
      double g = ps_kernel_f(&K, u) * 2.0 * (dim - 1) * M_PI * pow(u, dim - 1);
      double w = (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      s += (long double)w * g;
    }
    double integral = (double)(s * hs / 3.0L);
    char what[128];
    snprintf(what, sizeof what, "kernel %dD k=3: Simpson int f 2(N-1)pi u^(N-1) du = 1",
             dim);
    ps_check_rel(integral, 1.0, 1e-8, what);

    /* f' against a central difference with step 1e-5: truncation
     * h^2 f'''/6 ~ 1e-11 relative, round-off eps f/h ~ 1e-11; tol 1e-6 */
    const double us[] = {0.3, 1.0, 2.2, 3.7, 4.9};
    double worst = 0.0;
    for (size_t i = 0; i < sizeof us / sizeof *us; i++) {
      double u = us[i], dh = 1e-5;
      double fd = (ps_kernel_f(&K, u + dh) - ps_kernel_f(&K, u - dh)) / (2 * dh);
      double an = ps_kernel_df(&K, u);
      double e = fabs(an - fd) / fabs(fd);
      if (!(e <= worst)) worst = e; /* NaN-safe */
    }
    snprintf(what, sizeof what, "kernel %dD k=3: max rel |f' - central diff| at 5 u",
             dim);
    ps_check_le(worst, 1e-6, what);
    /* support: exact zeros at and beyond alpha (exact: a branch returns 0) */
    int zero = ps_kernel_f(&K, alpha) == 0.0 && ps_kernel_df(&K, alpha) == 0.0 &&
               ps_kernel_f(&K, 1.01 * alpha) == 0.0 &&
               ps_kernel_df(&K, 1.01 * alpha) == 0.0 &&
               ps_kernel_f(&K, 1e3 * alpha) == 0.0 &&
               ps_kernel_df(&K, 1e3 * alpha) == 0.0;
    ps_check(zero, "kernel %dD k=3: f and f' vanish for u >= alpha (exact)", dim);
    ps_check(ps_kernel_f(&K, 0.999 * alpha) > 0 && ps_kernel_df(&K, 0.5) < 0,
             "kernel %dD k=3: f > 0 and f' < 0 inside the support", dim);
  }
  ps_kernel K;
  ps_ctx quiet;
  ps_ctx_init(&quiet);
  ps_check(ps_kernel_init(&K, 2, 2, 0.0, &quiet) == PS_ERR_INPUT &&
               ps_kernel_init(&K, 2, 0, 5.1, &quiet) == PS_ERR_INPUT &&
               ps_kernel_init(&K, 4, 2, 5.1, &quiet) == PS_ERR_INPUT,
           "kernel: alpha <= 0, k < 1, dim 4 rejected with PS_ERR_INPUT");
}

/* ------------------------------------------------------------------ */
/* 2. k-d tree                                                         */

/* Radius queries from query points q[0..nq) against brute force: returns
 * the number of queries whose index set differs. Exact comparison: both
 * sides test the same floating-point squared distance < r^2. */
static ps_int radius_mismatches(const ps_kdtree *t, const double *x, ps_int n,
                                int dim, const double *q, ps_int nq,
                                double radius, ps_int *total, ps_ctx *ctx) {
  ps_int *out = NULL, cap = 0, cnt = 0, bad = 0;
  ps_int *ref = malloc((size_t)n * sizeof *ref);
  *total = 0;
  for (ps_int i = 0; i < nq; i++) {
    if (ps_kdtree_radius(t, &q[i * dim], radius, &out, &cap, &cnt, ctx))
      die("ps_kdtree_radius", ctx);
    ps_int nr = 0;
    for (ps_int j = 0; j < n; j++)
      if (d2_of(&x[j * dim], &q[i * dim], dim) < radius * radius) ref[nr++] = j;
    if (cnt > 0) qsort(out, (size_t)cnt, sizeof *out, cmp_int);
    if (cnt != nr || (nr && memcmp(out, ref, (size_t)nr * sizeof *ref) != 0)) bad++;
    *total += nr;
  }
  free(out);
  free(ref);
  return bad;
}

static void test_kdtree(ps_ctx *ctx) {
  const ps_int n = 2000;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 20210101);
  for (int dim = 2; dim <= 3; dim++) {
    double *x = malloc((size_t)(n * dim) * sizeof *x);
    double *q = malloc((size_t)(n * dim) * sizeof *q);
    for (ps_int i = 0; i < n * dim; i++) x[i] = gsl_rng_uniform(rng);
    /* queries: the points themselves and as many random off-cloud points
     * (some outside the unit box) */
    for (ps_int i = 0; i < n * dim; i++) q[i] = 1.2 * gsl_rng_uniform(rng) - 0.1;
    ps_kdtree *t = NULL;
    if (ps_kdtree_build(&t, x, n, dim, ctx)) die("ps_kdtree_build", ctx);
    const double radii[] = {0.0, 1e-3, dim == 2 ? 0.05 : 0.12, 0.4, 2.0};
    for (size_t r = 0; r < sizeof radii / sizeof *radii; r++) {
      ps_int tot1, tot2;
      ps_int bad = radius_mismatches(t, x, n, dim, x, n, radii[r], &tot1, ctx);
      bad += radius_mismatches(t, x, n, dim, q, n, radii[r], &tot2, ctx);
      ps_check(bad == 0,
               "kdtree %dD, %lld random points, radius %g: %lld of %lld query "
               "sets differ from brute force (%lld hits; exact)",
               dim, (long long)n, radii[r], (long long)bad, (long long)(2 * n),
               (long long)(tot1 + tot2));
    }
    /* knn, k = 5: same index sets and the same distances (exact: same
     * arithmetic; random points have no ties) */
    ps_int bad = 0;
    for (ps_int i = 0; i < n; i++) {
      ps_int idx[5], ref[5];
      double dist[5], rd[5];
      int f = ps_kdtree_knn(t, i, 5, idx, dist);
      int m = 0;
      for (ps_int j = 0; j < n; j++) {
        if (j == i) continue;
        double d2 = d2_of(&x[j * dim], &x[i * dim], dim);
        if (m == 5 && d2 >= rd[4]) continue;
        int s = m < 5 ? m++ : 4;
        while (s > 0 && rd[s - 1] > d2) {
          rd[s] = rd[s - 1];
          ref[s] = ref[s - 1];
          s--;
        }
        rd[s] = d2;
        ref[s] = j;
      }
      int ok = f == 5;
      for (int s = 0; ok && s < 5; s++) {
        if (dist[s] != sqrt(rd[s])) ok = 0;
        if (s && dist[s] < dist[s - 1]) ok = 0;
      }
      qsort(idx, 5, sizeof *idx, cmp_int);
      qsort(ref, 5, sizeof *ref, cmp_int);
      if (ok && memcmp(idx, ref, sizeof idx) != 0) ok = 0;
      if (!ok) bad++;
    }
    ps_check(bad == 0,
             "kdtree %dD knn k=5: %lld of %lld points differ from brute force "
             "(index sets and ascending distances, exact)",
             dim, (long long)bad, (long long)n);
    ps_kdtree_free(&t);
    free(x);
    free(q);
  }
  gsl_rng_free(rng);

  /* a regular lattice: many equal coordinates (exercises the median split
   * with ties); radius 2.5 d lies between lattice distances, so the sets
   * are unambiguous */
  {
    ps_particles P;
    ps_int counts[3] = {31, 29, 1};
    if (ps_geom_box(&P, 2, counts, 1.0, "square", 0.0, 1, ctx)) die("ps_geom_box", ctx);
    ps_kdtree *t = NULL;
    if (ps_kdtree_build(&t, P.x, P.n, 2, ctx)) die("ps_kdtree_build", ctx);
    ps_int tot;
    ps_int bad = radius_mismatches(t, P.x, P.n, 2, P.x, P.n, 2.5, &tot, ctx);
    ps_check(bad == 0, "kdtree on a 31x29 square lattice, radius 2.5 d: %lld query "
             "sets differ from brute force (exact)", (long long)bad);
    /* knn on the lattice: the 4 nearest of an interior point are at d */
    ps_int idx[4];
    double dist[4];
    ps_int mid = 14 * 31 + 15;
    int f = ps_kdtree_knn(t, mid, 4, idx, dist);
    ps_check(f == 4 && dist[0] == 1.0 && dist[3] == 1.0,
             "kdtree lattice knn k=4 of an interior point: all at distance d (exact)");
    ps_kdtree_free(&t);
    ps_particles_free(&P);
  }
  /* fewer points than k + 1 */
  {
    double x[8] = {0, 0, 1, 0, 0, 1, 1, 1};
    ps_kdtree *t = NULL;
    if (ps_kdtree_build(&t, x, 4, 2, ctx)) die("ps_kdtree_build", ctx);
    ps_int idx[5];
    double dist[5];
    int f = ps_kdtree_knn(t, 0, 5, idx, dist);
    ps_check(f == 3 && dist[0] == 1.0 && dist[1] == 1.0 && dist[2] == sqrt(2.0),
             "kdtree knn k=5 on 4 points: 3 found, distances 1, 1, sqrt 2 (exact)");
    ps_kdtree_free(&t);
  }
}

/* ------------------------------------------------------------------ */
/* 3. Eq. 115 sizes                                                    */

static void test_sizes(ps_ctx *ctx) {
  const double d = 2.5e-3;
  ps_particles P;
  ps_int counts[3] = {9, 9, 1};
  if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) die("ps_geom_sizes_eq115", ctx);
  /* interior: 4 neighbours at d and one of the 4 diagonal ones at sqrt2 d:
   * h = (4 + sqrt 2) d / 10; tol 1e-12: a sum of 5 rounded distances */
  ps_check_rel(P.h[4 * 9 + 4], (4.0 + sqrt(2.0)) / 10.0 * d, 1e-12,
               "Eq. 115 (n=5) square lattice interior: h = (4+sqrt2)/10 d");
  ps_check_rel(P.h[4 * 9 + 4] / d, 0.5414, 1e-4,
               "Eq. 115 square lattice: h/d = 0.5414 (4 digits)");
  ps_particles_free(&P);
  if (ps_geom_box(&P, 2, counts, d, "hex", 0.0, 1, ctx)) die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) die("ps_geom_sizes_eq115", ctx);
  /* hex: 6 neighbours at d (the offset rows are at sqrt(1/4 + 3/4) d), so
   * h = 5 d / 10; tol 1e-12: round-off of sqrt(3)/2 in the row spacing */
  ps_check_rel(P.h[4 * 9 + 4], 0.5 * d, 1e-12, "Eq. 115 (n=5) hex lattice interior: h = d/2");
  ps_check_rel(P.volume[0], d * d * sqrt(3.0) / 2.0, 1e-15, "hex lattice volume d^2 sqrt3/2");
  ps_particles_free(&P);
  /* 3D cubic: 6 neighbours at d, h = d/2 */
  ps_int c3[3] = {5, 5, 5};
  if (ps_geom_box(&P, 3, c3, d, "square", 0.0, 1, ctx)) die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) die("ps_geom_sizes_eq115", ctx);
  ps_check_rel(P.h[2 * 25 + 2 * 5 + 2], 0.5 * d, 1e-12, "Eq. 115 (n=5) cubic lattice interior: h = d/2");
  ps_particles_free(&P);
}

/* ------------------------------------------------------------------ */
/* 4./5. network against brute force                                   */

/* The brute-force arm list {a < b : r < alpha max(h_a, h_b), not cut by any
 * crack}, sorted by (a, b). Also counts the pairs removed by the cracks. */
static pr *brute_arms(const ps_particles *P, double alpha, const ps_crack *cr,
                      int ncr, ps_int *n_out, ps_int *n_cut) {
  ps_int cap = 1024, na = 0;
  pr *arms = malloc((size_t)cap * sizeof *arms);
  int dim = P->dim;
  *n_cut = 0;
  for (ps_int a = 0; a < P->n; a++)
    for (ps_int b = a + 1; b < P->n; b++) {
      double r = sqrt(d2_of(&P->x[b * dim], &P->x[a * dim], dim));
      double hm = P->h[a] > P->h[b] ? P->h[a] : P->h[b];
      if (!(r < alpha * hm)) continue;
      int cut = 0;
      for (int c = 0; c < ncr && !cut; c++)
        cut = seg_cross(&P->x[a * dim], &P->x[b * dim], cr[c].p0, cr[c].p1);
      if (cut) {
        (*n_cut)++;
        continue;
      }
      if (na == cap) {
        cap *= 2;
        arms = realloc(arms, (size_t)cap * sizeof *arms);
      }
      arms[na].a = a;
      arms[na].b = b;
      na++;
    }
  *n_out = na;
  return arms;
}

/* Compare net with the brute-force list and with the Eq. 70 weights;
 * families and n_arm0. label names the case in the output. */
static void compare_network(const ps_network *net, const ps_particles *P,
                            const ps_kernel *K, const ps_crack *cr, int ncr,
                            const char *label) {
  int dim = P->dim;
  ps_int nb, ncut;
  pr *ref = brute_arms(P, K->alpha, cr, ncr, &nb, &ncut);
  /* arm set: exact */
  int ordered = 1;
  pr *got = malloc((size_t)(net->n_arm + 1) * sizeof *got);
  for (ps_int i = 0; i < net->n_arm; i++) {
    got[i].a = net->a[i];
    got[i].b = net->b[i];
    if (!(net->a[i] < net->b[i])) ordered = 0;
  }
  qsort(got, (size_t)net->n_arm, sizeof *got, cmp_pr);
  int same = net->n_arm == nb &&
             (nb == 0 || memcmp(got, ref, (size_t)nb * sizeof *ref) == 0);
  ps_check(same && ordered,
           "%s: arm set = brute force {a<b : r < alpha max(h_a,h_b)}%s (%lld arms, "
           "network %lld; exact)",
           label, ncr ? " minus crossing arms" : "", (long long)nb,
           (long long)net->n_arm);
  if (ncr) {
    /* no network arm crosses a crack, by our own intersection test */
    ps_int crossing = 0;
    for (ps_int i = 0; i < net->n_arm; i++)
      for (int c = 0; c < ncr; c++)
        if (seg_cross(&P->x[net->a[i] * dim], &P->x[net->b[i] * dim], cr[c].p0,
                      cr[c].p1))
          crossing++;
    ps_check(crossing == 0 && ncut > 0,
             "%s: no arm crosses a crack (%lld do; %lld candidate pairs cut)", label,
             (long long)crossing, (long long)ncut);
  }
  /* weights: A_ab = -V_a V_b f'(r/h_a)/h_a^(N+1), r0 = |x_b - x_a|. tol
   * 1e-14: the same formula, a few roundings (h^(N+1) by repeated product
   * here, pow in src/). Arms outside a's own horizon must have A_ab == 0
   * exactly (f' = 0 there). */
  double worst = 0.0;
  ps_int bad_zero = 0, n_zero = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    ps_int a = net->a[i], b = net->b[i];
    double r = sqrt(d2_of(&P->x[b * dim], &P->x[a * dim], dim));
    double e = fabs(net->r0[i] - r) / r;
    if (!(e <= worst)) worst = e;
    for (int side = 0; side < 2; side++) {
      ps_int s = side ? b : a;
      double hp = 1.0;
      for (int k = 0; k <= dim; k++) hp *= P->h[s];
      double want = -P->volume[a] * P->volume[b] * ps_kernel_df(K, r / P->h[s]) / hp;
      double gotA = side ? net->A_ba[i] : net->A_ab[i];
      if (r >= K->alpha * P->h[s]) {
        n_zero++;
        if (gotA != 0.0) bad_zero++;
      } else {
        e = fabs(gotA - want) / fabs(want);
        if (!(e <= worst) || !(gotA > 0)) worst = gotA > 0 ? e : INFINITY;
      }
    }
  }
  char what[256];
  snprintf(what, sizeof what, "%s: max rel error of r0, A_ab, A_ba vs Eq. 70 formula",
           label);
  ps_check_le(worst, 1e-14, what);
  ps_check(bad_zero == 0 && n_zero > 0,
           "%s: A = 0 exactly on the side whose own horizon the arm exceeds "
           "(%lld such sides, %lld wrong)",
           label, (long long)n_zero, (long long)bad_zero);
  /* families: particle p lists exactly the arms incident to p (reference
   * degree from the brute-force list), sorted by strictly increasing other
   * end; n_arm0 = degree */
  ps_int *deg = calloc((size_t)P->n, sizeof *deg);
  for (ps_int i = 0; i < nb; i++) {
    deg[ref[i].a]++;
    deg[ref[i].b]++;
  }
  ps_int bad_fam = 0, bad_n0 = 0;
  int ptr_ok = net->fam_ptr[0] == 0 && net->fam_ptr[P->n] == 2 * net->n_arm;
  for (ps_int p = 0; p < P->n && ptr_ok; p++) {
    ps_int lo = net->fam_ptr[p], hi = net->fam_ptr[p + 1];
    int ok = hi - lo == deg[p];
    ps_int prev = -1;
    for (ps_int j = lo; ok && j < hi; j++) {
      ps_int arm = net->fam_arm[j];
      if (arm < 0 || arm >= net->n_arm) {
        ok = 0;
        break;
      }
      ps_int other;
      if (net->a[arm] == p)
        other = net->b[arm];
      else if (net->b[arm] == p)
        other = net->a[arm];
      else {
        ok = 0;
        break;
      }
      if (!(other > prev)) ok = 0;
      prev = other;
    }
    if (!ok) bad_fam++;
    if (net->n_arm0[p] != deg[p]) bad_n0++;
  }
  ps_check(ptr_ok && bad_fam == 0,
           "%s: families list exactly each particle's arms, sorted by other end "
           "(%lld particles wrong)",
           label, (long long)bad_fam);
  ps_check(bad_n0 == 0, "%s: n_arm0 = number of arms per particle (%lld wrong)", label,
           (long long)bad_n0);
  free(deg);
  free(got);
  free(ref);
}

/* A jittered box with Eq. 115 sizes scaled by a smooth factor in (0.6, 1.8)
 * (volumes scaled by the factor^N, to keep V ~ h^N). */
static void make_box(ps_particles *P, int dim, ps_int nx, ps_int ny, ps_int nz,
                     double d, unsigned long seed, ps_ctx *ctx) {
  ps_int counts[3] = {nx, ny, nz};
  if (ps_geom_box(P, dim, counts, d, "square", 0.3, seed, ctx)) die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(P, 5, ctx)) die("ps_geom_sizes_eq115", ctx);
  double L = nx * d, H = ny * d;
  for (ps_int a = 0; a < P->n; a++) {
    double x = P->x[a * dim], y = P->x[a * dim + 1];
    double s = 1.2 + 0.6 * sin(2.0 * M_PI * x / L) * cos(M_PI * y / H);
    P->h[a] *= s;
    P->volume[a] *= pow(s, dim);
  }
}

static void test_network_box(ps_ctx *ctx) {
  const double d = 1e-3;
  for (int dim = 2; dim <= 3; dim++) {
    ps_particles P;
    if (dim == 2)
      make_box(&P, 2, 36, 30, 1, d, 5, ctx);
    else
      make_box(&P, 3, 11, 10, 9, d, 6, ctx);
    ps_kernel K;
    if (ps_kernel_init(&K, dim, 2, 5.1, ctx)) die("ps_kernel_init", ctx);
    ps_network net;
    if (ps_network_build(&net, &P, &K, NULL, 0, ctx)) die("ps_network_build", ctx);
    char label[64];
    snprintf(label, sizeof label, "network %dD box (%lld particles)", dim,
             (long long)P.n);
    compare_network(&net, &P, &K, NULL, 0, label);
    double hmin = INFINITY, hmax = 0;
    for (ps_int a = 0; a < P.n; a++) {
      hmin = fmin(hmin, P.h[a]);
      hmax = fmax(hmax, P.h[a]);
    }
    /* exact: the same quotient of the same extremes */
    ps_check(net.max_h_ratio == hmax / hmin && net.n_particle == P.n && net.dim == dim,
             "%s: max_h_ratio = %.4g = max h/min h, n_particle, dim (exact)", label,
             net.max_h_ratio);
    ps_network_free(&net);
    ps_particles_free(&P);
  }

  /* a particle outside every horizon: PS_ERR_INPUT, network left freed */
  {
    ps_particles P;
    ps_int counts[3] = {6, 6, 1};
    if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) die("ps_geom_box", ctx);
    if (ps_geom_sizes_eq115(&P, 5, ctx)) die("ps_geom_sizes_eq115", ctx);
    P.x[0] = -100 * d; /* far away, with its small size */
    P.x[1] = -100 * d;
    ps_kernel K;
    ps_kernel_init(&K, 2, 2, 5.1, ctx);
    ps_network net;
    ps_ctx quiet;
    ps_ctx_init(&quiet);
    int rc = ps_network_build(&net, &P, &K, NULL, 0, &quiet);
    ps_check(rc == PS_ERR_INPUT && net.a == NULL && net.n_arm == 0,
             "network: an isolated particle gives PS_ERR_INPUT and a freed network");
    ps_particles_free(&P);
  }
}

static void test_network_crack(ps_ctx *ctx) {
  const double d = 1e-3;
  ps_particles P;
  make_box(&P, 2, 40, 30, 1, d, 9, ctx);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 5.1, ctx)) die("ps_kernel_init", ctx);
  /* an interior, slightly slanted crack across the middle */
  ps_crack cr[2] = {{{8.3 * d, 15.1 * d, 0}, {31.7 * d, 14.9 * d, 0}},
                    /* an edge crack entering from outside the bottom edge */
                    {{20.2 * d, -1.0 * d, 0}, {20.4 * d, 7.3 * d, 0}}};
  ps_network net;
  if (ps_network_build(&net, &P, &K, cr, 1, ctx)) die("ps_network_build", ctx);
  compare_network(&net, &P, &K, cr, 1, "network 2D box, crack across the middle");
  ps_network_free(&net);
  if (ps_network_build(&net, &P, &K, cr, 2, ctx)) die("ps_network_build", ctx);
  compare_network(&net, &P, &K, cr, 2, "network 2D box, two cracks");
  ps_network_free(&net);
  /* ps_crack_cuts against our own test, both directions, random segments
   * (exact agreement: no degenerate configurations at random) */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  int bad = 0, hits = 0;
  for (int i = 0; i < 100000; i++) {
    double x[2], y[2];
    for (int k = 0; k < 2; k++) {
      x[k] = 40 * d * gsl_rng_uniform(rng);
      y[k] = x[k] + 6 * d * (gsl_rng_uniform(rng) - 0.5);
    }
    int want = seg_cross(x, y, cr[0].p0, cr[0].p1);
    hits += want;
    if (ps_crack_cuts(&cr[0], x, y) != want || ps_crack_cuts(&cr[0], y, x) != want) bad++;
  }
  gsl_rng_free(rng);
  ps_check(bad == 0 && hits > 0,
           "ps_crack_cuts = own parametric test on 1e5 random segments, both "
           "directions (%d crossing, %d differ; exact)",
           hits, bad);
  ps_particles_free(&P);
}

/* 5b. The crack-tip rule (ps_crack_cuts): a crack ending exactly on a
 * lattice point (the corner of four cells of a square lattice, where
 * diagonal arms meet) keeps the arms through its tip, and the same crack
 * with its tip moved by +-1e-13 m (1e-10 of the spacing; the tolerance
 * is 1e-9 of an arm's length) cuts exactly the same arms; an arm that
 * crosses the crack 1e-6 of its length inside the tip is cut. */
static int same_arms(const ps_network *a, const ps_network *b) {
  if (a->n_arm != b->n_arm) return 0;
  for (ps_int i = 0; i < a->n_arm; i++)
    if (a->a[i] != b->a[i] || a->b[i] != b->b[i]) return 0;
  return 1;
}

/* the index of the arm joining particles a < b, or -1 */
static ps_int arm_of(const ps_network *net, ps_int a, ps_int b) {
  for (ps_int i = 0; i < net->n_arm; i++)
    if (net->a[i] == a && net->b[i] == b) return i;
  return -1;
}

static void test_crack_tip(ps_ctx *ctx) {
  const double d = 1e-3;
  ps_particles P;
  ps_int counts[3] = {12, 10, 1};
  if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) die("ps_geom_box", ctx);
  ps_geom_sizes_eq44(&P);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 3.5, ctx)) die("ps_kernel_init", ctx);
  /* particles at ((i + 1/2) d, (j + 1/2) d); the tip at the corner (6d, 5d) */
  ps_crack cr = {{-1.0 * d, 5.0 * d, 0}, {6.0 * d, 5.0 * d, 0}};
  ps_network ref;
  if (ps_network_build(&ref, &P, &K, &cr, 1, ctx)) die("ps_network_build", ctx);
  int same = 1;
  const double shift[4][2] = {{1e-13, 0}, {-1e-13, 0}, {0, 1e-13}, {0, -1e-13}};
  for (int v = 0; v < 4; v++) {
    ps_crack c2 = cr;
    c2.p1[0] += shift[v][0];
    c2.p1[1] += shift[v][1];
    ps_network net;
    if (ps_network_build(&net, &P, &K, &c2, 1, ctx)) die("ps_network_build", ctx);
    same &= same_arms(&ref, &net);
    ps_network_free(&net);
  }
  ps_check(same, "crack tip on a lattice point: the tip moved by +-1e-13 m in x or y "
                 "cuts the same arms (%lld arms)", (long long)ref.n_arm);
  /* particle (i, j) is i + 12 j: (5, 4) - (6, 5) and (6, 4) - (5, 5) pass
   * through the tip, (5, 4) - (5, 5) crosses the crack inside, (6, 4) -
   * (6, 5) passes beyond the tip */
  ps_int through = arm_of(&ref, 5 + 12 * 4, 6 + 12 * 5);
  ps_int through2 = arm_of(&ref, 6 + 12 * 4, 5 + 12 * 5);
  ps_int inside = arm_of(&ref, 5 + 12 * 4, 5 + 12 * 5);
  ps_int beyond = arm_of(&ref, 6 + 12 * 4, 6 + 12 * 5);
  ps_check(through >= 0 && through2 >= 0 && inside < 0 && beyond >= 0,
           "crack tip rule: the diagonal arms through the tip are kept, the arm across "
           "the crack 1/2 spacing inside it is cut, the one beyond it kept");
  /* the rule itself, both directions */
  const double tip[2] = {6.0 * d, 5.0 * d};
  double x[2] = {5.5 * d, 4.5 * d}, y[2] = {6.5 * d, 5.5 * d};
  double xi[2] = {x[0] - 1e-6 * d, x[1]}, yi[2] = {y[0] - 1e-6 * d, y[1]};
  double xo[2] = {x[0] + 1e-6 * d, x[1]}, yo[2] = {y[0] + 1e-6 * d, y[1]};
  double on[2] = {3.0 * d, 5.0 * d + 1e-16}, up[2] = {3.0 * d, 6.0 * d};
  ps_check(!ps_crack_cuts(&cr, x, y) && !ps_crack_cuts(&cr, y, x) &&
               ps_crack_cuts(&cr, xi, yi) && ps_crack_cuts(&cr, yi, xi) &&
               !ps_crack_cuts(&cr, xo, yo) && !ps_crack_cuts(&cr, yo, xo) &&
               !ps_crack_cuts(&cr, tip, up) && !ps_crack_cuts(&cr, on, up),
           "ps_crack_cuts: through the tip kept, 1e-6 of the arm inside it cut, outside "
           "kept (both directions); an arm from the tip or from the crack's line kept");
  int asym = 0;
  for (ps_int a = 0; a < P.n; a++)
    for (ps_int b = 0; b < P.n; b++)
      asym += ps_crack_cuts(&cr, &P.x[2 * a], &P.x[2 * b]) !=
              ps_crack_cuts(&cr, &P.x[2 * b], &P.x[2 * a]);
  ps_check(asym == 0, "ps_crack_cuts is symmetric on the lattice (%d pairs differ)", asym);
  ps_network_free(&ref);
  ps_particles_free(&P);
}

/* 5c. Networks that cannot be built: no arm at all, coincident particles
 * (whatever the size rule; named by index, and by cloud file and line when
 * the cloud carries them), a coordinate that is not finite. */
static void test_network_errors(ps_ctx *ctx) {
  const double d = 1e-3;
  ps_int counts[3] = {4, 4, 1};
  ps_kernel K;
  ps_network net;
  ps_particles P;
  ps_ctx q;
  ps_ctx_init(&q);
  if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) die("ps_geom_box", ctx);
  ps_geom_sizes_eq44(&P);
  ps_kernel_init(&K, 2, 2, 0.5, ctx); /* 0.5 h = 0.28 d: nobody */
  int rc = ps_network_build(&net, &P, &K, NULL, 0, &q);
  ps_check(rc == PS_ERR_INPUT && net.a == NULL &&
               strstr(q.msg, "no arms: the horizon holds no neighbours; alpha too small "
                             "or particles too far apart"),
           "no arms at all: PS_ERR_INPUT, '%s'", q.msg);
  ps_kernel_init(&K, 2, 2, 3.0, ctx);
  P.x[2 * 6] = P.x[2 * 5]; /* particle 6 onto particle 5 */
  P.x[2 * 6 + 1] = P.x[2 * 5 + 1];
  rc = ps_network_build(&net, &P, &K, NULL, 0, &q);
  ps_check(rc == PS_ERR_INPUT && net.a == NULL &&
               strstr(q.msg, "particles 5 and 6 coincide (at (0.0015, 0.0015))"),
           "coincident particles with Eq. 44 sizes: '%s'", q.msg);
  P.x[2 * 6] += 1e-13; /* 1e-10 of the spacing: still coincident */
  rc = ps_network_build(&net, &P, &K, NULL, 0, &q);
  ps_check(rc == PS_ERR_INPUT && strstr(q.msg, "particles 5 and 6 coincide"),
           "particles 1e-13 m apart (1e-10 h) coincide too");
  /* a cloud's file and lines */
  P.source = ps_calloc(16, 1, ctx);
  P.line = ps_calloc((size_t)P.n, sizeof *P.line, ctx);
  if (!P.source || !P.line) die("ps_calloc", ctx);
  snprintf(P.source, 16, "c.txt");
  for (ps_int a = 0; a < P.n; a++) P.line[a] = a + 3;
  rc = ps_network_build(&net, &P, &K, NULL, 0, &q);
  ps_check(rc == PS_ERR_INPUT &&
               strstr(q.msg, "c.txt:9: particles 5 and 6 coincide (at (") &&
               strstr(q.msg, "the first at line 8"),
           "coincident cloud particles named by file and line: '%s'", q.msg);
  rc = ps_geom_sizes_eq115(&P, 5, &q);
  ps_check(rc == PS_ERR_INPUT && strstr(q.msg, "c.txt:9: particles 5 and 6 coincide"),
           "Eq. 115 names the same pair: '%s'", q.msg);
  P.x[2 * 6] = INFINITY;
  rc = ps_network_build(&net, &P, &K, NULL, 0, &q);
  ps_check(rc == PS_ERR_INPUT && strstr(q.msg, "c.txt:9: particle 6: coordinate x is not "
                                               "finite"),
           "a coordinate that is not finite: '%s'", q.msg);
  ps_particles_free(&P);
}

/* 5d. The size estimate (estimate.c) against the network it predicts, and
 * ps_kdtree_count against the listing query. */
static void test_estimate(ps_ctx *ctx) {
  const double d = 1e-3;
  ps_particles P;
  make_box(&P, 2, 40, 30, 1, d, 9, ctx);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 5.1, ctx)) die("ps_kernel_init", ctx);
  ps_crack cr = {{8.3 * d, 15.1 * d, 0}, {31.7 * d, 14.9 * d, 0}};
  ps_network net;
  if (ps_network_build(&net, &P, &K, &cr, 1, ctx)) die("ps_network_build", ctx);
  ps_estimate_opts o = {1, 1, 1, 0, 1.0};
  ps_estimate e;
  if (ps_estimate_sample(&e, &P, 5.1, &cr, 1, &o, ctx)) die("ps_estimate_sample", ctx);
  ps_check_rel(e.arms, (double)net.n_arm, 0.03, "estimate of the arms (3%)");
  ps_check(e.factor_nnz >= e.tangent_nnz && e.mem_run > e.mem_build &&
               e.mem_build > e.mem_network && e.stage == 2 && e.sampled == 512,
           "estimate: factor >= tangent, run > info > network memory");
  ps_kdtree *t;
  if (ps_kdtree_build(&t, P.x, P.n, 2, ctx)) die("ps_kdtree_build", ctx);
  ps_int *nb = NULL, cap = 0, cnt, bad = 0;
  for (ps_int a = 0; a < P.n; a += 7) {
    double r = (0.5 + (a % 13)) * d;
    if (ps_kdtree_radius(t, &P.x[2 * a], r, &nb, &cap, &cnt, ctx)) die("radius", ctx);
    bad += ps_kdtree_count(t, &P.x[2 * a], r, P.n) != cnt;
    bad += ps_kdtree_count(t, &P.x[2 * a], r, 5) != (cnt < 5 ? cnt : 5);
  }
  ps_check(bad == 0 && ps_kdtree_count(t, P.x, 1.0, P.n) == P.n,
           "ps_kdtree_count = the listing query's count (capped; a ball over everything)");
  free(nb);
  ps_kdtree_free(&t);
  /* a horizon over the whole body is estimated at once: n (n - 1) / 2 arms
   * (to the sampling error: each sampled particle counts the pairs it
   * decides), n^2 tangent pairs */
  double t0 = ps_wtime();
  if (ps_estimate_sample(&e, &P, 1e6, NULL, 0, &o, ctx)) die("ps_estimate_sample", ctx);
  double dt = ps_wtime() - t0, n = (double)P.n;
  ps_check(fabs(e.arms - n * (n - 1) / 2) < 0.01 * n * (n - 1) / 2 && e.pairs == n * n &&
               dt < 30.0,
           "estimate of a horizon over the whole body: n(n-1)/2 arms (1%%, sampled), "
           "n^2 pairs, without building them (%.3f s; hang guard 30 s)",
           dt);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* ------------------------------------------------------------------ */
/* 6. elliptic disk                                                    */

static double disk_area_sum(const ps_particles *P) {
  long double s = 0.0L;
  for (ps_int a = 0; a < P->n; a++) s += P->volume[a];
  return (double)s;
}

static void test_disk_geometry(ps_ctx *ctx) {
  /* (a) total area = pi (c cosh xi_max)(c sinh xi_max); tol 1e-12: the
   * sub-cell areas are exact antiderivative differences of terms up to
   * sinh(2 pi)/4 ~ 134 (cancellation ~ 1e-14 each) */
  for (int j = 0; j < 2; j++) {
    ps_disk_params dp;
    ps_disk_params_default(&dp);
    dp.n_eta = 8;
    dp.n_xi = 14;
    dp.per_zone = 3;
    dp.jitter = j ? 0.3 : 0.0;
    ps_particles P;
    if (ps_geom_disk(&P, &dp, ctx)) die("ps_geom_disk", ctx);
    double want = M_PI * dp.c * cosh(dp.xi_max) * dp.c * sinh(dp.xi_max);
    char what[128];
    snprintf(what, sizeof what, "disk 8x14x3x3 jitter %.1f: sum V = pi a b", dp.jitter);
    ps_check_rel(disk_area_sum(&P), want, 1e-12, what);
    /* every particle inside the ellipse xi < xi_max and off the crack */
    ps_int bad = 0;
    for (ps_int a = 0; a < P.n; a++) {
      double xi, eta;
      ps_geom_elliptic_coords(P.x[2 * a], P.x[2 * a + 1], dp.c, &xi, &eta);
      if (!(xi < dp.xi_max && xi > 0)) bad++;
    }
    ps_check(bad == 0, "disk jitter %.1f: all particles inside the ellipse, none on "
             "the crack (%lld outside)", dp.jitter, (long long)bad);
    ps_particles_free(&P);
  }
  /* (c) boundary zone = outermost ring: flags = (zone 0 or n_xi-1), and
   * geometrically: elliptic xi (from the position) above the last zone edge
   * xi_max - (xi_max - xi_min)/n_xi (jitter stays within sub-cells) */
  {
    ps_disk_params dp;
    ps_disk_params_default(&dp);
    dp.n_eta = 10;
    dp.n_xi = 20;
    dp.jitter = 0.3;
    ps_particles P;
    if (ps_geom_disk(&P, &dp, ctx)) die("ps_geom_disk", ctx);
    double edge = dp.xi_max - (dp.xi_max - dp.xi_min) / dp.n_xi;
    ps_int bad_flag = 0, bad_geo = 0, n_flag = 0;
    for (ps_int a = 0; a < P.n; a++) {
      int outer = P.zone_xi[a] == 0 || P.zone_xi[a] == dp.n_xi - 1;
      if ((P.in_boundary_zone[a] != 0) != outer) bad_flag++;
      double xi, eta;
      ps_geom_elliptic_coords(P.x[2 * a], P.x[2 * a + 1], dp.c, &xi, &eta);
      if ((xi > edge) != (P.in_boundary_zone[a] != 0)) bad_geo++;
      n_flag += P.in_boundary_zone[a] != 0;
    }
    ps_int want_flag = 2LL * dp.n_eta * dp.per_zone * dp.per_zone;
    ps_check(bad_flag == 0 && bad_geo == 0 && n_flag == want_flag,
             "disk boundary zone: flagged = zone_xi 0 or n_xi-1 (%lld wrong), = "
             "elliptic xi > %.4f (%lld wrong), count %lld = 2 n_eta 25",
             (long long)bad_flag, edge, (long long)bad_geo, (long long)n_flag);
    ps_particles_free(&P);
  }
}

/* Build the disk network and report; returns arm count and size ratio. */
static void disk_network(const ps_disk_params *dp, ps_int *n_arm, double *ratio,
                         double *t_build, ps_int *n_part, int compare, ps_ctx *ctx) {
  ps_particles P;
  if (ps_geom_disk(&P, dp, ctx)) die("ps_geom_disk", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) die("ps_geom_sizes_eq115", ctx);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 5.1, ctx)) die("ps_kernel_init", ctx);
  ps_crack cr = {{-dp->c, 0, 0}, {dp->c, 0, 0}};
  ps_network net;
  double t0 = ps_wtime();
  if (ps_network_build(&net, &P, &K, &cr, 1, ctx)) die("ps_network_build", ctx);
  *t_build = ps_wtime() - t0;
  double hmin = INFINITY, hmax = 0;
  for (ps_int a = 0; a < P.n; a++) {
    hmin = fmin(hmin, P.h[a]);
    hmax = fmax(hmax, P.h[a]);
  }
  *n_arm = net.n_arm;
  *ratio = hmax / hmin;
  *n_part = P.n;
  if (compare) {
    char label[96];
    snprintf(label, sizeof label, "disk network %dx%dx%dx%d (crack between foci)",
             dp->n_eta, dp->n_xi, dp->per_zone, dp->per_zone);
    compare_network(&net, &P, &K, &cr, 1, label);
  }
  ps_network_free(&net);
  ps_particles_free(&P);
}

static void test_disk_network(ps_ctx *ctx) {
  /* brute-force comparison on a small disk (variable sizes over 2 orders
   * of magnitude, a crack): exact as in 4. */
  {
    ps_disk_params dp;
    ps_disk_params_default(&dp);
    dp.n_eta = 6;
    dp.n_xi = 12;
    dp.per_zone = 3;
    dp.jitter = 0.3;
    ps_int na, np;
    double ratio, t;
    disk_network(&dp, &na, &ratio, &t, &np, 1, ctx);
  }
  if (small_mode) {
    printf("(small mode: the paper-size disk checks are skipped)\n");
    return;
  }
  /* (b) the paper's disk: 20 x 40 zones of 5x5, xi in (-pi, pi), seed 11,
   * n = 5 in Eq. 115, alpha 5.1, k 2. Asserted on the regular (unjittered)
   * disk, which is deterministic: MODEL-NOTES' prototype gives 229.7k arms
   * (+1.5% on Table 1's 226,256) and a size ratio of 377. The tolerance of
   * 3% covers what the paper leaves unsaid (its noise algorithm): about
   * 25,000 arms lie within 1% of the cut-off alpha max(h), so the jittered
   * count swings with the noise amplitude (seed 11: -3.4% at jitter 0.1,
   * +0.04% at 0.2, +3.0% at 0.3); those are printed for information. */
  ps_disk_params dp;
  ps_disk_params_default(&dp);
  dp.seed = 11;
  dp.jitter = 0.0;
  ps_int na, np;
  double ratio, t;
  disk_network(&dp, &na, &ratio, &t, &np, 0, ctx);
  printf("disk %dx%d zones of %dx%d, no jitter: %lld particles, %lld arms, "
         "max h/min h = %.1f, network build %.3f s (information only)\n",
         dp.n_eta, dp.n_xi, dp.per_zone, dp.per_zone, (long long)np, (long long)na, ratio,
         t);
  ps_check(np == 20000, "paper disk: 20000 particles (got %lld)", (long long)np);
  ps_check_rel((double)na, 226256.0, 0.03, "paper disk: arm count vs Table 1 nA = 226256");
  /* the paper: "more than 400 times" (jittered); the regular disk: 377 */
  ps_check(ratio > 300, "paper disk: max h / min h = %.1f > 300", ratio);
  for (int j = 1; j <= 3; j++) {
    dp.jitter = 0.1 * j;
    disk_network(&dp, &na, &ratio, &t, &np, 0, ctx);
    printf("disk jitter %.1f (information): %lld arms (%+.2f%% on Table 1), max h/min h = "
           "%.1f, build %.3f s\n",
           dp.jitter, (long long)na, 100.0 * (na - 226256.0) / 226256.0, ratio, t);
  }
}

/* Westergaard's solution for the Griffith crack (-c, c) under equibiaxial
 * remote stress S: Z = S z / sqrt(z^2 - c^2), Zbar = S sqrt(z^2 - c^2);
 * 2G u = (kappa-1)/2 Re Zbar - y Im Z, 2G v = (kappa+1)/2 Im Zbar - y Re Z.
 * sqrt(z-c) sqrt(z+c) puts the cut on [-c, c]. */
static void westergaard(double x, double y, double c, double S, double G,
                        double kappa, double *u, double *v) {
  double complex z = x + I * y;
  double complex w = csqrt(z - c) * csqrt(z + c);
  double complex Z = S * z / w, Zb = S * w;
  *u = (0.5 * (kappa - 1) * creal(Zb) - y * cimag(Z)) / (2 * G);
  *v = (0.5 * (kappa + 1) * cimag(Zb) - y * creal(Z)) / (2 * G);
}

static void test_eq116(void) {
  const double c = 1.0 / 24.0, E = 210e9, nu = 0.3, S = 1e8;
  const double G = E / (2 * (1 + nu)), kappa = 3 - 4 * nu;
  double u, v, u2, v2;
  /* far field at radius 1e4 c: the crack's perturbation is O((c/r)^2) =
   * 1e-8; tol 1e-3 (the brief's) */
  double worst = 0.0;
  const double th[] = {0.3, 1.1, 2.0, 2.9, -0.7, -2.4};
  for (size_t i = 0; i < sizeof th / sizeof *th; i++) {
    double x = 1e4 * c * cos(th[i]), y = 1e4 * c * sin(th[i]);
    ps_geom_eq116(x, y, c, S, G, kappa, &u, &v);
    double uf = S * (1 - 2 * nu) * x / (2 * G), vf = S * (1 - 2 * nu) * y / (2 * G);
    double e = fmax(fabs(u - uf) / fabs(uf), fabs(v - vf) / fabs(vf));
    if (!(e <= worst)) worst = e;
  }
  ps_check_le(worst, 1e-3,
              "Eq. 116 at r = 1e4 c (6 angles): max rel error vs S(1-2nu)x/(2G)");
  /* Griffith opening at x = 0.3c: y = +-1e-13 c off the faces changes v by
   * O(1e-13) relative; tol 1e-9 */
  {
    double x = 0.3 * c, y = 1e-13 * c;
    ps_geom_eq116(x, y, c, S, G, kappa, &u, &v);
    ps_geom_eq116(x, -y, c, S, G, kappa, &u2, &v2);
    double want = 4 * (1 - nu * nu) * S * sqrt(c * c - x * x) / E;
    ps_check_rel(v - v2, want, 1e-9,
                 "Eq. 116 crack opening at x = 0.3c = Griffith 4(1-nu^2)S sqrt(c^2-x^2)/E");
    ps_check_le(fabs(u) / want, 1e-9, "Eq. 116 on the crack face: u = 0 (relative to opening)");
    ps_geom_eq116(0.0, 1e-13 * c, c, S, G, kappa, &u, &v);
    ps_geom_eq116(0.0, -1e-13 * c, c, S, G, kappa, &u2, &v2);
    ps_check_rel(v - v2, 4 * (1 - nu * nu) * S * c / E, 1e-9,
                 "Eq. 116 crack opening at x = 0 = 4(1-nu^2) S c / E");
  }
  /* symmetry of the principal branch and agreement with Westergaard at
   * generic points (near field included). Symmetry tol 1e-14 (cacosh
   * commutes with conjugation); Westergaard tol 1e-10 (two closed forms,
   * round-off amplified near the tips) */
  double wsym = 0.0, wwest = 0.0;
  const double pts[][2] = {{0.2, 0.3},  {1.3, 0.05}, {-0.7, 0.9}, {2.5, 1.7},
                           {-1.05, 0.02}, {0.0, 0.5}, {4.0, -3.0}, {-0.4, -0.1},
                           {11.0, 0.2}, {-5.5, -5.0}};
  for (size_t i = 0; i < sizeof pts / sizeof *pts; i++) {
    double x = pts[i][0] * c, y = pts[i][1] * c;
    ps_geom_eq116(x, y, c, S, G, kappa, &u, &v);
    ps_geom_eq116(x, -y, c, S, G, kappa, &u2, &v2);
    double mag = hypot(u, v);
    double e = hypot(u2 - u, v2 + v) / mag;
    if (!(e <= wsym)) wsym = e;
    double uw, vw;
    westergaard(x, y, c, S, G, kappa, &uw, &vw);
    e = hypot(u - uw, v - vw) / hypot(uw, vw);
    if (!(e <= wwest)) wwest = e;
  }
  ps_check_le(wsym, 1e-14, "Eq. 116: u(x,-y) = u(x,y), v(x,-y) = -v(x,y) (10 points)");
  ps_check_le(wwest, 1e-10, "Eq. 116 = Westergaard solution at 10 generic points (rel)");

  /* elliptic coordinates: principal branch (xi >= 0, |eta| <= pi) and
   * round trip through Eq. 114; tol 1e-13: round-off of cacosh, cosh */
  {
    double worst_rt = 0.0;
    for (size_t i = 0; i < sizeof pts / sizeof *pts; i++) {
      double x = pts[i][0] * c, y = pts[i][1] * c, xi, eta;
      ps_geom_elliptic_coords(x, y, c, &xi, &eta);
      double xr = c * cosh(xi) * cos(eta), yr = c * sinh(xi) * sin(eta);
      double e = hypot(xr - x, yr - y) / hypot(x, y);
      if (xi < 0 || fabs(eta) > M_PI || !(e <= 1.0)) e = INFINITY; /* NaN-safe */
      worst_rt = fmax(worst_rt, e);
    }
    ps_check_le(worst_rt, 1e-13, "elliptic coords: principal branch, round trip (rel)");
  }

  /* perimeter: large xi -> 2 pi c cosh xi; at xi = 10 the eccentricity is
   * 9.1e-5 and E(e) = pi/2 (1 - e^2/4 ...), so the relative gap is 2e-9:
   * tol 1e-8 */
  ps_check_rel(ps_geom_ellipse_perimeter(c, 10.0), 2 * M_PI * c * cosh(10.0), 1e-8,
               "ellipse perimeter, xi = 10: 2 pi c cosh xi");
  /* known cases against our own periodic trapezoid rule of
   * int_0^2pi sqrt(a^2 sin^2 t + b^2 cos^2 t) dt (exponentially convergent;
   * 20000 points): tol 1e-10 */
  const double xis[] = {0.05, 0.5, M_PI};
  for (size_t i = 0; i < sizeof xis / sizeof *xis; i++) {
    double a = c * cosh(xis[i]), b = c * sinh(xis[i]);
    int m = 20000;
    long double s = 0.0L;
    for (int j = 0; j < m; j++) {
      double t = 2 * M_PI * j / m;
      s += sqrt(a * a * sin(t) * sin(t) + b * b * cos(t) * cos(t));
    }
    double P = (double)(s * (2 * M_PI / m));
    char what[96];
    snprintf(what, sizeof what, "ellipse perimeter, xi = %.3g: own trapezoid integral",
             xis[i]);
    ps_check_rel(ps_geom_ellipse_perimeter(c, xis[i]), P, 1e-10, what);
  }
}

/* A disk whose crack line xi = 0 would cut through a row of sub-cells
 * (odd n_xi * per_zone with a symmetric xi range: one row would sit on the
 * crack and bridge it) is refused. */
static void test_disk_crack_row(ps_ctx *ctx) {
  ps_disk_params dp;
  ps_disk_params_default(&dp);
  dp.n_eta = 4;
  dp.n_xi = 7;
  dp.per_zone = 5;
  ps_particles P;
  int st = ps_geom_disk(&P, &dp, ctx);
  ps_check(st == PS_ERR_INPUT && strstr(ctx->msg, "sub-cell boundary"),
           "disk with n_xi * per_zone = 35 (crack through a row) refused: %s", ctx->msg);
  if (st == PS_OK) ps_particles_free(&P);
}

int main(int argc, char **argv) {
  small_mode = argc > 1 && strcmp(argv[1], "small") == 0;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  double t0 = ps_wtime();
  test_kernel(&ctx);
  test_kdtree(&ctx);
  test_sizes(&ctx);
  test_network_box(&ctx);
  test_network_crack(&ctx);
  test_crack_tip(&ctx);
  test_network_errors(&ctx);
  test_estimate(&ctx);
  test_disk_geometry(&ctx);
  test_disk_crack_row(&ctx);
  test_disk_network(&ctx);
  test_eq116();
  printf("t100_network: %.2f s in all (information only)\n", ps_wtime() - t0);
  return ps_check_summary();
}
