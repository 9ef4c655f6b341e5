/* t400_disk_elastic.c: the elastic elliptic-crack disk (jittered, as the
 * paper's Fig. 7) against the closed form Eq. 116, with the boundary zone
 * driven by Eq. 116 itself. The RMS displacement error over the interior
 * must fall at each of four densities (800 to 5,000 particles) and be
 * below 1.5% at about 3,000 particles (MODEL-NOTES' prototype: 2.9%, 1.7%,
 * 1.3% at 800, 1.8k, 3.2k). The load is small (S = 1e-3 sigma_y) so the
 * geometric nonlinearity is negligible against the discretisation error.
 * Also: the boundary stress (interface-crossing arm forces over the
 * interface perimeter) tends to the applied remote stress S with
 * refinement and is within 6% of it at 5,000 particles (Eq. 116's stress
 * at the interface, ~10c from the crack, differs from S by O((c/r)^2) ~
 * 1%; the rest is the irregular-cloud error, see t300; MODEL-NOTES'
 * prototype: 1.05 at 1.8k particles, 1.012 at 20k).
 * And the J-integral (Eq. 39 of Fallah et al. 2020, domain form) around a
 * tip at 5,000 particles against Griffith's J = pi S^2 c (1 - nu^2)/E, the
 * energy release rate of the field Eq. 116 is: within 3% on rings of
 * 0.2c-0.6c (the displacement field is 1% off at this size and J is
 * quadratic in it, plus the ring quadrature on a graded cloud), spread
 * 4% at most (path independence).
 * The jitter is the default 0.1 of a sub-cell per axis (particles at least
 * 0.8 sub-cell apart). The paper does not give its noise amplitude; the
 * error grows with it (3.2k particles: 0.5% unjittered, 1.2% at 0.1, 1.6%
 * at 0.15, 2.0% at 0.2, 3.3% at 0.3): doc/verification.md has the table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common.h"

static double j_spread, j_worst; /* of the last run (5,000 particles) */

static double run(int n_eta, int n_xi, ps_int *np, double *sig_ratio) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_disk_params dp;
  ps_disk_params_default(&dp);
  dp.n_eta = n_eta;
  dp.n_xi = n_xi;
  dp.jitter = 0.1;
  ps_particles P;
  if (ps_geom_disk(&P, &dp, &ctx)) abort();
  ps_crack cr = {.p0 = {-dp.c, 0, 0}, .p1 = {dp.c, 0, 0}};
  ps_network net;
  tc_network(&P, 5.1, &cr, 1, &net);
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  ps_int n = P.n;
  unsigned char *fixed = calloc((size_t)(2 * n), 1), *interior = calloc((size_t)n, 1);
  double *ubar = calloc((size_t)(2 * n), sizeof *ubar), *uref = calloc((size_t)(2 * n), sizeof *ubar);
  double *meas = calloc((size_t)(2 * n), sizeof *meas);
  double lambda = 1e-3, S = mat.sigma_y;
  for (ps_int a = 0; a < n; a++) {
    double x = P.x[2 * a], y = P.x[2 * a + 1], u, v, xi, eta;
    ps_geom_eq116(x, y, dp.c, S, mat.G, mat.kappa, &u, &v);
    uref[2 * a] = lambda * u;
    uref[2 * a + 1] = lambda * v;
    interior[a] = !P.in_boundary_zone[a];
    if (P.in_boundary_zone[a]) {
      fixed[2 * a] = fixed[2 * a + 1] = 1;
      ubar[2 * a] = u;
      ubar[2 * a + 1] = v;
      ps_geom_elliptic_coords(x, y, dp.c, &xi, &eta);
      double A = dp.c * cosh(xi), B = dp.c * sinh(xi);
      double nx = x / (A * A), ny = y / (B * B), nn = hypot(nx, ny);
      meas[2 * a] = nx / nn;
      meas[2 * a + 1] = ny / nn;
    }
  }
  ps_solver *s = tc_solve(&P, &net, &mat, fixed, ubar, lambda);
  const double *u = ps_solver_u(s), *T = ps_solver_arm_tension(s);
  const double *q = ps_solver_arm_direction(s);
  double err = ps_post_rms_error(2, n, u, uref, interior);
  double L = ps_geom_ellipse_perimeter(dp.c, M_PI - 2 * M_PI / n_xi);
  *sig_ratio = ps_post_boundary_stress(&net, T, q, meas, L, NULL) / (lambda * S);
  printf("# disk %dx%d: %lld particles, %lld arms, size ratio %.0f, RMS error %.4f, "
         "boundary stress / S %.4f\n",
         n_eta, n_xi, (long long)n, (long long)net.n_arm, net.max_h_ratio, err, *sig_ratio);
  /* J around the right tip (c, 0) by Eq. 39 against Griffith's
   * J = pi S^2 c (1 - nu^2) / E (plane strain) for the remote stress
   * lambda S: rings l = 0.2c .. 0.6c (q = 1 inside l/2) */
  double *sig = malloc(4 * (size_t)n * sizeof *sig), *H = malloc(4 * (size_t)n * sizeof *H);
  ps_post_stress_tensor(&P, &net, T, q, sig);
  ps_post_displacement_gradient(&P, &net, ps_solver_arm_state(s), u, H);
  double Sr = lambda * S, Jref = M_PI * Sr * Sr * dp.c * (1 - mat.nu * mat.nu) / mat.E;
  double tip[2] = {dp.c, 0.0}, jlo = INFINITY, jhi = -INFINITY;
  j_worst = 0;
  for (int k = 2; k <= 6; k++) {
    double l = 0.1 * k * dp.c, J = ps_post_j_domain(&P, sig, H, tip, 0.5 * l, l) / Jref;
    jlo = fmin(jlo, J);
    jhi = fmax(jhi, J);
    j_worst = fmax(j_worst, fabs(J - 1));
  }
  j_spread = jhi - jlo;
  printf("# disk %dx%d: J (Eq. 39) / Griffith's pi S^2 c (1 - nu^2)/E over rings 0.2c..0.6c: "
         "%.4f .. %.4f\n", n_eta, n_xi, jlo, jhi);
  free(sig);
  free(H);
  *np = n;
  ps_solver_free(s);
  free(fixed);
  free(interior);
  free(ubar);
  free(uref);
  free(meas);
  ps_network_free(&net);
  ps_particles_free(&P);
  return err;
}

int main(void) {
  int sizes[4][2] = {{4, 8}, {6, 12}, {8, 16}, {10, 20}};
  double err[4], ratio[4];
  ps_int np[4];
  for (int i = 0; i < 4; i++) err[i] = run(sizes[i][0], sizes[i][1], &np[i], &ratio[i]);
  for (int i = 1; i < 4; i++)
    ps_check(err[i] < err[i - 1], "RMS error falls: %.4f (%lld particles) < %.4f (%lld)",
             err[i], (long long)np[i], err[i - 1], (long long)np[i - 1]);
  ps_check_le(err[2], 0.015, "RMS displacement error at 3,200 particles");
  for (int i = 1; i < 4; i++)
    ps_check(fabs(ratio[i] - 1) < fabs(ratio[i - 1] - 1),
             "boundary stress / S tends to 1: %.4f (%lld particles), %.4f (%lld)",
             ratio[i], (long long)np[i], ratio[i - 1], (long long)np[i - 1]);
  ps_check_rel(ratio[3], 1.0, 0.06, "boundary stress / S at 5,000 particles");
  ps_check_le(j_worst, 0.03, "5,000 particles: |J / Griffith's J - 1| over rings 0.2c..0.6c");
  ps_check_le(j_spread, 0.04, "5,000 particles: J path independence (spread / J_ref)");
  return ps_check_summary();
}
