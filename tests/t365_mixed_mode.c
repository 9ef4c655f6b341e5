/* t365_mixed_mode.c: J for a crack of any direction and K_I, K_II by the
 * interaction integral (src/post/post.c: ps_post_j_domain_dir,
 * ps_post_j_contour_dir, ps_post_k_interaction), 2D, bond model, partial
 * volumes only (surface correction off, as t360's FE comparison).
 *
 * (0) The auxiliary Williams fields (ps_post_williams) against their own
 *     definitions: stress = Hooke's law of the gradient's symmetric part,
 *     and the J of the K = 1 field on a circle = 1/E' (plane stress and
 *     strain, modes I and II), 1e-6 (a 20,000-point rule on the circle).
 * (1) Rotation invariance: t360's edge-cracked plate at spacing 1 mm
 *     (5,150 particles, crack tip at x = 10.2 mm: no particle on the
 *     diagonals |x1| = |x2| of the square rings, where the choice of q's
 *     gradient would be decided by round-off) as a point cloud, once as
 *     it is and once with the particles, the crack and the loads turned by
 *     30 degrees about the origin (the clamp and the loaded rows as cloud
 *     blocks, the forces turned). The turned problem is the same discrete
 *     problem (arms, cuts and partial volumes depend on distances only;
 *     the surface correction, built from strains along x and y, does not,
 *     hence off), so J (both forms), K_I and K_II in the crack-tip frame
 *     agree to round-off: 1e-5 relative (measured 2e-15). The problem is
 *     symmetric about the crack line: |K_II| <= 1e-3 K_I (measured 5e-16).
 * (2) The inclined centre crack of data/cases/inclined-crack-bond.yaml
 *     (2a = 20 mm, a 160 mm square plate, W = 16 a, spacing 1 mm: a = 10
 *     spacings, 25,600 particles) under remote tension sigma along y at
 *     beta = 0, 30, 45 and 60 degrees; closed form (an infinite plate):
 *     K_I = sigma sqrt(pi a) cos^2 beta, K_II = sigma sqrt(pi a) sin beta
 *     cos beta, times the finite-width factor sqrt(sec(pi a / W)) = 1.010
 *     (exact for beta = 0 in a long strip; taken for both modes).
 *     Rings l = 4, 6, 8 mm (q = 1 inside l/2), both tips.
 *     - both tips give the same J, K_I, K_II (the plate is symmetric under
 *       a half turn; the supports carry almost no load): 1e-3 of sigma
 *       sqrt(pi a) (measured <= 3e-4);
 *     - path independence: K_I, K_II over the three rings within 5% of
 *       their mean (K_II: 2% of sigma sqrt(pi a) when it is ~ 0);
 *     - K_I / K_I(beta = 0) = cos^2 beta and K_II / K_I(beta = 0) = sin
 *       beta cos beta within 4% (ring means): the ratio removes what the
 *       closed form cannot know of the discrete crack (its effective
 *       length at a horizon of 0.3 a) and most of the finite plate;
 *       K_II / K_I = tan beta within 4%;
 *     - K_I, K_II against the closed form itself within 8% (ring means):
 *       at beta = 0 the PD plate gives K_I 4.5% above the width-corrected
 *       closed form, and the same (+3.5..4%) at spacing 2/3 mm (a = 15
 *       spacings), so this is the bond model's own crack (horizon 0.2-0.3
 *       a) and its uncorrected square-lattice moduli, not the evaluation,
 *       which (0), (1) and the ratios check;
 *     - J_dom = (K_I^2 + K_II^2)/E' within 10% (ring means): exact for an
 *       isotropic linear solid; the bond model on a square lattice
 *       without its surface correction is neither exactly isotropic nor
 *       of modulus E (t360, doc/verification.md), which J (the model's
 *       own energy) and the interaction integral (isotropic auxiliary
 *       fields with the input E, nu) see differently, more so in shear:
 *       +1.7% at beta = 0, +4% at 30, +8% at 60, +9% at 45.
 *     At 45 degrees the crack runs along the lattice's diagonals (its
 *     centre moved half a spacing along x, one more column, so that it
 *     meets no particle; the plate stays symmetric under a half turn) and
 *     the 8 mm ring falls 10-20% below the others at this resolution (at
 *     spacing 2/3 mm the pure mode-II case's spread is 3%): there the path
 *     bound is 15% and the ratio bounds 6%.
 * (3) Pure mode II: the 45-degree crack under sigma_yy = sigma, sigma_xx =
 *     -sigma (tractions on all four edges) has no normal stress on the
 *     crack plane: |K_I| <= 3% of K_II (measured 1.9%), and K_II = sigma
 *     sqrt(pi a) within 8% (as in (2); measured +3.4%, the rings 199, 193,
 *     163 kPa sqrt(m)).
 * The supports: see the case file (a one-particle support leaves the
 * floating plate so ill-conditioned that Newton stalls for beta = 0). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "common.h"

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t365: %s failed: %s\n", what, ctx->msg);
  exit(2);
}

#define NL 3

/* J (both forms), K_I and K_II of a solved problem for one tip and the
 * rings l[0..NL) */
typedef struct tip_result {
  double J[NL], Jc[NL], KI[NL], KII[NL];
} tip_result;

static void evaluate(const ps_problem *pb, const ps_solver *s, const double *tip,
                     const double *dir, const double *l, double dx, tip_result *r) {
  const ps_particles *P = &pb->P;
  const double *u = ps_solver_u(s), *T = ps_solver_arm_tension(s);
  const double *q = ps_solver_arm_direction(s);
  double *sig = malloc(4 * P->n * sizeof *sig), *H = malloc(4 * P->n * sizeof *H);
  ps_post_stress_tensor(P, &pb->net, T, q, sig);
  ps_post_displacement_gradient(P, &pb->net, ps_solver_arm_state(s), u, H);
  for (int i = 0; i < NL; i++) {
    double K[2];
    r->J[i] = ps_post_j_domain_dir(P, sig, H, tip, dir, 0.5 * l[i], l[i]);
    r->Jc[i] = ps_post_j_contour_dir(P, &pb->net, T, q, sig, H, tip, dir, l[i], dx);
    ps_post_k_interaction(P, sig, H, tip, dir, 0.5 * l[i], l[i], pb->mat.E, pb->mat.nu,
                          pb->mat.plane, K);
    r->KI[i] = K[0];
    r->KII[i] = K[1];
  }
  free(sig);
  free(H);
}

static double mean3(const double *v) { return (v[0] + v[1] + v[2]) / 3.0; }

/* ---- (0) the auxiliary fields ---- */

static void williams_fields(void) {
  const double E = 1e9, nu = 0.3, R = 0.01;
  const int N = 20000;
  for (int plane = 0; plane < 2; plane++) {
    double mu = E / (2 * (1 + nu));
    double lam = plane == PS_PLANE_STRESS ? E * nu / (1 - nu * nu)
                                          : E * nu / ((1 + nu) * (1 - 2 * nu));
    double Ep = plane == PS_PLANE_STRESS ? E : E / (1 - nu * nu);
    for (int mode = 1; mode <= 2; mode++) {
      double worst = 0, J = 0, scale = 1 / sqrt(2 * M_PI * R);
      for (int k = 0; k < N; k++) {
        double th = -M_PI + (k + 0.5) * 2 * M_PI / N, s[4], h[4];
        ps_post_williams(mode, R * cos(th), R * sin(th), E, nu, plane, s, h);
        double e11 = h[0], e22 = h[3], e12 = 0.5 * (h[1] + h[2]);
        double t[4] = {lam * (e11 + e22) + 2 * mu * e11, 2 * mu * e12, 2 * mu * e12,
                       lam * (e11 + e22) + 2 * mu * e22};
        for (int i = 0; i < 4; i++) worst = fmax(worst, fabs(t[i] - s[i]) / scale);
        double W = 0.5 * (s[0] * h[0] + s[1] * h[1] + s[2] * h[2] + s[3] * h[3]);
        double n[2] = {cos(th), sin(th)}, tr = 0;
        for (int i = 0; i < 2; i++)
          for (int j = 0; j < 2; j++) tr += s[2 * i + j] * n[j] * h[2 * i];
        J += (W * n[0] - tr) * R * 2 * M_PI / N;
      }
      ps_check(worst <= 1e-6 && fabs(J * Ep - 1) <= 1e-6,
               "Williams field mode %d, %s: Hooke's law to %.1e, J E' / K^2 = %.8f", mode,
               plane == PS_PLANE_STRESS ? "plane stress" : "plane strain", worst, J * Ep);
    }
  }
}

/* ---- (1) rotation invariance ---- */

/* Solve t360's plate (spacing 1 mm) as a cloud turned by theta about the
 * origin; J and K at the turned tip. */
static void edge_crack_turned(double theta, const double *l, tip_result *r) {
  const double dx = 1e-3, p = 10e6, c = cos(theta), s = sin(theta);
  const int nx = 103, ny = 50;
  char cloud[256], yaml[256];
  snprintf(cloud, sizeof cloud, "t365_cloud_%ld.txt", (long)getpid());
  snprintf(yaml, sizeof yaml, "t365_case_%ld.yaml", (long)getpid());
  FILE *f = fopen(cloud, "w");
  if (!f) {
    fprintf(stderr, "t365: cannot write %s\n", cloud);
    exit(2);
  }
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
      int block = x > 0.1 ? 1 : j == ny - 1 ? 2 : j == 0 ? 3 : 0;
      fprintf(f, "%.17g %.17g %.17g %d\n", c * x - s * y, s * x + c * y, dx * dx, block);
    }
  fclose(f);
  const double p0[2] = {-0.001, 0.025}, p1[2] = {0.0102, 0.025};
  f = fopen(yaml, "w");
  fprintf(f,
          "name: t365-turned\n"
          "geometry:\n  type: cloud\n  dim: 2\n  file: %s\n"
          "  cracks: [[[%.17g, %.17g], [%.17g, %.17g]]]\n"
          "material:\n  model: bond\n  E: 1.0e9\n  nu: 0.3333333333333333\n"
          "  plane: stress\n  plastic: false\n  horizon_factor: 3\n"
          "  surface_correction: false\n"
          "loading:\n  type: boundary\n  boundary:\n"
          "    - select: {block: 1}\n      fix: [x, y]\n"
          "    - select: {block: 2}\n      traction: {y: 1.0e6}\n"
          "    - select: {block: 3}\n      traction: {y: -1.0e6}\n"
          "path:\n  load_step: 1.0\n  max_load: 1.0\n"
          "output:\n  fields: false\n",
          cloud, c * p0[0] - s * p0[1], s * p0[0] + c * p0[1], c * p1[0] - s * p1[1],
          s * p1[0] + c * p1[1]);
  fclose(f);
  ps_ctx ctx;
  ps_case cs;
  ps_problem pb;
  ps_run_result res;
  ps_solver *sv = NULL;
  tc_setup_case_file(yaml, &cs, &pb, &ctx);
  remove(cloud);
  remove(yaml);
  /* the tractions of t360 (p on the top row, -p on the bottom one; a
   * force p V / dx per particle), turned */
  for (ps_int a = 0; a < pb.P.n; a++) {
    double sg = pb.P.block[a] == 2 ? 1.0 : pb.P.block[a] == 3 ? -1.0 : 0.0;
    pb.fext[2 * a] = -s * sg * p * pb.P.volume[a] / dx;
    pb.fext[2 * a + 1] = c * sg * p * pb.P.volume[a] / dx;
  }
  if (ps_run_keep(&pb, INFINITY, NULL, &res, &sv, &ctx)) die_ctx("turned run", &ctx);
  const double tip[2] = {c * p1[0] - s * p1[1], s * p1[0] + c * p1[1]}, dir[2] = {c, s};
  evaluate(&pb, sv, tip, dir, l, dx, r);
  ps_solver_free(sv);
  ps_problem_free(&pb);
}

static void rotation_invariance(void) {
  const double l[NL] = {0.004, 0.006, 0.008}, theta = 30.0 * M_PI / 180.0;
  tip_result r0, r1;
  edge_crack_turned(0.0, l, &r0);
  edge_crack_turned(theta, l, &r1);
  double worst = 0, mode2 = 0;
  for (int i = 0; i < NL; i++) {
    printf("# edge crack, cloud, l = %.0f mm: J_dom %.2f / %.2f N/m, J_cont %.2f / %.2f, "
           "K_I %.1f / %.1f kPa sqrt(m), K_II %.3g / %.3g (as is / turned 30 deg); "
           "(K_I^2 + K_II^2)/E = %.2f N/m\n",
           l[i] * 1e3, r0.J[i], r1.J[i], r0.Jc[i], r1.Jc[i], r0.KI[i] * 1e-3,
           r1.KI[i] * 1e-3, r0.KII[i] * 1e-3, r1.KII[i] * 1e-3,
           (r0.KI[i] * r0.KI[i] + r0.KII[i] * r0.KII[i]) / 1e9);
    worst = fmax(worst, fabs(r1.J[i] / r0.J[i] - 1));
    worst = fmax(worst, fabs(r1.Jc[i] / r0.Jc[i] - 1));
    worst = fmax(worst, fabs(r1.KI[i] / r0.KI[i] - 1));
    worst = fmax(worst, fabs(r1.KII[i] - r0.KII[i]) / r0.KI[i]);
    mode2 = fmax(mode2, fmax(fabs(r0.KII[i]), fabs(r1.KII[i])) / r0.KI[i]);
  }
  ps_check_le(worst, 1e-5, "J_dom, J_cont, K_I, K_II of the plate turned by 30 degrees "
                           "(relative to the plate as it is)");
  ps_check_le(mode2, 1e-3, "|K_II| / K_I of the symmetric edge crack");
}

/* ---- (2), (3) the inclined centre crack ---- */

/* Solve the plate of data/cases/inclined-crack-bond.yaml with its crack
 * turned to beta about the plate's centre, under sigma_yy = sigma and
 * sigma_xx = sxx; J and K at both tips. */
static void inclined(const ps_case *base, double beta, double yoff, double sxx,
                     const double *l, tip_result *r) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 1 : 0;
  ps_case cs;
  if (ps_case_copy(&cs, base, &ctx)) die_ctx("case copy", &ctx); /* entries are added */
  double a = 0.010, xc = 0.080, yc = 0.080 + yoff, dx = cs.spacing;
  if (fabs(fabs(tan(beta)) - 1) < 1e-9) {
    /* at 45 degrees a crack through the plate's centre (a cell corner)
     * runs through particles; one more column puts the centre half a
     * spacing to the right, on no particle, the plate still symmetric
     * under a half turn about it */
    cs.counts[0]++;
    xc += 0.5 * dx;
  }
  const double e[2] = {cos(beta), sin(beta)};
  for (int k = 0; k < 2; k++) {
    cs.cracks[0].p0[k] = (k ? yc : xc) - a * e[k];
    cs.cracks[0].p1[k] = (k ? yc : xc) + a * e[k];
  }
  /* the supports carry no load: the Newton residual of this floating
   * plate stalls near 1e-8 of the load for some cracks */
  cs.solver.tolerance = 1e-7;
  if (sxx != 0.0) { /* side tractions: sigma_xx on the first and last columns */
    double W = cs.counts[0] * dx;
    ps_bc left = cs.bc[3], right = cs.bc[3]; /* a traction entry as a template */
    for (int k = 0; k < 3; k++) {
      left.sel.lo[k] = right.sel.lo[k] = -INFINITY;
      left.sel.hi[k] = right.sel.hi[k] = INFINITY;
      left.traction_set[k] = right.traction_set[k] = 0;
      left.traction[k] = right.traction[k] = 0;
    }
    left.sel.hi[0] = dx;
    right.sel.lo[0] = W - dx;
    left.traction_set[0] = right.traction_set[0] = 1;
    left.traction[0] = -sxx;
    right.traction[0] = sxx;
    if (ps_case_add_bc(&cs, &left, &ctx) || ps_case_add_bc(&cs, &right, &ctx))
      die_ctx("side tractions", &ctx);
  }
  ps_problem pb;
  ps_run_result res;
  ps_solver *sv = NULL;
  if (ps_problem_setup(&pb, &cs, &ctx)) die_ctx("inclined setup", &ctx);
  if (ps_run_keep(&pb, INFINITY, NULL, &res, &sv, &ctx)) die_ctx("inclined run", &ctx);
  const double *t[2] = {cs.cracks[0].p0, cs.cracks[0].p1};
  const double d[2][2] = {{-e[0], -e[1]}, {e[0], e[1]}};
  for (int k = 0; k < 2; k++) evaluate(&pb, sv, t[k], d[k], l, dx, &r[k]);
  ps_solver_free(sv);
  ps_problem_free(&pb);
  ps_case_free(&cs);
}

int main(void) {
  williams_fields();
  rotation_invariance();

  ps_ctx ctx;
  ps_ctx_init(&ctx);
  const char *srcdir = getenv("srcdir") ? getenv("srcdir") : ".";
  char path[1024];
  snprintf(path, sizeof path, "%s/data/cases/inclined-crack-bond.yaml", srcdir);
  ps_case cs;
  ps_case_defaults(&cs);
  if (ps_case_load(&cs, path, &ctx)) die_ctx("case", &ctx);
  const double l[NL] = {0.004, 0.006, 0.008};
  const double sigma = cs.bc[2].traction[1], a = 0.010, W = cs.counts[0] * cs.spacing;
  const double K0 = sigma * sqrt(M_PI * a), fw = sqrt(1.0 / cos(M_PI * a / W));
  const double E = cs.mat.E; /* plane stress: E' = E */
  const double betas[4] = {0.0, 30.0, 45.0, 60.0};
  double KI0 = 0;
  for (int b = 0; b < 4; b++) {
    double beta = betas[b] * M_PI / 180.0, cb = cos(beta), sb = sin(beta);
    tip_result r[2];
    inclined(&cs, beta, 0.0, 0.0, l, r);
    double sym = 0, worst_j = 0;
    for (int i = 0; i < NL; i++) {
      sym = fmax(sym, fabs(r[1].J[i] / r[0].J[i] - 1));
      sym = fmax(sym, fabs(r[1].KI[i] - r[0].KI[i]) / K0);
      sym = fmax(sym, fabs(r[1].KII[i] - r[0].KII[i]) / K0);
      double Jk = (r[1].KI[i] * r[1].KI[i] + r[1].KII[i] * r[1].KII[i]) / E;
      worst_j = fmax(worst_j, fabs(r[1].J[i] / Jk - 1));
      printf("# beta = %2.0f deg, l = %.0f mm: K_I %.2f kPa sqrt(m) (closed form x %.3f: "
             "%.2f), K_II %.2f (%.2f), J_dom %.3f N/m, J_cont %.3f, (K_I^2 + K_II^2)/E' "
             "%.3f\n",
             betas[b], l[i] * 1e3, r[1].KI[i] * 1e-3, fw, fw * K0 * cb * cb * 1e-3,
             r[1].KII[i] * 1e-3, fw * K0 * sb * cb * 1e-3, r[1].J[i], r[1].Jc[i], Jk);
    }
    ps_check(sym <= 1e-3,
             "beta = %.0f: the two tips give the same J, K_I, K_II (%.2g)", betas[b], sym);
    double kI = mean3(r[1].KI), kII = mean3(r[1].KII), spI = 0, spII = 0;
    for (int i = 0; i < NL; i++) {
      spI = fmax(spI, fabs(r[1].KI[i] - kI));
      spII = fmax(spII, fabs(r[1].KII[i] - kII));
    }
    printf("# beta = %2.0f deg: ring mean K_I %.2f kPa sqrt(m) (%+.2f%% vs the closed "
           "form x %.3f), K_II %.2f (%+.2f%%)\n",
           betas[b], kI * 1e-3, 100 * (kI / (fw * K0 * cb * cb) - 1), fw, kII * 1e-3,
           b ? 100 * (kII / (fw * K0 * sb * cb) - 1) : 0.0);
    /* 45 degrees: the 8 mm ring falls off at this resolution (see the
     * header); looser bounds there */
    double tol_path = b == 2 ? 0.15 : 0.05, tol_ratio = b == 2 ? 0.06 : 0.04;
    ps_check(spI <= tol_path * fabs(kI) && spII <= fmax(tol_path * fabs(kII), 0.02 * K0),
             "beta = %.0f: K_I, K_II path independent over rings 4..8 mm (spread %.2f%%, "
             "%.2f kPa sqrt(m); bound %.0f%%)", betas[b], 100 * spI / fabs(kI), spII * 1e-3,
             100 * tol_path);
    double jm = mean3(r[1].J), jk = (kI * kI + kII * kII) / E;
    ps_check(fabs(jm / jk - 1) <= 0.10,
             "beta = %.0f: J_dom = (K_I^2 + K_II^2)/E' (ring means %.3f, %.3f N/m: %+.2f%%; "
             "worst ring %.2f%%)", betas[b], jm, jk, 100 * (jm / jk - 1), 100 * worst_j);
    if (b == 0) {
      KI0 = kI;
      ps_check_le(fabs(kII) / kI, 0.01, "beta = 0: |K_II| / K_I");
      ps_check_rel(kI, fw * K0, 0.08, "beta = 0: K_I vs sigma sqrt(pi a) sqrt(sec(pi a/W))");
      continue;
    }
    ps_check_rel(kI / KI0, cb * cb, tol_ratio, "K_I(beta) / K_I(0) = cos^2 beta");
    ps_check_rel(kII / KI0, sb * cb, tol_ratio, "K_II(beta) / K_I(0) = sin beta cos beta");
    ps_check_rel(kII / kI, sb / cb, tol_ratio, "K_II / K_I = tan beta");
    ps_check_rel(kI, fw * K0 * cb * cb, 0.08, "K_I vs sigma sqrt(pi a) cos^2 beta (x width)");
    ps_check_rel(kII, fw * K0 * sb * cb, 0.08,
                 "K_II vs sigma sqrt(pi a) sin beta cos beta (x width)");
  }

  /* (3) pure mode II */
  tip_result r[2];
  inclined(&cs, M_PI / 4, 0.0, -sigma, l, r);
  double kI = mean3(r[1].KI), kII = mean3(r[1].KII);
  for (int i = 0; i < NL; i++)
    printf("# pure mode II (beta 45, sigma_xx = -sigma_yy), l = %.0f mm: K_I %.2f, K_II "
           "%.2f kPa sqrt(m) (closed form x %.3f: 0, %.2f), J_dom %.3f N/m, K_II^2/E' "
           "%.3f\n",
           l[i] * 1e3, r[1].KI[i] * 1e-3, r[1].KII[i] * 1e-3, fw, fw * K0 * 1e-3, r[1].J[i],
           r[1].KII[i] * r[1].KII[i] / E);
  ps_check_le(fabs(kI) / kII, 0.03, "pure mode II: |K_I| / K_II");
  ps_check_rel(kII, fw * K0, 0.08, "pure mode II: K_II vs sigma sqrt(pi a) (x width)");
  return ps_check_summary();
}
