/* t115_estimate.c: the size estimate (src/network/estimate.c) against the
 * network it predicts (arms to 3%), the consistency of its figures,
 * ps_kdtree_count against the listing query, and a horizon over the whole
 * body estimated without building its arms. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "geomnet.h"

static void test_estimate(ps_ctx *ctx) {
  const double d = 1e-3;
  ps_particles P;
  tg_make_box(&P, 2, 40, 30, 1, d, 9, ctx);
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, 5.1, ctx)) tg_die("ps_kernel_init", ctx);
  ps_crack cr = {.p0 = {8.3 * d, 15.1 * d, 0}, .p1 = {31.7 * d, 14.9 * d, 0}};
  ps_network net;
  if (ps_network_build(&net, &P, &K, &cr, 1, ctx)) tg_die("ps_network_build", ctx);
  ps_estimate_opts o = {1, 1, 1, 0, 1.0};
  ps_estimate e;
  if (ps_estimate_sample(&e, &P, 5.1, &cr, 1, &o, ctx)) tg_die("ps_estimate_sample", ctx);
  ps_check_rel(e.arms, (double)net.n_arm, 0.03, "estimate of the arms (3%)");
  ps_check(e.factor_nnz >= e.tangent_nnz && e.mem_run > e.mem_build &&
               e.mem_build > e.mem_network && e.stage == 2 && e.sampled == 512,
           "estimate: factor >= tangent, run > info > network memory");
  ps_kdtree *t;
  if (ps_kdtree_build(&t, P.x, P.n, 2, ctx)) tg_die("ps_kdtree_build", ctx);
  ps_int *nb = NULL, cap = 0, cnt, bad = 0;
  for (ps_int a = 0; a < P.n; a += 7) {
    double r = (0.5 + (a % 13)) * d;
    if (ps_kdtree_radius(t, &P.x[2 * a], r, &nb, &cap, &cnt, ctx)) tg_die("radius", ctx);
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
  if (ps_estimate_sample(&e, &P, 1e6, NULL, 0, &o, ctx)) tg_die("ps_estimate_sample", ctx);
  double dt = ps_wtime() - t0, n = (double)P.n;
  ps_check(fabs(e.arms - n * (n - 1) / 2) < 0.01 * n * (n - 1) / 2 && e.pairs == n * n &&
               dt < 30.0,
           "estimate of a horizon over the whole body: n(n-1)/2 arms (1%%, sampled), "
           "n^2 pairs, without building them (%.3f s; hang guard 30 s)",
           dt);
  ps_network_free(&net);
  ps_particles_free(&P);
}

int main(int argc, char **argv) {
  (void)argc;
  (void)argv;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  double t0 = ps_wtime();
  test_estimate(&ctx);
  printf("t115_estimate: %.2f s in all (information only)\n", ps_wtime() - t0);
  return ps_check_summary();
}
