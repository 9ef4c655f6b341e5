/* t105_geom.c: the geometry (src/geom), checked against independent
 * computations:
 *  1. k-d tree: radius and k-nearest queries = brute force, exactly.
 *  2. Eq. 115 sizes on the square, hexagonal and cubic lattices.
 *  3. the elliptic disk of Eq. 114: exact total area, boundary zone flags,
 *     tip refinement (exact area, count, closer particles, the rest kept),
 *     a crack line through a row of sub-cells refused.
 *  4. Eq. 116 against its limits (far field, Griffith opening, symmetry)
 *     and against the Westergaard solution; elliptic coordinates; the
 *     ellipse perimeter. */
#include <complex.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "geomnet.h"

static int cmp_int(const void *u, const void *v) {
  ps_int a = *(const ps_int *)u, b = *(const ps_int *)v;
  return a < b ? -1 : a > b;
}

/* ------------------------------------------------------------------ */
/* 1. k-d tree                                                         */

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
      tg_die("ps_kdtree_radius", ctx);
    ps_int nr = 0;
    for (ps_int j = 0; j < n; j++)
      if (tg_d2(&x[j * dim], &q[i * dim], dim) < radius * radius) ref[nr++] = j;
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
    if (ps_kdtree_build(&t, x, n, dim, ctx)) tg_die("ps_kdtree_build", ctx);
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
        double d2 = tg_d2(&x[j * dim], &x[i * dim], dim);
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
    if (ps_geom_box(&P, 2, counts, 1.0, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
    ps_kdtree *t = NULL;
    if (ps_kdtree_build(&t, P.x, P.n, 2, ctx)) tg_die("ps_kdtree_build", ctx);
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
    if (ps_kdtree_build(&t, x, 4, 2, ctx)) tg_die("ps_kdtree_build", ctx);
    ps_int idx[5];
    double dist[5];
    int f = ps_kdtree_knn(t, 0, 5, idx, dist);
    ps_check(f == 3 && dist[0] == 1.0 && dist[1] == 1.0 && dist[2] == sqrt(2.0),
             "kdtree knn k=5 on 4 points: 3 found, distances 1, 1, sqrt 2 (exact)");
    ps_kdtree_free(&t);
  }
}

/* ------------------------------------------------------------------ */
/* 2. Eq. 115 sizes                                                    */

static void test_sizes(ps_ctx *ctx) {
  const double d = 2.5e-3;
  ps_particles P;
  ps_int counts[3] = {9, 9, 1};
  if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) tg_die("ps_geom_sizes_eq115", ctx);
  /* interior: 4 neighbours at d and one of the 4 diagonal ones at sqrt2 d:
   * h = (4 + sqrt 2) d / 10; tol 1e-12: a sum of 5 rounded distances */
  ps_check_rel(P.h[4 * 9 + 4], (4.0 + sqrt(2.0)) / 10.0 * d, 1e-12,
               "Eq. 115 (n=5) square lattice interior: h = (4+sqrt2)/10 d");
  ps_check_rel(P.h[4 * 9 + 4] / d, 0.5414, 1e-4,
               "Eq. 115 square lattice: h/d = 0.5414 (4 digits)");
  ps_particles_free(&P);
  if (ps_geom_box(&P, 2, counts, d, "hex", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) tg_die("ps_geom_sizes_eq115", ctx);
  /* hex: 6 neighbours at d (the offset rows are at sqrt(1/4 + 3/4) d), so
   * h = 5 d / 10; tol 1e-12: round-off of sqrt(3)/2 in the row spacing */
  ps_check_rel(P.h[4 * 9 + 4], 0.5 * d, 1e-12, "Eq. 115 (n=5) hex lattice interior: h = d/2");
  ps_check_rel(P.volume[0], d * d * sqrt(3.0) / 2.0, 1e-15, "hex lattice volume d^2 sqrt3/2");
  ps_particles_free(&P);
  /* 3D cubic: 6 neighbours at d, h = d/2 */
  ps_int c3[3] = {5, 5, 5};
  if (ps_geom_box(&P, 3, c3, d, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) tg_die("ps_geom_sizes_eq115", ctx);
  ps_check_rel(P.h[2 * 25 + 2 * 5 + 2], 0.5 * d, 1e-12, "Eq. 115 (n=5) cubic lattice interior: h = d/2");
  ps_particles_free(&P);
}

/* ------------------------------------------------------------------ */
/* 3. elliptic disk                                                    */

static double disk_area_sum(const ps_particles *P) {
  long double s = 0.0L;
  for (ps_int a = 0; a < P->n; a++) s += P->volume[a];
  return (double)s;
}

static void test_disk_geometry(ps_ctx *ctx) {
  /* total area = pi (c cosh xi_max)(c sinh xi_max); tol 1e-12: the
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
    if (ps_geom_disk(&P, &dp, ctx)) tg_die("ps_geom_disk", ctx);
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
  /* boundary zone = outermost ring: flags = (zone 0 or n_xi-1), and
   * geometrically: elliptic xi (from the position) above the last zone edge
   * xi_max - (xi_max - xi_min)/n_xi (jitter stays within sub-cells) */
  {
    ps_disk_params dp;
    ps_disk_params_default(&dp);
    dp.n_eta = 10;
    dp.n_xi = 20;
    dp.jitter = 0.3;
    ps_particles P;
    if (ps_geom_disk(&P, &dp, ctx)) tg_die("ps_geom_disk", ctx);
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

/* the distance of particle a from the nearer tip (+-c, 0) */
static double tip_distance(const ps_particles *P, ps_int a, double c) {
  double x = P->x[2 * a], y = P->x[2 * a + 1];
  return fmin(hypot(x - c, y), hypot(x + c, y));
}

/* the distance from the nearest tip of the particle closest to one */
static double nearest_to_tip(const ps_particles *P, double c) {
  double best = INFINITY;
  for (ps_int a = 0; a < P->n; a++) best = fmin(best, tip_distance(P, a, c));
  return best;
}

/* Tip refinement (refine_tips, refine_radius): the sub-cells within the
 * radius of a tip split into k^2 cells of exact area, so the total area
 * is still pi a b (1e-12, as above), the count is ps_geom_disk_count's
 * and the particles near the tips are k times closer to them (the
 * nearest within 1.5/k of the unrefined disk's); the rest of the disk is
 * the unrefined one, jitter included. refine_tips 1, or radius 0, gives
 * the default disk bit for bit. */
static void test_disk_refine(ps_ctx *ctx) {
  ps_disk_params dp;
  ps_disk_params_default(&dp);
  dp.n_eta = 8;
  dp.n_xi = 14;
  dp.per_zone = 3;
  dp.jitter = 0.2;
  ps_particles P0, P1, P2;
  if (ps_geom_disk(&P0, &dp, ctx)) tg_die("ps_geom_disk", ctx);
  dp.refine_tips = 3;
  dp.refine_radius = 0.3 * dp.c;
  if (ps_geom_disk(&P1, &dp, ctx)) tg_die("ps_geom_disk refined", ctx);
  double want = M_PI * dp.c * cosh(dp.xi_max) * dp.c * sinh(dp.xi_max);
  ps_check_rel(disk_area_sum(&P1), want, 1e-12,
               "disk 8x14x3x3 refined 3x within 0.3 c of the tips: sum V = pi a b");
  ps_int far_same = 0, far = 0, near = 0;
  for (ps_int a = 0; a < P1.n; a++) near += tip_distance(&P1, a, dp.c) < 0.3 * dp.c;
  for (ps_int a = 0; a < P0.n; a++) {
    double x = P0.x[2 * a], y = P0.x[2 * a + 1];
    if (tip_distance(&P0, a, dp.c) < 0.6 * dp.c) continue;
    far++;
    for (ps_int b = 0; b < P1.n; b++)
      if (P1.x[2 * b] == x && P1.x[2 * b + 1] == y && P1.volume[b] == P0.volume[a]) {
        far_same++;
        break;
      }
  }
  double r0 = nearest_to_tip(&P0, dp.c), r1 = nearest_to_tip(&P1, dp.c);
  ps_check(P1.n == (ps_int)ps_geom_disk_count(&dp) && P1.n > P0.n && near > 0 &&
               far_same == far && r1 < 1.5 / 3 * r0,
           "disk refined 3x at the tips: %lld particles (count %.0f; unrefined %lld), %lld "
           "within 0.3 c, the %lld beyond 0.6 c unchanged (%lld), nearest to a tip %.3g of "
           "the unrefined disk's", (long long)P1.n, ps_geom_disk_count(&dp),
           (long long)P0.n, (long long)near, (long long)far, (long long)far_same, r1 / r0);
  dp.refine_radius = 0.0;
  if (ps_geom_disk(&P2, &dp, ctx)) tg_die("ps_geom_disk radius 0", ctx);
  int same = P2.n == P0.n;
  for (ps_int a = 0; same && a < P0.n; a++)
    same = P2.x[2 * a] == P0.x[2 * a] && P2.x[2 * a + 1] == P0.x[2 * a + 1] &&
           P2.volume[a] == P0.volume[a];
  ps_check(same, "disk with refine_tips 3 and refine_radius 0: the unrefined disk bit for bit");
  dp.refine_tips = 0;
  dp.refine_radius = 0.1;
  ps_particles P3;
  int st = ps_geom_disk(&P3, &dp, ctx);
  ps_check(st == PS_ERR_INPUT && strstr(ctx->msg, "refine_tips"),
           "disk refine_tips 0 refused: %s", ctx->msg);
  if (st == PS_OK) ps_particles_free(&P3);
  ps_particles_free(&P0);
  ps_particles_free(&P1);
  ps_particles_free(&P2);
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

/* ------------------------------------------------------------------ */
/* 4. Eq. 116, elliptic coordinates, perimeter                         */

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

int main(int argc, char **argv) {
  (void)argc;
  (void)argv;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  double t0 = ps_wtime();
  test_kdtree(&ctx);
  test_sizes(&ctx);
  test_disk_geometry(&ctx);
  test_disk_refine(&ctx);
  test_disk_crack_row(&ctx);
  test_eq116();
  printf("t105_geom: %.2f s in all (information only)\n", ps_wtime() - t0);
  return ps_check_summary();
}
