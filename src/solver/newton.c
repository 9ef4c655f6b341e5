/* newton.c: solver state, Newton's method with an energy line search, the
 * linear predictor of an increment, commit/restore of the plastic state,
 * and arm breaking with re-equilibration. */
#include "ps_solver.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void ps_solver_opts_default(ps_solver_opts *o) {
  o->tolerance = 1e-8;
  o->max_iterations = 30;
  o->max_small_steps = 5;
  o->line_search = 1;
  o->linear = ps_linsolve_cholmod;
  o->reuse_factor = 1;
  o->pcg_rtol = 1e-6;
  o->pcg_max_iterations = 25;
  o->pcg_skip_arms = 0;
  o->reanalyze = 0;
  o->majorant = 1;
  o->cg_forcing_adaptive = 1;
  o->cg_forcing_max = 0.5;
  o->cg_forcing = PS_CG_FORCING_FIXED;
  o->matrix_free = 1;
  o->cg_single_precision = 1;
  o->cg_truncate = 1;
  o->threads = 0;
}

void ps_solver_free(ps_solver *s) {
  ps_linsolve_destroy(&s->ls);
  ps_linsolve_destroy(&s->ls_fallback);
  ps_linsolve_destroy(&s->ls_pre);
  ps_system_free(&s->sys_pre);
  ps_system_free(&s->sys);
  ps_arm_state_free(&s->st);
  ps_arm_state_free(&s->st_saved);
  ps_model_free(&s->model);
  ps_team_free(s->team);
  free(s->u);
  free(s->u_saved);
  free(s->u_prev);
  free(s->ubar);
  free(s->f);
  free(s->rhs);
  free(s->du);
  free(s->work);
  free(s->pcg_work);
  free(s->u_trial);
  free(s->work_dof);
  free(s->diag_saved);
  free(s->arm_state_at_factor);
  free(s->f_trial);
  memset(s, 0, sizeof *s);
}

/* evaluate at u into f/energy (and, with tangent, the tangent: its data
 * only when CG applies it matrix-free; factor_tangent assembles it) */
static int eval(ps_solver *s, const double *u, double *f, double *energy,
                int tangent, ps_ctx *ctx) {
  double t = ps_wtime();
  int want = !tangent ? PS_EVAL_FORCES
             : s->opts.reuse_factor && s->opts.matrix_free ? PS_EVAL_OPERATOR
                                                            : PS_EVAL_TANGENT;
  int status = ps_system_eval(&s->sys, &s->model, &s->st, s->P->x, u, f,
                              energy, want, ctx);
  if (s->fext && status == PS_OK)
    for (ps_int j = 0; j < s->sys.n_dof; j++) {
      f[j] -= s->lambda * s->fext[j];
      *energy -= s->lambda * s->fext[j] * u[j];
    }
  s->t_assembly += ps_wtime() - t;
  return status;
}

void ps_solver_set_forces(ps_solver *s, const double *fext) { s->fext = fext; }

/* the arms' tangent-changing state (yielding, broken) */
static inline unsigned char arm_state(const ps_arm_state *st, ps_int i) {
  return (unsigned char)(st->yielding[i] | (st->broken[i] << 1));
}

/* the changed-arm count is needed only by solver.cg_skip_arms and the
 * verbose log */
static int tracks_arm_state(const ps_solver *s, const ps_ctx *ctx) {
  return s->opts.pcg_skip_arms > 0 || ctx->verbosity >= 2;
}

static void snapshot_arm_state(ps_solver *s, const ps_ctx *ctx) {
  if (!tracks_arm_state(s, ctx)) return;
  for (ps_int i = 0; i < s->net->n_arm; i++) s->arm_state_at_factor[i] = arm_state(&s->st, i);
}

/* arms whose state differs from the snapshot, counting up to limit */
static ps_int arms_changed(const ps_solver *s, ps_int limit) {
  ps_int n = 0;
  for (ps_int i = 0; i < s->net->n_arm && n <= limit; i++)
    n += s->arm_state_at_factor[i] != arm_state(&s->st, i);
  return n;
}

/* assemble the tangent of the last evaluation into sys.A (timed as
 * assembly) */
static int assemble(ps_solver *s, ps_ctx *ctx) {
  if (s->sys.assembled) return PS_OK;
  double t = ps_wtime();
  int status = ps_system_assemble(&s->sys, ctx);
  s->t_assembly += ps_wtime() - t;
  return status;
}

/* Factor sys.A with the chosen backend; on a matrix that is not positive
 * definite fall back to UMFPACK. Returns PS_OK, PS_SINGULAR (message in
 * ctx names the particle), or fatal. */
static int factor_tangent(ps_solver *s, ps_ctx *ctx) {
  ps_int bad = -1;
  PS_CHECK(assemble(s, ctx));
  snapshot_arm_state(s, ctx);
  char name[256] = "unknown dof";
  int status = ps_linsolve_factor(&s->ls, &s->sys.A, &bad, ctx);
  if (status < 0) return status;
  if (status == PS_OK) {
    s->ls_last = &s->ls;
    s->have_factor = 1;
    return PS_OK;
  }
  if (bad >= 0 && bad < s->sys.n_free)
    ps_system_dof_name(&s->sys, s->P->x, s->sys.dof_of_free[bad], name, sizeof name);
  if (s->ls.type != ps_linsolve_umfpack) {
    ps_log(ctx, 1, "  note: tangent %s at %s: UMFPACK for this system\n",
           status == PS_NOT_POSDEF ? "not positive definite" : "singular", name);
    if (!s->ls_fallback.type)
      PS_CHECK(ps_linsolve_create(&s->ls_fallback, ps_linsolve_umfpack, ctx));
    status = ps_linsolve_factor(&s->ls_fallback, &s->sys.A, &bad, ctx);
    if (status < 0) return status;
    s->n_fallback++;
    if (status == PS_OK) {
      s->ls_last = &s->ls_fallback;
      s->have_factor = 1;
      return PS_OK;
    }
  }
  s->have_factor = 0;
  return ps_error(ctx, PS_SINGULAR, "tangent stiffness is singular (%s)", name);
}

int ps_solver_create(ps_solver *s, const ps_particles *P,
                     const ps_network *net, const ps_model_type *type,
                     const ps_material *mat, const unsigned char *fixed,
                     const double *ubar, const ps_solver_opts *opts,
                     ps_ctx *ctx) {
  int status = PS_OK, d = net->dim;
  memset(s, 0, sizeof *s);
  s->P = P;
  s->net = net;
  s->opts = *opts;
  ps_int nd = (ps_int)d * net->n_particle;
  /* a quick necessary condition: each direction has a prescribed dof */
  for (int k = 0; k < d; k++) {
    int any = 0;
    for (ps_int a = 0; a < net->n_particle && !any; a++) any = fixed[a * d + k];
    if (!any)
      return ps_error(ctx, PS_ERR_INPUT,
                      "the model has no supports in direction %c: no particle has "
                      "a prescribed %c displacement (see loading.boundary)",
                      "xyz"[k], "xyz"[k]);
  }
  PS_CHECK_GOTO(ps_model_create(&s->model, type, P, net, mat, ctx));
  PS_CHECK_GOTO(ps_system_create_pattern(&s->sys, net, fixed, type->family_coupling, ctx));
  PS_CHECK_GOTO(ps_arm_state_alloc(&s->st, net->n_arm, ctx));
  PS_CHECK_GOTO(ps_arm_state_alloc(&s->st_saved, net->n_arm, ctx));
  int threads = opts->threads > 0 ? opts->threads : ps_cpu_count();
  PS_CHECK_GOTO(ps_team_create(&s->team, threads < PS_MAX_THREADS ? threads : PS_MAX_THREADS,
                               ctx));
  s->sys.team = s->team;
  PS_CHECK_GOTO(ps_linsolve_create(&s->ls, opts->linear, ctx));
  s->ls.team = s->team;
  s->ls.reanalyze = opts->reanalyze;
  s->ls.single_precision = opts->cg_single_precision;
  if (opts->majorant && type->family_coupling && opts->reuse_factor) {
    PS_CHECK_GOTO(ps_system_create_pattern(&s->sys_pre, net, fixed, 0, ctx));
    PS_CHECK_GOTO(ps_linsolve_create(&s->ls_pre, ps_linsolve_cholmod, ctx));
    s->ls_pre.single_precision = opts->cg_single_precision;
    s->ls_pre.team = s->team;
    /* a majorant is factored when CG has failed, for the Newton systems
     * that follow (~240 CG iterations per factor in the paper's sweep):
     * its float copy (0.06 s at 20k, ~6 CG iterations) pays from the
     * first solve, unlike the two-horizon factor of an elastic solve */
    s->ls_pre.single_after = 0;
  }
  ps_int nf = s->sys.n_free;
  s->u = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->u_saved = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->u_prev = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->work_dof = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->ubar = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->f = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->u_trial = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->f_trial = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->rhs = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->du = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->work = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->diag_saved = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->arm_state_at_factor = ps_calloc((size_t)net->n_arm + 1, 1, ctx);
  s->pcg_work = ps_calloc((size_t)(4 * nf), sizeof *s->u, ctx);
  if (!s->pcg_work || !s->u_prev || !s->work_dof || !s->u || !s->u_saved || !s->ubar || !s->f || !s->u_trial || !s->f_trial ||
      !s->rhs || !s->du || !s->work || !s->diag_saved ||
      !s->arm_state_at_factor) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  for (ps_int j = 0; j < nd; j++) s->ubar[j] = fixed[j] ? ubar[j] : 0.0;
  /* support check: the tangent at rest must be nonsingular */
  PS_CHECK_GOTO(eval(s, s->u, s->f, &s->energy, 1, ctx));
  status = factor_tangent(s, ctx);
  if (status > 0) {
    char msg[sizeof ctx->msg];
    snprintf(msg, sizeof msg, "%s", ctx->msg);
    status = ps_error(ctx, PS_ERR_INPUT,
                      "the model is not properly supported: %s at rest. A rigid-body "
                      "motion is free or a particle is held by no arm; check "
                      "loading.boundary",
                      msg);
    goto cleanup;
  }
  if (status < 0) goto cleanup;
  ps_solver_commit(s);
cleanup:
  if (status < 0) ps_solver_free(s);
  return status;
}

/* du = K_ff^-1 rhs by CG with the factor held by ls as preconditioner, at
 * most maxit iterations, counted into the run's CG statistics. Returns
 * PS_OK, PS_NOT_POSDEF (negative curvature: du is CG's truncated
 * iterate), PS_DIVERGED (not converged), or fatal. */
static int pcg(ps_solver *s, ps_linsolve *ls, int maxit, int *its, ps_ctx *ctx) {
  double t0 = ps_wtime();
  *its = 0;
  ps_operator K = s->opts.matrix_free ? ps_system_operator(&s->sys) : ps_csc_operator(&s->sys.A);
  int status = ps_linsolve_pcg(ls, &K, s->rhs, s->du, s->cg_rtol, maxit,
                               s->pcg_work, its, ctx);
  s->t_pcg += ps_wtime() - t0;
  s->pcg_iterations += *its;
  return status;
}

/* 1 when CG's status says it met negative curvature and opts.cg_truncate
 * takes its iterate as the direction (counted and logged), else 0. Near a
 * running crack tip the tangent can be indefinite; Steihaug's truncated CG
 * then still gives a descent direction for the line search, where a fresh
 * factorisation would fail in CHOLMOD and cost an UMFPACK LU (and often a
 * shifted factorisation after it, as UMFPACK's step points uphill). */
static int truncated(ps_solver *s, int status, int its, const char *with, ps_ctx *ctx) {
  if (status != PS_NOT_POSDEF || !s->opts.cg_truncate) return 0;
  s->pcg_truncated++;
  ps_log(ctx, 2, "    CG with %s met negative curvature at iteration %d: truncated "
                 "direction\n", with, its + 1);
  return 1;
}

/* Factor the one-horizon majorant of the tangent of the last evaluation
 * (opts.majorant); on success it is the factor CG reuses. Returns PS_OK,
 * PS_DIVERGED (not positive definite: the caller factors the tangent), or
 * fatal. */
static int factor_majorant(ps_solver *s, ps_ctx *ctx) {
  ps_int bad = -1;
  PS_CHECK(ps_system_assemble_majorant(&s->sys_pre, &s->sys, ctx));
  int status = ps_linsolve_factor(&s->ls_pre, &s->sys_pre.A, &bad, ctx);
  if (status < 0) return status;
  if (status != PS_OK) {
    ps_log(ctx, 2, "    majorant not positive definite: factoring the tangent\n");
    return PS_DIVERGED;
  }
  s->ls_last = &s->ls_pre;
  s->have_factor = 1;
  snapshot_arm_state(s, ctx);
  return PS_OK;
}

/* du = K_ff^-1 rhs by CG preconditioned with a fresh factor of the
 * one-horizon majorant of the tangent (opts.majorant), capped at
 * pcg_max_iterations. Returns PS_OK, PS_DIVERGED when the majorant is not
 * positive definite or CG does not converge (the caller factors K), or
 * fatal. */
static int solve_by_majorant(ps_solver *s, ps_ctx *ctx) {
  int status = factor_majorant(s, ctx);
  if (status != PS_OK) return status;
  int its;
  status = pcg(s, &s->ls_pre, s->opts.pcg_max_iterations, &its, ctx);
  if (status < 0) return status;
  if (truncated(s, status, its, "a fresh majorant factor", ctx)) status = PS_OK;
  if (status == PS_OK) {
    ps_log(ctx, 2, "    CG with a fresh majorant factor: %d iterations\n", its);
    return PS_OK;
  }
  s->pre_failures++;
  ps_log(ctx, 2, "    CG with a fresh majorant factor did not converge in %d iterations: "
                 "factoring the tangent\n", its);
  return PS_DIVERGED;
}

/* du = K_ff^-1 rhs for the tangent just assembled: CG preconditioned by
 * the last factor when allowed, else (or when CG fails) a fresh factor.
 * Returns PS_OK, PS_SINGULAR, or fatal. */
static int solve_tangent(ps_solver *s, ps_ctx *ctx) {
  if (s->opts.reuse_factor && s->have_factor) {
    /* When a failed CG is followed by a factorisation of the tangent
     * itself, CG pays while its iterations cost less than that
     * factorisation: cap them at (mean factorisation time) / (mean CG
     * iteration time). Not when a fresh majorant follows (opts.majorant):
     * CG with it needs about as many iterations as with an old factor
     * (12.9 against 13.0 per solve at 5k), so giving up early only adds
     * factorisations; with faster factorisations the cap fell to ~14 at
     * 20k and the runs near the plastic limit factored the majorant 3x
     * as often (c/750: 94 -> 349, 194 -> 293 s). */
    int maxit = s->opts.pcg_max_iterations;
    const ps_linsolve_stats *ls = &s->ls_last->stats;
    if (!s->sys_pre.net && s->pcg_iterations > 0 && ls->n_factor > 0) {
      double t_it = s->t_pcg / (double)s->pcg_iterations;
      double t_fac = ls->t_factor / (double)ls->n_factor;
      double cap = t_fac / t_it;
      if (cap < maxit) maxit = cap < 2 ? 2 : (int)cap;
    }
    /* each arm that yielded, unloaded or broke since the factorisation
     * changes the tangent by a rank-one term; with solver.cg_skip_arms > 0
     * CG is not tried when that many changed (in exact arithmetic CG may
     * need one iteration per term; in practice it often needs far fewer,
     * doc/performance.md, hence off by default) */
    ps_int limit = s->opts.pcg_skip_arms, changed = -1;
    if (tracks_arm_state(s, ctx)) changed = arms_changed(s, limit > 0 ? limit : s->net->n_arm);
    if (limit > 0 && changed >= limit) {
      s->pcg_skipped++;
      ps_log(ctx, 2, "    %lld+ arms changed state since the last factorisation: "
                     "refactoring\n", (long long)changed);
      goto refactor;
    }
    int its;
    int status = pcg(s, (ps_linsolve *)s->ls_last, maxit, &its, ctx);
    if (status < 0) return status;
    s->pcg_solves++;
    if (truncated(s, status, its, "the old factor", ctx)) return PS_OK;
    if (status == PS_OK) {
      ps_log(ctx, 2, "    CG with the old factor: %d iterations (%lld arms changed state)\n",
             its, (long long)changed);
      return PS_OK;
    }
    s->pcg_failures++;
    ps_log(ctx, 2, "    CG with the old factor did not converge in %d iterations (%lld "
                   "arms changed state): refactoring\n", its, (long long)changed);
    if (s->sys_pre.net) { /* a fresh majorant, also when the old factor was one */
      int status = solve_by_majorant(s, ctx);
      if (status <= 0) return status;
    }
  }
refactor:;
  int status = factor_tangent(s, ctx);
  if (status != PS_OK) return status;
  return ps_linsolve_solve((ps_linsolve *)s->ls_last, s->rhs, s->du, ctx);
}

/* A descent direction where the tangent is indefinite (near a running
 * crack tip, a Newton step of UMFPACK on K can point uphill in energy):
 * du = (K + mu diag K)^-1 rhs, mu raised tenfold from 1e-4 until the
 * shifted matrix factors as positive definite (Levenberg-Marquardt).
 * Returns PS_OK, PS_SINGULAR (no shift up to mu = 10 worked), or fatal. */
static int shifted_direction(ps_solver *s, ps_ctx *ctx) {
  ps_csc *A = &s->sys.A;
  ps_int n = A->n, bad;
  PS_CHECK(assemble(s, ctx));
  for (ps_int k = 0; k < n; k++) s->diag_saved[k] = A->x[A->p[k + 1] - 1];
  int status = PS_SINGULAR;
  for (double mu = 1e-4; mu <= 10.0 && status != PS_OK; mu *= 10.0) {
    for (ps_int k = 0; k < n; k++)
      A->x[A->p[k + 1] - 1] = s->diag_saved[k] * (1.0 + mu) + (s->diag_saved[k] == 0.0);
    status = ps_linsolve_factor(&s->ls, A, &bad, ctx);
    if (status < 0) break;
    if (status == PS_OK) ps_log(ctx, 2, "    indefinite tangent: shifted by %.0e diag\n", mu);
  }
  for (ps_int k = 0; k < n; k++) A->x[A->p[k + 1] - 1] = s->diag_saved[k];
  if (status != PS_OK) {
    s->have_factor = 0;
    return status < 0 ? status
                      : ps_error(ctx, PS_SINGULAR, "no positive definite shift of the tangent");
  }
  s->ls_last = &s->ls;
  s->have_factor = 1;
  s->n_shifted++;
  snapshot_arm_state(s, ctx);
  return ps_linsolve_solve(&s->ls, s->rhs, s->du, ctx);
}

static double norm_free(const ps_system *sys, const double *f) {
  double s = 0;
  for (ps_int k = 0; k < sys->n_free; k++) {
    double v = f[sys->dof_of_free[k]];
    s += v * v;
  }
  return sqrt(s);
}

static double norm_fixed(const ps_system *sys, const double *f) {
  double s = 0;
  for (ps_int j = 0; j < sys->n_dof; j++)
    if (sys->fixed[j]) s += f[j] * f[j];
  return sqrt(s);
}

/* The relative CG tolerance of Newton iteration `it` at the relative
 * residual rel (rel_prev: the last iteration's; *eta: the last forcing
 * term in, this one out; adaptive rule only): by the adaptive rule when
 * `adaptive`, else by the fixed rule with opts.cg_forcing (which stays at
 * its default PS_CG_FORCING_FIXED when the case chose adaptive, for a
 * solve that has handed over). */
static double cg_tolerance(const ps_solver_opts *o, int adaptive, int it, double rel,
                           double rel_prev, double *eta) {
  double t;
  if (adaptive) {
    /* Eisenstat-Walker choice 2: as loose as the last Newton step was
     * slow to converge, no tighter than the safeguard from the last
     * eta (a single lucky step does not force an exact solve) */
    double e = o->cg_forcing_max;
    if (it > 0 && rel_prev > 0) {
      e = PS_EW_GAMMA * pow(rel / rel_prev, PS_EW_ALPHA);
      double guard = PS_EW_GAMMA * pow(*eta, PS_EW_ALPHA);
      if (guard > PS_EW_SAFEGUARD) e = fmax(e, guard);
      e = fmin(e, o->cg_forcing_max);
    }
    *eta = e;
    t = fmax(o->pcg_rtol, e);
  } else {
    /* max(cg_tolerance, min(1e-2, cg_forcing x rel)) */
    t = fmax(o->pcg_rtol, fmin(PS_CG_FORCING_MAX, o->cg_forcing * rel));
    if (o->cg_forcing <= 0) return t;
  }
  /* never tighter than the Newton tolerance asks for: a full step leaves
   * the linear residual t x rel (plus a quadratic term), so t =
   * PS_CG_OVERSOLVE x tolerance / rel already converges (Kelley's
   * safeguard against oversolving the last iteration) */
  return fmax(t, PS_CG_OVERSOLVE * o->tolerance / rel);
}

int ps_newton_solve(ps_solver *s, ps_ctx *ctx) {
  const ps_system *sys = &s->sys;
  ps_int nf = sys->n_free, nd = sys->n_dof;
  PS_CHECK(eval(s, s->u, s->f, &s->energy, 0, ctx));
  int small_steps = 0;     /* line-search steps < PS_SMALL_STEP in a row */
  double rel_before = 0.0; /* the residual before the first of them */
  double rel_prev = 0.0, eta = 0.0; /* the forcing term's history */
  /* the adaptive rule's loose CG solves pay while Newton converges slowly
   * anyway, but a solve needs more, cheaper iterations with it; one that
   * reaches max_iterations under it is not given up but continues with
   * the fixed rule's tight CG solves for up to max_iterations more (the
   * paper's c/500 run otherwise stalled in a breaking round that the
   * fixed rule converges, doc/performance.md) */
  int adaptive = s->opts.cg_forcing_adaptive, budget = s->opts.max_iterations;
  for (int it = 0;; it++) {
    double rn = norm_free(sys, s->f), ref = norm_fixed(sys, s->f);
    double rel = ref > 0 ? rn / ref : rn;
    s->last_iterations = it;
    s->last_residual = rel;
    ps_log(ctx, 2, "    newton %2d  |r|/|R| = %.3e  energy = %.10g\n", it, rel, s->energy);
    if (!isfinite(rel) || !isfinite(s->energy)) {
      s->last_reason = PS_NEWTON_NOT_FINITE;
      return PS_DIVERGED;
    }
    if (rel <= s->opts.tolerance || rn == 0.0) {
      s->last_reason = PS_NEWTON_CONVERGED;
      return PS_OK;
    }
    if (it >= budget && adaptive) {
      adaptive = 0;
      budget = s->opts.max_iterations > INT_MAX - it ? INT_MAX : it + s->opts.max_iterations;
      small_steps = 0; /* the fixed rule's steps are judged afresh */
      s->n_handovers++;
      ps_log(ctx, 2, "    adaptive CG tolerance: max_iterations reached, fixed rule from here\n");
    }
    if (it >= budget) {
      s->last_reason = PS_NEWTON_MAX_ITER;
      return PS_DIVERGED;
    }
    /* stagnation: near a plastic limit load the line search finds only
     * steps of 1e-3..1e-9 along Newton directions (arms at the kink of the
     * perfectly plastic law), and the residual creeps (1.04e-5 ->
     * 1.03e-5 over 20 iterations at 20k, c/1000); such a solve never
     * converged in the runs we logged, so it fails now, not at
     * max_iterations, and the path cuts its increment sooner */
    if (s->opts.max_small_steps > 0 && small_steps >= s->opts.max_small_steps &&
        rel > 0.9 * rel_before) {
      s->last_reason = PS_NEWTON_STAGNATED;
      s->n_stagnated++;
      return PS_DIVERGED;
    }
    PS_CHECK(eval(s, s->u, s->f, &s->energy, 1, ctx));
    for (ps_int k = 0; k < nf; k++) s->rhs[k] = -s->f[sys->dof_of_free[k]];
    /* inexact Newton: far from the solution a rough direction does as
     * well (the line search guards it) */
    s->cg_rtol = cg_tolerance(&s->opts, adaptive, it, rel, rel_prev, &eta);
    rel_prev = rel;
    int status = solve_tangent(s, ctx);
    if (status < 0) return status;
    if (status > 0) {
      s->last_reason = PS_NEWTON_SINGULAR;
      return PS_DIVERGED;
    }
    s->newton_iterations++;
    /* energy line search: dE/ds at s = 0 is f . du */
    double g0 = 0, E0 = s->energy, step = 1.0, E1 = E0;
    for (ps_int k = 0; k < nf; k++) g0 += s->f[sys->dof_of_free[k]] * s->du[k];
    if (g0 >= 0 && s->opts.line_search) { /* uphill: the tangent is indefinite */
      status = shifted_direction(s, ctx);
      if (status < 0) return status;
      if (status > 0) {
        s->last_reason = PS_NEWTON_SINGULAR;
        return PS_DIVERGED;
      }
      g0 = 0;
      for (ps_int k = 0; k < nf; k++) g0 += s->f[sys->dof_of_free[k]] * s->du[k];
    }
    int accepted = 0;
    for (int ls = 0; ls < 16; ls++) {
      memcpy(s->u_trial, s->u, (size_t)nd * sizeof *s->u);
      for (ps_int k = 0; k < nf; k++) s->u_trial[sys->dof_of_free[k]] += step * s->du[k];
      status = eval(s, s->u_trial, s->f_trial, &E1, 0, ctx);
      if (status < 0 && status != PS_ERR_SOLVER) return status;
      int finite = status == PS_OK && isfinite(E1);
      if (finite && !s->opts.line_search) {
        accepted = 1;
        break;
      }
      /* the energy change. Within PS_ENERGY_RESOLUTION |E0| it is below
       * the round-off of the energy (a sum over all arms) and its sign
       * means nothing: near a plastic limit, where a Newton step changes
       * the energy by ~1e-11 |E0| already at residuals ~1e-5, the line
       * search then cut steps at random and Newton stalled. There the
       * trapezoid rule on the directional derivatives g = f . du, exact
       * for a quadratic along du and free of cancellation, stands in. */
      double dE = E1 - E0;
      if (finite && fabs(dE) <= PS_ENERGY_RESOLUTION * fabs(E0)) {
        double g1 = 0;
        for (ps_int k = 0; k < nf; k++) g1 += s->f_trial[sys->dof_of_free[k]] * s->du[k];
        dE = 0.5 * step * (g0 + g1);
      }
      if (finite && dE <= 1e-4 * step * g0) { /* Armijo */
        accepted = 1;
        break;
      }
      /* backtrack: minimiser of the quadratic through E0, g0 and dE (with
       * the trapezoid: the zero of the secant of g) */
      double next = 0.5 * step;
      if (finite) {
        double denom = 2.0 * (dE - g0 * step);
        if (denom > 0) next = -g0 * step * step / denom;
        if (next < 0.1 * step) next = 0.1 * step;
        if (next > 0.5 * step) next = 0.5 * step;
      }
      step = next;
      s->n_line_search_cuts++;
    }
    if (!accepted) {
      s->last_reason = PS_NEWTON_LINE_SEARCH;
      ctx->msg[0] = '\0';
      return PS_DIVERGED;
    }
    if (step < 1.0) ps_log(ctx, 2, "    line search step %.3g\n", step);
    if (step < PS_SMALL_STEP) {
      if (small_steps++ == 0) rel_before = rel;
    } else {
      small_steps = 0;
    }
    double *t = s->u;
    s->u = s->u_trial;
    s->u_trial = t;
    t = s->f;
    s->f = s->f_trial;
    s->f_trial = t;
    s->energy = E1;
  }
}

void ps_solver_commit(ps_solver *s) {
  ps_int na = s->net->n_arm;
  memcpy(s->st.eps_p, s->st.eps_p_trial, (size_t)(2 * na) * sizeof *s->st.eps_p);
  ps_arm_state_copy(&s->st_saved, &s->st);
  memcpy(s->u_saved, s->u, (size_t)s->sys.n_dof * sizeof *s->u);
}

void ps_solver_restore(ps_solver *s) {
  ps_arm_state_copy(&s->st, &s->st_saved);
  memcpy(s->u, s->u_saved, (size_t)s->sys.n_dof * sizeof *s->u);
}

int ps_solver_step(ps_solver *s, double lambda, ps_ctx *ctx) {
  const ps_system *sys = &s->sys;
  double lambda0 = s->lambda, dl = lambda - lambda0;
  ps_int nd = sys->n_dof, nf = sys->n_free;
  int secant = s->have_prev && lambda0 > s->lambda_prev;
  double *u_start = s->u_trial; /* keep the start for the secant history */
  memcpy(u_start, s->u, (size_t)nd * sizeof *s->u);
  if (secant) {
    /* u += dl/(lambda0 - lambda_prev) (u - u_prev) */
    double r = dl / (lambda0 - s->lambda_prev);
    for (ps_int k = 0; k < nf; k++) {
      ps_int j = sys->dof_of_free[k];
      s->u[j] += r * (s->u[j] - s->u_prev[j]);
    }
  } else if (s->have_factor) {
    /* predictor: K_ff du_f = -(r_f + K_fp du_p) with the last factor */
    for (ps_int j = 0; j < nd; j++) s->work_dof[j] = sys->fixed[j] ? dl * s->ubar[j] : 0.0;
    ps_system_coupling(&s->sys, s->work_dof, s->work);
    for (ps_int k = 0; k < nf; k++) {
      ps_int j = sys->dof_of_free[k];
      s->rhs[k] = -(s->f[j] + s->work[k]) + (s->fext ? dl * s->fext[j] : 0.0);
    }
    PS_CHECK(ps_linsolve_solve((ps_linsolve *)s->ls_last, s->rhs, s->du, ctx));
    for (ps_int k = 0; k < nf; k++) s->u[sys->dof_of_free[k]] += s->du[k];
  }
  for (ps_int j = 0; j < nd; j++)
    if (sys->fixed[j]) s->u[j] = lambda * s->ubar[j];
  s->lambda = lambda;
  memcpy(s->u_prev, u_start, (size_t)nd * sizeof *s->u); /* u_trial is reused */
  double lambda_start = lambda0;
  int status = ps_newton_solve(s, ctx);
  if (status == PS_OK) {
    s->lambda_prev = lambda_start;
    s->have_prev = 1;
  } else {
    s->have_prev = 0;
  }
  if (status == PS_DIVERGED) {
    ps_solver_restore(s);
    s->lambda = lambda0;
    /* a fresh factor at the restored state for the next try: of the
     * majorant when there is one (it serves CG as well as the tangent's
     * own factor does, and costs a sixth: the failed increments near the
     * plastic limit load each paid a two-horizon factorisation, 1.3 s at
     * 20k, and CG iterations 3x dearer after it) */
    PS_CHECK(eval(s, s->u, s->f, &s->energy, 1, ctx));
    int st2 = s->sys_pre.net ? factor_majorant(s, ctx) : PS_DIVERGED;
    if (st2 > 0) st2 = factor_tangent(s, ctx);
    if (st2 < 0) return st2;
  }
  return status;
}

int ps_solver_break_round(ps_solver *s, ps_int max_count, ps_int *n_broken,
                          ps_ctx *ctx) {
  PS_CHECK(s->model.type->break_arms(&s->model, &s->st, max_count, n_broken, ctx));
  if (*n_broken == 0) return PS_OK;
  s->have_prev = 0; /* do not extrapolate across a break */
  ps_log(ctx, 2, "    %lld arms broke, re-equilibrating\n", (long long)*n_broken);
  int status = ps_newton_solve(s, ctx);
  if (status != PS_OK) return status;
  ps_solver_commit(s);
  return PS_OK;
}

int ps_solver_evaluate(ps_solver *s, ps_ctx *ctx) {
  return eval(s, s->u, s->f, &s->energy, 0, ctx);
}

ps_int ps_solver_count_yielding(const ps_solver *s) {
  ps_int n = 0;
  for (ps_int i = 0; i < s->net->n_arm; i++) n += s->st.yielding[i] && !s->st.broken[i];
  return n;
}

const char *ps_newton_reason_text(int reason) {
  switch (reason) {
  case PS_NEWTON_CONVERGED: return "converged";
  case PS_NEWTON_MAX_ITER: return "no convergence within solver.max_iterations";
  case PS_NEWTON_LINE_SEARCH: return "line search failed";
  case PS_NEWTON_NOT_FINITE: return "residual not finite";
  case PS_NEWTON_SINGULAR: return "singular tangent";
  case PS_NEWTON_STAGNATED:
    return "stagnated: solver.max_small_steps tiny line-search steps in a row";
  }
  return "unknown reason";
}

void ps_solver_get_stats(const ps_solver *s, ps_solver_stats *st) {
  memset(st, 0, sizeof *st);
  st->newton_iterations = s->newton_iterations;
  st->factorisations = s->ls.stats.n_factor + s->ls_fallback.stats.n_factor;
  st->n_fallback = s->n_fallback;
  st->solves = s->ls.stats.n_solve + s->ls_fallback.stats.n_solve;
  st->pcg_iterations = s->pcg_iterations;
  st->pcg_failures = s->pcg_failures;
  st->pcg_skipped = s->pcg_skipped;
  st->majorant_factorisations = s->ls_pre.stats.n_factor;
  st->majorant_failures = s->pre_failures;
  st->shifted_steps = s->n_shifted;
  st->cg_truncated = s->pcg_truncated;
  st->stagnated = s->n_stagnated;
  st->handovers = s->n_handovers;
  st->line_search_cuts = s->n_line_search_cuts;
  st->n_free = s->sys.n_free;
  st->threads = ps_team_size(s->team);
  st->serial_share = s->sys_pre.net ? s->ls_pre.stats.serial_share : s->ls.stats.serial_share;
  st->nnz_tangent = s->sys.A.p ? (double)s->sys.A.p[s->sys.n_free] : 0.0;
  st->nnz_factor = s->ls.stats.nnz_factor;
  st->flops_factor = s->ls.stats.flops_factor;
  st->nnz_majorant_factor = s->ls_pre.stats.nnz_factor;
  st->t_assembly = s->t_assembly;
  st->t_analyze = s->ls.stats.t_analyze + s->ls_fallback.stats.t_analyze;
  st->t_factor = s->ls.stats.t_factor + s->ls_fallback.stats.t_factor;
  st->t_solve = s->ls.stats.t_solve + s->ls_fallback.stats.t_solve;
  st->t_majorant_factor = s->ls_pre.stats.t_factor;
  st->t_cg = s->t_pcg;
}

double ps_solver_lambda(const ps_solver *s) { return s->lambda; }
const double *ps_solver_u(const ps_solver *s) { return s->u; }
const double *ps_solver_arm_tension(const ps_solver *s) { return s->sys.T; }
const double *ps_solver_arm_direction(const ps_solver *s) { return s->sys.q; }
const double *ps_solver_arm_elongation(const ps_solver *s) { return s->sys.dl; }
const ps_arm_state *ps_solver_arm_state(const ps_solver *s) { return &s->st; }
int ps_solver_last_reason(const ps_solver *s) { return s->last_reason; }
double ps_solver_last_residual(const ps_solver *s) { return s->last_residual; }
