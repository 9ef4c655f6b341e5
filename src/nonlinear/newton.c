/* newton.c: Newton's method on r_free(u) = 0 (ps_newton_solve): at each
 * iterate the direction du from K_ff du = -r_free (direction.c, to the
 * CG tolerance of the forcing rule, forcing.c), the step along it by the
 * line search on the energy phi(alpha) = E(u + alpha du), phi'(alpha) =
 * f(u + alpha du) . du (linesearch.c), and the stopping tests. */
#include "solver_impl.h"

#include <limits.h>
#include <math.h>
#include <string.h>

/* 1 when dof j is this process's (ps_nl_problem.owned) */
static inline int owns(const ps_nl_problem *p, ps_int j) { return !p->owned || p->owned[j]; }

double ps_nl_relative_residual(const ps_nl_problem *p, const double *f, double *rn) {
  double s[2] = {0, 0}; /* ||f_free||^2, ||f_fixed||^2 (the reactions) */
  for (ps_int k = 0; k < p->n_free; k++) {
    double v = f[p->dof_of_free[k]];
    if (owns(p, p->dof_of_free[k])) s[0] += v * v;
  }
  for (ps_int j = 0; j < p->n_dof; j++)
    if (p->fixed[j] && owns(p, j)) s[1] += f[j] * f[j];
  ps_comm_sum(p->comm, s, 2);
  double ref = sqrt(s[1]);
  *rn = sqrt(s[0]);
  return ref > 0 ? *rn / ref : *rn;
}

/* f_free . x, x[n_free] */
static double dot_free(const ps_nl_problem *p, const double *f, const double *x) {
  double g = 0;
  for (ps_int k = 0; k < p->n_free; k++)
    if (owns(p, p->dof_of_free[k])) g += f[p->dof_of_free[k]] * x[k];
  return ps_comm_sum1(p->comm, g);
}

/* the merit function of the line search: phi(alpha) = E(u + alpha du),
 * evaluated into u_trial, f_trial */
static int trial_energy(void *data, double alpha, double *phi, ps_ctx *ctx) {
  ps_solver *s = data;
  const ps_nl_problem *p = &s->prob;
  memcpy(s->u_trial, s->u, (size_t)p->n_dof * sizeof *s->u);
  for (ps_int k = 0; k < p->n_free; k++) s->u_trial[p->dof_of_free[k]] += alpha * s->du[k];
  return ps_nl_eval(s, s->u_trial, s->f_trial, phi, 0, ctx);
}

/* phi'(alpha) = f(u + alpha du) . du at the last trial */
static double trial_slope(void *data) {
  const ps_solver *s = data;
  return dot_free(&s->prob, s->f_trial, s->du);
}

/* The Newton direction at the current iterate (tangent evaluated, rhs =
 * -r_free), and *g0 = r_free . du, the energy's slope along it. Where du
 * points uphill (g0 >= 0: K indefinite) and the line search is on, the
 * shifted tangent's direction replaces it. Returns PS_OK, PS_SINGULAR, or
 * fatal. */
static int descent_direction(ps_solver *s, double *g0, ps_ctx *ctx) {
  int status = ps_nl_direction(s, ctx);
  if (status != PS_OK) return status;
  s->newton_iterations++;
  *g0 = dot_free(&s->prob, s->f, s->du);
  if (*g0 >= 0 && s->opts.line_search) {
    status = ps_nl_shifted_direction(s, ctx);
    if (status != PS_OK) return status;
    *g0 = dot_free(&s->prob, s->f, s->du);
  }
  return PS_OK;
}

/* end the solve: reason into s->last_reason; PS_OK when converged, else
 * PS_DIVERGED */
static int finish(ps_solver *s, int reason) {
  s->last_reason = reason;
  return reason == PS_NEWTON_CONVERGED ? PS_OK : PS_DIVERGED;
}

int ps_newton_solve(ps_solver *s, ps_ctx *ctx) {
  const ps_nl_problem *p = &s->prob;
  const ps_solver_opts *o = &s->opts;
  PS_CHECK(ps_nl_eval(s, s->u, s->f, &s->energy, 0, ctx));
  ps_forcing forcing;
  ps_forcing_init(&forcing, o->cg_forcing_adaptive, o->cg_forcing_max, o->cg_forcing,
                  o->pcg_rtol, o->tolerance);
  ps_linesearch_opts lo;
  ps_linesearch_opts_default(&lo);
  lo.backtrack = o->line_search;
  ps_linesearch ls;
  ps_linesearch_init(&ls, &lo);
  const ps_merit phi = {trial_energy, trial_slope, s};
  int small_steps = 0;     /* line-search steps < PS_SMALL_STEP in a row */
  double rel_before = 0.0; /* the residual before the first of them */
  int budget = o->max_iterations;
  for (int it = 0;; it++) {
    double rn, rel = ps_nl_relative_residual(p, s->f, &rn);
    s->last_iterations = it;
    s->last_residual = rel;
    ps_log(ctx, 2, "    newton %2d  |r|/|R| = %.3e  energy = %.10g\n", it, rel, s->energy);
    if (!isfinite(rel) || !isfinite(s->energy)) return finish(s, PS_NEWTON_NOT_FINITE);
    if (rel <= o->tolerance || rn == 0.0) return finish(s, PS_NEWTON_CONVERGED);
    /* the adaptive rule's rough CG solves need more Newton iterations: at
     * max_iterations the solve goes on under the fixed rule for
     * max_iterations more */
    if (it >= budget && forcing.adaptive) {
      ps_forcing_handover(&forcing);
      budget = o->max_iterations > INT_MAX - it ? INT_MAX : it + o->max_iterations;
      small_steps = 0; /* the fixed rule's steps are judged afresh */
      s->n_handovers++;
      ps_log(ctx, 2, "    adaptive CG tolerance: max_iterations reached, fixed rule from here\n");
    }
    if (it >= budget) return finish(s, PS_NEWTON_MAX_ITER);
    /* stagnation: line-search steps below PS_SMALL_STEP in a row (arms at
     * the kink of the perfectly plastic law near a limit load) that cut
     * the residual by less than 10% together */
    if (o->max_small_steps > 0 && small_steps >= o->max_small_steps &&
        rel > 0.9 * rel_before) {
      s->n_stagnated++;
      return finish(s, PS_NEWTON_STAGNATED);
    }
    PS_CHECK(ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx));
    for (ps_int k = 0; k < p->n_free; k++) s->rhs[k] = -s->f[p->dof_of_free[k]];
    s->cg_rtol = ps_forcing_next(&forcing, rel);
    double g0 = 0;
    int status = descent_direction(s, &g0, ctx);
    if (status < 0) return status;
    if (status > 0) return finish(s, PS_NEWTON_SINGULAR);
    status = ps_linesearch_search(&ls, &phi, s->energy, g0, ctx);
    if (status < 0) return status;
    s->n_line_search_cuts += ls.cuts;
    if (ls.reason != PS_LINESEARCH_ACCEPTED) {
      ctx->msg[0] = '\0';
      return finish(s, PS_NEWTON_LINE_SEARCH);
    }
    if (ls.step < 1.0) ps_log(ctx, 2, "    line search step %.3g\n", ls.step);
    if (ls.step < PS_SMALL_STEP) {
      if (small_steps++ == 0) rel_before = rel;
    } else {
      small_steps = 0;
    }
    double *t = s->u; /* accept: u, f <- u_trial, f_trial */
    s->u = s->u_trial;
    s->u_trial = t;
    t = s->f;
    s->f = s->f_trial;
    s->f_trial = t;
    s->energy = ls.value;
  }
}

const char *ps_newton_reason_text(int reason) {
  switch (reason) {
  case PS_NEWTON_CONVERGED: return "converged";
  case PS_NEWTON_MAX_ITER: return "no convergence within solver.max_iterations";
  case PS_NEWTON_LINE_SEARCH: return "line search failed";
  case PS_NEWTON_NOT_FINITE: return "residual not finite";
  case PS_NEWTON_SINGULAR: return "singular tangent";
  case PS_NEWTON_NO_DISSIPATION: return "no arm dissipates along the step";
  case PS_NEWTON_NO_PROGRESS: return "no progress: the residual stopped falling (a cycle among arm states)";
  case PS_NEWTON_STAGNATED:
    return "stagnated: solver.max_small_steps tiny line-search steps in a row";
  }
  return "unknown reason";
}
