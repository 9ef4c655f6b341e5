/* t350_plate_hole.c: the bond-based model (Fallah et al. 2020) and the
 * plate with a hole, for the bond-based and the virtual-fibre model.
 *
 * (1) Bond-based model on a square lattice (m = 3, plane stress, nu =
 *     1/3, surface correction on), uniform uniaxial strain eps0 = 1e-7:
 *     the Eq. 24 stress of the centre particle is sigma_xx = C11 eps0,
 *     C11 = E / (1 - nu^2), to 1e-5. Closed form: with the correction of
 *     Li & Hao Eq. A.3-A.6, an interior particle's energy under this strain
 *     is the continuum's 1/2 C11 eps0^2 by construction, and its Eq. 24
 *     stress is the derivative of that energy (the tolerance covers the
 *     geometric nonlinearity, O(eps0), and round-off). sigma_yy: the
 *     correction scales the cross term alike, so sigma_yy = C11 eps0
 *     S22/S4 with the lattice sums S of Eq. 7 times Eq. A.2 over the
 *     lattice vectors, summed independently here (1e-5). It is 6% below
 *     the continuum's C12 = nu C11 at m = 3 (reported, not asserted: the
 *     anisotropy of a square lattice, not an error of the code).
 * (2) Patch test of the bond model: an affine field leaves particles more
 *     than two horizons from the edge with zero force (1e-9 of the
 *     median arm force; round-off is ~1e-14). Nearer the edge the
 *     surface correction makes bond constants differ between the two
 *     sides of a particle, so it does not hold there (known, not tested).
 * (3) The plate with a hole of data/cases/plate-hole-{bond,fibre}.yaml
 *     (Fallah Table 1, 101 x 101 spacings): solved through the same
 *     set-up and run code as `peristatic run`, stresses by Eq. 24:
 *     - equilibrium: the mean sigma_xx over a column of particles (a cut
 *       through the plate away from the hole) equals p to 1e-4 (the column
 *       mean of Eq. 24 is the cut traction exactly for a field uniform
 *       along x; the variation of this field across a horizon adds a small
 *       term, 4e-6 measured next to the clamp);
 *     - sigma_xx along the vertical section through the hole centre, from
 *       one horizon plus two spacings off the hole edge to r = 4R, against
 *       Kirsch (Eq. 30): ratio in [0.98, 1.053] for the bond model: 2%
 *       for the discretisation (the paper reports 1.19% one horizon from
 *       the hole) and +3.3% for the finite plate (converged FE of this
 *       plate gives SCF 3.098 against Kirsch's 3, MODEL-NOTES); the
 *       fibre model is allowed [0.98, 1.10]: the same plus the fibre
 *       network's lattice-sum modulus error (up to 7% on regular lattices,
 *       doc/verification.md), which changes a clamped plate's stresses;
 *     - sigma_yy along the horizontal section over the same range within
 *       0.03 p of Kirsch (absolute: Kirsch crosses zero there; 0.033 p is
 *       the finite-plate allowance above);
 *     - the largest sigma_xx on the vertical section is at the particle
 *       nearest the hole and exceeds Kirsch there (the skin effect of PD
 *       raises it, Fallah section 5.1: PD 3.4 against FE about 3).
 * (4) The ordinary state-based model (state.c): the Eq. 24 stress of a
 *     square-lattice interior under uniaxial strain equals the lattice's
 *     own C11, C12 from sums over the lattice vectors written out here
 *     (1e-5; their distance from the continuum is reported); Poisson's
 *     ratio of a plane-stress strip in uniaxial stress (nu = 0.1 .. 0.4)
 *     equals the lattice's C12/C11 within 0.01 (free edges and grips, as
 *     t500), reported against the input; and the plate with a hole with
 *     the fibre model's band (no surface correction: the bond model
 *     without one measures 1.06-1.09, doc/verification.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common.h"

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t350: %s failed: %s\n", what, ctx->msg);
  exit(2);
}

static int cmp_d(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* A square-lattice box of nx x ny particles, spacing d, with uniform
 * sizes d and the arms within reach spacings (the set-up of the lattice
 * models), and an elastic material with horizon m d. */
static void lattice_box(ps_int nx, ps_int ny, double d, double reach, ps_particles *P,
                        ps_network *net) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_int counts[3] = {nx, ny, 1};
  ps_kernel K;
  if (ps_geom_box(P, 2, counts, d, "square", 0.0, 1, &ctx)) die_ctx("box", &ctx);
  for (ps_int a = 0; a < P->n; a++) P->h[a] = d;
  if (ps_kernel_init(&K, 2, 2, reach, &ctx) || ps_network_build(net, P, &K, NULL, 0, &ctx))
    die_ctx("network", &ctx);
}

static ps_material lattice_material(double nu, int plane, double m, double d) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_material mat = tc_material(nu, plane);
  mat.plastic = 0;
  mat.horizon = m * d;
  mat.spacing = d;
  if (ps_material_finish(&mat, 2, &ctx)) die_ctx("material", &ctx);
  return mat;
}

/* Eq. 24 stress (xx, yy) of the centre particle of an n x n lattice box
 * with every particle displaced by the uniaxial strain u_x = eps0 x
 * (u, sig: work arrays of 2 and 4 values per particle) */
static void centre_stress_uniaxial(tc_evaluator *ev, const ps_particles *P,
                                   const ps_network *net, ps_int n, double eps0, double *u,
                                   double *sig, double out[2]) {
  for (ps_int a = 0; a < P->n; a++) {
    u[2 * a] = eps0 * P->x[2 * a];
    u[2 * a + 1] = 0.0;
  }
  tc_eval(ev, P, u);
  ps_post_stress_tensor(P, net, ev->sys.T, ev->sys.q, sig);
  ps_int c = (n / 2) * n + n / 2; /* the centre particle */
  out[0] = sig[4 * c];
  out[1] = sig[4 * c + 3];
}

/* (1) and (2): a square-lattice box, all particles displaced affinely */
static void bond_lattice(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  const ps_int n = 25;
  const double d = 1e-3, E = 1e9, nu = 1.0 / 3.0, m = 3.0, eps0 = 1e-7;
  ps_particles P;
  ps_network net;
  lattice_box(n, n, d, m * (1 + 1e-9), &P, &net);
  ps_material mat = lattice_material(nu, PS_PLANE_STRESS, m, d);
  mat.E = E;
  mat.surface_correction = 1;
  if (ps_material_finish(&mat, 2, &ctx)) die_ctx("material", &ctx);
  tc_evaluator ev;
  tc_evaluator_create_model(&ev, ps_model_bond, &P, &net, &mat);
  double *u = calloc((size_t)(2 * P.n), sizeof *u), *sig = malloc(4 * P.n * sizeof *sig);
  double sc[2];
  centre_stress_uniaxial(&ev, &P, &net, n, eps0, u, sig, sc);
  double C11 = E / (1 - nu * nu), C12 = nu * C11;
  /* the lattice's own cross term, summed here independently over the
   * lattice vectors: sigma_yy = C11 eps0 S22 / S4 with S = sum c(xi) v(xi)
   * xi n_x^2 n_y^2 (S22) or n_x^4 (S4) */
  double S4 = 0, S22 = 0;
  for (int i = -4; i <= 4; i++)
    for (int j = -4; j <= 4; j++) {
      double xi = d * hypot(i, j);
      if ((i == 0 && j == 0) || xi > m * d) continue;
      double v = xi <= (m - 0.5) * d ? 1.0 : 0.5 + (m * d - xi) / d; /* Eq. A.2 */
      double w = (1 - xi / (m * d)) * v * xi, nx = d * i / xi, ny = d * j / xi;
      S4 += w * nx * nx * nx * nx;
      S22 += w * nx * nx * ny * ny;
    }
  printf("# bond, uniaxial strain: sigma_xx / (C11 eps0) = %.10f, sigma_yy / (C12 eps0) "
         "= %.5f (the square lattice's cross term, m = 3: 3 S22/S4 = %.5f; the continuum "
         "and Cauchy's relation give 1)\n",
         sc[0] / (C11 * eps0), sc[1] / (C12 * eps0), 3 * S22 / S4);
  ps_check_rel(sc[0], C11 * eps0, 1e-5, "bond: sigma_xx = C11 eps0 (surface correction)");
  ps_check_rel(sc[1], C11 * eps0 * S22 / S4, 1e-5,
               "bond: sigma_yy = C11 eps0 S22/S4 (lattice sum)");

  /* (2) patch test: general affine field with a rotation */
  const double H[4] = {2e-4, -3e-4, 5e-4, -1e-4};
  for (ps_int a = 0; a < P.n; a++)
    for (int i = 0; i < 2; i++)
      u[2 * a + i] = H[2 * i] * P.x[2 * a] + H[2 * i + 1] * P.x[2 * a + 1];
  tc_eval(&ev, &P, u);
  double *Tabs = malloc(net.n_arm * sizeof *Tabs);
  for (ps_int i = 0; i < net.n_arm; i++) Tabs[i] = fabs(ev.sys.T[i]);
  qsort(Tabs, (size_t)net.n_arm, sizeof *Tabs, cmp_d);
  double Tmed = Tabs[net.n_arm / 2], worst = 0;
  double lo[2] = {0, 0}, hi[2] = {n * d, n * d};
  ps_int n_int = 0;
  for (ps_int a = 0; a < P.n; a++) {
    if (tc_dist_to_box_face(&P.x[2 * a], lo, hi, 2) < 2 * m * d + 0.5 * d) continue;
    n_int++;
    worst = fmax(worst, hypot(ev.f[2 * a], ev.f[2 * a + 1]) / Tmed);
  }
  ps_check(n_int > 50, "bond patch: %lld interior particles", (long long)n_int);
  ps_check_le(worst, 1e-9, "bond patch: interior force / median arm force");
  free(Tabs);
  free(u);
  free(sig);
  tc_evaluator_free(&ev);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* Lattice sums of the state model over the square lattice vectors within
 * delta + dx/2 (influence delta/xi, partial volumes, cell area dx^2):
 * C11 = 2 a d^2 S1^2 + 2 b S4, C12 = 2 a d^2 S1^2 + 2 b S22 in plane
 * stress/strain (2D constants of state.c, written out again here). */
static void state_lattice_moduli(const ps_material *mat, double dx, double m, double *C11,
                                 double *C12) {
  double delta = m * dx, S1 = 0, S4 = 0, S22 = 0;
  for (int i = -5; i <= 5; i++)
    for (int j = -5; j <= 5; j++) {
      double xi = dx * hypot(i, j);
      if ((i == 0 && j == 0) || xi >= delta + 0.5 * dx) continue;
      double v = xi <= delta - 0.5 * dx ? 1.0 : 0.5 + (delta - xi) / dx;
      double w = delta / xi * v * dx * dx, nx = dx * i / xi, ny = dx * j / xi;
      S1 += w * xi * nx * nx;
      S4 += w * xi * xi * nx * nx * nx * nx;
      S22 += w * xi * xi * nx * nx * ny * ny;
    }
  double a = 0.5 * (mat->K - 2 * mat->G), b = 6 * mat->G / (M_PI * pow(delta, 4));
  double d = 2 / (M_PI * pow(delta, 3));
  *C11 = 2 * a * d * d * S1 * S1 + 2 * b * S4;
  *C12 = 2 * a * d * d * S1 * S1 + 2 * b * S22;
}

/* (4) the state model: Eq. 24 stress of a lattice interior under uniaxial
 * strain against the lattice sums, and Poisson's ratio of a strip */
static void state_lattice(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  const ps_int n = 25;
  const double d = 1e-3, m = 3.0, eps0 = 1e-7;
  ps_particles P;
  ps_network net;
  lattice_box(n, n, d, m + 0.5 * (1 - 1e-9), &P, &net);
  ps_material mat = lattice_material(0.3, PS_PLANE_STRAIN, m, d);
  tc_evaluator ev;
  tc_evaluator_create_model(&ev, ps_model_state, &P, &net, &mat);
  double *u = calloc((size_t)(2 * P.n), sizeof *u), *sig = malloc(4 * P.n * sizeof *sig);
  double sc[2];
  centre_stress_uniaxial(&ev, &P, &net, n, eps0, u, sig, sc);
  double C11, C12;
  state_lattice_moduli(&mat, d, m, &C11, &C12);
  double C11c = mat.K + mat.G, C12c = mat.K - mat.G; /* 2D continuum */
  printf("# state, plane strain nu 0.3, uniaxial strain: sigma_xx/(C11 eps0) = %.8f, "
         "sigma_yy/(C12 eps0) = %.8f against the lattice sums; the lattice's C11, C12 are "
         "%.4f, %.4f of the continuum's\n",
         sc[0] / (C11 * eps0), sc[1] / (C12 * eps0), C11 / C11c, C12 / C12c);
  ps_check_rel(sc[0], C11 * eps0, 1e-5, "state: sigma_xx = lattice C11 eps0");
  ps_check_rel(sc[1], C12 * eps0, 1e-5, "state: sigma_yy = lattice C12 eps0");
  free(u);
  free(sig);
  tc_evaluator_free(&ev);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* Poisson's ratio of the state model: a plane-stress strip 60 x 20
 * spacings pulled by grips (fictitious layers, x only, one row held in y)
 * in uniaxial stress; -eps_yy/eps_xx of the least-squares strain of the
 * middle third against the lattice's own C12/C11 (plane stress: uniaxial
 * stress gives nu = C12/C11 on a square lattice) within 0.01 (the strip's
 * free edges and grips, as t500), and reported against the input nu */
static void state_poisson(double nu) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  const double d = 1e-3, m = 3.0, eps = 1e-4;
  const ps_int nx = 66, ny = 20; /* 3 grip columns each side */
  ps_particles P;
  ps_network net;
  lattice_box(nx, ny, d, m + 0.5 * (1 - 1e-9), &P, &net);
  ps_material mat = lattice_material(nu, PS_PLANE_STRESS, m, d);
  unsigned char *fixed = calloc((size_t)(2 * P.n), 1), *mask = calloc((size_t)P.n, 1);
  double *ubar = calloc((size_t)(2 * P.n), sizeof *ubar);
  double L = nx * d;
  for (ps_int a = 0; a < P.n; a++) {
    double x = P.x[2 * a], y = P.x[2 * a + 1];
    int left = x < 3 * d, right = x > L - 3 * d;
    if (left || right) {
      fixed[2 * a] = 1;
      ubar[2 * a] = eps * x;
      if (left && fabs(y - 10.5 * d) < 0.25 * d) fixed[2 * a + 1] = 1; /* no rigid y */
    }
    mask[a] = x > L / 3 && x < 2 * L / 3 && y > 3 * d && y < (ny - 3) * d;
  }
  ps_solver *s = NULL;
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  if (ps_solver_create(&s, &P, &net, ps_model_state, &mat, fixed, ubar, &o, &ctx) ||
      ps_solver_step(s, 1.0, &ctx) != PS_OK)
    die_ctx("solve", &ctx);
  double e[4], C11, C12;
  if (ps_post_fit_strain(&P, ps_solver_u(s), mask, e, &ctx)) die_ctx("fit", &ctx);
  state_lattice_moduli(&mat, d, m, &C11, &C12);
  double nu_meas = -e[3] / e[0];
  printf("# state, plane stress, input nu %.2f: strip nu = %.4f; the lattice's C12/C11 = "
         "%.4f\n", nu, nu_meas, C12 / C11);
  char what[120];
  snprintf(what, sizeof what, "state: strip Poisson ratio (input %.1f) vs the lattice's C12/C11",
           nu);
  ps_check(fabs(nu_meas - C12 / C11) <= 0.01, "%s: %.4f vs %.4f", what, nu_meas, C12 / C11);
  ps_solver_free(s);
  free(fixed);
  free(mask);
  free(ubar);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* Kirsch (Eq. 30) for remote sigma0 = 1 along x: sigma_xx on x = cx at
 * distance r (theta = 90 deg) and sigma_yy on y = cy (theta = 0) */
static double kirsch_xx_vertical(double r, double R) {
  double q = R * R / (r * r);
  return 1 + 0.5 * q + 1.5 * q * q;
}
static double kirsch_yy_horizontal(double r, double R) {
  double q = R * R / (r * r);
  return 0.5 * ((1 + q) - (1 + 3 * q * q));
}

/* the plate at n x n spacings (the case files have n = 101) */
static void plate_n(const char *model, double ratio_hi, int n);
static void plate(const char *model, double ratio_hi) { plate_n(model, ratio_hi, 0); }

static void plate_n(const char *model, double ratio_hi, int n) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 1 : 0;
  const char *srcdir = getenv("srcdir") ? getenv("srcdir") : ".";
  char path[1024];
  snprintf(path, sizeof path, "%s/data/cases/plate-hole-%s.yaml", srcdir, model);
  ps_case cs;
  ps_problem pb;
  ps_run_result res;
  ps_solver *s = NULL;
  ps_case_defaults(&cs);
  if (ps_case_load(&cs, path, &ctx)) die_ctx("case", &ctx);
  if (n > 0) { /* refine: keep the plate, its fictitious layer and loads */
    cs.spacing = 0.05 / n;
    cs.counts[0] = n + 3;
    cs.counts[1] = n;
    cs.origin[0] = -3 * cs.spacing;
    cs.bc[1].sel.lo[0] = 0.05 - cs.spacing;
  }
  if (ps_problem_setup(&pb, &cs, &ctx)) die_ctx("setup", &ctx);
  if (ps_run_keep(&pb, INFINITY, NULL, &res, &s, &ctx)) die_ctx("run", &ctx);
  const ps_particles *P = &pb.P;
  double *sig = malloc(4 * P->n * sizeof *sig);
  ps_post_stress_tensor(P, &pb.net, ps_solver_arm_tension(s), ps_solver_arm_direction(s),
                        sig);
  const double p = cs.bc[1].traction[0], dx = cs.spacing, R = cs.holes[0][2];
  const double cx = cs.holes[0][0], cy = cs.holes[0][1], delta = 3 * dx;
  /* equilibrium on two cuts, left and right of the hole */
  const double cuts[2] = {0.0125, 0.0375};
  for (int k = 0; k < 2; k++) {
    double sum = 0;
    ps_int cnt = 0, col = (ps_int)floor((cuts[k] - cs.origin[0]) / dx);
    double xc = cs.origin[0] + (col + 0.5) * dx;
    for (ps_int a = 0; a < P->n; a++)
      if (fabs(P->x[2 * a] - xc) < 0.25 * dx) {
        sum += sig[4 * a];
        cnt++;
      }
    char what[160];
    snprintf(what, sizeof what, "%s: mean sigma_xx / p on the cut x = %.4f m (%lld particles)",
             model, xc, (long long)cnt);
    ps_check_rel(sum / cnt / p, 1.0, 1e-4, what);
  }
  /* the sections */
  double worst_lo = INFINITY, worst_hi = -INFINITY, worst_yy = 0, r_first = INFINITY;
  double s_first = 0, s_max = -INFINITY, r_max = 0;
  ps_int n_sec = 0;
  for (ps_int a = 0; a < P->n; a++) {
    double x = P->x[2 * a], y = P->x[2 * a + 1];
    if (fabs(x - cx) < 0.25 * dx && y > cy) { /* vertical section, above the hole */
      double r = y - cy, sxx = sig[4 * a] / p;
      if (r < r_first) {
        r_first = r;
        s_first = sxx;
      }
      if (sxx > s_max) {
        s_max = sxx;
        r_max = r;
      }
      if (r - R >= delta + 2 * dx && r <= 4 * R) {
        double ratio = sxx / kirsch_xx_vertical(r, R);
        worst_lo = fmin(worst_lo, ratio);
        worst_hi = fmax(worst_hi, ratio);
        n_sec++;
      }
    }
    if (fabs(y - cy) < 0.25 * dx && x > cx) { /* horizontal section, right */
      double r = x - cx;
      if (r - R >= delta + 2 * dx && r <= 4 * R)
        worst_yy = fmax(worst_yy, fabs(sig[4 * a + 3] / p - kirsch_yy_horizontal(r, R)));
    }
  }
  printf("# %s, %.0f spacings: %lld particles, %lld arms, %.1f s; nearest the hole r = %.3f R: sigma_xx/p = %.4f "
         "(Kirsch there %.4f; SCF at r = R: Kirsch 3, FE 3.098, Fallah PD 3.4)\n",
         model, 0.05 / dx, (long long)P->n, (long long)pb.net.n_arm, res.wall, r_first / R, s_first,
         kirsch_xx_vertical(r_first, R));
  printf("# %s: sigma_xx / Kirsch on the vertical section, %lld particles from r = R + "
         "delta + 2 dx to 4R: %.4f .. %.4f; |sigma_yy/p - Kirsch| <= %.4f\n",
         model, (long long)n_sec, worst_lo, worst_hi, worst_yy);
  ps_check(n_sec >= 5, "%s: %lld section particles compared", model, (long long)n_sec);
  ps_check(worst_lo >= 0.98 && worst_hi <= ratio_hi,
           "%s: sigma_xx / Kirsch in [0.98, %.3f] on the vertical section (%.4f .. %.4f)",
           model, ratio_hi, worst_lo, worst_hi);
  char what[160];
  snprintf(what, sizeof what, "%s: sigma_yy on the horizontal section, |. - Kirsch| / p",
           model);
  ps_check_le(worst_yy, 0.03, what);
  ps_check(r_max == r_first && s_first > kirsch_xx_vertical(r_first, R),
           "%s: sigma_xx peaks next to the hole (r = %.3f R) above Kirsch", model,
           r_max / R);
  free(sig);
  ps_solver_free(s);
  ps_problem_free(&pb);
}

int main(void) {
  bond_lattice();
  plate("bond", 1.053);
  plate("fibre", 1.10);
  state_lattice();
  for (int i = 1; i <= 4; i++) state_poisson(0.1 * i);
  plate("state", 1.10);
  /* make check-long: the bond model refined to the paper's grid (601
   * spacings: 361k particles, ~7 GB) */
  if (getenv("PS_CHECK_LONG")) {
    const int ns[3] = {201, 401, 601};
    for (int i = 0; i < 3; i++) plate_n("bond", 1.053, ns[i]);
  }
  return ps_check_summary();
}
