/* t300_patch.c: patch tests of the fibre model.
 * (1) Regular square and hexagonal lattices: an affine deformation (with a
 *     finite rotation) leaves the interior particles (farther than two
 *     horizons plus one spacing from the edge, so that every particle whose
 *     mean strain enters their force has a complete neighbourhood) with
 *     zero force. Tolerance 1e-8 of the median arm force: round-off of
 *     sums of ~60 arm forces is ~1e-14, so 1e-8 leaves room but catches
 *     any wrong weight, sign or missing term (those give O(1)).
 * (2) An irregular, variable-size cloud (jittered, spacing graded 3:1
 *     across the box) with an affine field prescribed on a skin two
 *     horizons wide: the least-squares strain of the solved interior is
 *     within 2% of the imposed one, and the boundary stress (normal
 *     reactions of the skin over the skin/interior interface) within 6% of
 *     N K eps for an equibiaxial strain eps. An irregular cloud does not
 *     pass the patch test exactly (first-moment error of a disordered
 *     neighbourhood; MODEL-NOTES: 1-2% strain, ~5% stress at this size),
 *     hence these tolerances. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common.h"

static int cmp_d(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

static void regular(const char *lattice) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_particles P;
  ps_network net;
  ps_int counts[3] = {30, 32, 1};
  double d = 1e-3;
  if (ps_geom_box(&P, 2, counts, d, lattice, 0.0, 1, &ctx)) abort();
  tc_network(&P, 5.1, NULL, 0, &net);
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  tc_evaluator ev;
  tc_evaluator_create(&ev, &net, &mat);
  double *u = calloc((size_t)(2 * P.n), sizeof *u), *f = NULL;
  /* y = R (I + E) x: strain plus a rotation of 0.2 rad */
  double E[4] = {1.3e-3, 0.4e-3, 0.4e-3, -0.7e-3}, c = cos(0.2), s = sin(0.2);
  for (ps_int a = 0; a < P.n; a++) {
    const double *x = &P.x[2 * a];
    double y0 = x[0] + E[0] * x[0] + E[1] * x[1], y1 = x[1] + E[2] * x[0] + E[3] * x[1];
    u[2 * a] = c * y0 - s * y1 - x[0];
    u[2 * a + 1] = s * y0 + c * y1 - x[1];
  }
  tc_eval(&ev, &P, u);
  f = ev.f;
  double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30}, hmax = 0;
  for (ps_int a = 0; a < P.n; a++) {
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], P.x[2 * a + k]);
      hi[k] = fmax(hi[k], P.x[2 * a + k]);
    }
    hmax = fmax(hmax, P.h[a]);
  }
  double *T = malloc((size_t)net.n_arm * sizeof *T);
  for (ps_int i = 0; i < net.n_arm; i++) T[i] = fabs(ev.sys.T[i]);
  qsort(T, (size_t)net.n_arm, sizeof *T, cmp_d);
  double Tmed = T[net.n_arm / 2], fmaxi = 0;
  ps_int n_int = 0;
  for (ps_int a = 0; a < P.n; a++) {
    if (tc_dist_to_box_face(&P.x[2 * a], lo, hi, 2) <= 2 * 5.1 * hmax + d) continue;
    n_int++;
    fmaxi = fmax(fmaxi, hypot(f[2 * a], f[2 * a + 1]));
  }
  char what[128];
  snprintf(what, sizeof what, "%s lattice (%lld interior particles): max interior force "
           "/ median arm force", lattice, (long long)n_int);
  ps_check(n_int > 50, "%s lattice: enough interior particles (%lld)", lattice,
           (long long)n_int);
  ps_check_le(fmaxi / Tmed, 1e-8, what);
  free(T);
  free(u);
  tc_evaluator_free(&ev);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* jittered box with spacing graded 3:1 along x */
static void graded_cloud(ps_particles *P, ps_int nx, ps_int ny, double L) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_int counts[3] = {nx, ny, 1};
  if (ps_geom_box(P, 2, counts, L / nx, "square", 0.3, 5, &ctx)) abort();
  double g = 1.0; /* X = L (t + g t^2)/(1 + g), t = x/L: dX/dx from 1/2 to 3/2 */
  for (ps_int a = 0; a < P->n; a++) {
    double t = P->x[2 * a] / L;
    P->x[2 * a] = L * (t + g * t * t) / (1 + g);
    P->volume[a] *= (1 + 2 * g * t) / (1 + g);
  }
}

static void irregular(void) {
  ps_particles P;
  ps_network net;
  double L = 0.05;
  graded_cloud(&P, 56, 56, L);
  tc_network(&P, 5.1, NULL, 0, &net);
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  double hmax = 0;
  for (ps_int a = 0; a < P.n; a++) hmax = fmax(hmax, P.h[a]);
  double w = 2 * 5.1 * hmax; /* skin width: two horizons of the largest particle */
  double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
  for (ps_int a = 0; a < P.n; a++)
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], P.x[2 * a + k]);
      hi[k] = fmax(hi[k], P.x[2 * a + k]);
    }
  ps_int n = P.n;
  unsigned char *fixed = calloc((size_t)(2 * n), 1), *interior = calloc((size_t)n, 1);
  double *ubar = calloc((size_t)(2 * n), sizeof *ubar);
  double *meas = calloc((size_t)(2 * n), sizeof *meas);
  double E[2][4] = {{1.0e-4, 0.3e-4, 0.3e-4, -0.45e-4}, {1.0e-4, 0, 0, 1.0e-4}};
  for (int load = 0; load < 2; load++) {
    ps_int n_int = 0;
    for (ps_int a = 0; a < n; a++) {
      const double *x = &P.x[2 * a];
      double dist = tc_dist_to_box_face(x, lo, hi, 2);
      int skin = dist < w;
      fixed[2 * a] = fixed[2 * a + 1] = (unsigned char)skin;
      interior[a] = !skin;
      n_int += !skin;
      ubar[2 * a] = E[load][0] * x[0] + E[load][1] * x[1];
      ubar[2 * a + 1] = E[load][2] * x[0] + E[load][3] * x[1];
      meas[2 * a] = meas[2 * a + 1] = 0;
      if (skin) { /* outward normal of the nearest face */
        double dl[4] = {x[0] - lo[0], hi[0] - x[0], x[1] - lo[1], hi[1] - x[1]};
        int m = 0;
        for (int k = 1; k < 4; k++)
          if (dl[k] < dl[m]) m = k;
        meas[2 * a + m / 2] = m % 2 ? 1.0 : -1.0;
      }
    }
    ps_solver *s = tc_solve(&P, &net, &mat, fixed, ubar, 1.0);
    if (load == 0) {
      ps_ctx ctx;
      ps_ctx_init(&ctx);
      double eps[4];
      ps_post_fit_strain(&P, ps_solver_u(s), interior, eps, &ctx);
      double num = 0, den = 0;
      for (int k = 0; k < 4; k++) {
        num += (eps[k] - E[0][k]) * (eps[k] - E[0][k]);
        den += E[0][k] * E[0][k];
      }
      char what[160];
      snprintf(what, sizeof what,
               "irregular cloud (%lld particles, %lld interior, size ratio %.1f): "
               "fitted interior strain rel. error",
               (long long)n, (long long)n_int, net.max_h_ratio);
      ps_check_le(sqrt(num / den), 0.02, what);
    } else {
      double perim = 2 * ((hi[0] - lo[0] - 2 * w) + (hi[1] - lo[1] - 2 * w));
      double sig = ps_post_boundary_stress(&net, ps_solver_arm_tension(s),
                                           ps_solver_arm_direction(s), meas, perim, NULL);
      double want = 2 * mat.K * E[1][0]; /* N K eps, plane strain K (Eq. 81) */
      ps_check_rel(sig, want, 0.06, "irregular cloud: equibiaxial boundary stress vs N K eps");
    }
    ps_solver_free(s);
  }
  free(fixed);
  free(interior);
  free(ubar);
  free(meas);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* The PD stress tensor (Eq. 24 of Fallah et al.) at the centre of a
 * regular lattice under an affine small strain.
 * (a) Against the network's own traction: the force of the arms crossing a
 *     vertical line x = x0 (between columns) over a window of whole lattice
 *     periods, per unit length, is sigma . e_x exactly for a homogeneous
 *     deformation of a lattice; tolerance 1e-9 (round-off).
 * (b) Against the continuum stress of the input moduli (plane strain,
 *     sigma = 2 G dev(eps) + K tr(eps) I): tolerance 7%, the lattice-sum
 *     error of the network's moduli at a horizon of ~2.8 spacings (measured:
 *     hex 6.1% uniformly soft, square 1-3.3% with cubic anisotropy;
 *     doc/verification.md). */
static void stress_tensor(const char *lattice) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_particles P;
  ps_network net;
  int hex = !strcmp(lattice, "hex");
  ps_int counts[3] = {24, 26, 1};
  double d = 1e-3;
  if (ps_geom_box(&P, 2, counts, d, lattice, 0.0, 1, &ctx)) abort();
  tc_network(&P, 5.1, NULL, 0, &net);
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  tc_evaluator ev;
  tc_evaluator_create(&ev, &net, &mat);
  double *u = calloc((size_t)(2 * P.n), sizeof *u);
  double *sig = calloc((size_t)(4 * P.n), sizeof *sig);
  double E[2][4] = {{1e-6, 0, 0, 1e-6}, {1e-6, 0.4e-6, 0.4e-6, -0.3e-6}};
  ps_int c = 13 * 24 + 12; /* a centre particle */
  /* the cut: x0 between columns 11 and 12 (hex: 11.25 d avoids both row
   * offsets), window of whole periods centred on the particle */
  double x0 = hex ? 12.25 * d : 12.0 * d, per = hex ? sqrt(3.0) * d : d;
  double y1 = P.x[2 * c + 1] - 3 * per, y2 = y1 + 6 * per;
  for (int load = 0; load < 2; load++) {
    for (ps_int a = 0; a < P.n; a++) {
      const double *x = &P.x[2 * a];
      u[2 * a] = E[load][0] * x[0] + E[load][1] * x[1];
      u[2 * a + 1] = E[load][2] * x[0] + E[load][3] * x[1];
    }
    tc_eval(&ev, &P, u);
    ps_post_stress_tensor(&P, &net, ev.sys.T, ev.sys.q, sig);
    /* (a) traction across x = x0: force on the left part from the right */
    double t[2] = {0, 0};
    for (ps_int i = 0; i < net.n_arm; i++) {
      const double *xa = &P.x[2 * net.a[i]], *xb = &P.x[2 * net.b[i]];
      if ((xa[0] - x0) * (xb[0] - x0) >= 0) continue;
      double yc = xa[1] + (x0 - xa[0]) / (xb[0] - xa[0]) * (xb[1] - xa[1]);
      if (yc < y1 || yc >= y2) continue;
      double sgn = xa[0] < x0 ? 1.0 : -1.0; /* q points from a to b */
      for (int k = 0; k < 2; k++) t[k] += sgn * ev.sys.T[i] * ev.sys.q[2 * i + k];
    }
    double L = y2 - y1, e1 = fabs(t[0] / L - sig[4 * c]), e2 = fabs(t[1] / L - sig[4 * c + 2]);
    char what[200];
    snprintf(what, sizeof what, "%s lattice, %s strain: Eq. 24 (sxx %.6g, syx %.6g) vs "
             "traction across a cut (%.6g, %.6g), rel. error",
             lattice, load ? "general" : "equibiaxial", sig[4 * c], sig[4 * c + 2],
             t[0] / L, t[1] / L);
    ps_check_le(hypot(e1, e2) / fabs(sig[4 * c]), 1e-9, what);
    /* (b) against the continuum */
    double tr = E[load][0] + E[load][3], want[4], num = 0, den = 0;
    for (int k = 0; k < 4; k++)
      want[k] = 2 * mat.G * (E[load][k] - (k == 0 || k == 3 ? tr / 2 : 0)) +
                (k == 0 || k == 3 ? mat.K * tr : 0);
    for (int k = 0; k < 4; k++) {
      num += (sig[4 * c + k] - want[k]) * (sig[4 * c + k] - want[k]);
      den += want[k] * want[k];
    }
    snprintf(what, sizeof what, "%s lattice, %s strain: Eq. 24 stress vs continuum "
             "(sxx %.4g/%.4g, syy %.4g/%.4g, sxy %.4g/%.4g), rel. error",
             lattice, load ? "general" : "equibiaxial", sig[4 * c], want[0], sig[4 * c + 3],
             want[3], sig[4 * c + 1], want[1]);
    ps_check_le(sqrt(num / den), 0.07, what);
  }
  free(u);
  free(sig);
  tc_evaluator_free(&ev);
  ps_network_free(&net);
  ps_particles_free(&P);
}

int main(void) {
  regular("square");
  regular("hex");
  stress_tensor("hex");
  stress_tensor("square");
  irregular();
  return ps_check_summary();
}
