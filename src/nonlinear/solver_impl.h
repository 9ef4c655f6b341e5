/* solver_impl.h: what the files of src/nonlinear share and no other layer
 * sees: the solver's struct, the evaluation of the problem at a trial u,
 * and the direction strategy (direction.c) that Newton (newton.c) and the
 * path steps (solver.c) call. Newton and the direction strategy reach the
 * problem only through s->prob (ps_nl_problem.h); the peridynamic problem
 * behind it (s->pd, problem_pd.h) is solver.c's. Outside src/nonlinear
 * only its own unit test (t210) includes it. */
#ifndef PS_SOLVER_IMPL_H
#define PS_SOLVER_IMPL_H

#include "ps_solver.h"
#include "forcing.h"
#include "linesearch.h"
#include "ps_nl_problem.h"

struct ps_pd; /* problem_pd.h */

/* The solver's state (ps_solver.h's opaque type). */
struct ps_solver {
  ps_nl_problem prob;        /* all Newton and the directions see */
  struct ps_pd *pd;         /* the peridynamic problem behind prob (NULL
                               for a problem made by hand) */
  const ps_linsolve_type *linear; /* opts.linear resolved */
  ps_linsolve ls;           /* the chosen backend */
  ps_linsolve ls_fallback;  /* UMFPACK, created on first need */
  ps_linsolve ls_ldl;       /* CHOLMOD simplicial LDL^T, the constrained
                               step's factor of an indefinite tangent
                               (lu_first), created on first need */
  const ps_linsolve *ls_last; /* which one holds the current factor */
  int have_majorant;        /* 1: the direction strategy uses a majorant
                               (prob.has_majorant: opts.majorant, a model
                               with family terms, opts.reuse_factor);
                               ls_pre exists */
  ps_linsolve ls_pre;       /* the majorant's CHOLMOD factor */
  ps_team *team;            /* opts.threads threads (NULL: one) */
  int have_factor;          /* a factor of a recent tangent is available */
  int keep_factors;         /* 1: the linear solvers keep the matrix of
                               their factor (ps_solver_keep_factors) */
  ps_solver_opts opts;

  /* the load factor lambda and the external forces are the problem's
   * (pd->lambda, pd->fext) */
  double *u, *u_saved;      /* [n_dof] displacements, m */
  double *u_prev;           /* [n_dof] converged u of the previous load
                               factor lambda_prev (secant predictor) */
  double lambda_prev;
  double lambda_saved;      /* the load factor of the last commit */
  int ldl_ok;               /* 1: lu_first may use LDL^T (no family terms) */
  int lu_first;             /* 1: ps_nl_factor_tangent goes straight to an
                               indefinite factor, LDL^T (UMFPACK when it
                               meets a zero pivot): the constrained step
                               on an indefinite tangent */
  int indefinite;           /* 1: the last factor of the tangent itself
                               was an indefinite one (UMFPACK's, LDL^T's):
                               K is indefinite (a constrained step then
                               solves by solve_tangent's route) */
  int lu_current;           /* 1: ls_last holds an indefinite factor of
                               the current tangent (set by the factors,
                               cleared by solve_tangent when the tangent
                               changes) */
  int shifted_current;      /* 1: ls holds the factor of the current
                               tangent shifted (ps_nl_factor_shifted);
                               likewise */
  int have_prev;            /* u_prev valid: no arm broke since */
  double *ubar;             /* [n_dof] prescribed displacement at lambda 1 */
  double *f;                /* [n_dof] internal forces at u (reactions at
                               prescribed dofs, residual at free ones) */
  double energy;            /* stored energy at u, J (per m in 2D) */
  double *rhs, *du, *work;  /* [n_free] */
  double *pcg_work;         /* [4 n_free] */
  double *u_trial, *f_trial;/* [n_dof] line-search work */
  double *work_dof;         /* [n_dof] */
  double *diag_saved;       /* [n_free] diagonal of the tangent while shifted */

  /* arc-length path following (ps_solver_arclength_step; allocated at
   * its first call) */
  double *al_q;             /* [n_free] load vector -dr_free/dlambda */
  double *al_v;             /* [n_free] K_ff^-1 al_q */
  double *al_dr;            /* [n_free] K_ff^-1 (-r_free) */
  double al_scale;          /* U: norm of K_ff^-1 q at the first step, m */
  double *al_g;             /* [n_dof] gradient of the step's dissipation */
  double dissipated;        /* energy dissipated by the arms up to the last
                               commit (ps_pd_dissipation summed), J */
  int al_have_dir;          /* u_prev, lambda_prev hold the start of the
                               last converged arc-length increment */

  /* statistics of the run */
  ps_int newton_iterations, n_fallback, n_line_search_cuts;
  ps_int n_shifted;         /* Newton directions from a shifted tangent */
  ps_int pcg_iterations, pcg_solves, pcg_failures;
  ps_int pcg_skipped;       /* CG not tried: too many arms changed state,
                               or (no majorant) lagging the factor cost
                               more than a new one */
  ps_int its_since_factor, solves_since_factor; /* CG with the current
                               factor: iterations and solves */
  ps_int its_fresh;         /* CG iterations of the first solve with it */
  ps_int pre_failures;      /* CG with a fresh majorant factor that failed */
  ps_int gmres_iterations;  /* GMRES on an indefinite tangent
                               (ps_nl_shifted_gmres) */
  ps_int pcg_truncated;     /* Newton directions from CG truncated at
                               negative curvature (opts.cg_truncate) */
  ps_int n_handovers;       /* Newton solves that reached max_iterations
                               under the adaptive CG tolerance and went
                               on with the fixed rule */
  ps_int n_stagnated;       /* Newton solves ended as stagnated
                               (opts.max_small_steps) */
  double cg_rtol;           /* CG tolerance of the current Newton iteration */
  double t_pcg;             /* wall seconds spent in CG */
  int last_reason;          /* enum ps_newton_reason of the last solve */
  int last_iterations;      /* iterations of the last solve */
  double last_residual;     /* relative residual at its end */
};

/* the problem's evaluate: f[n_dof] and *energy at u[n_dof], with tangent
 * = 1 also the tangent (for the peridynamic problem f_int(u) - lambda
 * fext and Psi(u) - lambda fext . u). Returns evaluate's status. */
static inline int ps_nl_eval(ps_solver *s, const double *u, double *f, double *energy,
                             int tangent, ps_ctx *ctx) {
  return s->prob.ops->evaluate(s->prob.data, u, f, energy, tangent, ctx);
}

/* Allocate s's work arrays for s->prob's dofs. Returns PS_OK or
 * PS_ERR_NOMEM (ps_solver_free releases what was allocated). */
int ps_nl_alloc_work(ps_solver *s, ps_ctx *ctx);

/* Newton's convergence measure: norm(f_free) / norm(f_fixed) (the
 * reactions), or norm(f_free) when there are none; *rn = norm(f_free). */
double ps_nl_relative_residual(const ps_nl_problem *p, const double *f, double *rn);

/* s->du = K_ff^-1 s->rhs for the tangent K of the last evaluation with
 * one: CG preconditioned by the last factor (opts.reuse_factor); when CG
 * does not converge, CG with a fresh factor of the majorant
 * (s->have_majorant); then a fresh factor of K, by UMFPACK where K is not
 * positive definite. CG that meets negative curvature gives its truncated
 * iterate (opts.cg_truncate). Returns PS_OK, PS_SINGULAR (no factor of K:
 * the message names the particle), or fatal. */
int ps_nl_direction(ps_solver *s, ps_ctx *ctx);

/* s->du = (K + mu diag K)^-1 s->rhs with the smallest mu in 1e-4, 1e-3,
 * .., 10 for which the shifted K factors as positive definite
 * (Levenberg-Marquardt): a descent direction where K is indefinite.
 * Returns PS_OK, PS_SINGULAR (no such mu), or fatal. */
int ps_nl_shifted_direction(ps_solver *s, ps_ctx *ctx);

/* Factor the tangent of the last evaluation (assembling it first) with
 * the chosen backend, by UMFPACK when it is not positive definite; the
 * factor the next directions reuse. Returns PS_OK, PS_SINGULAR (the
 * message names the particle and direction), or fatal. */
int ps_nl_factor_tangent(ps_solver *s, ps_ctx *ctx);

/* A fresh factor for the next directions at the state of the last
 * evaluation with a tangent: the majorant's (s->have_majorant) when it is
 * positive definite, else the tangent's (ps_nl_factor_tangent). Returns
 * PS_OK, PS_SINGULAR, or fatal. */
int ps_nl_fresh_factor(ps_solver *s, ps_ctx *ctx);

/* A positive definite factor of the shifted tangent K + mu diag K of the
 * last evaluation with one (mu = 1e-4, 1e-3, .., 10, the first that
 * CHOLMOD's LL^T takes; a zero diagonal entry shifted to 1) into s->ls,
 * the factor the next directions reuse. Returns PS_OK, PS_SINGULAR (no
 * such mu), or fatal. */
int ps_nl_factor_shifted(ps_solver *s, ps_ctx *ctx);

/* du = K_ff^-1 rhs for an indefinite K by GMRES preconditioned by the
 * factor of the shifted tangent (ps_nl_factor_shifted, made first when
 * refactor = 1), to the relative residual s->cg_rtol in at most
 * PS_GMRES_MAX_ITERATIONS. Returns PS_OK, PS_DIVERGED (no such factor,
 * or GMRES did not converge), or fatal. */
#define PS_GMRES_MAX_ITERATIONS 30
int ps_nl_shifted_gmres(ps_solver *s, int refactor, ps_ctx *ctx);

#endif
