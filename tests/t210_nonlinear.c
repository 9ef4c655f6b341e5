/* t210_nonlinear.c: the pieces of the nonlinear solver (src/nonlinear) on
 * their own and together.
 *  - The line search on 1-D merit functions with known answers: a full
 *    step accepted at once; a quartic whose cut is the minimiser of the
 *    interpolating quadratic; cuts clamped to [0.1, 0.5] of the step; a
 *    merit function that is not finite beyond 0.3 (halvings); a change
 *    below the energy's round-off judged by the slopes' trapezoid; a
 *    direction that is not a descent one (no step after 16 cuts); a fatal
 *    status passed through; backtracking off.
 *  - The forcing rule against its formulas: Eisenstat-Walker choice 2
 *    (first iteration, safeguard, cap), the fixed rule (cap, rtol floor),
 *    Kelley's floor, exact Newton.
 *  - Newton through ps_solver_create on a three-particle truss of the
 *    bond model (arms are linear springs T = k dl in arm length, so the
 *    problem is nonlinear through the geometry alone): particle 1 at
 *    (0, H) held by arms to particles 0 and 2 at (-L, 0), (L, 0), whose
 *    displacements are prescribed (pulled out to +-L'), with or without
 *    a force F on particle 1 along y. Equilibrium: x_1 = 0 by symmetry,
 *    and y_1 solves 2 T(y) y / l(y) = F, l = sqrt(L'^2 + y^2 + e^2 r0^2),
 *    T = k (l - r0 sqrt(1 + e^2)) (e = PS_ARM_LENGTH_ROUNDING), so
 *    y_1 = 0 for F = 0 and L' > r0; for F != 0 the root is bracketed and
 *    bisected here. Exact Newton (a fresh factor per iteration) converges
 *    quadratically: rel_k+1 <= 10 rel_k^2 once rel_k < 1e-2.
 *  - The direction strategy on a plastic fibre-model box pulled in x (a
 *    nonlinear problem with family terms): CG with the old factor and the
 *    majorant, CG without the majorant, a fresh factor each iteration,
 *    the assembled instead of the matrix-free product, and UMFPACK all
 *    reach |r| <= tol |R| and the same u (to 1e-6 of its norm), each
 *    through its own route (the counters say which). And the compressed
 *    truss, whose tangent is indefinite on the way to equilibrium,
 *    reaches its closed-form equilibrium.
 *  - Newton and the direction strategy on a problem made by hand (a
 *    2-dof quartic energy with a known minimiser, ps_nl_problem_ops
 *    written here): no model, no assembly; converged to the minimiser,
 *    with CG on the old factor or a fresh factor per iteration. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
/* the module's own unit test: it sets the solver's state and options
 * directly, so it reads the struct (solver_impl.h) */
#include "nonlinear/solver_impl.h"
#include "nonlinear/problem_pd.h"

/* ---- the line search ---------------------------------------------- */

/* phi(alpha) = a4 (alpha - m)^4 + a2 (alpha - m)^2 + c0 (+ noise beyond
 * `finite_below`: not finite), slope its derivative */
typedef struct {
  double a4, a2, m, c0;
  double finite_below;   /* phi is inf for alpha >= this */
  double noise;          /* added to phi(alpha) for alpha > 0 */
  int fatal;             /* 1: value returns PS_ERR_NOMEM */
  int solver_error;      /* 1: value returns PS_ERR_SOLVER beyond finite_below */
  int calls;
  double last;
} merit1d;

static double m_phi(const merit1d *f, double a) {
  double d = a - f->m;
  return f->a4 * d * d * d * d + f->a2 * d * d + f->c0;
}
static double m_dphi(const merit1d *f, double a) {
  double d = a - f->m;
  return 4 * f->a4 * d * d * d + 2 * f->a2 * d;
}
static int m_value(void *data, double alpha, double *phi, ps_ctx *ctx) {
  merit1d *f = data;
  f->calls++;
  f->last = alpha;
  if (f->fatal) return ps_error(ctx, PS_ERR_NOMEM, "out of memory");
  if (alpha >= f->finite_below) {
    if (f->solver_error) return ps_error(ctx, PS_ERR_SOLVER, "arm length not finite");
    *phi = INFINITY;
    return PS_OK;
  }
  *phi = m_phi(f, alpha) + (alpha > 0 ? f->noise : 0.0);
  return PS_OK;
}
static double m_slope(void *data) {
  merit1d *f = data;
  return m_dphi(f, f->last);
}

/* run a default search on f; returns the search object */
static ps_linesearch search(merit1d *f, int backtrack) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_linesearch_opts o;
  ps_linesearch_opts_default(&o);
  o.backtrack = backtrack;
  ps_linesearch ls;
  ps_linesearch_init(&ls, &o);
  ps_merit phi = {m_value, m_slope, f};
  f->calls = 0;
  int status = ps_linesearch_search(&ls, &phi, m_phi(f, 0.0), m_dphi(f, 0.0), &ctx);
  if (status != PS_OK) ls.reason = -1;
  return ls;
}

static void test_linesearch(void) {
  /* a quadratic with its minimiser at 1: the full step */
  merit1d q = {0, 2.385, 1.0, -0.7, INFINITY, 0, 0, 0, 0, 0};
  ps_linesearch ls = search(&q, 1);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.step == 1.0 && ls.cuts == 0 &&
               q.calls == 1,
           "line search, quadratic with minimiser 1: full step accepted at once "
           "(reason %d, step %g, %d cuts)", ls.reason, ls.step, ls.cuts);
  ps_check_rel(ls.value, -0.7, 1e-15, "line search: value at the accepted step");

  /* a quartic with its minimiser at 0.3: phi(1) > phi(0), so the step is
   * cut to the minimiser of the quadratic through phi(0), phi'(0), phi(1),
   * which then passes Armijo */
  merit1d qu = {1.7, 0, 0.3, 0.25, INFINITY, 0, 0, 0, 0, 0};
  double g0 = m_dphi(&qu, 0), d1 = m_phi(&qu, 1) - m_phi(&qu, 0);
  double want = -g0 * 1.0 * 1.0 / (2.0 * (d1 - g0 * 1.0));
  ls = search(&qu, 1);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.cuts == 1,
           "line search, quartic with minimiser 0.3: accepted after one cut (reason %d, "
           "%d cuts)", ls.reason, ls.cuts);
  ps_check_rel(ls.step, want, 1e-15, "line search, quartic: the cut is the quadratic's minimiser");
  ps_check(want > 0.1 && want < 0.5 && m_phi(&qu, ls.step) < m_phi(&qu, 0),
           "line search, quartic: cut %.6f inside [0.1, 0.5], energy decreased", want);

  /* a quadratic with its minimiser at 0.004: the interpolant is exact,
   * so the cuts go 1 -> 0.1 -> 0.01 (clamped to a tenth of the step) ->
   * 0.004 (the minimiser, inside [0.001, 0.005]) */
  merit1d st = {0, 100.0, 0.004, 0, INFINITY, 0, 0, 0, 0, 0};
  ls = search(&st, 1);
  ps_check(ls.cuts == 3 && ls.reason == PS_LINESEARCH_ACCEPTED,
           "line search, minimiser at 0.004: accepted after 3 cuts (%d)", ls.cuts);
  ps_check_rel(ls.step, 0.004, 1e-12,
               "line search: two cuts clamped to 0.1 of the step, then the minimiser");

  /* Armijo just fails at alpha = 1 with the quadratic's minimiser just
   * above 0.5: the cut is clamped to 0.5. phi = g0 a + K a^2 with
   * K = 0.99995 |g0| */
  merit1d ha = {0, 0.99995, 0.5 / 0.99995, 0, INFINITY, 0, 0, 0, 0, 0};
  ha.c0 = -ha.a2 * ha.m * ha.m; /* phi(0) = 0 */
  ls = search(&ha, 1);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.cuts == 1 && ls.step == 0.5,
           "line search: a cut above half the step is clamped to 0.5 (step %.17g, %d cuts)",
           ls.step, ls.cuts);

  /* not finite beyond 0.3: halvings 1 -> 0.5 -> 0.25, then Armijo holds
   * on the convex phi with minimiser 0.6 */
  merit1d nf = {0, 1.3, 0.6, 0, 0.3, 0, 0, 0, 0, 0};
  ls = search(&nf, 1);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.step == 0.25 && ls.cuts == 2,
           "line search, phi = inf beyond 0.3: step 0.25 after 2 halvings (step %g, %d cuts)",
           ls.step, ls.cuts);
  nf.solver_error = 1;
  ls = search(&nf, 1);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.step == 0.25 && ls.cuts == 2,
           "line search, PS_ERR_SOLVER beyond 0.3: treated as not finite, step 0.25");

  /* backtracking off: the first finite trial, even uphill */
  merit1d up = {0, 1.0, -0.5, 0, 0.3, 0, 0, 0, 0, 0};
  ls = search(&up, 0);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.step == 0.25 && ls.cuts == 2,
           "line search off: first finite trial accepted (step %g, %d cuts)", ls.step, ls.cuts);

  /* a direction that is not a descent one (phi'(0) > 0, phi increasing):
   * no step, after max_tries cuts */
  ls = search(&up, 1);
  ps_check(ls.reason == PS_LINESEARCH_NO_STEP && ls.cuts == 16 && up.calls == 16,
           "line search, uphill direction: no step after 16 cuts (reason %d: %s, %d cuts)",
           ls.reason, ps_linesearch_reason_text(ls.reason), ls.cuts);

  /* the energy's change below its round-off (1e-10 |phi(0)|): the value
   * says uphill (noise +1e-3 on phi(0) = 1e8), the slopes' trapezoid
   * 0.5 (phi'(0) + phi'(1)) = -0.3 s says downhill: full step accepted */
  merit1d ro = {0, 0.5e-6, 0.8, 1e8, INFINITY, 1e-3, 0, 0, 0, 0};
  ro.c0 = 1e8 - ro.a2 * ro.m * ro.m; /* phi(0) = 1e8 */
  ls = search(&ro, 1);
  ps_check(ls.reason == PS_LINESEARCH_ACCEPTED && ls.step == 1.0 && ls.cuts == 0,
           "line search, change below round-off: judged by the slopes, full step "
           "(reason %d, step %g)", ls.reason, ls.step);
  ro.noise = 1e-1; /* 1e-9 |phi(0)|: above the resolution, the value decides */
  ls = search(&ro, 1);
  ps_check(ls.cuts > 0, "line search, change above round-off: judged by the value (%d cuts)",
           ls.cuts);

  /* a fatal status of the merit function is returned as it is */
  merit1d fa = {0, 1.0, 1.0, 0, INFINITY, 0, 1, 0, 0, 0};
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_linesearch_opts o;
  ps_linesearch_opts_default(&o);
  ps_linesearch L;
  ps_linesearch_init(&L, &o);
  ps_merit phi = {m_value, m_slope, &fa};
  ps_check(ps_linesearch_search(&L, &phi, 0.0, -2.0, &ctx) == PS_ERR_NOMEM,
           "line search: a fatal status of phi is returned");
}

/* ---- the forcing rule ---------------------------------------------- */

static void test_forcing(void) {
  ps_forcing F;
  double tol = 1e-8, rtol = 1e-6, emax = 0.5;
  ps_forcing_init(&F, 1, emax, PS_CG_FORCING_FIXED, rtol, tol);
  ps_check_rel(ps_forcing_next(&F, 1e-2), emax, 0, "forcing, adaptive: eta_0 = eta_max");
  /* rel 1e-2 -> 1e-3: e = 0.9 (0.1)^2 = 0.009 < safeguard 0.9 0.5^2 = 0.225 */
  ps_check_rel(ps_forcing_next(&F, 1e-3), PS_EW_GAMMA * pow(emax, 2), 1e-15,
               "forcing, adaptive: the safeguard 0.9 eta_k-1^2 when above 0.1");
  /* rel 1e-3 -> 1e-5: e = 0.9e-4, safeguard 0.9 0.225^2 = 0.0456 < 0.1 not
   * applied; Kelley's floor 0.1 tol / rel = 1e-4 is larger */
  double t = ps_forcing_next(&F, 1e-5);
  ps_check_rel(F.eta, PS_EW_GAMMA * pow(1e-5 / 1e-3, 2), 1e-15,
               "forcing, adaptive: eta_k = 0.9 (rel_k / rel_k-1)^2");
  ps_check_rel(t, PS_CG_OVERSOLVE * tol / 1e-5, 1e-15,
               "forcing, adaptive: Kelley's floor 0.1 tol / rel");
  /* the residual grows fourfold: 0.9 * 16 capped at eta_max */
  ps_check_rel(ps_forcing_next(&F, 4e-5), emax, 0, "forcing, adaptive: capped at eta_max");
  /* a tighter cap than rtol: rtol wins */
  ps_forcing_init(&F, 1, 1e-8, PS_CG_FORCING_FIXED, rtol, 1e-20);
  ps_check_rel(ps_forcing_next(&F, 1e-3), rtol, 0, "forcing, adaptive: never below rtol_min");

  ps_forcing_init(&F, 0, emax, 100.0, rtol, tol);
  ps_check_rel(ps_forcing_next(&F, 1e-3), PS_CG_FORCING_MAX, 0,
               "forcing, fixed: 100 rel capped at PS_CG_FORCING_MAX");
  ps_check_rel(ps_forcing_next(&F, 1e-6), PS_CG_OVERSOLVE * tol / 1e-6, 1e-15,
               "forcing, fixed: Kelley's floor 0.1 tol / rel above 100 rel");
  ps_forcing_init(&F, 0, emax, 100.0, rtol, 1e-12);
  ps_check_rel(ps_forcing_next(&F, 1e-6), 1e-4, 1e-15, "forcing, fixed: 100 rel");
  ps_forcing_init(&F, 0, emax, 100.0, rtol, 1e-14);
  ps_check_rel(ps_forcing_next(&F, 1e-9), rtol, 0, "forcing, fixed: not below rtol_min");
  ps_forcing_init(&F, 0, emax, 0.0, rtol, tol);
  ps_check_rel(ps_forcing_next(&F, 1e-9), rtol, 0,
               "forcing, c = 0: rtol_min always (exact Newton, no floor)");
  /* a handover keeps the history and switches to the fixed rule */
  ps_forcing_init(&F, 1, emax, 100.0, rtol, tol);
  ps_forcing_next(&F, 1e-2);
  ps_forcing_handover(&F);
  ps_check(!F.adaptive && F.k == 1 && F.rel_prev == 1e-2, "forcing: handover to the fixed rule");
  ps_check_rel(ps_forcing_next(&F, 1e-5), 1e-3, 1e-15, "forcing: fixed rule after the handover");
}

/* ---- Newton on the truss -------------------------------------------- */

typedef struct {
  ps_particles P;
  ps_network net;
  ps_material mat;
  unsigned char fixed[6];
  double ubar[6], fext[6];
  double L, H, Lp; /* half span, height, half span after loading */
} truss;

static int truss_build(truss *t, double L, double H, double D, ps_ctx *ctx) {
  memset(t, 0, sizeof *t);
  t->L = L;
  t->H = H;
  t->Lp = L + D;
  if (ps_particles_alloc(&t->P, 2, 3, ctx)) return -1;
  double x[6] = {-L, 0, 0, H, L, 0};
  for (int j = 0; j < 6; j++) t->P.x[j] = x[j];
  for (int a = 0; a < 3; a++) {
    t->P.volume[a] = 1.3e-6;
    t->P.h[a] = 1.0e-3;
  }
  ps_kernel K; /* arms r < 1.5 h: 0-1 and 1-2, not 0-2 */
  if (ps_kernel_init(&K, 2, 2, 1.5, ctx) || ps_network_build(&t->net, &t->P, &K, NULL, 0, ctx))
    return -1;
  ps_material m = {.E = 2.1e11, .nu = 0.25, .plane = PS_PLANE_STRAIN, .yield_strain = 2e-3,
                   .plastic = 0, .delta = INFINITY, .rho = 7800, .horizon = 1.6e-3,
                   .spacing = 1e-3};
  t->mat = m;
  if (ps_material_finish(&t->mat, 2, ctx)) return -1;
  for (int k = 0; k < 2; k++) t->fixed[k] = t->fixed[4 + k] = 1;
  t->ubar[0] = -D;
  t->ubar[4] = D;
  return PS_OK;
}

static void truss_free(truss *t) {
  ps_network_free(&t->net);
  ps_particles_free(&t->P);
}

/* the equilibrium height y of particle 1 under the force F (closed form
 * up to a bisected root): g(y) = 2 k dl(y) y / l(y) - F */
static double truss_g(const truss *t, double k, double r0, double y, double F) {
  double e = PS_ARM_LENGTH_ROUNDING;
  double l = sqrt(t->Lp * t->Lp + y * y + e * e * r0 * r0);
  return 2 * k * (l - r0 * sqrt(1 + e * e)) * y / l - F;
}

static double truss_height(const truss *t, double k, double r0, double F) {
  if (F == 0) return 0.0;
  double lo = 0, hi = 10 * t->L; /* g(0) = -F < 0, g(hi) > 0 */
  for (int i = 0; i < 200; i++) {
    double mid = 0.5 * (lo + hi);
    if (truss_g(t, k, r0, mid, F) > 0)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

static double norm_free(const ps_solver *s) {
  double r = 0;
  for (ps_int k = 0; k < s->prob.n_free; k++) {
    double v = s->f[s->prob.dof_of_free[k]];
    r += v * v;
  }
  return sqrt(r);
}
static double norm_fixed(const ps_solver *s) {
  double r = 0;
  for (ps_int j = 0; j < s->prob.n_dof; j++)
    if (s->prob.fixed[j]) r += s->f[j] * s->f[j];
  return sqrt(r);
}

/* solve the truss under F in one step; check the closed form */
/* y_start: NAN for one ps_solver_step from rest (predictor and Newton);
 * else Newton alone from particle 1 at height y_start, the supports
 * already displaced. With `outcome` NULL, checks convergence and the
 * closed form; else only reports the Newton reason there (and the
 * message in msg[256]). Returns the solver's statistics. */
static ps_solver_stats truss_case(const char *name, double D, double H, double F_over_kL,
                                  double y_start, const ps_solver_opts *o, int *outcome,
                                  char *msg) {
  ps_solver_stats st;
  memset(&st, 0, sizeof st);
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 2 : 0;
  truss t;
  ps_solver *s = NULL;
  if (truss_build(&t, 1.0e-3, H, D, &ctx) ||
      ps_solver_create(&s, &t.P, &t.net, ps_model_bond, &t.mat, t.fixed, t.ubar, o, &ctx)) {
    ps_check(0, "%s: set-up: %s", name, ctx.msg);
    return st;
  }
  double k = s->pd->model.arm_k[0], r0 = t.net.r0[0];
  double F = F_over_kL * k * t.L;
  t.fext[3] = F;
  ps_solver_set_forces(s, t.fext);
  int status;
  if (isnan(y_start)) {
    status = ps_solver_step(s, 1.0, &ctx);
  } else {
    s->pd->lambda = 1.0;
    for (int j = 0; j < 6; j++) s->u[j] = t.ubar[j];
    s->u[3] = y_start - t.H;
    status = ps_newton_solve(s, &ctx);
  }
  const double *u = ps_solver_u(s);
  if (outcome) {
    *outcome = status < 0 ? -1 : ps_solver_last_reason(s);
    snprintf(msg, 256, "%.200s", ctx.msg);
    ps_solver_get_stats(s, &st);
    ps_solver_free(s);
    truss_free(&t);
    return st;
  }
  ps_check(status == PS_OK && ps_solver_last_reason(s) == PS_NEWTON_CONVERGED,
           "%s: Newton converged (%d iterations, reason: %s)", name, s->last_iterations,
           ps_newton_reason_text(ps_solver_last_reason(s)));
  double rn = norm_free(s), R = norm_fixed(s);
  ps_check(rn <= o->tolerance * R, "%s: |r| = %.3g <= tol |R| = %.3g", name, rn,
           o->tolerance * R);
  double y = truss_height(&t, k, r0, F);
  ps_check(fabs(u[2]) <= 1e-12 * t.L, "%s: x_1 = %.3g m = 0 (symmetry)", name, u[2]);
  char what[160];
  if (F == 0) {
    ps_check(fabs(t.H + u[3]) <= 1e-10 * t.L, "%s: y_1 = %.3g m = 0 (taut)", name, t.H + u[3]);
  } else {
    snprintf(what, sizeof what, "%s: y_1 against the root of 2 T y / l = F", name);
    ps_check_rel(t.H + u[3], y, 1e-9, what);
  }
  /* reaction at particle 2 along x: T L' / l */
  double e = PS_ARM_LENGTH_ROUNDING;
  double l = sqrt(t.Lp * t.Lp + y * y + e * e * r0 * r0);
  double T = k * (l - r0 * sqrt(1 + e * e));
  snprintf(what, sizeof what, "%s: reaction T L'/l at the right support", name);
  ps_check_rel(s->f[4], T * t.Lp / l, 1e-8, what);
  ps_solver_get_stats(s, &st);
  printf("# %s: %lld Newton its, %lld factorisations, %lld CG its, %lld UMFPACK, "
         "%lld shifted, %lld truncated, %lld line-search cuts\n",
         name, (long long)st.newton_iterations, (long long)st.factorisations,
         (long long)st.pcg_iterations, (long long)st.n_fallback, (long long)st.shifted_steps,
         (long long)st.cg_truncated, (long long)st.line_search_cuts);
  ps_solver_free(s);
  truss_free(&t);
  return st;
}

/* the truss pushed in (L' < r0) from particle 1 just above the line: the
 * arms are compressed and the tangent indefinite at the start (the free
 * particle's y stiffness 2 (k (y/l)^2 + (T/l)(1 - (y/l)^2)) < 0 with
 * T < 0, x stiffness > 0, no coupling by symmetry).
 *  - CG with the old factor (of the tangent at rest) meets negative
 *    curvature; its truncated iterate is a descent direction, and Newton
 *    reaches the closed-form equilibrium.
 *  - Without truncation (and with fresh factors) CHOLMOD finds K not
 *    positive definite, UMFPACK factors it, and its step points uphill
 *    (the residual is along y, where K's curvature is negative). The
 *    shifted tangent K + mu diag K cannot help where a diagonal entry is
 *    itself negative: all six shifts (mu = 1e-4 .. 10) fail and the solve
 *    ends as singular, after 1 + 1 + 1 + 6 factorisations (create,
 *    CHOLMOD, UMFPACK, shifts). */
static void truss_indefinite(void) {
  const double D = -0.1e-3, H = 0.05e-3, F = 0.01, y0 = 0.01e-3;
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  o.tolerance = 1e-10;
  ps_solver_stats st =
      truss_case("indefinite, CG with the old factor", D, H, F, y0, &o, NULL, NULL);
  ps_check(st.cg_truncated > 0, "indefinite, CG with the old factor: truncated at "
           "negative curvature (%lld)", (long long)st.cg_truncated);
  const char *names[2] = {"indefinite, CG not truncated", "indefinite, fresh factors"};
  for (int i = 0; i < 2; i++) {
    o.cg_truncate = 0;
    o.reuse_factor = i == 0;
    int reason;
    char msg[256];
    st = truss_case(names[i], D, H, F, y0, &o, &reason, msg);
    ps_check(reason == PS_NEWTON_SINGULAR && st.n_fallback == 1 && st.factorisations == 9 &&
                 st.shifted_steps == 0 && strstr(msg, "no positive definite shift"),
             "%s: UMFPACK, uphill, no shift works: %s (%lld fallback, %lld "
             "factorisations; %s)", names[i], ps_newton_reason_text(reason),
             (long long)st.n_fallback, (long long)st.factorisations, msg);
  }
}

/* exact Newton from a fixed start, stopped after m = 1, 2, .. iterations:
 * the relative residuals rel_m converge quadratically */
static void truss_rate(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  truss t;
  ps_solver *s = NULL;
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  o.reuse_factor = 0;         /* a fresh factor per iteration: exact Newton */
  o.cg_forcing_adaptive = 0;  /* no handover at max_iterations */
  o.tolerance = 1e-15;
  if (truss_build(&t, 1.0e-3, 0.3e-3, 0.1e-3, &ctx) ||
      ps_solver_create(&s, &t.P, &t.net, ps_model_bond, &t.mat, t.fixed, t.ubar, &o, &ctx)) {
    ps_check(0, "rate: set-up: %s", ctx.msg);
    return;
  }
  t.fext[3] = 0.2 * s->pd->model.arm_k[0] * t.L;
  ps_solver_set_forces(s, t.fext);
  s->pd->lambda = 1.0;
  double u0[6];
  for (int j = 0; j < 6; j++) u0[j] = t.ubar[j];
  u0[3] = -0.5 * t.H; /* start half-way down */
  double rel[12];
  int n = 0, ok = 1;
  for (int m = 1; m <= 10; m++) {
    memcpy(s->u, u0, sizeof u0);
    s->opts.max_iterations = m;
    if (ps_newton_solve(s, &ctx) < 0) break;
    rel[n++] = s->last_residual;
    if (s->last_reason == PS_NEWTON_CONVERGED || s->last_residual < 1e-14) break;
  }
  int quad = 0;
  for (int i = 0; i + 1 < n; i++) {
    printf("# exact Newton: rel_%d = %.3e\n", i + 1, rel[i]);
    if (rel[i] < 1e-2 && rel[i + 1] > 1e-14) {
      quad++;
      ok &= rel[i + 1] <= 10 * rel[i] * rel[i];
    }
  }
  printf("# exact Newton: rel_%d = %.3e\n", n, rel[n - 1]);
  ps_check(n >= 3 && quad >= 2 && ok,
           "truss, exact Newton: rel_k+1 <= 10 rel_k^2 once rel_k < 1e-2 (%d iterations, "
           "%d pairs checked)", n, quad);
  ps_solver_free(s);
  truss_free(&t);
}

/* ---- the direction strategy on a plastic fibre box ------------------- */

typedef struct {
  const char *name;
  void (*set)(ps_solver_opts *o);
} strategy;

static void s_default(ps_solver_opts *o) { (void)o; }
static void s_no_majorant(ps_solver_opts *o) { o->majorant = 0; }
static void s_direct(ps_solver_opts *o) { o->reuse_factor = 0; }
static void s_assembled(ps_solver_opts *o) { o->matrix_free = 0; }
static void s_umfpack(ps_solver_opts *o) { snprintf(o->linear, sizeof o->linear, "umfpack"); }
static void s_fixed_forcing(ps_solver_opts *o) { o->cg_forcing_adaptive = 0; }
static void s_short_cg(ps_solver_opts *o) { o->pcg_max_iterations = 2; }

static void test_strategies(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 2 : 0;
  ps_particles P;
  ps_network net;
  ps_int counts[3] = {7, 6, 1};
  ps_kernel K;
  if (ps_geom_box(&P, 2, counts, 1.0e-3, "square", 0.2, 11, &ctx) ||
      ps_geom_sizes_eq115(&P, 5, &ctx) || ps_kernel_init(&K, 2, 2, 3.5, &ctx) ||
      ps_network_build(&net, &P, &K, NULL, 0, &ctx)) {
    ps_check(0, "box: %s", ctx.msg);
    return;
  }
  ps_material mat = {.E = 2.1e11, .nu = 0.3, .plane = PS_PLANE_STRAIN, .yield_strain = 1e-3,
                     .plastic = 1, .delta = INFINITY, .rho = 7800};
  ps_material_finish(&mat, 2, &ctx);
  ps_int nd = 2 * P.n;
  unsigned char *fixed = calloc((size_t)nd, 1);
  double *ubar = calloc((size_t)nd, sizeof *ubar), *u_ref = calloc((size_t)nd, sizeof *u_ref);
  double xmin = INFINITY, xmax = -INFINITY;
  for (ps_int a = 0; a < P.n; a++) {
    xmin = fmin(xmin, P.x[2 * a]);
    xmax = fmax(xmax, P.x[2 * a]);
  }
  for (ps_int a = 0; a < P.n; a++) { /* clamp the left column, pull the right one */
    double x = P.x[2 * a];
    if (x < xmin + 0.5e-3 || x > xmax - 0.5e-3) {
      fixed[2 * a] = fixed[2 * a + 1] = 1;
      ubar[2 * a] = x > xmax - 0.5e-3 ? 3.0 * mat.yield_strain * (xmax - xmin) : 0.0;
    }
  }
  const strategy all[] = {{"CG with old factor and majorant", s_default},
                          {"CG without majorant", s_no_majorant},
                          {"fresh factor per iteration", s_direct},
                          {"assembled product", s_assembled},
                          {"UMFPACK", s_umfpack},
                          {"fixed forcing rule", s_fixed_forcing},
                          {"CG capped at 2 iterations, majorant", s_short_cg}};
  double unorm = 0;
  for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
    ps_solver_opts o;
    ps_solver_opts_default(&o);
    o.tolerance = 1e-10;
    all[i].set(&o);
    ps_solver *s = NULL;
    if (ps_solver_create(&s, &P, &net, ps_model_fibre, &mat, fixed, ubar, &o, &ctx)) {
      ps_check(0, "%s: create: %s", all[i].name, ctx.msg);
      continue;
    }
    int status = PS_OK;
    for (int step = 1; step <= 4 && status == PS_OK; step++) {
      status = ps_solver_step(s, 0.25 * step, &ctx);
      if (status == PS_OK) ps_solver_commit(s);
    }
    ps_solver_stats st;
    ps_solver_get_stats(s, &st);
    double rn = norm_free(s), R = norm_fixed(s);
    ps_check(status == PS_OK && rn <= o.tolerance * R,
             "box, %s: converged, |r| = %.3g <= tol |R| = %.3g", all[i].name, rn,
             o.tolerance * R);
    const double *u = ps_solver_u(s);
    if (i == 0) {
      memcpy(u_ref, u, (size_t)nd * sizeof *u);
      for (ps_int j = 0; j < nd; j++) unorm += u[j] * u[j];
      unorm = sqrt(unorm);
      ps_check(ps_solver_count_yielding(s) > 0 && st.pcg_iterations > 0 &&
                   st.majorant_factorisations + st.factorisations >= 1,
               "box, %s: arms yield (%lld), CG used (%lld iterations, %lld majorant "
               "factorisations)", all[i].name, (long long)ps_solver_count_yielding(s),
               (long long)st.pcg_iterations, (long long)st.majorant_factorisations);
    } else {
      double d = 0;
      for (ps_int j = 0; j < nd; j++) d += (u[j] - u_ref[j]) * (u[j] - u_ref[j]);
      ps_check(sqrt(d) <= 1e-6 * unorm, "box, %s: same u as CG with the majorant "
               "(|du| / |u| = %.3g)", all[i].name, sqrt(d) / unorm);
    }
    if (all[i].set == s_direct)
      ps_check(st.pcg_iterations == 0 && st.factorisations == 1 + st.newton_iterations,
               "box, %s: no CG, one factorisation per Newton iteration (%lld, %lld)",
               all[i].name, (long long)st.factorisations, (long long)st.newton_iterations);
    if (all[i].set == s_no_majorant)
      ps_check(st.majorant_factorisations == 0 && st.pcg_iterations > 0,
               "box, %s: no majorant factor", all[i].name);
    if (all[i].set == s_short_cg)
      ps_check(st.pcg_failures > 0 && st.majorant_factorisations > 0,
               "box, %s: CG with the old factor fails (%lld), a fresh majorant factor "
               "follows (%lld)", all[i].name, (long long)st.pcg_failures,
               (long long)st.majorant_factorisations);
    if (all[i].set == s_umfpack)
      ps_check(st.factorisations >= 1 && st.n_fallback == 0, "box, %s: LU as the chosen "
               "backend, no fallback", all[i].name);
    printf("# box, %s: %lld Newton its, %lld factorisations, %lld majorant, %lld CG its, "
           "%lld line-search cuts\n",
           all[i].name, (long long)st.newton_iterations, (long long)st.factorisations,
           (long long)st.majorant_factorisations, (long long)st.pcg_iterations,
           (long long)st.line_search_cuts);
    ps_solver_free(s);
  }
  free(fixed);
  free(ubar);
  free(u_ref);
  ps_network_free(&net);
  ps_particles_free(&P);
}

/* ---- Newton and the directions on a problem made by hand ---------- */

/* E(u) = x^4/4 + x^2/2 + y^2 + x y/2, x = u_0 - 1, y = u_1 + 2: convex,
 * its minimiser u = (1, -2); f = grad E, K = [[3x^2 + 1, 1/2], [1/2, 2]].
 * Both dofs free (rel = |r|). No model, no assembly: the solver core sees
 * only these operations (ps_nl_problem.h). */
typedef struct {
  double K[3];              /* K00, K01, K11 at the last tangent */
  ps_int Ap[3], Ai[3];
  double Ax[3];
  ps_csc A;
  int evaluations, tangents, marks;
  ps_int dofs[2];
  unsigned char fixed[2];
  int with_majorant;        /* 1: a majorant P = diag(4 K00, K11) */
  ps_int Pp[3], Pi[2];
  double Px[2];
  ps_csc P;
} quartic;

static int q_evaluate(void *prob, const double *u, double *f, double *energy,
                      int want_tangent, ps_ctx *ctx) {
  (void)ctx;
  quartic *q = prob;
  double x = u[0] - 1, y = u[1] + 2;
  q->evaluations++;
  f[0] = x * x * x + x + 0.5 * y;
  f[1] = 2 * y + 0.5 * x;
  *energy = 0.25 * x * x * x * x + 0.5 * x * x + y * y + 0.5 * x * y;
  if (want_tangent) {
    q->tangents++;
    q->K[0] = 3 * x * x + 1;
    q->K[1] = 0.5;
    q->K[2] = 2;
  }
  return PS_OK;
}
static void q_apply(void *prob, const double *x, double *y) {
  const quartic *q = prob;
  y[0] = q->K[0] * x[0] + q->K[1] * x[1];
  y[1] = q->K[1] * x[0] + q->K[2] * x[1];
}
static int q_assemble(void *prob, int majorant, ps_csc **A, ps_ctx *ctx) {
  quartic *q = prob;
  if (majorant && q->with_majorant) {
    q->Px[0] = 4 * q->K[0];
    q->Px[1] = q->K[2];
    *A = &q->P;
    return PS_OK;
  }
  if (majorant) return ps_error(ctx, PS_ERR_INPUT, "no majorant");
  memcpy(q->Ax, q->K, sizeof q->K); /* upper triangle: (0,0); (0,1), (1,1) */
  *A = &q->A;
  return PS_OK;
}
static void q_mark(void *prob) { ((quartic *)prob)->marks++; }
static ps_int q_changed(void *prob, ps_int limit) {
  (void)prob;
  (void)limit;
  return 0;
}
static void q_dof_name(void *prob, ps_int k, char *buf, size_t len) {
  (void)prob;
  snprintf(buf, len, "dof %lld", (long long)k);
}

static const ps_nl_problem_ops quartic_ops = {q_evaluate, q_apply,   q_assemble,
                                              q_mark,     q_changed, q_dof_name};

/* the quartic (with its majorant: with_majorant) and a solver made by
 * hand around it (its options at their defaults, CHOLMOD; ls_pre too with
 * a majorant), or NULL when out of memory */
static ps_solver *quartic_solver(quartic *q, int with_majorant, ps_ctx *ctx, int *status) {
  memset(q, 0, sizeof *q);
  q->Ap[1] = 1;
  q->Ap[2] = 3;
  q->Ai[2] = 1;
  q->A = (ps_csc){2, q->Ap, q->Ai, q->Ax};
  q->with_majorant = with_majorant;
  q->Pp[1] = 1;
  q->Pp[2] = 2;
  q->Pi[1] = 1;
  q->P = (ps_csc){2, q->Pp, q->Pi, q->Px};
  q->dofs[1] = 1;
  ps_solver *s = calloc(1, sizeof *s);
  if (!s) return NULL;
  ps_solver_opts_default(&s->opts);
  s->prob = (ps_nl_problem){&quartic_ops, q, 2, 2, q->dofs, q->fixed, with_majorant};
  *status = ps_linsolve_create(&s->ls, ps_linsolve_cholmod, ctx);
  if (*status == PS_OK && with_majorant)
    *status = ps_linsolve_create(&s->ls_pre, ps_linsolve_cholmod, ctx);
  if (*status == PS_OK) *status = ps_nl_alloc_work(s, ctx);
  s->have_majorant = with_majorant;
  return s;
}

static void test_hand_problem(void) {
  const char *names[2] = {"a fresh factor each iteration", "CG with the old factor"};
  for (int reuse = 1; reuse >= 0; reuse--) {
    ps_ctx ctx;
    ps_ctx_init(&ctx);
    ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 2 : 0;
    quartic q;
    int status = PS_OK;
    ps_solver *s = quartic_solver(&q, 0, &ctx, &status);
    if (!s) {
      ps_check(0, "hand-made problem: out of memory");
      return;
    }
    s->opts.tolerance = 1e-12;
    s->opts.reuse_factor = reuse;
    if (status == PS_OK) {
      s->u[0] = 5.0; /* x = 4: far from the minimiser, where K changes */
      s->u[1] = 0.0;
      status = ps_newton_solve(s, &ctx);
    }
    ps_check(status == PS_OK && s->last_reason == PS_NEWTON_CONVERGED,
             "hand-made problem, %s: Newton converged (%d: %s; %s)", names[reuse], status,
             ps_newton_reason_text(s->last_reason), ctx.msg);
    ps_check(s->u && fabs(s->u[0] - 1) <= 1e-10 && fabs(s->u[1] + 2) <= 1e-10,
             "hand-made problem, %s: u = (%.15g, %.15g) = (1, -2)", names[reuse],
             s->u ? s->u[0] : NAN, s->u ? s->u[1] : NAN);
    ps_check(q.tangents == (int)s->newton_iterations && q.marks == 0,
             "hand-made problem, %s: one tangent per Newton iteration (%d, %lld), no "
             "marks without pcg_skip_arms (%d)", names[reuse], q.tangents,
             (long long)s->newton_iterations, q.marks);
    if (reuse)
      ps_check(s->pcg_iterations > 0 && s->ls.stats.n_factor < s->newton_iterations,
               "hand-made problem, %s: CG used (%lld iterations), fewer factors (%lld) "
               "than Newton iterations (%lld)", names[reuse], (long long)s->pcg_iterations,
               (long long)s->ls.stats.n_factor, (long long)s->newton_iterations);
    else
      ps_check(s->pcg_iterations == 0 && s->ls.stats.n_factor == s->newton_iterations,
               "hand-made problem, %s: no CG, %lld factors for %lld Newton iterations",
               names[reuse], (long long)s->ls.stats.n_factor,
               (long long)s->newton_iterations);
    printf("# hand-made problem, %s: %lld Newton its, %lld factors, %lld CG its, %lld "
           "line-search cuts, %d evaluations\n", names[reuse],
           (long long)s->newton_iterations, (long long)s->ls.stats.n_factor,
           (long long)s->pcg_iterations, (long long)s->n_line_search_cuts, q.evaluations);
    ps_solver_free(s);
  }
}

/* The first Newton system of a problem with a majorant, when CG with the
 * majorant's fresh factor fails (capped at one iteration, and P is not a
 * multiple of K): the tangent is factored next and solves it. The
 * majorant is factored once (CG with that same factor again, and a second
 * factor of the same P, would fail the same way), the tangent once. */
static void test_first_system_majorant(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 2 : 0;
  quartic q;
  int status = PS_OK;
  ps_solver *s = quartic_solver(&q, 1, &ctx, &status);
  if (!s) {
    ps_check(0, "first system: out of memory");
    return;
  }
  s->opts.pcg_max_iterations = 1;
  s->cg_rtol = 1e-10;
  double Kdu[2] = {0, 0};
  if (status == PS_OK) {
    s->u[0] = 3.0; /* x = 2 */
    status = ps_nl_eval(s, s->u, s->f, &s->energy, 1, &ctx);
    s->rhs[0] = -s->f[0];
    s->rhs[1] = -s->f[1];
    if (status == PS_OK) status = ps_nl_direction(s, &ctx);
    q_apply(&q, s->du, Kdu);
  }
  double err = hypot(Kdu[0] - s->rhs[0], Kdu[1] - s->rhs[1]) / hypot(s->rhs[0], s->rhs[1]);
  ps_check(status == PS_OK && err < 1e-12 && s->pre_failures == 1 &&
               s->ls_pre.stats.n_factor == 1 && s->ls.stats.n_factor == 1,
           "first system, CG with the fresh majorant factor fails: solved by the tangent's "
           "factor (|K du - rhs| / |rhs| = %.1e), majorant factored %lld time(s), CG failures "
           "with it %lld, tangent factored %lld time(s)",
           err, (long long)s->ls_pre.stats.n_factor, (long long)s->pre_failures,
           (long long)s->ls.stats.n_factor);
  ps_solver_free(s);
}

/* the linear solver is named in the options and resolved by
 * ps_solver_create: an unknown name is an input error, and *s stays NULL */
static void test_unknown_linear(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  truss t;
  ps_solver dummy;
  ps_solver *s = &dummy; /* not NULL: create must set it */
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  snprintf(o.linear, sizeof o.linear, "%s", "cholmod-supernodal");
  if (truss_build(&t, 1.0e-3, 0.3e-3, 0.1e-3, &ctx)) {
    ps_check(0, "unknown linear solver: set-up: %s", ctx.msg);
    return;
  }
  int status =
      ps_solver_create(&s, &t.P, &t.net, ps_model_bond, &t.mat, t.fixed, t.ubar, &o, &ctx);
  ps_check(status == PS_ERR_INPUT && s == NULL &&
               strstr(ctx.msg, "unknown linear solver 'cholmod-supernodal'"),
           "unknown linear solver: PS_ERR_INPUT, no solver (%d: %s)", status, ctx.msg);
  ps_solver_free(s);
  truss_free(&t);
}

int main(void) {
  test_linesearch();
  test_unknown_linear();
  test_forcing();
  test_hand_problem();
  test_first_system_majorant();
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  o.tolerance = 1e-10;
  truss_case("truss pulled taut", 0.1e-3, 0.3e-3, 0.0, NAN, &o, NULL, NULL);
  truss_case("truss pulled, force up", 0.1e-3, 0.3e-3, 0.2, NAN, &o, NULL, NULL);
  truss_case("truss pushed in, force up", -0.1e-3, 0.05e-3, 0.01, NAN, &o, NULL, NULL);
  o.reuse_factor = 0;
  truss_case("truss pushed in, force up, direct", -0.1e-3, 0.05e-3, 0.01, NAN, &o, NULL, NULL);
  truss_indefinite();
  truss_rate();
  test_strategies();
  return ps_check_summary();
}
