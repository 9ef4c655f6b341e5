/* t420_arclength.c: arc-length path following (path.control: arc_length,
 * issue 20; ps_solver_arclength_step, src/path/control_arclength.c).
 *
 * (1) Same equilibrium points as load control on elastic cases (geometric
 *     nonlinearity only, so the path does not matter): for each increment
 *     of an arc-length path, a second solver is stepped by load control to
 *     the same load factor; the displacements agree to 1e-6 (relative, all
 *     dofs; Newton tolerance 1e-10). Two loadings, so that both parts of
 *     the load vector q = fext_f - K_fp ubar_p are exercised: a plate with
 *     a hole under a traction (q = fext), and a bar pulled by prescribed
 *     displacements (q = -K_fp ubar).
 * (2) A load maximum: the fibre model in plane stress with nu = 0.3 < 1/3
 *     and yield_rule total softens as arms yield (its family coefficient
 *     turns negative; stall.c's advice), so a plate with a hole under a
 *     traction has a limit point. Load control stalls there
 *     (PS_PATH_STALLED); arc-length passes it: every increment converges,
 *     the load factor rises to a maximum and falls on the descending
 *     branch until the stop rule (below stop_load_drop = 0.5 of the
 *     maximum: PS_PATH_LOAD_DROP). The independent number is load
 *     control's last converged load factor, a lower bound of the limit
 *     load on the same equilibrium path: the arc-length maximum (a sampled
 *     point of the path, also a lower bound) must agree within 1%. Past the
 *     maximum the plastic mechanism keeps growing: the largest particle
 *     displacement rises while the load factor falls.
 * (0) Snap-through of a two-arm shallow truss (von Mises truss; bond
 *     model, linear springs T = k dl, nonlinear through the geometry):
 *     particles at (-L, 0), (0, H), (L, 0), H = 0.3 L, the ends held, the
 *     apex held in x and pushed down by lambda F0. Closed form:
 *     lambda(y) = -2 k dl(y) y / (l(y) F0), l = sqrt(L^2 + y^2 + e^2
 *     r0^2), dl = l - r0 sqrt(1 + e^2) (e = PS_ARM_LENGTH_ROUNDING), F0
 *     chosen so that the limit point is at lambda = 1. Arc-length steps
 *     (ps_solver_arclength_step, fixed ds) trace it from y = H through the
 *     limit point, through y = 0 (lambda = 0), the lower limit point
 *     (lambda = -1) and on to the far branch y < -H: every converged
 *     point within 1e-6 of the closed form, the sampled extremes within
 *     1% of +-1.
 * (3) Plane strain (the same plate, yield_rule total): no maximum (the
 *     arms realign, the load keeps rising slowly), but arc-length follows
 *     the collapse knee and agrees with load control at the same load
 *     factor within 2% where both are fine enough (backward-Euler
 *     increments of plasticity depend on the step, so only a loose
 *     agreement is expected). */
#include "check.h"
#include "common.h"
#include "path/ps_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t420: %s failed: %s\n", what, ctx->msg);
  printf("FAIL: %s\n", what);
  exit(2);
}

static void write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f || fputs(text, f) < 0 || fclose(f)) {
    fprintf(stderr, "t420: cannot write %s\n", path);
    exit(2);
  }
}

static void setup_text(ps_problem *pb, const char *path, const char *text) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_case cs;
  write_text(path, text);
  ps_case_defaults(&cs);
  if (ps_case_load(&cs, path, &ctx)) die_ctx("case", &ctx);
  if (ps_problem_setup(pb, &cs, &ctx)) die_ctx("setup", &ctx);
  remove(path);
}

/* the plate with a hole (33 x 30 spacings of 1 mm, hole R = 4 mm at the
 * centre), clamped through a layer left of x = 0, a traction in x on the
 * right column; material and path lines appended */
static void plate_text(char *buf, size_t len, const char *material, const char *path) {
  snprintf(buf, len,
           "name: t420-plate\n"
           "geometry:\n  type: box\n  counts: [33, 30]\n  spacing: 0.001\n"
           "  origin: [-0.003, 0.0]\n  holes: [[0.015, 0.015, 0.004]]\n"
           "material:\n  model: fibre\n  E: 1.0e9\n  nu: 0.3\n%s"
           "loading:\n  type: boundary\n  boundary:\n"
           "    - select: {x_max: 0.0}\n      fix: [x, y]\n"
           "    - select: {x_min: 0.0289}\n      traction: {x: 2.0e6}\n"
           "solver:\n  tolerance: 1.0e-10\n"
           "path:\n%s",
           material, path);
}

static double norm_diff(ps_int n, const double *a, const double *b, double *nb) {
  double d = 0, s = 0;
  for (ps_int j = 0; j < n; j++) {
    d += (a[j] - b[j]) * (a[j] - b[j]);
    s += b[j] * b[j];
  }
  *nb = sqrt(s);
  return sqrt(d);
}

static double max_abs_u(const ps_problem *pb, const double *u) {
  double m = 0;
  for (ps_int a = 0; a < pb->P.n; a++) {
    double s = 0;
    for (int k = 0; k < pb->P.dim; k++) s += u[a * pb->P.dim + k] * u[a * pb->P.dim + k];
    if (s > m) m = s;
  }
  return sqrt(m);
}

/* ---- (0) snap-through of a shallow two-arm truss ---- */

static double truss_lambda(double L, double r0, double k, double F0, double y) {
  double e = PS_ARM_LENGTH_ROUNDING;
  double l = sqrt(L * L + y * y + e * e * r0 * r0);
  return -2 * k * (l - r0 * sqrt(1 + e * e)) * y / (l * F0);
}

static void snap_through(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  const double L = 1.0e-3, H = 0.3e-3;
  ps_particles P;
  ps_network net;
  ps_kernel K;
  if (ps_particles_alloc(&P, 2, 3, &ctx)) die_ctx("particles", &ctx);
  double x[6] = {-L, 0, 0, H, L, 0};
  for (int j = 0; j < 6; j++) P.x[j] = x[j];
  for (int a = 0; a < 3; a++) {
    P.volume[a] = 1.3e-6;
    P.h[a] = 1.0e-3;
  }
  /* arms r < 1.5 h: 0-1 and 1-2, not 0-2 */
  if (ps_kernel_init(&K, 2, 2, 1.5, &ctx) || ps_network_build(&net, &P, &K, NULL, 0, &ctx))
    die_ctx("network", &ctx);
  ps_material mat = {.E = 2.1e11, .nu = 0.25, .plane = PS_PLANE_STRAIN, .yield_strain = 2e-3,
                     .plastic = 0, .delta = INFINITY, .rho = 7800, .horizon = 1.6e-3,
                     .spacing = 1e-3};
  if (ps_material_finish(&mat, 2, &ctx)) die_ctx("material", &ctx);
  unsigned char fixed[6] = {1, 1, 1, 0, 1, 1};
  double ubar[6] = {0}, fext[6] = {0};
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  o.tolerance = 1e-12;
  o.threads = 1;
  ps_solver *s = NULL;
  if (ps_solver_create(&s, &P, &net, ps_model_bond, &mat, fixed, ubar, &o, &ctx))
    die_ctx("solver", &ctx);
  /* k from a first load step (T = k dl), F0 from the closed form's maximum */
  fext[3] = -1.0;
  ps_solver_set_forces(s, fext);
  if (ps_solver_step(s, 1e-3, &ctx) != PS_OK) die_ctx("first step", &ctx);
  double k = ps_solver_arm_tension(s)[0] / ps_solver_arm_elongation(s)[0], r0 = net.r0[0];
  double F0 = 0, ymax = 0;
  for (int i = 1; i < 100000; i++) { /* scan, then golden section */
    double y = H * i / 100000.0, f = truss_lambda(L, r0, k, 1.0, y);
    if (f > F0) F0 = f, ymax = y;
  }
  double a = ymax - H / 1e5, b = ymax + H / 1e5, g = 0.5 * (sqrt(5.0) - 1);
  for (int i = 0; i < 100; i++) {
    double c = b - g * (b - a), d = a + g * (b - a);
    if (truss_lambda(L, r0, k, 1.0, c) > truss_lambda(L, r0, k, 1.0, d))
      b = d;
    else
      a = c;
  }
  F0 = truss_lambda(L, r0, k, 1.0, 0.5 * (a + b));
  ps_solver_free(s);
  s = NULL;
  fext[3] = -F0;
  if (ps_solver_create(&s, &P, &net, ps_model_bond, &mat, fixed, ubar, &o, &ctx))
    die_ctx("solver", &ctx);
  ps_solver_set_forces(s, fext);
  /* arc-length steps of fixed length to y < -1.2 H */
  double worst = 0, lmax = -INFINITY, lmin = INFINITY, y = H;
  int n = 0, ok = 1, crossed = 0, down = 0;
  double lprev = 0;
  while (y > -1.2 * H && n < 400) {
    int st = ps_solver_arclength_step(s, 0.1, 0.0, &ctx);
    if (st < 0) die_ctx("arc-length step", &ctx);
    if (st != PS_OK) {
      ok = 0;
      break;
    }
    ps_solver_commit(s);
    n++;
    double lam = ps_solver_lambda(s);
    y = H + ps_solver_u(s)[3];
    double d = fabs(lam - truss_lambda(L, r0, k, F0, y));
    if (d > worst) worst = d;
    if (y > 0 && lam > lmax) lmax = lam; /* the upper limit point */
    if (y > -H && lam < lmin) lmin = lam; /* the lower one */
    crossed |= y < 0;
    down += lam < lprev;
    lprev = lam;
  }
  printf("  truss: %d arc-length steps to y = %.3f H, limit points sampled at load factors "
         "%.6f and %.6f (closed form 1 and -1), %d steps with the load falling; largest distance from the "
         "closed form %.2e\n",
         n, y / H, lmax, lmin, down, worst);
  ps_check(ok && crossed && y <= -1.2 * H,
           "truss: arc-length traces the snap-through to the far branch (%d steps)", n);
  ps_check_le(worst, 1e-6, "truss: every point on the closed-form curve");
  ps_check(lmax <= 1 + 1e-6 && lmax >= 0.99 && lmin >= -1 - 1e-6 && lmin <= -0.99,
           "truss: both limit points passed (load factor %.5f and %.5f, closed form +-1)",
           lmax, lmin);
  /* load control from rest: past lambda = 1 there is no nearby
   * equilibrium; Newton either fails or jumps to the far branch */
  ps_solver_free(s);
  s = NULL;
  if (ps_solver_create(&s, &P, &net, ps_model_bond, &mat, fixed, ubar, &o, &ctx))
    die_ctx("solver", &ctx);
  ps_solver_set_forces(s, fext);
  double lam = 0;
  int st = PS_OK;
  while (st == PS_OK && lam < 1.1) {
    lam += 0.05;
    st = ps_solver_step(s, lam, &ctx);
    if (st < 0) die_ctx("load-control step", &ctx);
    if (st == PS_OK) ps_solver_commit(s);
  }
  y = H + ps_solver_u(s)[3];
  printf("  truss under load control: %s at load factor %.2f (y = %.3f H)\n",
         st == PS_OK ? "converged" : "failed", lam, y / H);
  ps_check(st != PS_OK || y < -H,
           "truss: load control cannot follow the descending branch (%s at load factor "
           "%.2f, y = %.3f H)", st == PS_OK ? "jumped to the far branch" : "failed", lam, y / H);
  ps_solver_free(s);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* ---- (1) the same equilibrium points as load control ---- */

static void same_points(const char *what, const char *path, const char *text) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_problem pb;
  setup_text(&pb, path, text);
  ps_solver *a = tc_problem_solver(&pb), *b = tc_problem_solver(&pb);
  ps_path_problem pp = tc_path_problem(&pb, "t420");
  ps_path p;
  if (ps_path_init(&p, a, &pp, &pb.cs.path, ps_step_control_arc_length, &ctx))
    die_ctx("path", &ctx);
  double worst = 0, lmax = 0;
  int n = 0, all = 1;
  ps_int nd = pb.P.n * pb.P.dim;
  while (ps_path_test(&p) == PS_PATH_CONTINUE) {
    if (ps_path_iterate(&p, &ctx)) die_ctx("arc-length increment", &ctx);
    if (p.end) break;
    all &= p.last.converged;
    double lambda = ps_solver_lambda(a);
    if (ps_solver_step(b, lambda, &ctx) != PS_OK) die_ctx("load-control step", &ctx);
    ps_solver_commit(b);
    double nu, d = norm_diff(nd, ps_solver_u(a), ps_solver_u(b), &nu);
    if (d / nu > worst) worst = d / nu;
    if (lambda > lmax) lmax = lambda;
    n++;
  }
  printf("  %s: %d arc-length increments to load factor %.4f (end %d: %s), largest "
         "relative difference from load control %.2e\n",
         what, n, lmax, p.end, p.stop_reason, worst);
  ps_check(n >= 3 && all && p.end == PS_PATH_MAX_LOAD,
           "%s: arc-length reached max_load in %d converged increments", what, n);
  ps_check_le(worst, 1e-6, "arc-length and load control: the same displacements at the same "
                           "load factor (elastic)");
  ps_path_free(&p);
  ps_solver_free(a);
  ps_solver_free(b);
  ps_problem_free(&pb);
}

/* ---- (2) a load maximum ---- */

static void load_maximum(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  char text[2048];
  const char *mat = "  plane: stress\n  yield_strain: 0.002\n";
  plate_text(text, sizeof text, mat, "  load_step: 0.02\n  max_load: 3.0\n");
  ps_problem pb;
  setup_text(&pb, "t420_tmp_max.yaml", text);
  ps_path_problem pp = tc_path_problem(&pb, "t420");

  /* load control: stalls at the limit load */
  ps_solver *s = tc_problem_solver(&pb);
  ps_path p;
  if (ps_path_init(&p, s, &pp, &pb.cs.path, ps_step_control_load, &ctx)) die_ctx("path", &ctx);
  while (ps_path_test(&p) == PS_PATH_CONTINUE)
    if (ps_path_iterate(&p, &ctx)) die_ctx("load-control increment", &ctx);
  double lambda_load = ps_solver_lambda(s); /* the last committed state */
  printf("  load control: end %d (%s), last converged load factor %.6f\n", p.end,
         p.stop_reason, lambda_load);
  ps_check(p.end == PS_PATH_STALLED, "plane stress, softening: load control stalls at the "
                                     "limit load (load factor %.5f)", lambda_load);
  ps_path_free(&p);
  ps_solver_free(s);

  /* arc-length: through the maximum and down the descending branch */
  s = tc_problem_solver(&pb);
  ps_path_opts o = pb.cs.path;
  o.control = PS_CONTROL_ARC_LENGTH;
  if (ps_path_init(&p, s, &pp, &o, ps_step_control_arc_length, &ctx)) die_ctx("path", &ctx);
  int n = 0, all = 1, i_max = 0, after = 0, grows = 1;
  double lmax = 0, last = 0, um_prev = 0;
  while (ps_path_test(&p) == PS_PATH_CONTINUE) {
    if (ps_path_iterate(&p, &ctx)) die_ctx("arc-length increment", &ctx);
    if (p.end) break;
    n++;
    all &= p.last.converged;
    last = p.last.lambda;
    double um = max_abs_u(&pb, ps_solver_u(s));
    if (last > lmax) {
      lmax = last;
      i_max = n;
    } else {
      after++;
      grows &= um > um_prev;
    }
    um_prev = um;
    printf("    %3d  load factor %.6f  max |u| %.4e m  yielding %lld\n", n, last, um,
           (long long)p.last.yielding);
  }
  printf("  arc-length: end %d (%s), maximum load factor %.6f at increment %d, %d "
         "increments past it, last %.5f\n",
         p.end, p.stop_reason, lmax, i_max, after, last);
  ps_check(all && n > 0, "arc-length: every increment converged (%d)", n);
  ps_check(p.end == PS_PATH_LOAD_DROP && after >= 3 && last < 0.5 * lmax,
           "arc-length passes the limit point: %d increments past the maximum, down to "
           "%.3f of it", after, last / lmax);
  ps_check_rel(lmax, lambda_load, 0.01, "the arc-length maximum against load control's last "
                                        "converged load factor (1%)");
  ps_check(grows, "past the maximum the largest displacement grows at every increment");
  /* past the maximum the tangent is indefinite: the corrector's solves go
   * by GMRES with the shifted tangent's factor before any UMFPACK factor
   * (solve_tangent); the checks above are on that route's path */
  ps_solver_stats st;
  ps_solver_get_stats(s, &st);
  printf("  arc-length: %lld GMRES iterations, %lld UMFPACK factors\n",
         (long long)st.gmres_iterations, (long long)st.n_fallback);
  ps_check(st.gmres_iterations > 0, "the indefinite tangents were solved by GMRES (%lld "
           "iterations)", (long long)st.gmres_iterations);
  ps_path_free(&p);
  ps_solver_free(s);
  ps_problem_free(&pb);
}

/* ---- (3) plane strain: the collapse knee, no maximum ---- */

/* the load factor's displacement fext.u / sum |fext| */
static double load_displacement(const ps_problem *pb, const double *u) {
  double w = 0, a = 0;
  for (ps_int j = 0; j < pb->P.n * pb->P.dim; j++) {
    w += pb->fext[j] * u[j];
    a += fabs(pb->fext[j]);
  }
  return w / a;
}

static void plane_strain_knee(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  char text[2048];
  plate_text(text, sizeof text, "  plane: strain\n  yield_strain: 0.002\n",
             "  load_step: 0.05\n  max_load: 1.4\n  control: arc_length\n  arc_length_max: 0.2\n"
             "  max_increments: 400\n");
  ps_problem pb;
  setup_text(&pb, "t420_tmp_knee.yaml", text);
  ps_path_problem pp = tc_path_problem(&pb, "t420");
  ps_solver *s = tc_problem_solver(&pb), *b = tc_problem_solver(&pb);
  ps_path p;
  if (ps_path_init(&p, s, &pp, &pb.cs.path, ps_step_control_arc_length, &ctx))
    die_ctx("path", &ctx);
  int n = 0, all = 1, its = 0;
  double worst = 0, lam_b = 0;
  while (ps_path_test(&p) == PS_PATH_CONTINUE) {
    if (ps_path_iterate(&p, &ctx)) die_ctx("arc-length increment", &ctx);
    if (p.end) break;
    n++;
    all &= p.last.converged;
    its += p.last.newton_iterations;
    /* load control in steps of at most 0.01 to the same load factor */
    double lambda = p.last.lambda;
    while (lam_b < lambda) {
      double t = fmin(lam_b + 0.01, lambda);
      if (ps_solver_step(b, t, &ctx) != PS_OK) die_ctx("load-control step", &ctx);
      ps_solver_commit(b);
      lam_b = t;
    }
    double ua = load_displacement(&pb, ps_solver_u(s)), ub = load_displacement(&pb, ps_solver_u(b));
    double d = fabs(ua - ub) / fabs(ub);
    if (d > worst) worst = d;
  }
  double u_end = load_displacement(&pb, ps_solver_u(s));
  printf("  plane strain: %d arc-length increments, %d Newton iterations, end %d (%s), "
         "displacement %.4e m at load factor %.4f; largest difference from load control "
         "in steps of 0.01: %.2e\n",
         n, its, p.end, p.stop_reason, u_end, ps_solver_lambda(s), worst);
  ps_check(all && p.end == PS_PATH_MAX_LOAD, "plane strain: arc-length reaches max_load, every "
                                             "increment converged");
  ps_check_le(worst, 0.02, "plane strain: the loaded edge's displacement as load control's "
                           "(2%)");
  ps_path_free(&p);
  ps_solver_free(s);
  ps_solver_free(b);
  ps_problem_free(&pb);
}

int main(void) {
  char text[2048];
  printf("t420: arc-length path following\n");
  snap_through();
  plate_text(text, sizeof text, "  plane: stress\n  plastic: false\n",
             "  load_step: 0.1\n  max_load: 8.0\n  control: arc_length\n  arc_length_max: 0.4\n");
  same_points("plate with a hole, traction (elastic, plane stress)", "t420_tmp_plate.yaml", text);
  same_points("bar, prescribed displacement (elastic, plane strain)", "t420_tmp_bar.yaml",
              "name: t420-bar\n"
              "geometry:\n  type: box\n  dim: 2\n  counts: [40, 10]\n  spacing: 1.0e-3\n"
              "  lattice: hex\n"
              "material:\n  E: 210.0e9\n  nu: 0.3\n  plane: strain\n  plastic: false\n"
              "loading:\n  type: boundary\n  boundary:\n"
              "    - select: {x_max: 0.0035}\n      fix: [x]\n"
              "    - select: {x_max: 0.0035, y_min: 0.004, y_max: 0.0055}\n      fix: [y]\n"
              "    - select: {x_min: 0.0365}\n      displace: {x: 0.002}\n      measure: true\n"
              "solver:\n  tolerance: 1.0e-10\n"
              "path:\n  load_step: 0.1\n  max_load: 1.0\n  control: arc_length\n");
  load_maximum();
  plane_strain_knee();
  return ps_check_summary();
}
