/* t425_dissipation.c: softening bond arms (material.fracture.
 * softening_ratio) and dissipation control (path.control: dissipation,
 * issue 20; ps_solver_dissipation_step, src/path/control_dissipation.c).
 *
 * (1) The softening arm law against its closed forms, on a plate of bond
 *     arms stretched uniformly: (a) the incremental energy is the
 *     potential of the arm forces (central differences of the energy
 *     against the residual, 1e-6 relative: second-order differences of a
 *     piecewise quadratic); (b) an arm stretched to s1 = r s0 has
 *     dissipated 1/2 k dl0 dl1 (the area under its envelope, 1e-12) and
 *     carries nothing; (c) unloading follows the secant to the origin.
 * (2) The dissipation constraint's linearisation (ps_pd_dissipation's
 *     gradient) against central differences of D along random directions
 *     from a state with loading, unloading and elastic arms, 1e-6
 *     relative; (2b) the softening arms' tangent likewise; (2c) the fibre
 *     model's plastic dissipation (total reading) likewise.
 * (3) A notched plate of softening arms under dissipation control: every
 *     increment converges; once dissipation starts each increment
 *     dissipates its tau (the total never falls); the energy balance
 *     W - Psi = D holds within 1% (W the trapezoid sum of reaction x grip
 *     displacement along the converged states, Psi the stored energy, D
 *     the dissipated energy: an independent check of the path being a
 *     sequence of equilibrium states and of the bookkeeping; the 1% is
 *     the trapezoid rule's error on the curved softening branch).
 * (4) The same plate with path.load_until_unstable: the increments are
 *     load control's (each load factor a multiple of load_step and the
 *     boundary stress that of a load-controlled run at that load, 1e-9
 *     relative: the same solves) until a load increment fails or its
 *     rounds break more than path.unstable_arms arms; then the path goes
 *     back to the last settled state and goes on under dissipation
 *     control to below 10% of the peak, every increment converged, with
 *     the energy balance of (3).
 * (5) The solver's snapshot (the path's way back): a state taken, a step
 *     taken from it and committed, the state put back equals the one
 *     taken, bit for bit.
 * (6) The run's reductions go through ctx->comm (ps_util.h; step 1 of
 *     doc/design-distributed.md): the path of (4) with a comm of one
 *     process whose operations are the identity but count their calls
 *     gives every increment's load factor, boundary stress, stored and
 *     dissipated energy and broken arms bit for bit as with no comm, and
 *     the residual norms (the one reduction of two values per Newton
 *     iterate) and the energies and slopes (one value) reach the comm at
 *     least once per Newton iteration each. The operations on several MPI
 *     processes are checked by tests/comm_check under t990_petsc.sh. */
#include "check.h"
#include "common.h"
#include "nonlinear/problem_pd.h"
#include "path/ps_path.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t425: %s failed: %s\n", what, ctx->msg);
  printf("FAIL: %s\n", what);
  exit(2);
}

static void setup_text(ps_problem *pb, const char *path, const char *text) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_case cs;
  FILE *f = fopen(path, "w");
  if (!f || fputs(text, f) < 0 || fclose(f)) {
    fprintf(stderr, "t425: cannot write %s\n", path);
    exit(2);
  }
  ps_case_defaults(&cs);
  if (ps_case_load(&cs, path, &ctx)) die_ctx("case", &ctx);
  if (ps_problem_setup(pb, &cs, &ctx)) die_ctx("setup", &ctx);
  remove(path);
}

/* a 20 x 20 plate (1 mm) of constant-micromodulus bond arms with s0 =
 * 1e-3, s1 = 5e-3; an edge crack from the left to x = 14 mm at mid
 * height; bottom grip fixed, top grip pulled in y; path lines appended */
static void plate_text(char *buf, size_t len, const char *path) {
  snprintf(buf, len,
           "name: t425\n"
           "geometry:\n  type: box\n  dim: 2\n  counts: [20, 20]\n  spacing: 1.0e-3\n"
           "  cracks: [[[-0.001, 0.01], [0.014, 0.01]]]\n"
           "material:\n  model: bond\n  E: 72.0e9\n  nu: 0.3333333333333333\n"
           "  plane: stress\n  horizon_factor: 3.015\n  micromodulus: constant\n"
           "  partial_volumes: false\n  surface_correction: false\n"
           "  fracture: {critical_stretch: 1.0e-3, softening_ratio: 5}\n"
           "loading:\n  type: boundary\n  boundary:\n"
           "    - select: {y_max: 0.003}\n      fix: [x, y]\n"
           "    - select: {y_min: 0.017}\n      fix: [x]\n      displace: {y: 1.0e-4}\n"
           "      measure: true\n"
           "solver:\n  tolerance: 1.0e-10\n"
           "path:\n%s",
           path);
}

/* u = eps_x x + eps_y y (+ noise), free and prescribed dofs alike */
static void affine(const ps_problem *pb, double ex, double ey, double noise, gsl_rng *r,
                   double *u) {
  for (ps_int a = 0; a < pb->P.n; a++) {
    u[2 * a] = ex * pb->P.x[2 * a] + noise * (gsl_rng_uniform(r) - 0.5);
    u[2 * a + 1] = ey * pb->P.x[2 * a + 1] + noise * (gsl_rng_uniform(r) - 0.5);
  }
}

/* |g . e - (D(u + h e) - D(u - h e)) / 2h| / |g . e| with g the gradient
 * of ps_pd_dissipation at u (f, g, w: work of n_dof) */
static double gradient_error(ps_pd *pd, const double *u, const double *e, double h, double *f,
                             double *g, double *w) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_nl_problem p = ps_pd_problem(pd);
  ps_int nd = p.n_dof;
  double E, ge = 0;
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  ps_pd_dissipation(pd, g);
  for (ps_int j = 0; j < nd; j++) ge += g[j] * e[j];
  for (ps_int j = 0; j < nd; j++) w[j] = u[j] + h * e[j];
  p.ops->evaluate(p.data, w, f, &E, 0, &ctx);
  double Dp = ps_pd_dissipation(pd, NULL);
  for (ps_int j = 0; j < nd; j++) w[j] = u[j] - h * e[j];
  p.ops->evaluate(p.data, w, f, &E, 0, &ctx);
  double Dm = ps_pd_dissipation(pd, NULL);
  return fabs((Dp - Dm) / (2 * h) - ge) / fabs(ge);
}

static void arm_law(void) {
  ps_problem pb;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  char text[4096];
  plate_text(text, sizeof text, "  load_step: 0.05\n");
  setup_text(&pb, "t425-law.yaml", text);
  ps_pd *pd = NULL;
  unsigned char *none = calloc((size_t)pb.P.n * 2, 1);
#define FRESH_PD()                                                                             \
  do {                                                                                         \
    ps_pd_free(pd);                                                                            \
    pd = NULL;                                                                                 \
    if (ps_pd_create(&pd, &pb.P, &pb.net, ps_model_type_find("bond"), &pb.mat, none, 0, 0,    \
                     &ctx))                                                                    \
      die_ctx("pd", &ctx);                                                                     \
  } while (0)
  FRESH_PD();
  ps_nl_problem p = ps_pd_problem(pd);
  ps_int nd = p.n_dof;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f);
  double *g = calloc((size_t)nd, sizeof *g), *e = calloc((size_t)nd, sizeof *e);
  double *w = calloc((size_t)nd, sizeof *w), E;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 425);
  const ps_network *net = &pb.net;
  const double s0 = 1e-3, s1 = 5e-3, h = 1e-3 * 1e-7; /* h: 1e-7 of a cell */

  /* (1a) energy against forces, from a committed damaged state (2.5 s0
   * in x, s0/2 in y: softening, unloading and elastic arms) */
  affine(&pb, 2.5 * s0, 0.5 * s0, 0.0, r, u);
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  ps_pd_commit(pd);
  double worst = 0;
  for (int trial = 0; trial < 3; trial++) {
    affine(&pb, (2.5 - 0.3 * trial) * s0 + 1e-4 * trial, 0.6 * s0, 2e-7, r, u);
    for (ps_int j = 0; j < nd; j++) e[j] = gsl_rng_uniform(r) - 0.5;
    p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
    double fe = 0;
    for (ps_int j = 0; j < nd; j++) fe += f[j] * e[j];
    double Ep, Em;
    for (ps_int j = 0; j < nd; j++) w[j] = u[j] + h * e[j];
    p.ops->evaluate(p.data, w, f, &Ep, 0, &ctx);
    for (ps_int j = 0; j < nd; j++) w[j] = u[j] - h * e[j];
    p.ops->evaluate(p.data, w, f, &Em, 0, &ctx);
    double fd = (Ep - Em) / (2 * h), rel = fabs(fd - fe) / fabs(fe);
    if (rel > worst) worst = rel;
  }
  printf("  (1a) incremental energy vs forces: worst relative difference %.2e\n", worst);
  ps_check(worst < 1e-6, "softening arms: the energy is the potential of the forces");

  /* (1b) stretched to s1 everywhere in x: the arms along x dissipated
   * 1/2 k dl0 dl1 and carry nothing */
  FRESH_PD();
  p = ps_pd_problem(pd);
  affine(&pb, s1 * 1.2, 0.0, 0.0, r, u);
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  double dmax = 0;
  ps_int n_x = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    double dy = pb.P.x[2 * net->b[i] + 1] - pb.P.x[2 * net->a[i] + 1];
    if (fabs(dy) > 1e-12 || !(pd->model.arm_k[i] > 0)) continue;
    double dD, r0 = net->r0[i], k = pd->model.arm_k[i];
    double D = pd->model.type->arm_dissipation(&pd->model, &pd->st_saved, &pd->st, i,
                                               pd->sys.dl[i], &dD);
    double D0 = pd->model.type->arm_dissipation(&pd->model, &pd->st_saved, &pd->st_saved, i,
                                                0.0, &dD);
    double want = 0.5 * k * (s0 * r0) * (s1 * r0);
    double d = fabs(D - D0 - want) / want + fabs(pd->sys.T[i]) / (k * s0 * r0);
    if (d > dmax) dmax = d;
    n_x++;
  }
  printf("  (1b) %lld arms along x past s1: dissipated vs 1/2 k dl0 dl1, force: worst %.2e\n",
         (long long)n_x, dmax);
  ps_check(n_x > 0 && dmax < 1e-12, "a fully softened arm dissipated its envelope's area");

  /* (1c) from 2 s0 back to s0: the secant T_env(2 s0) / (2 s0) */
  FRESH_PD();
  p = ps_pd_problem(pd);
  affine(&pb, 2 * s0, 0.0, 0.0, r, u);
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  ps_pd_commit(pd);
  affine(&pb, s0, 0.0, 0.0, r, u);
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  double umax = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    double dy = pb.P.x[2 * net->b[i] + 1] - pb.P.x[2 * net->a[i] + 1];
    if (fabs(dy) > 1e-12 || !(pd->model.arm_k[i] > 0)) continue;
    double k = pd->model.arm_k[i], r0 = net->r0[i];
    double env = k * s0 * r0 * (s1 - 2 * s0) / (s1 - s0); /* T_env at 2 s0 */
    double want = env / 2.0;                             /* secant at s0: half of it */
    double d = fabs(pd->sys.T[i] - want) / want;
    if (d > umax) umax = d;
  }
  printf("  (1c) unloading on the secant: worst relative difference %.2e\n", umax);
  ps_check(umax < 1e-6, "a softened arm unloads towards the origin");

  /* (2) the dissipation's gradient against central differences */
  FRESH_PD();
  p = ps_pd_problem(pd);
  affine(&pb, 2.5 * s0, 0.5 * s0, 0.0, r, u);
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  ps_pd_commit(pd);
  worst = 0;
  for (int trial = 0; trial < 3; trial++) {
    /* no arm within 0.05 s0 of its committed largest stretch, where D
     * has a kink (the lattice diagonals: (ex + ey)/2 against 1.5 s0) */
    affine(&pb, (2.6 + 0.2 * trial) * s0, 0.3 * s0, 2e-9, r, u);
    for (ps_int j = 0; j < nd; j++) e[j] = gsl_rng_uniform(r) - 0.5;
    double rel = gradient_error(pd, u, e, h, f, g, w);
    if (rel > worst) worst = rel;
  }
  printf("  (2) dissipation gradient vs central differences: worst %.2e\n", worst);
  ps_check(worst < 1e-6, "the dissipation constraint's linearisation");

  /* (2b) the tangent (an arm loading at two evaluations in a row: its
   * slope) against central differences of the forces */
  double *Ke = calloc((size_t)nd, sizeof *Ke), *fp = calloc((size_t)nd, sizeof *fp);
  worst = 0;
  for (int trial = 0; trial < 3; trial++) {
    affine(&pb, (2.6 + 0.2 * trial) * s0, 0.4 * s0, 2e-7, r, u);
    for (ps_int j = 0; j < nd; j++) e[j] = gsl_rng_uniform(r) - 0.5;
    p.ops->evaluate(p.data, u, f, &E, 1, &ctx);
    p.ops->evaluate(p.data, u, f, &E, 1, &ctx); /* the loading arms now take their slope */
    ps_system_apply(&pd->sys, e, Ke);
    ps_int na = net->n_arm;
    double *D0 = malloc(na * sizeof *D0), *T1 = malloc(na * sizeof *T1), *l1 = malloc(na * sizeof *l1);
    unsigned char *y0 = malloc(na);
    memcpy(D0, pd->sys.tan.D, na * sizeof *D0);
    memcpy(y0, pd->st.yielding, na);
    for (ps_int j = 0; j < nd; j++) w[j] = u[j] + h * e[j];
    p.ops->evaluate(p.data, w, fp, &E, 0, &ctx);
    memcpy(T1, pd->sys.T, na * sizeof *T1);
    memcpy(l1, pd->sys.dl, na * sizeof *l1);
    for (ps_int j = 0; j < nd; j++) w[j] = u[j] - h * e[j];
    p.ops->evaluate(p.data, w, f, &E, 0, &ctx);
    if (getenv("T425_VERBOSE")) {
      int shown = 0;
      for (ps_int i = 0; i < na && shown < 6; i++) {
        double fdD = (T1[i] - pd->sys.T[i]) / (l1[i] - pd->sys.dl[i]);
        if (fabs(fdD - D0[i]) > 1e-6 * fabs(pd->model.arm_k[i])) {
          printf("    arm %lld: D %g fd %g k %g yielding %d\n", (long long)i, D0[i], fdD,
                 pd->model.arm_k[i], y0[i]);
          shown++;
        }
      }
    }
    free(D0), free(T1), free(l1), free(y0);
    double num = 0, den = 0;
    for (ps_int j = 0; j < nd; j++) {
      double fd = (fp[j] - f[j]) / (2 * h);
      num += (fd - Ke[j]) * (fd - Ke[j]);
      den += Ke[j] * Ke[j];
    }
    if (sqrt(num / den) > worst) worst = sqrt(num / den);
  }
  printf("  (2b) tangent vs central differences of the forces: %.2e\n", worst);
  ps_check(worst < 1e-6, "the softening arms' tangent (slope while loading)");
  free(Ke);
  free(fp);
  gsl_rng_free(r);
  free(u), free(f), free(g), free(e), free(w), free(none);
  ps_pd_free(pd);
  ps_problem_free(&pb);
}

/* (2c) the fibre model's plastic dissipation (total reading): its
 * gradient against central differences, from a committed plastic state
 * loaded further (arms flowing, elastic and unloading ones) */
static void fibre_gradient(void) {
  ps_problem pb;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  setup_text(&pb, "t425-fibre.yaml",
             "name: t425-fibre\n"
             "geometry:\n  type: box\n  dim: 2\n  counts: [12, 12]\n  spacing: 1.0e-3\n"
             "material:\n  model: fibre\n  E: 1.0e9\n  nu: 0.3\n  plane: strain\n"
             "  yield_strain: 1.0e-3\n  yield_rule: total\n"
             "loading:\n  type: boundary\n  boundary:\n"
             "    - select: {x_max: 0.001}\n      fix: [x, y]\n"
             "    - select: {x_min: 0.010}\n      displace: {x: 1.0e-4}\n");
  ps_pd *pd = NULL;
  unsigned char *none = calloc((size_t)pb.P.n * 2, 1);
  if (ps_pd_create(&pd, &pb.P, &pb.net, ps_model_type_find("fibre"), &pb.mat, none, 0, 0, &ctx))
    die_ctx("pd", &ctx);
  ps_nl_problem p = ps_pd_problem(pd);
  ps_int nd = p.n_dof;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f);
  double *g = calloc((size_t)nd, sizeof *g), *e = calloc((size_t)nd, sizeof *e);
  double *w = calloc((size_t)nd, sizeof *w), E, h = 1e-3 * 1e-7, worst = 0, ey = 1e-3;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 4252);
  affine(&pb, 3.0 * ey, -1.0 * ey, 0.0, r, u);
  p.ops->evaluate(p.data, u, f, &E, 0, &ctx);
  ps_pd_commit(pd);
  for (int trial = 0; trial < 3; trial++) {
    affine(&pb, (3.4 + 0.3 * trial) * ey, -1.25 * ey, 2e-9, r, u);
    for (ps_int j = 0; j < nd; j++) e[j] = gsl_rng_uniform(r) - 0.5;
    double rel = gradient_error(pd, u, e, h, f, g, w);
    if (rel > worst) worst = rel;
  }
  printf("  (2c) fibre plastic dissipation gradient vs central differences: worst %.2e\n",
         worst);
  ps_check(worst < 1e-6, "the fibre model's dissipation gradient (total reading)");
  gsl_rng_free(r);
  free(u), free(f), free(g), free(e), free(w), free(none);
  ps_pd_free(pd);
  ps_problem_free(&pb);
}

/* The plate of plate_text with the path lines `path_lines` (written to
 * `file` and read back), its solver on one thread and its path under the
 * case's path.control. */
typedef struct plate_run {
  ps_problem pb;
  ps_solver *s;
  ps_path path;
} plate_run;

static void plate_run_start(plate_run *r, const char *file, const char *path_lines,
                            ps_ctx *ctx) {
  char text[4096];
  plate_text(text, sizeof text, path_lines);
  setup_text(&r->pb, file, text);
  ps_problem *pb = &r->pb;
  ps_solver_opts o = pb->cs.solver;
  o.threads = 1;
  const ps_model_type *bond = ps_model_type_find("bond");
  r->s = NULL;
  if (ps_solver_create(&r->s, &pb->P, &pb->net, bond, &pb->mat, pb->fixed, pb->ubar, &o, ctx))
    die_ctx("solver", ctx);
  ps_path_problem pp = {.P = &pb->P, .net = &pb->net, .model = bond, .mat = &pb->mat,
                        .measure = pb->measure, .measure_length = pb->measure_length,
                        .name = "t425"};
  if (ps_path_init(&r->path, r->s, &pp, &pb->cs.path, ps_step_control_find(pb->cs.path.control),
                   ctx))
    die_ctx("path", ctx);
}

static void plate_run_free(plate_run *r) {
  ps_path_free(&r->path);
  ps_solver_free(r->s);
  ps_problem_free(&r->pb);
}

/* The energy balance along a path: W, the trapezoid sum of the reaction
 * times the grip's displacement over the converged states, against the
 * stored energy Psi and the dissipated D (plastic or softening, and the
 * broken arms'): W - Psi = D on a path of equilibrium states. */
typedef struct balance {
  double ubar;            /* the grip's prescribed displacement at load factor 1 */
  double W, R0, l0, R_peak, D, error;
} balance;

static balance balance_start(const ps_problem *pb) {
  balance b = {0};
  for (ps_int j = 0; j < pb->net.n_particle * 2; j++)
    if (pb->fixed[j] && fabs(pb->ubar[j]) > b.ubar) b.ubar = fabs(pb->ubar[j]);
  b.error = 1;
  return b;
}

/* the path's last increment into b (b->error the relative balance error
 * there) */
static void balance_add(balance *b, const ps_path *path, const ps_problem *pb,
                        const ps_solver *s) {
  double R = path->last.sigma * pb->measure_length, l = path->last.lambda;
  b->W += 0.5 * (R + b->R0) * (l - b->l0) * b->ubar;
  b->R0 = R;
  b->l0 = l;
  if (R > b->R_peak) b->R_peak = R;
  b->D = ps_solver_dissipated(s) + ps_solver_arm_state(s)->broken_energy;
  if (b->D > 0) b->error = fabs(b->W - ps_solver_stored_energy(s) - b->D) / b->D;
}

static void controlled_run(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  plate_run r;
  plate_run_start(&r, "t425-run.yaml",
                  "  load_step: 0.01\n  control: dissipation\n  stop_load_drop: 0.1\n"
                  "  max_increments: 3000\n",
                  &ctx);
  ps_solver *s = r.s;
  ps_path *path = &r.path;
  balance b = balance_start(&r.pb);
  double D_last = 0;
  int all_converged = 1, monotone = 1, n_diss = 0, n_inc = 0;
  while (ps_path_test(path) == PS_PATH_CONTINUE) {
    if (ps_path_iterate(path, &ctx)) die_ctx("iterate", &ctx);
    if (path->end) break;
    n_inc++;
    all_converged &= path->last.converged;
    balance_add(&b, path, &r.pb, s);
    if (b.D < D_last - 1e-12 * fabs(D_last)) monotone = 0;
    if (b.D > D_last) n_diss++;
    D_last = b.D;
    if (getenv("T425_VERBOSE"))
      printf("    %3d lambda %.8f R %.6g W %.8g Psi %.8g D %.8g\n", n_inc, path->last.lambda,
             b.R0, b.W, ps_solver_stored_energy(s), b.D);
  }
  double R0 = b.R0, R_peak = b.R_peak, W = b.W, worst_bal = b.error;
  printf("  (3) %d increments (%d dissipating), end: %s; reaction %.4g of its peak, %lld "
         "arms broken; dissipated %.6g J/m, W - Psi = %.6g J/m (balance error %.2e)\n",
         n_inc, n_diss, path->stop_reason, R0 / R_peak, (long long)path->broken_total, D_last,
         W - ps_solver_stored_energy(s), worst_bal);
  ps_check(all_converged, "every increment converged");
  ps_check(path->end == PS_PATH_FRACTURED && R0 < 0.1 * R_peak,
           "past the peak along the descending branch to below 10%% of the peak reaction");
  ps_check(n_diss >= 10, "dissipation control took over once the arms softened");
  ps_check(monotone, "the dissipated energy never falls");
  ps_check(worst_bal < 0.01, "energy balance W - Psi = D within 1%%");
  plate_run_free(&r);
}

/* (4): the load phase of dissipation control */
static void load_phase_run(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  plate_run r, ref;
  /* the reference: load control over the same load factors */
  plate_run_start(&ref, "t425-load.yaml",
                  "  load_step: 0.01\n  load_step_after_break: 0.01\n"
                  "  max_increments: 3000\n  max_load: 2.0\n",
                  &ctx);
  plate_run_start(&r, "t425-phase.yaml",
                  "  load_step: 0.01\n  load_step_after_break: 0.01\n  control: dissipation\n"
                  "  load_until_unstable: true\n  unstable_arms: 10\n  stop_load_drop: 0.1\n"
                  "  max_increments: 3000\n",
                  &ctx);
  ps_solver *s = r.s;
  ps_path *path = &r.path, *pload = &ref.path;
  balance b = balance_start(&r.pb);
  double worst_load = 0;
  int all_converged = 1, n_load = 0, n_after = 0, load_ok = 1;
  while (ps_path_test(path) == PS_PATH_CONTINUE) {
    if (ps_path_iterate(path, &ctx)) die_ctx("iterate", &ctx);
    if (path->end) break;
    all_converged &= path->last.converged;
    double l = path->last.lambda;
    if (!n_after && ps_path_load_phase_arms(path) > 0) {
      /* still load control: the same increment as the load-controlled run */
      n_load++;
      if (ps_path_test(pload) != PS_PATH_CONTINUE || ps_path_iterate(pload, &ctx))
        die_ctx("load-controlled run", &ctx);
      double e = fabs(path->last.sigma - pload->last.sigma) / fabs(pload->last.sigma);
      if (e > worst_load) worst_load = e;
      load_ok &= fabs(l - 0.01 * n_load) < 1e-12 && pload->last.lambda == l;
    } else {
      n_after++;
    }
    balance_add(&b, path, &r.pb, s);
  }
  double R0 = b.R0, R_peak = b.R_peak, bal = b.error;
  printf("  (4) %d load-controlled increments (boundary stress within %.1e of load "
         "control's), then %d under dissipation control; end: %s; reaction %.4g of its "
         "peak; balance error %.2e\n",
         n_load, worst_load, n_after, path->stop_reason, R0 / R_peak, bal);
  ps_check(n_load >= 5 && load_ok && worst_load < 1e-9,
           "the load phase is load control's path (load factors and boundary stresses)");
  ps_check(n_after >= 10, "dissipation control took over from the load phase");
  ps_check(all_converged, "every increment converged");
  ps_check(path->end == PS_PATH_FRACTURED && R0 < 0.1 * R_peak,
           "past the peak to below 10%% of the peak reaction");
  ps_check(bal < 0.01, "energy balance W - Psi = D within 1%% after the switch");
  plate_run_free(&r);
  plate_run_free(&ref);
}

/* (5): a snapshot put back is the state taken */
static void snapshot(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  plate_run r;
  plate_run_start(&r, "t425-snap.yaml", "  load_step: 0.01\n", &ctx);
  ps_solver *s = r.s;
  ps_solver_snapshot snap = {0}, back = {0};
  /* into the softening range: arms soften and dissipate */
  for (int k = 1; k <= 15; k++) {
    if (ps_solver_step(s, 0.01 * k, &ctx)) die_ctx("step", &ctx);
    ps_solver_commit(s);
  }
  if (ps_solver_snapshot_take(s, &snap, &ctx)) die_ctx("snapshot", &ctx);
  double lambda = ps_solver_lambda(s), D = ps_solver_dissipated(s);
  int moved = 1;
  for (int k = 16; k <= 19; k++) {
    moved &= ps_solver_step(s, 0.01 * k, &ctx) == PS_OK;
    ps_solver_commit(s);
  }
  moved &= ps_solver_dissipated(s) > D;
  if (ps_solver_snapshot_restore(s, &snap, &ctx) < 0) die_ctx("restore", &ctx);
  if (ps_solver_snapshot_take(s, &back, &ctx)) die_ctx("snapshot", &ctx);
  printf("  (5) snapshot of %zu bytes at load factor %g, a step to 0.19 (%s), put back\n",
         snap.size, lambda, moved ? "dissipating" : "NOT dissipating");
  ps_check(moved && back.size == snap.size && !memcmp(back.data, snap.data, snap.size) &&
               ps_solver_lambda(s) == lambda && ps_solver_dissipated(s) == D,
           "a snapshot put back is the state taken, bit for bit");
  ps_solver_snapshot_free(&snap);
  ps_solver_snapshot_free(&back);
  plate_run_free(&r);
}

/* (6): a comm of one process that counts its calls by the number of
 * values reduced */
typedef struct counting {
  long sums[8], others;
} counting;
static void count_sum(void *data, double *x, int n) {
  (void)x;
  counting *c = data;
  c->sums[n < 8 ? n : 7]++;
}
static void count_other(void *data, double *x, int n) {
  (void)x;
  (void)n;
  ((counting *)data)->others++;
}

static void routed_run(void) {
  const char *lines = "  load_step: 0.01\n  load_step_after_break: 0.01\n  control: dissipation\n"
                      "  load_until_unstable: true\n  unstable_arms: 10\n  stop_load_drop: 0.1\n"
                      "  max_increments: 3000\n";
  counting cnt = {{0}, 0};
  const ps_comm comm = {0, 1, &cnt, count_sum, count_other, count_other, NULL};
  ps_ctx ctx, ctx_c;
  ps_ctx_init(&ctx);
  ps_ctx_init(&ctx_c);
  ctx_c.comm = &comm;
  plate_run a, b;
  plate_run_start(&a, "t425-comm0.yaml", lines, &ctx);
  plate_run_start(&b, "t425-comm1.yaml", lines, &ctx_c);
  int same = 1, n_inc = 0, ta;
  while ((ta = ps_path_test(&a.path)) == PS_PATH_CONTINUE) {
    if (ps_path_iterate(&a.path, &ctx)) die_ctx("iterate", &ctx);
    if (ps_path_test(&b.path) != PS_PATH_CONTINUE) {
      same = 0;
      break;
    }
    if (ps_path_iterate(&b.path, &ctx_c)) die_ctx("iterate with the comm", &ctx_c);
    if (a.path.end || b.path.end) {
      same &= a.path.end == b.path.end;
      break;
    }
    n_inc++;
    const ps_path_increment *x = &a.path.last, *y = &b.path.last;
    same &= x->lambda == y->lambda && x->sigma == y->sigma &&
            ps_solver_stored_energy(a.s) == ps_solver_stored_energy(b.s) &&
            ps_solver_dissipated(a.s) == ps_solver_dissipated(b.s) &&
            a.path.broken_total == b.path.broken_total;
  }
  ps_solver_stats st;
  ps_solver_get_stats(b.s, &st);
  printf("  (6) %d increments, %lld Newton iterations, %lld arms broken; the comm summed "
         "%ld single values and %ld pairs (%ld other calls)\n",
         n_inc, (long long)st.newton_iterations, (long long)b.path.broken_total, cnt.sums[1],
         cnt.sums[2], cnt.others);
  if (ta != PS_PATH_CONTINUE) same &= ps_path_test(&b.path) == ta && b.path.end == a.path.end;
  ps_check(same && n_inc >= 10,
           "a comm of one process changes no number of the path (bit for bit)");
  ps_check(cnt.sums[2] >= st.newton_iterations && st.newton_iterations > 0,
           "every Newton iterate's residual norms go through the comm");
  ps_check(cnt.sums[1] >= 2 * st.newton_iterations,
           "energies and slopes go through the comm");
  plate_run_free(&a);
  plate_run_free(&b);
}

int main(void) {
  arm_law();
  fibre_gradient();
  controlled_run();
  load_phase_run();
  snapshot();
  routed_run();
  return ps_check_summary();
}
