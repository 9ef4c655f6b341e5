/* t360_j_integral.c: the J-integral of the edge-cracked plate of Fallah et
 * al. (2020), section 5.2, with the bond-based model
 * (data/cases/edge-crack-bond.yaml, spacing 0.5 mm: 6x the paper's), by
 * the equivalent domain integral (Eq. 39, ps_post_j_domain) on square
 * rings around the tip (q = 1 inside l/2, 0 outside l).
 *
 * (1) Path independence: J over rings with l = 3, 4, 5, 6, 8 mm varies
 *     by at most 2% (the paper: 0.3% on its 6x finer grid; here the
 *     inner rings are only 3-6 spacings wide); the same for the contour
 *     form (Eq. 36, ps_post_j_contour) on squares of half-width l, and the
 *     two forms agree within 2% on each square (the paper: < 1%).
 * (2) J against an independent number of the same model: the energy
 *     release rate from the compliance, G = (W(a + da) - W(a - da)) /
 *     (2 * 2 da) with W = fext . u the work of the tractions (at fixed
 *     load, -dPi/da = 1/2 dW/da), from two more solves with the crack
 *     ending at 9.5 and 10.5 mm (two spacings apart). Within 3%: the
 *     central difference over two spacings of a lattice crack front.
 * (3) J against the finite-element value 6.794 MPa mm = 6794 N/m (Abaqus,
 *     the paper; 6.7955 by a converged true-2D FE model, MODEL-NOTES),
 *     without the surface correction (partial volumes only, as Fallah's
 *     PD): within 3% (the paper's PD approaches FE to about 1% on its
 *     finer grids, Fig. 15; 3% allows for our 6x coarser grid), for
 *     both forms.
 *     With the surface correction (the default) J is 5% below FE: the
 *     correction makes C11 exact, but the square lattice's C12 and C66
 *     stay 6% low (t350), a solid 2.7% stiffer in tension, which explains
 *     about half; (2) shows that the J evaluation is not the cause.
 *     Reported here, discussed in doc/verification.md, not asserted
 *     against FE.
 * With PS_CHECK_LONG set (make check-long), (3) is repeated at spacings of
 * 1, 0.5, 0.25 and the paper's 0.0833 mm (721,800 particles, 13 GB, ~5
 * min): the error must shrink from 1 mm and be within 3% at 0.25 and
 * 0.0833 mm (both readings are printed, except at the finest). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common.h"

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t360: %s failed: %s\n", what, ctx->msg);
  exit(2);
}

static const double J_FE = 6794.0; /* N/m */

/* Solve the case with the crack ending at crack_end (m) and the surface
 * correction on or off; return the work of the tractions and, when J is
 * not NULL, J by Eq. 39 for the rings l[0..nl). */
static double solve(const ps_case *base, double crack_end, int correction, const double *l,
                    int nl, double *J, double *Jc) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 1 : 0;
  ps_case cs = *base;
  cs.cracks[0].p1[0] = crack_end;
  cs.mat.surface_correction = correction;
  ps_problem pb;
  ps_run_result res;
  ps_solver *s = NULL;
  if (ps_problem_setup(&pb, &cs, &ctx)) die_ctx("setup", &ctx);
  if (ps_run_keep(&pb, INFINITY, NULL, &res, &s, &ctx)) die_ctx("run", &ctx);
  const ps_particles *P = &pb.P;
  const double *u = ps_solver_u(s), *T = ps_solver_arm_tension(s);
  const double *q = ps_solver_arm_direction(s);
  double W = 0;
  for (ps_int j = 0; j < 2 * P->n; j++) W += pb.fext[j] * u[j];
  if (J) {
    double *sig = malloc(4 * P->n * sizeof *sig), *H = malloc(4 * P->n * sizeof *H);
    ps_post_stress_tensor(P, &pb.net, T, q, sig);
    ps_post_displacement_gradient(P, &pb.net, ps_solver_arm_state(s), u, H);
    const double tip[2] = {crack_end, cs.cracks[0].p1[1]};
    for (int i = 0; i < nl; i++) J[i] = ps_post_j_domain(P, sig, H, tip, 0.5 * l[i], l[i]);
    if (Jc)
      for (int i = 0; i < nl; i++)
        Jc[i] = ps_post_j_contour(P, &pb.net, T, q, sig, H, tip, l[i], cs.spacing);
    free(sig);
    free(H);
  }
  ps_solver_free(s);
  ps_problem_free(&pb);
  return W;
}

/* ps_post_displacement_gradient recovers an affine field exactly, also
 * beside a crack (one-sided fits there): 1e-10 relative (round-off) */
static void gradient_of_affine(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_int counts[3] = {20, 16, 1};
  ps_particles P;
  ps_network net;
  if (ps_geom_box(&P, 2, counts, 1e-3, "square", 0.2, 3, &ctx)) die_ctx("box", &ctx);
  ps_crack cr = {.p0 = {-1e-3, 8e-3, 0}, .p1 = {10e-3, 8e-3, 0}};
  tc_network(&P, 3.5, &cr, 1, &net);
  const double G[4] = {3e-4, -2e-4, 5e-4, 1e-4}; /* du_j/dx_k = G[2j + k] */
  double *u = malloc(2 * P.n * sizeof *u), *H = malloc(4 * P.n * sizeof *H), worst = 0;
  for (ps_int a = 0; a < P.n; a++)
    for (int j = 0; j < 2; j++)
      u[2 * a + j] = 1e-6 + G[2 * j] * P.x[2 * a] + G[2 * j + 1] * P.x[2 * a + 1];
  ps_post_displacement_gradient(&P, &net, NULL, u, H);
  for (ps_int a = 0; a < P.n; a++)
    for (int k = 0; k < 4; k++) worst = fmax(worst, fabs(H[4 * a + k] - G[k]) / 5e-4);
  ps_check_le(worst, 1e-10, "displacement gradient of an affine field (crack included)");
  free(u);
  free(H);
  ps_network_free(&net);
  ps_particles_free(&P);
}

int main(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  gradient_of_affine();
  const char *srcdir = getenv("srcdir") ? getenv("srcdir") : ".";
  char path[1024];
  snprintf(path, sizeof path, "%s/data/cases/edge-crack-bond.yaml", srcdir);
  ps_case cs;
  ps_case_defaults(&cs);
  if (ps_case_load(&cs, path, &ctx)) die_ctx("case", &ctx);
  const double a = cs.cracks[0].p1[0], da = cs.spacing;
  const double l[] = {0.003, 0.004, 0.005, 0.006, 0.008};
  const int nl = 5;
  double J[5], J0[5];

  double Jc[5], Jc0[5];
  solve(&cs, a, 1, l, nl, J, Jc);
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < nl; i++) {
    printf("# surface correction on: l = %.0f mm: J_dom = %.1f N/m (%+.2f%% vs FE %.0f), "
           "J_cont = %.1f (%+.2f%%)\n",
           l[i] * 1e3, J[i], 100 * (J[i] / J_FE - 1), J_FE, Jc[i], 100 * (Jc[i] / J_FE - 1));
    lo = fmin(lo, J[i]);
    hi = fmax(hi, J[i]);
  }
  ps_check_le((hi - lo) / lo, 0.02, "J_dom path independence over rings of 3..8 mm");
  double clo = INFINITY, chi = -INFINITY, worst_pair = 0;
  for (int i = 0; i < nl; i++) {
    clo = fmin(clo, Jc[i]);
    chi = fmax(chi, Jc[i]);
    worst_pair = fmax(worst_pair, fabs(Jc[i] / J[i] - 1));
  }
  ps_check_le((chi - clo) / clo, 0.02, "J_cont path independence over contours of 3..8 mm");
  ps_check_le(worst_pair, 0.02, "|J_cont / J_dom - 1| on the same squares (Fallah: < 1%)");

  double Wm = solve(&cs, a - da, 1, NULL, 0, NULL, NULL),
         Wp = solve(&cs, a + da, 1, NULL, 0, NULL, NULL);
  double G = 0.5 * (Wp - Wm) / (2 * da);
  printf("# compliance: W(a - dx) = %.6f N, W(a + dx) = %.6f N: G = %.1f N/m\n", Wm, Wp, G);
  ps_check_rel(J[2], G, 0.03, "J (ring 5 mm) = energy release rate from the compliance");

  solve(&cs, a, 0, l, nl, J0, Jc0);
  for (int i = 0; i < nl; i++)
    printf("# surface correction off: l = %.0f mm: J_dom = %.1f N/m (%+.2f%% vs FE), J_cont = "
           "%.1f (%+.2f%%)\n",
           l[i] * 1e3, J0[i], 100 * (J0[i] / J_FE - 1), Jc0[i], 100 * (Jc0[i] / J_FE - 1));
  ps_check_rel(J0[2], J_FE, 0.03, "J_dom without surface correction vs FE 6.794 MPa mm");
  ps_check_rel(Jc0[2], J_FE, 0.03, "J_cont without surface correction vs FE 6.794 MPa mm");

  /* make check-long: three refinements, spacing 1, 0.5, 0.25 mm (the
   * finest has 81k particles and needs ~4 GB) */
  if (getenv("PS_CHECK_LONG")) {
    const double dxs[4] = {1e-3, 0.5e-3, 0.25e-3, 0.1e-3 / 1.2}; /* last: the paper's */
    double err[4];
    for (int r = 0; r < 4; r++) {
      ps_case c;
      if (ps_case_copy(&c, &cs, &ctx)) die_ctx("case copy", &ctx); /* its entries change */
      double dx = dxs[r];
      c.spacing = dx;
      c.counts[0] = (ps_int)lround(0.1 / dx) + 3;
      c.counts[1] = (ps_int)lround(0.05 / dx);
      c.bc[1].sel.lo[1] = 0.05 - dx; /* the top row */
      c.bc[2].sel.hi[1] = dx;        /* the bottom row */
      double Jon[5] = {0, 0, 0, 0, 0}, Joff[5];
      if (r < 3) solve(&c, a, 1, l, nl, Jon, NULL); /* the finest: 722k particles, 13 GB */
      solve(&c, a, 0, l, nl, Joff, NULL);
      if (r < 3)
        printf("# refinement dx = %.4f mm: J(5 mm ring) = %.1f N/m (%+.2f%%) with the surface "
               "correction, %.1f N/m (%+.2f%%) without\n",
               dx * 1e3, Jon[2], 100 * (Jon[2] / J_FE - 1), Joff[2], 100 * (Joff[2] / J_FE - 1));
      else
        printf("# refinement dx = %.4f mm: J(5 mm ring) = %.1f N/m (%+.2f%%) without the "
               "surface correction (with it: not run at this size)\n",
               dx * 1e3, Joff[2], 100 * (Joff[2] / J_FE - 1));
      err[r] = fabs(Joff[2] / J_FE - 1);
      ps_case_free(&c);
    }
    /* at 1 mm the 5 mm ring is 2.5 spacings wide inside a 3 mm horizon:
     * no accuracy is expected there, only that refining reduces it */
    ps_check(err[2] < err[0] && err[1] < err[0],
             "J without surface correction: the error vs FE shrinks from dx = 1 mm "
             "(%.2f%%) to 0.5 and 0.25 mm (%.2f%%, %.2f%%)", 100 * err[0], 100 * err[1],
             100 * err[2]);
    ps_check_le(err[2], 0.03, "J without surface correction vs FE at dx = 0.25 mm");
    ps_check_le(err[3], 0.03, "J without surface correction vs FE at the paper's dx = 0.0833 mm");
  }
  return ps_check_summary();
}
