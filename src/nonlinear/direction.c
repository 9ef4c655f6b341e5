/* direction.c: the Newton direction du = K_ff^-1 rhs (rhs = -r_free) and
 * the factors behind it. In order of cost:
 * It sees the problem only through s->prob (ps_nl_problem.h): K is its
 * tangent (applied by apply, a matrix by assemble), the arms' state its
 * mark/changed.
 *   1. CG on K (matrix-free), preconditioned by the last factor, of an
 *      earlier tangent or of its majorant: K changes between Newton
 *      iterations by one rank-one term per arm that yielded, unloaded or
 *      broke, so an old factor is a good preconditioner;
 *   2. (models with family terms) CG preconditioned by a fresh factor of
 *      the one-horizon majorant P >= K (the problem's assemble with
 *      majorant 1; for peridynamics ps_system_assemble_majorant, whose
 *      spectrum bound is in ps_assembly.h). Such a model's first Newton
 *      system is solved this way too, and the majorant's factor is made
 *      again once lagging it has cost more than a new one
 *      (lagging_costs_more): its factor is 2-3x smaller than K's, so its
 *      solves are that much cheaper, and CG needs only a few more
 *      iterations with it;
 *   3. a fresh factor of K itself, by UMFPACK where CHOLMOD finds K not
 *      positive definite;
 * and, when du points uphill in energy (K indefinite), the shifted
 * tangent K + mu diag K (ps_nl_shifted_direction). CG that meets negative
 * curvature returns Steihaug's truncated iterate, a descent direction
 * (opts.cg_truncate). */
#include "solver_impl.h"

#include <math.h>

/* the count of changes since the last factor (ps_nl_problem changed) is
 * needed only by opts.pcg_skip_arms and the verbose log */
static int tracks_arm_state(const ps_solver *s, const ps_ctx *ctx) {
  /* (for the log of one process only where the count is a collective:
   * processes of a run may log at different levels) */
  return s->opts.pcg_skip_arms > 0 ||
         (ctx->verbosity >= 2 && !(ctx->comm && ctx->comm->size > 1));
}

/* record the problem's tangent-changing state at a new factor */
static void snapshot_arm_state(ps_solver *s, const ps_ctx *ctx) {
  s->its_since_factor = s->solves_since_factor = 0;
  if (!tracks_arm_state(s, ctx)) return;
  s->prob.ops->mark(s->prob.data);
}

/* the free tangent (majorant 0) or its majorant (1) of the last
 * evaluation with one, as a matrix */
static int assemble(ps_solver *s, int majorant, ps_csc **A, ps_ctx *ctx) {
  return s->prob.ops->assemble(s->prob.data, majorant, A, ctx);
}

/* y = K_ff x, the problem's product, as an operator for CG */
static void apply_tangent(void *data, const double *x, double *y) {
  const ps_nl_problem *p = data;
  p->ops->apply(p->data, x, y);
}

int ps_nl_factor_tangent(ps_solver *s, ps_ctx *ctx) {
  ps_int bad = -1;
  ps_csc *A = NULL;
  PS_CHECK(assemble(s, 0, &A, ctx));
  snapshot_arm_state(s, ctx);
  char name[256] = "unknown dof";
  /* the first factor to try: CHOLMOD's LL^T; for lu_first LDL^T without
   * pivoting where it pays, else none (straight to UMFPACK below) */
  ps_linsolve *first = &s->ls;
  const int share = s->ls.global_row != NULL; /* a distributed model's */
  if (s->lu_first && !share) {
    first = s->ldl_ok ? &s->ls_ldl : NULL;
    if (first && !first->type) {
      PS_CHECK(ps_linsolve_create(first, ps_linsolve_cholmod_ldl, ctx));
      first->keep_matrix = s->keep_factors;
    }
  }
  int status = first ? ps_linsolve_factor(first, A, &bad, ctx) : PS_NOT_POSDEF;
  if (status < 0) return status;
  if (status == PS_OK) {
    s->ls_last = first;
    s->have_factor = 1;
    s->indefinite = first != &s->ls; /* LDL^T: lu_first on an indefinite K */
    s->lu_current = s->indefinite;
    s->shifted_current = 0;
    return PS_OK;
  }
  if (share && status == PS_NOT_POSDEF) {
    /* a share's factor is MUMPS's LDL^T of the whole system, which
     * solves the indefinite one too; the one-process fallbacks below
     * would factor this process's rows only */
    s->ls_last = first;
    s->have_factor = 1;
    s->indefinite = s->lu_current = 1;
    s->shifted_current = 0;
    return PS_OK;
  }
  if (bad >= 0 && bad < s->prob.n_free) s->prob.ops->dof_name(s->prob.data, bad, name, sizeof name);
  if (s->ls.type != ps_linsolve_umfpack && !share) {
    /* once a run at level 1: softening arms make it routine */
    if (!s->lu_first)
      ps_log(ctx, s->n_fallback ? 2 : 1, "  note: tangent %s at %s: UMFPACK for this system\n",
             status == PS_NOT_POSDEF ? "not positive definite" : "singular", name);
    if (!s->ls_fallback.type) {
      PS_CHECK(ps_linsolve_create(&s->ls_fallback, ps_linsolve_umfpack, ctx));
      s->ls_fallback.keep_matrix = s->keep_factors;
    }
    status = ps_linsolve_factor(&s->ls_fallback, A, &bad, ctx);
    if (status < 0) return status;
    s->n_fallback++;
    if (status == PS_OK) {
      s->ls_last = &s->ls_fallback;
      s->have_factor = 1;
      s->indefinite = s->lu_current = 1;
      s->shifted_current = 0;
      return PS_OK;
    }
  }
  s->have_factor = 0;
  return ps_error(ctx, PS_SINGULAR, "tangent stiffness is singular (%s)", name);
}

/* du = K_ff^-1 rhs by CG preconditioned by the factor held by ls, to the
 * relative residual s->cg_rtol in at most maxit iterations (counted and
 * timed). Returns PS_OK, PS_NOT_POSDEF (negative curvature: du is CG's
 * truncated iterate), PS_DIVERGED (not converged), or fatal. */
static int pcg(ps_solver *s, ps_linsolve *ls, int maxit, int *its, ps_ctx *ctx) {
  double t0 = ps_wtime();
  *its = 0;
  ps_operator K = {s->prob.n_free, apply_tangent, &s->prob, s->prob.owned_free};
  int status = ps_linsolve_pcg(ls, &K, s->rhs, s->du, s->cg_rtol, maxit,
                               s->pcg_work, its, ctx);
  s->t_pcg += ps_wtime() - t0;
  s->pcg_iterations += *its;
  if (s->solves_since_factor == 0) s->its_fresh = *its;
  s->its_since_factor += *its;
  s->solves_since_factor++;
  return status;
}

/* 1 when CG met negative curvature (status PS_NOT_POSDEF) and
 * opts.cg_truncate takes its iterate as the direction (counted, logged),
 * else 0. Steihaug: the iterate before the direction of negative
 * curvature is a descent direction for the line search, where a factor
 * of the indefinite K would fail in CHOLMOD. */
static int truncated(ps_solver *s, int status, int its, const char *with, ps_ctx *ctx) {
  if (status != PS_NOT_POSDEF || !s->opts.cg_truncate) return 0;
  s->pcg_truncated++;
  ps_log(ctx, 2, "    CG with %s met negative curvature at iteration %d: truncated "
                 "direction\n", with, its + 1);
  return 1;
}

/* Factor the one-horizon majorant of the tangent of the last evaluation;
 * on success it is the factor CG reuses. Returns PS_OK, PS_DIVERGED (not
 * positive definite: the caller factors the tangent), or fatal. */
static int factor_majorant(ps_solver *s, ps_ctx *ctx) {
  ps_int bad = -1;
  ps_csc *P = NULL;
  PS_CHECK(assemble(s, 1, &P, ctx));
  int status = ps_linsolve_factor(&s->ls_pre, P, &bad, ctx);
  if (status < 0) return status;
  if (status != PS_OK) {
    ps_log(ctx, 2, "    majorant not positive definite: factoring the tangent\n");
    return PS_DIVERGED;
  }
  s->ls_last = &s->ls_pre;
  s->have_factor = 1;
  s->indefinite = s->lu_current = s->shifted_current = 0;
  snapshot_arm_state(s, ctx);
  return PS_OK;
}

int ps_nl_fresh_factor(ps_solver *s, ps_ctx *ctx) {
  int status = s->have_majorant ? factor_majorant(s, ctx) : PS_DIVERGED;
  if (status > 0) status = ps_nl_factor_tangent(s, ctx);
  return status;
}

/* du = K_ff^-1 rhs by CG preconditioned by a fresh factor of the majorant,
 * at most pcg_max_iterations. Returns PS_OK, PS_DIVERGED when the
 * majorant is not positive definite or CG does not converge (the caller
 * factors K), or fatal. */
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

/* How many CG iterations with the current factor cost as much as a new
 * factorisation, from the factor's own counts, not from timings (so
 * that a run's result does not depend on the machine's load): a CG
 * iteration is dominated by the two triangular solves, 4 nnz(L) flops,
 * and a supernodal factorisation runs its flops_factor about
 * PS_FACTOR_RATE times faster than the solves run theirs (measured 4-7
 * on the development machine, doc/performance.md). At least 2. */
#define PS_FACTOR_RATE 5.0
static double factor_in_iterations(const ps_linsolve_stats *ls) {
  if (!(ls->nnz_factor > 0 && ls->flops_factor > 0)) return 2.0;
  return fmax(2.0, ls->flops_factor / (PS_FACTOR_RATE * 4.0 * ls->nnz_factor));
}

/* The iteration cap of CG with the old factor. Without a majorant, a
 * failed CG is followed by a factorisation of K, so CG pays while its
 * iterations cost less than one: the cap is min(pcg_max_iterations,
 * factor_in_iterations). With a majorant the next step is CG again, with
 * a fresh majorant factor, which needs about as many iterations: the cap
 * is pcg_max_iterations. */
static int old_factor_cap(const ps_solver *s) {
  int maxit = s->opts.pcg_max_iterations;
  if (!s->have_majorant && s->ls_last->stats.n_factor > 0) {
    double cap = factor_in_iterations(&s->ls_last->stats);
    if (cap < maxit) maxit = (int)cap;
  }
  return maxit;
}

/* 1 when keeping the old factor has cost more than a new one. A fresh
 * factor of the current tangent solves in one CG iteration, so the
 * iterations beyond one per solve since the last factorisation are what
 * lagging it cost; once they are more than a factorisation's worth
 * (factor_in_iterations), refactor. (A crack that runs changes the
 * tangent a little at every breaking round: each CG stays under the cap
 * of old_factor_cap, yet the rounds add up.) With a majorant the new
 * factor is the majorant's (solve_with_old_factor), and a majorant's
 * factor is lagged by the same rule with two changes: a fresh one solves
 * in the iterations of its first solve (s->its_fresh), which are the
 * baseline of its excess instead of one; and its solves run in single
 * precision from the first (half the bytes of the double solves that
 * factor_in_iterations counts), so it is worth twice the iterations. An
 * UMFPACK or LDL^T factor beside a majorant is not lagged by this rule
 * (CG's cap and a fresh majorant factor decide, old_factor_cap). */
static int lagging_costs_more(const ps_solver *s) {
  const ps_linsolve_stats *ls = &s->ls_last->stats;
  if (ls->n_factor == 0) return 0;
  if (!s->have_majorant || s->ls_last == &s->ls)
    return (double)(s->its_since_factor - s->solves_since_factor) > factor_in_iterations(ls);
  if (s->ls_last != &s->ls_pre) return 0;
  ps_int base = s->its_fresh > 1 ? s->its_fresh : 1;
  double worth = factor_in_iterations(ls) * (s->ls_pre.single_precision ? 2.0 : 1.0);
  return (double)(s->its_since_factor - s->solves_since_factor * base) > worth;
}

/* Steps 1 and 2 of the strategy. Returns PS_OK (du found), PS_DIVERGED
 * (factor K), or fatal. Each arm that changed state since the last factor
 * changes K by a rank-one term; with opts.pcg_skip_arms = n > 0, CG is not
 * tried when n or more did. */
static int solve_with_old_factor(ps_solver *s, ps_ctx *ctx) {
  int maxit = old_factor_cap(s);
  ps_int limit = s->opts.pcg_skip_arms, changed = -1;
  if (tracks_arm_state(s, ctx)) changed = s->prob.ops->changed(s->prob.data, limit);
  if (limit > 0 && changed >= limit) {
    s->pcg_skipped++;
    ps_log(ctx, 2, "    %lld+ arms changed state since the last factorisation: "
                   "refactoring\n", (long long)changed);
    return PS_DIVERGED;
  }
  if (lagging_costs_more(s)) {
    s->pcg_skipped++;
    ps_log(ctx, 2, "    CG with the old factor has cost more than a factorisation since "
                   "it was made: refactoring\n");
    return s->have_majorant ? solve_by_majorant(s, ctx) : PS_DIVERGED;
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
  if (s->have_majorant) return solve_by_majorant(s, ctx); /* also when the old
                                                  factor was a majorant's */
  return PS_DIVERGED;
}

int ps_nl_direction(ps_solver *s, ps_ctx *ctx) {
  /* with a majorant, its factor preconditions from the first system on
   * (the tangent's factor at rest only proved the supports); when CG
   * fails with it, the tangent is factored (CG with that same factor, and
   * another factor of the same majorant, would fail the same way) */
  if (s->opts.reuse_factor && s->have_majorant && s->ls_pre.stats.n_factor == 0) {
    int status = solve_by_majorant(s, ctx);
    if (status <= 0) return status;
  } else if (s->opts.reuse_factor && s->have_factor) {
    int status = solve_with_old_factor(s, ctx);
    if (status <= 0) return status;
  }
  int status = ps_nl_factor_tangent(s, ctx);
  if (status != PS_OK) return status;
  /* an iterative backend solves as far as CG would (the forcing term) */
  ps_linsolve *ls = (ps_linsolve *)s->ls_last;
  ls->rtol = s->cg_rtol;
  status = ps_linsolve_solve(ls, s->rhs, s->du, ctx);
  ls->rtol = 0.0;
  return status;
}

int ps_nl_factor_shifted(ps_solver *s, ps_ctx *ctx) {
  ps_csc *A = NULL;
  PS_CHECK(assemble(s, 0, &A, ctx));
  ps_int n = A->n, bad;
  for (ps_int k = 0; k < n; k++) s->diag_saved[k] = A->x[A->p[k + 1] - 1];
  int status = PS_SINGULAR;
  for (double mu = 1e-4; mu <= 10.0 && status != PS_OK; mu *= 10.0) {
    for (ps_int k = 0; k < n; k++) /* a zero diagonal entry shifted to 1 */
      A->x[A->p[k + 1] - 1] = s->diag_saved[k] * (1.0 + mu) + (s->diag_saved[k] == 0.0);
    status = ps_linsolve_factor(&s->ls, A, &bad, ctx);
    if (status < 0) break;
    if (status == PS_OK) ps_log(ctx, 2, "    indefinite tangent: shifted by %.0e diag\n", mu);
  }
  for (ps_int k = 0; k < n; k++) A->x[A->p[k + 1] - 1] = s->diag_saved[k];
  s->lu_current = 0;
  s->shifted_current = status == PS_OK;
  if (status != PS_OK) {
    s->have_factor = 0;
    return status < 0 ? status
                      : ps_error(ctx, PS_SINGULAR, "no positive definite shift of the tangent");
  }
  s->ls_last = &s->ls;
  s->have_factor = 1;
  snapshot_arm_state(s, ctx);
  return PS_OK;
}

int ps_nl_shifted_direction(ps_solver *s, ps_ctx *ctx) {
  int status = ps_nl_factor_shifted(s, ctx);
  if (status != PS_OK) return status;
  s->n_shifted++;
  return ps_linsolve_solve(&s->ls, s->rhs, s->du, ctx);
}

int ps_nl_shifted_gmres(ps_solver *s, int refactor, ps_ctx *ctx) {
  if (refactor) {
    int status = ps_nl_factor_shifted(s, ctx);
    if (status != PS_OK) return status < 0 ? status : PS_DIVERGED;
  }
  ps_operator K = {s->prob.n_free, apply_tangent, &s->prob, s->prob.owned_free};
  int its = 0;
  double t0 = ps_wtime();
  int status = ps_linsolve_gmres(&s->ls, &K, s->rhs, s->du, s->cg_rtol, PS_GMRES_MAX_ITERATIONS,
                                 &its, ctx);
  s->t_pcg += ps_wtime() - t0;
  s->gmres_iterations += its;
  if (status < 0) return status;
  ps_log(ctx, 2, "    GMRES with the shifted tangent's factor: %d iterations%s\n", its,
         status == PS_OK ? "" : ", not converged");
  return status == PS_OK ? PS_OK : PS_DIVERGED;
}
