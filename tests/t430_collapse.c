/* t430_collapse.c: plastic collapse of a strip of the fibre model under
 * uniaxial tension, followed by arc-length (path.control: arc_length;
 * issue 20), against the model's own limit stress (doc/path-following.md,
 * "Plastic collapse of a strip").
 *
 * The limit stress. A fully plastic arm holds G(N+2) eps_y s (Eq. 110-111)
 * with s = +-1 the sign of its plastic flow; the stress of a homogeneous
 * state is sigma = N <S n n> (the mean over directions, the continuum limit
 * of Eq. 24: sigma = 2 G eps + (K - G) tr eps 1 when elastic, N = 2).
 * - deviatoric reading: S = G(N+2) eps_y s - m + N K epsbar with s the sign
 *   of the arm's deviatoric elongation; the flow is isochoric, so under
 *   uniaxial stress s = sign(cos 2 theta) and sigma_xx - sigma_yy = 8 G eps_y
 *   <|cos 2 theta|> 2 = 16 G eps_y / pi; the isotropic terms (m, K epsbar)
 *   take sigma_yy to 0: sigma_lim = 16 G eps_y / pi = (6/pi) sigma_y at
 *   nu = 1/3, either plane.
 * - total reading: S = G(N+2) eps_y s + Kc epsbar, Kc = N K - G(N+2), s the
 *   sign of the total elongation. At constant load with every arm plastic
 *   only epsbar can move the stress, so where Kc != 0 the flow on a plateau
 *   keeps epsbar fixed: isochoric, the same s and the same limit 16 G
 *   eps_y / pi (plane strain, Kc = 3E/4 at nu = 1/3). In plane stress Kc =
 *   E (3 nu - 1)/(1 - nu^2): below nu = 1/3 it is negative and the
 *   fully plastic strip softens (t420's limit point); at nu = 1/3 it
 *   vanishes, epsbar drops out, and the lateral flow ratio r (d eps =
 *   diag(1, -r)) is fixed by sigma_yy = 0: s = +1 for tan^2 theta < 1/r,
 *   and <s sin^2 theta> = 0 gives theta0 - sin(2 theta0)/2 = pi/4 (theta0
 *   = 1.1549, r = 0.196; GSL Brent), sigma_lim = 8 G eps_y (4 theta0 / pi -
 *   1) = 1.4115 sigma_y.
 * The discrete form: the same sums over the family of an interior particle
 * of the strip, sigma = (1/(2 V)) sum_b (A_ab + A_ba) r0 S n n (Eq. 24 for
 * a homogeneous state, A_ab = A_ba inside a square lattice), with the
 * flow signs the reading implies (for total at nu = 1/3 in plane stress
 * the root in r is a step function on a lattice: the direction class on
 * the boundary carries the S between +-S_y that makes sigma_yy = 0).
 *
 * The strip: 70 x 16 spacings of a square lattice (E 1 GPa, nu = 1/3,
 * eps_y = 0.002, small strains so that the arms' realignment stays small),
 * held in x through a fictitious layer of 3 columns left of x = 0 (one row
 * also in y), lateral motion free everywhere; the load is a body force
 * spread over the last 4 columns (sigma_y W at load factor 1, W = 16 d):
 * a load on one column would be carried by that column's arms alone and
 * yield there first. The strip is long (L/W > 4) so that the ends'
 * lateral constraint does not reach the middle (at L = 40, W = 30 the
 * middle's sigma_yy grew to 0.06 sigma_y along the plateau).
 * What is measured: the Eq. 24 stress averaged over the particles of the
 * middle third of the length more than two horizons from the free edges
 * (the interior: complete families two deep). The section's load factor
 * (force / (sigma_y W)) is lower by the free edges' boundary layer (the
 * particles near an edge have truncated families: fewer arms cross the
 * section there), and in the readings with an epsbar term it keeps rising
 * slowly: an edge particle's family weights x arms more than y arms, so
 * its epsbar grows with the isochoric flow and its N K epsbar (or Kc
 * epsbar) with it.
 * Checks, for deviatoric (plane stress and strain) and total (plane strain,
 * and plane stress at nu = 1/3):
 * (i)  arc-length converges at every increment to a strain of 7 eps_y
 *      (grip displacement / L); on the stretch from 5 to 7 eps_y the
 *      interior stress stays constant within 0.5% (what moves it is the
 *      arms' realignment, O(strain) = 1e-2: measured 0.1-0.4%) and the
 *      load factor within 2% (the edge layer's hardening above: measured
 *      0.1-1.2%);
 * (ii) the interior plateau equals the closed form within 1% (the issue's
 *      tolerance; the lattice's own sum is 0.2% below the continuum's for
 *      16 G eps_y / pi, and realignment adds up to 0.6% at 7 eps_y) and
 *      the discrete sum within 1%;
 * (iii) load control on the same strip (total, plane stress: the flattest
 *      plateau) cannot follow it: in steps of 0.025 every increment
 *      converges (no crash), but the one from 1.325 (below the plateau) to
 *      1.35 (above it) strains the grip by more than 10 eps_y at once
 *      (before it: at most 2 eps_y an increment), landing where the arms'
 *      realignment carries the load (the arc-length path keeps rising by
 *      0.07% an eps_y). It does not stall at the limit: run on, the
 *      increments keep finding such states and the run stalls only at load
 *      factor 1.754, at a grip strain of 4,365 eps_y (8.7) - a large-strain
 *      state, not the limit (doc/path-following.md). */
#include "check.h"
#include "common.h"
#include "path/ps_path.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_roots.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { NX = 70, NY = 16, M_LOAD = 4 };
static const double D = 1e-3, EY = 0.002, E_MOD = 1e9, NU = 1.0 / 3.0;

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t430: %s failed: %s\n", what, ctx->msg);
  printf("FAIL: %s\n", what);
  exit(2);
}

static void write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f || fputs(text, f) < 0 || fclose(f)) {
    fprintf(stderr, "t430: cannot write %s\n", path);
    exit(2);
  }
}

/* the strip (cell centres at ((i + 1/2) d, (j + 1/2) d), the strip proper
 * 0 < x < L = NX d) */
static void setup_strip(ps_problem *pb, const char *plane, const char *rule,
                        const char *control) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  char text[4096];
  double L = NX * D;
  snprintf(text, sizeof text,
           "name: t430-strip\n"
           "geometry:\n  type: box\n  counts: [%d, %d]\n  spacing: %.17g\n  lattice: square\n"
           "  origin: [%.17g, 0.0]\n"
           "material:\n  model: fibre\n  E: %.17g\n  nu: %.17g\n  plane: %s\n"
           "  yield_strain: %.17g\n  yield_rule: %s\n"
           "loading:\n  type: boundary\n  boundary:\n"
           "    - select: {x_max: 0.0}\n      fix: [x]\n"
           "    - select: {x_max: 0.0, y_min: %.17g, y_max: %.17g}\n      fix: [y]\n"
           "    - select: {x_min: %.17g}\n      traction: {x: %.17g}\n"
           "solver:\n  tolerance: 1.0e-10\n"
           "path:\n  control: %s\n  load_step: 0.05\n  arc_length_max: 0.2\n"
           "  arc_length_iterations: 20\n  max_load: 3.0\n  max_increments: 200\n",
           NX + 3, NY, D, -3 * D, E_MOD, NU, plane, EY, rule, 0.5 * NY * D - 0.6 * D,
           0.5 * NY * D + 0.4 * D, L - M_LOAD * D, E_MOD * EY / M_LOAD, control);
  ps_case cs;
  write_text("t430_tmp.yaml", text);
  ps_case_defaults(&cs);
  if (ps_case_load(&cs, "t430_tmp.yaml", &ctx)) die_ctx("case", &ctx);
  if (ps_problem_setup(pb, &cs, &ctx)) die_ctx("setup", &ctx);
  remove("t430_tmp.yaml");
}

/* ---- the continuum ---- */

/* <|cos 2 theta|> over the circle by quadrature (2/pi in closed form) */
static double abs_cos2(double t, void *p) {
  (void)p;
  return fabs(cos(2 * t)) / (2 * M_PI);
}

/* theta0 - sin(2 theta0)/2 - pi/4: <s sin^2 theta> = 0 */
static double zone_edge(double t, void *p) {
  (void)p;
  return t - 0.5 * sin(2 * t) - M_PI / 4;
}

static double brent(gsl_function *f, double lo, double hi) {
  gsl_root_fsolver *rs = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(rs, f, lo, hi);
  double r = 0.5 * (lo + hi);
  for (int it = 0; it < 100; it++) {
    gsl_root_fsolver_iterate(rs);
    r = gsl_root_fsolver_root(rs);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(rs), gsl_root_fsolver_x_upper(rs),
                               1e-14, 0) == GSL_SUCCESS)
      break;
  }
  gsl_root_fsolver_free(rs);
  return r;
}

/* ---- the lattice: the family of the particle nearest the centre ---- */

typedef struct {
  double w[4096], c2[4096], s2[4096]; /* (A_ab + A_ba) r0 / (2 V), cos^2, sin^2 */
  int n;
} family;

static void central_family(const ps_problem *pb, family *F) {
  double xc = 0.5 * NX * D, yc = 0.5 * NY * D, best = INFINITY;
  ps_int c = 0;
  for (ps_int a = 0; a < pb->P.n; a++) {
    double dx = pb->P.x[2 * a] - xc, dy = pb->P.x[2 * a + 1] - yc;
    if (dx * dx + dy * dy < best) best = dx * dx + dy * dy, c = a;
  }
  F->n = 0;
  for (ps_int k = pb->net.fam_ptr[c]; k < pb->net.fam_ptr[c + 1] && F->n < 4096; k++) {
    ps_int i = pb->net.fam_arm[k], b = pb->net.a[i] == c ? pb->net.b[i] : pb->net.a[i];
    double nx = (pb->P.x[2 * b] - pb->P.x[2 * c]) / pb->net.r0[i];
    double ny = (pb->P.x[2 * b + 1] - pb->P.x[2 * c + 1]) / pb->net.r0[i];
    F->w[F->n] = (pb->net.A_ab[i] + pb->net.A_ba[i]) * pb->net.r0[i] / (2 * pb->P.volume[c]);
    F->c2[F->n] = nx * nx;
    F->s2[F->n] = ny * ny;
    F->n++;
  }
}

/* isochoric flow (deviatoric; total with Kc != 0): sigma_xx - sigma_yy =
 * G(N+2) eps_y sum w |cos^2 - sin^2| */
static double lattice_isochoric(const family *F, double Gc) {
  double s = 0;
  for (int j = 0; j < F->n; j++) s += F->w[j] * fabs(F->c2[j] - F->s2[j]);
  return Gc * EY * s;
}

/* total reading with Kc = 0: s = +1 for tan^2 < t*, -1 beyond, the class
 * tan^2 = t* at the x in [-1, 1] that makes sigma_yy = 0 */
static double lattice_total_kc0(const family *F, double Gc) {
  for (int cand = 0; cand < F->n; cand++) {
    double t = F->s2[cand] / fmax(F->c2[cand], 1e-300);
    double syy = 0, sxx = 0, cyy = 0, cxx = 0;
    for (int j = 0; j < F->n; j++) {
      double tj = F->s2[j] / fmax(F->c2[j], 1e-300);
      if (fabs(tj - t) <= 1e-9 * fmax(t, 1)) {
        cyy += F->w[j] * F->s2[j];
        cxx += F->w[j] * F->c2[j];
      } else {
        double s = tj < t ? 1.0 : -1.0;
        syy += F->w[j] * s * F->s2[j];
        sxx += F->w[j] * s * F->c2[j];
      }
    }
    if (cyy <= 0) continue;
    double x = -syy / cyy;
    if (x >= -1 && x <= 1) return Gc * EY * (sxx + x * cxx);
  }
  return NAN;
}

/* ---- one strip along a path ---- */

typedef struct {
  double strain, lambda, sig, syy; /* grip strain / eps_y; load factor; interior Eq. 24 */
} state;

typedef struct {
  state st[256];
  int n, all_converged, end;
  char reason[160];
} history;

static void measure(const ps_problem *pb, ps_solver *s, double *sig, state *out) {
  double L = NX * D, ymax = NY * D;
  /* the horizon of an interior particle (alpha h, h = 0.541 d by Eq. 115;
   * the edge particles' sizes are larger) */
  double h_in = 0;
  int n_in = 0;
  for (ps_int a = 0; a < pb->P.n; a++) {
    double x = pb->P.x[2 * a], y = pb->P.x[2 * a + 1];
    if (fabs(x - L / 2) < 2 * D && fabs(y - ymax / 2) < 2 * D) h_in += pb->P.h[a], n_in++;
  }
  double hor = 5.1 * h_in / n_in;
  const double *u = ps_solver_u(s);
  double ue = 0, sxx = 0, syy = 0;
  int ne = 0, ni = 0;
  for (ps_int a = 0; a < pb->P.n; a++)
    if (pb->P.x[2 * a] > L - M_LOAD * D) ue += u[2 * a], ne++;
  ps_post_stress_tensor(&pb->P, &pb->net, ps_solver_arm_tension(s), ps_solver_arm_direction(s),
                        sig);
  for (ps_int a = 0; a < pb->P.n; a++) {
    double x = pb->P.x[2 * a], y = pb->P.x[2 * a + 1];
    if (x > L / 3 && x < 2 * L / 3 && y > 2 * hor && ymax - y > 2 * hor) {
      sxx += sig[4 * a];
      syy += sig[4 * a + 3];
      ni++;
    }
  }
  out->strain = ue / ne / L / EY;
  out->lambda = ps_solver_lambda(s);
  out->sig = sxx / ni / (E_MOD * EY);
  out->syy = syy / ni / (E_MOD * EY);
}

/* arc-length (or load control) until the grip strain passes strain_end */
static void run(ps_problem *pb, const ps_step_control_type *ctl, double strain_end,
                history *H) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_path_problem pp = tc_path_problem(pb, "t430");
  ps_solver *s = tc_problem_solver(pb);
  ps_path p;
  double *sig = malloc(4 * (size_t)pb->P.n * sizeof *sig);
  if (!sig) abort();
  if (ps_path_init(&p, s, &pp, &pb->cs.path, ctl, &ctx)) die_ctx("path", &ctx);
  H->n = 0;
  H->all_converged = 1;
  while (ps_path_test(&p) == PS_PATH_CONTINUE && H->n < 256) {
    if (ps_path_iterate(&p, &ctx)) die_ctx("increment", &ctx);
    if (p.end) break;
    H->all_converged &= p.last.converged;
    state *x = &H->st[H->n++];
    measure(pb, s, sig, x);
    if (x->strain > strain_end) break;
  }
  H->end = p.end;
  snprintf(H->reason, sizeof H->reason, "%s", p.stop_reason);
  ps_path_free(&p);
  ps_solver_free(s);
  free(sig);
}

/* the plateau: states with strain in [a, b]; mean interior stress, its
 * relative spread, the load factor's relative change */
static int plateau(const history *H, double a, double b, double *mean, double *spread,
                   double *dlambda) {
  double lo = INFINITY, hi = -INFINITY, s = 0, l0 = NAN, l1 = NAN;
  int n = 0;
  for (int j = 0; j < H->n; j++) {
    const state *x = &H->st[j];
    if (x->strain < a || x->strain > b) continue;
    s += x->sig;
    lo = fmin(lo, x->sig);
    hi = fmax(hi, x->sig);
    if (n == 0) l0 = x->lambda;
    l1 = x->lambda;
    n++;
  }
  *mean = n ? s / n : NAN;
  *spread = n ? (hi - lo) / *mean : NAN;
  *dlambda = n ? (l1 - l0) / l0 : NAN;
  return n;
}

int main(void) {
  gsl_set_error_handler_off();
  printf("t430: plastic collapse of a strip under uniaxial tension (arc-length)\n");
  /* (a) the continuum */
  gsl_integration_workspace *ws = gsl_integration_workspace_alloc(200);
  gsl_function fc = {abs_cos2, NULL};
  double mean_abs, err;
  gsl_integration_qags(&fc, 0, 2 * M_PI, 1e-13, 1e-12, 200, ws, &mean_abs, &err);
  gsl_integration_workspace_free(ws);
  ps_problem pb;
  setup_strip(&pb, "stress", "deviatoric", "arc_length");
  double G = pb.mat.G, Gc = 4 * G, sy = E_MOD * EY;
  double c_iso = 2 * Gc * EY * mean_abs / sy; /* N G(N+2) eps_y <|cos 2t|> */
  ps_check_rel(c_iso, 16 * G * EY / M_PI / sy, 1e-10,
               "continuum, isochoric flow: N G(N+2) eps_y <|cos 2 theta|> (GSL) = 16 G eps_y / pi");
  gsl_function fz = {zone_edge, NULL};
  double t0 = brent(&fz, 0.8, 1.5);
  double c_kc0 = 8 * G * EY * (4 * t0 / M_PI - 1) / sy;
  printf("  closed forms / sigma_y: isochoric %.6f (6/pi = %.6f), total in plane stress at nu = "
         "1/3 %.6f (theta0 = %.6f, lateral flow ratio %.4f)\n",
         c_iso, 6 / M_PI, c_kc0, t0, 1 / (tan(t0) * tan(t0)));
  /* (b) the lattice */
  family F;
  central_family(&pb, &F);
  double d_iso = lattice_isochoric(&F, Gc) / sy, d_kc0 = lattice_total_kc0(&F, Gc) / sy;
  printf("  lattice sums / sigma_y (%d arms of an interior particle): isochoric %.6f (%+.2f%%), "
         "total in plane stress %.6f (%+.2f%%)\n",
         F.n, d_iso, 100 * (d_iso / c_iso - 1), d_kc0, 100 * (d_kc0 / c_kc0 - 1));
  ps_problem_free(&pb);

  /* the runs */
  const struct {
    const char *plane, *rule;
    int kc0;
  } runs[] = {{"stress", "deviatoric", 0}, {"strain", "deviatoric", 0}, {"strain", "total", 0},
              {"stress", "total", 1}};
  static history H;
  double plateau_kc0 = NAN;
  int n_kc0 = 0;
  for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
    char what[200];
    setup_strip(&pb, runs[r].plane, runs[r].rule, "arc_length");
    run(&pb, ps_step_control_arc_length, 7.0, &H);
    double c = runs[r].kc0 ? c_kc0 : c_iso, dd = runs[r].kc0 ? d_kc0 : d_iso;
    double mean, spread, dl;
    int n = plateau(&H, 5.0, 7.5, &mean, &spread, &dl);
    printf("  %s, plane %s: %d increments to strain %.2f eps_y (load factor %.5f); plateau "
           "5-7 eps_y: %d states, interior sigma_xx %.5f sigma_y (sigma_yy %+.5f), spread "
           "%.2e, load factor change %+.2e\n",
           runs[r].rule, runs[r].plane, H.n, H.n ? H.st[H.n - 1].strain : 0,
           H.n ? H.st[H.n - 1].lambda : 0, n, mean, H.n ? H.st[H.n - 1].syy : 0, spread, dl);
    for (int j = 0; j < H.n; j += 4)
      printf("    strain %6.3f eps_y  load factor %.5f  interior sigma_xx %.5f\n", H.st[j].strain,
             H.st[j].lambda, H.st[j].sig);
    snprintf(what, sizeof what, "%s, plane %s: arc-length converged to 7 eps_y along the "
             "plateau (%d increments)", runs[r].rule, runs[r].plane, H.n);
    ps_check(H.all_converged && H.n > 0 && H.st[H.n - 1].strain > 7.0 && n >= 3, "%s", what);
    snprintf(what, sizeof what, "%s, plane %s: interior stress constant from 5 to 7 eps_y",
             runs[r].rule, runs[r].plane);
    ps_check_le(spread, 0.005, what);
    snprintf(what, sizeof what, "%s, plane %s: load factor constant from 5 to 7 eps_y",
             runs[r].rule, runs[r].plane);
    ps_check_le(fabs(dl), 0.02, what);
    snprintf(what, sizeof what, "%s, plane %s: plateau vs the closed form", runs[r].rule,
             runs[r].plane);
    ps_check_rel(mean, c, 0.01, what);
    snprintf(what, sizeof what, "%s, plane %s: plateau vs the lattice sum", runs[r].rule,
             runs[r].plane);
    ps_check_rel(mean, dd, 0.01, what);
    if (runs[r].kc0) {
      plateau_kc0 = H.n ? H.st[H.n - 1].lambda : NAN;
      n_kc0 = n;
    }
    ps_problem_free(&pb);
  }

  /* (iii) load control on the same strip (total, plane stress), in steps
   * of 0.025 to max_load 1.35: the increment from 1.325 (below the
   * plateau) to 1.35 (above it) */
  setup_strip(&pb, "stress", "total", "load");
  pb.cs.path.load_step = 0.025;
  pb.cs.path.max_load = 1.35;
  run(&pb, ps_step_control_load, 1e9, &H);
  double jump = H.n > 1 ? H.st[H.n - 1].strain - H.st[H.n - 2].strain : 0;
  double before = 0;
  for (int j = 1; j + 1 < H.n; j++) before = fmax(before, H.st[j].strain - H.st[j - 1].strain);
  printf("  load control (total, plane stress): end %d (%s) after %d increments; the last, "
         "from load factor %.4f to %.4f (plateau %.5f), strained the grip by %.2f eps_y "
         "(largest before: %.2f eps_y) to %.2f eps_y, interior sigma_xx %.5f sigma_y\n",
         H.end, H.reason, H.n, H.n > 1 ? H.st[H.n - 2].lambda : 0,
         H.n ? H.st[H.n - 1].lambda : 0, plateau_kc0, jump, before,
         H.n ? H.st[H.n - 1].strain : 0, H.n ? H.st[H.n - 1].sig : 0);
  ps_check(H.end == PS_PATH_MAX_LOAD && H.all_converged && H.n > 2 &&
               H.st[H.n - 2].lambda < plateau_kc0 && H.st[H.n - 1].lambda > plateau_kc0,
           "load control: every increment converged, the last one across the plateau load");
  ps_check(jump > 10 && before < 2,
           "load control steps over the plateau: one increment strains the grip by %.1f eps_y "
           "(> 10; arc-length crossed 5-7 eps_y in %d steps)", jump, n_kc0);
  ps_problem_free(&pb);
  return ps_check_summary();
}
