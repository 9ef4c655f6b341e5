/* t110_network.c: the arm network (src/network), checked against
 * independent computations:
 *  1. network = O(n^2) brute force (arm set, weights of Eq. 70, families,
 *     n_arm0) on jittered variable-size boxes, 2D and 3D.
 *  2. pre-cracks: no arm crosses a crack; every other arm is present; the
 *     crack-tip rule (an arm through a tip is kept, to 1e-13 m shifts);
 *     networks that cannot be built (no arms, coincident particles, a
 *     coordinate not finite) and their messages.
 *  3. the elliptic disk's network: brute force on a small disk; at the
 *     paper's size (20,000 particles) Table 1's arm count and size ratio.
 * Run "t110_network small" for the small disk only (for valgrind): the
 * paper-size checks of 3 are then skipped. */
#include <gsl/gsl_math.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "geomnet.h"

static int small_mode = 0;

/* Our own segment test (parametric, not orientation signs as in src/):
 * does the open segment x-y cross the open segment p-q? */
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

/* ------------------------------------------------------------------ */
/* 1./2. network against brute force                                   */

/* the cracks of a brute-force list */
typedef struct {
  const ps_crack *cr;
  int n;
} crack_list;

static int cuts_any(const void *arg, const double *x, const double *y) {
  const crack_list *l = arg;
  for (int c = 0; c < l->n; c++)
    if (seg_cross(x, y, l->cr[c].p0, l->cr[c].p1)) return 1;
  return 0;
}

/* The brute-force arm list {a < b : r < alpha max(h_a, h_b), not cut by any
 * crack}, sorted by (a, b). Also counts the pairs removed by the cracks. */
static tg_pair *brute_arms(const ps_particles *P, double alpha, const ps_crack *cr,
                           int ncr, ps_int *n_out, ps_int *n_cut) {
  crack_list l = {cr, ncr};
  return tg_brute_arms(P, alpha, cuts_any, &l, n_out, n_cut);
}

/* Compare net with the brute-force list and with the Eq. 70 weights;
 * families and n_arm0. label names the case in the output. */
static void compare_network(const ps_network *net, const ps_particles *P,
                            const ps_kernel *K, const ps_crack *cr, int ncr,
                            const char *label) {
  int dim = P->dim;
  ps_int nb, ncut;
  tg_pair *ref = brute_arms(P, K->alpha, cr, ncr, &nb, &ncut);
  /* arm set: exact */
  int ordered = 1;
  tg_pair *got = malloc((size_t)(net->n_arm + 1) * sizeof *got);
  for (ps_int i = 0; i < net->n_arm; i++) {
    got[i].a = net->a[i];
    got[i].b = net->b[i];
    if (!(net->a[i] < net->b[i])) ordered = 0;
  }
  qsort(got, (size_t)net->n_arm, sizeof *got, tg_cmp_pair);
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
    double r = sqrt(tg_d2(&P->x[b * dim], &P->x[a * dim], dim));
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

static void test_network_box(ps_ctx *ctx) {
  const double d = 1e-3;
  for (int dim = 2; dim <= 3; dim++) {
    ps_particles P;
    if (dim == 2)
      tg_make_box(&P, 2, 36, 30, 1, d, 5, ctx);
    else
      tg_make_box(&P, 3, 11, 10, 9, d, 6, ctx);
    ps_kernel K;
    if (ps_kernel_init(&K, dim, 2, 5.1, ctx)) tg_die("ps_kernel_init", ctx);
    ps_network net;
    if (ps_network_build(&net, &P, &K, NULL, 0, ctx)) tg_die("ps_network_build", ctx);
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
    if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
    if (ps_geom_sizes_eq115(&P, 5, ctx)) tg_die("ps_geom_sizes_eq115", ctx);
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
  tg_make_box(&P, 2, 40, 30, 1, d, 9, ctx);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 5.1, ctx)) tg_die("ps_kernel_init", ctx);
  /* an interior, slightly slanted crack across the middle */
  ps_crack cr[2] = {{.p0 = {8.3 * d, 15.1 * d, 0}, .p1 = {31.7 * d, 14.9 * d, 0}},
                    /* an edge crack entering from outside the bottom edge */
                    {.p0 = {20.2 * d, -1.0 * d, 0}, .p1 = {20.4 * d, 7.3 * d, 0}}};
  ps_network net;
  if (ps_network_build(&net, &P, &K, cr, 1, ctx)) tg_die("ps_network_build", ctx);
  compare_network(&net, &P, &K, cr, 1, "network 2D box, crack across the middle");
  ps_network_free(&net);
  if (ps_network_build(&net, &P, &K, cr, 2, ctx)) tg_die("ps_network_build", ctx);
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

/* 2b. The crack-tip rule (ps_crack_cuts): a crack ending exactly on a
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
  if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
  ps_geom_sizes_eq44(&P);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 3.5, ctx)) tg_die("ps_kernel_init", ctx);
  /* particles at ((i + 1/2) d, (j + 1/2) d); the tip at the corner (6d, 5d) */
  ps_crack cr = {.p0 = {-1.0 * d, 5.0 * d, 0}, .p1 = {6.0 * d, 5.0 * d, 0}};
  ps_network ref;
  if (ps_network_build(&ref, &P, &K, &cr, 1, ctx)) tg_die("ps_network_build", ctx);
  int same = 1;
  const double shift[4][2] = {{1e-13, 0}, {-1e-13, 0}, {0, 1e-13}, {0, -1e-13}};
  for (int v = 0; v < 4; v++) {
    ps_crack c2 = cr;
    c2.p1[0] += shift[v][0];
    c2.p1[1] += shift[v][1];
    ps_network net;
    if (ps_network_build(&net, &P, &K, &c2, 1, ctx)) tg_die("ps_network_build", ctx);
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

/* 2c. Networks that cannot be built: no arm at all, coincident particles
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
  if (ps_geom_box(&P, 2, counts, d, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
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
  if (!P.source || !P.line) tg_die("ps_calloc", ctx);
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
  /* points 2e200 apart: their squared distance overflows; that is no
   * coincidence (and no NaN) */
  {
    ps_particles F;
    ps_int c2[3] = {2, 1, 1};
    if (ps_geom_box(&F, 2, c2, d, "square", 0.0, 1, ctx)) tg_die("ps_geom_box", ctx);
    F.x[0] = -1e200;
    F.x[2] = 1e200;
    F.h[0] = F.h[1] = 1e200;
    rc = ps_network_build(&net, &F, &K, NULL, 0, &q);
    ps_check(rc == PS_ERR_INPUT && !strstr(q.msg, "coincide") && !strstr(q.msg, "nan"),
             "points 2e200 apart: refused, not as coincident: '%s'", q.msg);
    if (rc == PS_OK) ps_network_free(&net);
    ps_particles_free(&F);
  }
  P.x[2 * 6] = INFINITY;
  rc = ps_network_build(&net, &P, &K, NULL, 0, &q);
  ps_check(rc == PS_ERR_INPUT && strstr(q.msg, "c.txt:9: particle 6: coordinate x is not "
                                               "finite"),
           "a coordinate that is not finite: '%s'", q.msg);
  ps_particles_free(&P);
}

/* ------------------------------------------------------------------ */
/* 3. the elliptic disk's network                                      */

/* Build the disk network and report; returns arm count and size ratio. */
static void disk_network(const ps_disk_params *dp, ps_int *n_arm, double *ratio,
                         double *t_build, ps_int *n_part, int compare, ps_ctx *ctx) {
  ps_particles P;
  if (ps_geom_disk(&P, dp, ctx)) tg_die("ps_geom_disk", ctx);
  if (ps_geom_sizes_eq115(&P, 5, ctx)) tg_die("ps_geom_sizes_eq115", ctx);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 5.1, ctx)) tg_die("ps_kernel_init", ctx);
  ps_crack cr = {.p0 = {-dp->c, 0, 0}, .p1 = {dp->c, 0, 0}};
  ps_network net;
  double t0 = ps_wtime();
  if (ps_network_build(&net, &P, &K, &cr, 1, ctx)) tg_die("ps_network_build", ctx);
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
   * of magnitude, a crack): exact as in 1. */
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
  /* the paper's disk: 20 x 40 zones of 5x5, xi in (-pi, pi), seed 11,
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

int main(int argc, char **argv) {
  small_mode = argc > 1 && strcmp(argv[1], "small") == 0;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  double t0 = ps_wtime();
  test_network_box(&ctx);
  test_network_crack(&ctx);
  test_crack_tip(&ctx);
  test_network_errors(&ctx);
  test_disk_network(&ctx);
  printf("t110_network: %.2f s in all (information only)\n", ps_wtime() - t0);
  return ps_check_summary();
}
