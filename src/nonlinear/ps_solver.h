/* ps_solver.h: the nonlinear solver of src/nonlinear: Newton's method on
 * the discrete system of an arm network, and the steps of a
 * displacement-controlled path (predictor, commit/restore, a round of arm
 * breaking) that the path layer drives.
 *
 * A ps_solver owns the state of a run on one network: displacements u (m),
 * the per-arm plastic state, the system (residual/tangent) and the linear
 * solvers. Prescribed dofs follow u_p = lambda * ubar_p (lambda: the load
 * factor). Newton solves r_free(u) = 0 to ||r_free|| <= tol ||reactions||:
 *   - the direction du solves K_ff du = -r_free (direction.c: CG on the
 *     matrix-free tangent preconditioned by the last factor, a fresh
 *     factor of the one-horizon majorant, a factor of K itself, UMFPACK
 *     where K is not positive definite, a shifted K where du points
 *     uphill), CG to the tolerance of the forcing rule (forcing.h);
 *   - the step along du by the backtracking line search on the energy
 *     (linesearch.h).
 * The pieces, one file each: solver.c (lifecycle, predictor, commit,
 * breaking round, statistics), newton.c (the Newton loop), direction.c,
 * linesearch.c, forcing.c; solver_impl.h declares what they share. */
#ifndef PS_SOLVER_H
#define PS_SOLVER_H

#include "../assembly/ps_assembly.h"
#include "../linsolve/ps_linsolve.h"
#include "forcing.h"
#include "linesearch.h"

/* Why a Newton solve ended (as PETSc's SNESConvergedReason). */
enum ps_newton_reason {
  PS_NEWTON_CONVERGED = 0,
  PS_NEWTON_MAX_ITER = 1,      /* not converged within max_iterations */
  PS_NEWTON_LINE_SEARCH = 2,   /* no acceptable step along the direction */
  PS_NEWTON_NOT_FINITE = 3,    /* NaN or inf in the residual */
  PS_NEWTON_SINGULAR = 4,      /* tangent singular, also for UMFPACK */
  PS_NEWTON_STAGNATED = 5      /* line-search steps below PS_SMALL_STEP that
                                  together cut the residual by < 10%, for
                                  opts.max_small_steps iterations in a row */
};

/* a line-search step below this counts towards stagnation (newton.c) */
#define PS_SMALL_STEP 1e-2


/* Settings of the nonlinear solve and the path. */
typedef struct ps_solver_opts {
  double tolerance;       /* relative residual (default 1e-8) */
  int max_iterations;     /* per Newton solve (default 30) */
  int max_small_steps;    /* a Newton solve fails as stagnated after this
                             many line-search steps in a row below
                             PS_SMALL_STEP that cut the residual by less
                             than 10% together (0: never; default 5) */
  int line_search;        /* 1: the energy line search (linesearch.h;
                             default); 0: the first finite step of the
                             halvings from the full step */
  const ps_linsolve_type *linear; /* default CHOLMOD, UMFPACK as fallback */
  int reuse_factor;       /* 1 (default): solve each Newton system by CG
                             preconditioned with the last factor, and
                             refactor only when CG does not converge within
                             pcg_max_iterations (doc/performance.md);
                             0: a fresh factor per Newton iteration */
  double pcg_rtol;        /* relative tolerance of that CG (default 1e-6) */
  int cg_forcing_adaptive; /* inexact Newton (forcing.h), 1 (default): CG
                             stops at Eisenstat and Walker's choice-2
                             forcing term eta_k = 0.9 (|r_k| / |r_k-1|)^2
                             (safeguarded; cg_forcing_max at the first
                             iteration of a solve and at most): rough CG
                             solves while Newton converges slowly, tight
                             ones once it converges fast; a solve that
                             reaches max_iterations goes on with the fixed
                             rule (cg_forcing) for max_iterations more.
                             0: the fixed rule */
  double cg_forcing_max;  /* its loosest CG tolerance (default 0.5) */
  double cg_forcing;      /* the fixed rule: CG stops at the relative
                             residual max(pcg_rtol, min(PS_CG_FORCING_MAX,
                             cg_forcing x the relative Newton residual));
                             0: always pcg_rtol (exact Newton). Both
                             rules (but cg_forcing 0) stop CG no tighter
                             than PS_CG_OVERSOLVE x tolerance / the
                             relative Newton residual (default
                             PS_CG_FORCING_FIXED; with the adaptive rule,
                             used after a handover) */
  int pcg_max_iterations; /* default 25 */
  int pcg_skip_arms;      /* skip CG when at least this many arms changed
                             state (yield, break) since the last
                             factorisation; 0: never skip (default 0) */
  int matrix_free;        /* 1: CG applies the tangent matrix-free
                             (ps_system_apply: arm and rank-one family
                             terms) and the two-horizon matrix is
                             assembled only to be factored (default 1;
                             doc/performance.md) */
  int cg_truncate;        /* 1: when CG meets a direction of negative
                             curvature (an indefinite tangent), its last
                             iterate is the Newton direction (truncated CG,
                             a descent direction) instead of a fresh
                             factorisation and UMFPACK (default 1,
                             doc/performance.md) */
  int cg_single_precision; /* 1: CG's preconditioner uses the factor's
                             values rounded to single precision (half the
                             memory traffic of its triangular solves;
                             default 1, doc/performance.md) */
  int reanalyze;          /* 1: symbolic analysis before every
                             factorisation (benchmark comparison; 0) */
  int threads;            /* threads of the CG products and preconditioner
                             solves (ps_team): 0 (default) as many as the
                             CPUs this process may use, at most
                             PS_PARTS (ps_util.h); the numbers a run gives do
                             not depend on it */
  int majorant;           /* 1: for models with family terms, when CG with
                             the old factor fails, factor the one-horizon
                             majorant of the tangent
                             (ps_system_assemble_majorant, fewer nonzeros)
                             and run CG with it before factoring the
                             two-horizon tangent itself (default 1,
                             doc/performance.md) */
} ps_solver_opts;

/* The solver's state. Internal: other layers read it through the
 * accessors and ps_solver_get_stats below (src/app/run.c still reads some
 * fields directly, so the definition stays in this header until it no
 * longer does; then it moves to solver_impl.h). */
typedef struct ps_solver {
  const ps_particles *P;
  const ps_network *net;
  ps_model model;
  ps_system sys;
  ps_arm_state st, st_saved;
  ps_linsolve ls;           /* the chosen backend */
  ps_linsolve ls_fallback;  /* UMFPACK, created on first need */
  const ps_linsolve *ls_last; /* which one holds the current factor */
  int have_majorant;        /* 1: the direction strategy uses a majorant
                               (opts.majorant, a model with family terms,
                               opts.reuse_factor); sys_pre and ls_pre exist */
  ps_system sys_pre;        /* one-horizon majorant of sys's tangent */
  ps_linsolve ls_pre;       /* its CHOLMOD factor */
  ps_team *team;            /* opts.threads threads (NULL: one) */
  int have_factor;          /* a factor of a recent tangent is available */
  ps_solver_opts opts;

  double lambda;            /* current load factor */
  double *u, *u_saved;      /* [n_dof] displacements, m */
  double *u_prev;           /* [n_dof] converged u of the previous load
                               factor lambda_prev (secant predictor) */
  double lambda_prev;
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
  const double *fext;       /* [n_dof] external forces at load factor 1 (N;
                               per unit thickness in 2D), zero on prescribed
                               dofs, or NULL; not owned */

  /* statistics of the run */
  ps_int newton_iterations, n_fallback, n_line_search_cuts;
  ps_int n_shifted;         /* Newton directions from a shifted tangent */
  ps_int pcg_iterations, pcg_solves, pcg_failures;
  ps_int pcg_skipped;       /* CG not tried: too many arms changed state */
  ps_int pre_failures;      /* CG with a fresh majorant factor that failed */
  ps_int pcg_truncated;     /* Newton directions from CG truncated at
                               negative curvature (opts.cg_truncate) */
  ps_int n_handovers;       /* Newton solves that reached max_iterations
                               under the adaptive CG tolerance and went
                               on with the fixed rule */
  ps_int n_stagnated;       /* Newton solves ended as stagnated
                               (opts.max_small_steps) */
  unsigned char *arm_state_at_factor; /* [n_arm] yielding | 2 broken, when the
                               last factor was computed */
  double cg_rtol;           /* CG tolerance of the current Newton iteration */
  double t_pcg;             /* wall seconds spent in CG */
  double t_assembly;
  int last_reason;          /* enum ps_newton_reason of the last solve */
  int last_iterations;      /* iterations of the last solve */
  double last_residual;     /* relative residual at its end */
} ps_solver;

/* Create a solver for the network with the prescribed-dof mask `fixed` and
 * prescribed field ubar (both [n_dof], copied). The model type and material
 * choose the constitutive law. Checks that the unloaded structure is
 * supported: the tangent at rest must be positive definite, otherwise
 * PS_ERR_INPUT names the loose particle and direction. Returns PS_OK,
 * PS_ERR_INPUT, PS_ERR_NOMEM, PS_ERR_SOLVER. */
int ps_solver_create(ps_solver *s, const ps_particles *P,
                     const ps_network *net, const ps_model_type *type,
                     const ps_material *mat, const unsigned char *fixed,
                     const double *ubar, const ps_solver_opts *opts,
                     ps_ctx *ctx);
void ps_solver_free(ps_solver *s);

/* Default options: tol 1e-8, 30 iterations, line search on, CHOLMOD,
 * factor reuse on (CG tolerance 1e-6, 25 iterations). */
void ps_solver_opts_default(ps_solver_opts *o);

/* Newton at the current prescribed values (and forces), from the current
 * u: u and the arm states' trial values end at the last accepted
 * iterate. Stops converged when ||r_free|| <= opts.tolerance ||r_fixed||
 * (or ||r_free|| when there are no reactions, or r_free = 0); fails at
 * max_iterations (under the adaptive forcing rule: it then hands over to
 * the fixed rule for max_iterations more), on a residual or energy that
 * is not finite, a singular tangent, a line search without a step, or
 * opts.max_small_steps steps in a row below PS_SMALL_STEP that cut the
 * residual by less than 10% together. Returns PS_OK (converged),
 * PS_DIVERGED (recoverable; s->last_reason says why) or a fatal status;
 * s->last_iterations and s->last_residual say where it ended. */
int ps_newton_solve(ps_solver *s, ps_ctx *ctx);

/* Move the load factor to `lambda` with a predictor and Newton. The
 * predictor extrapolates the last two converged load factors (secant)
 * when no arm broke in between, else it solves with the last factor
 * (tangent predictor). Returns PS_OK, PS_DIVERGED (state restored to
 * the last commit), or fatal. Does not commit. */
int ps_solver_step(ps_solver *s, double lambda, ps_ctx *ctx);

/* Load the model by the forces lambda * fext as well (tractions given as
 * forces on particles; fext zero on prescribed dofs, kept by the caller).
 * The residual becomes f_int - lambda fext and the energy Psi - lambda
 * fext . u. Call before the first ps_solver_step. */
void ps_solver_set_forces(ps_solver *s, const double *fext);

/* Accept the converged state: eps_p <- trial; save it as the restore
 * point. */
void ps_solver_commit(ps_solver *s);
/* Return to the last committed state. */
void ps_solver_restore(ps_solver *s);

/* One round of fracture: break the arms past the elongation limit (model
 * rule; with max_count > 0 only the max_count arms past it by the most)
 * and re-equilibrate at the same load; commits when converged. *n_broken
 * gets the number broken (0: the state is settled, nothing done). Returns
 * PS_OK, PS_DIVERGED (the re-equilibration failed: the state is that of
 * the failed attempt; ps_solver_restore goes back to before the round),
 * or fatal. */
int ps_solver_break_round(ps_solver *s, ps_int max_count, ps_int *n_broken,
                          ps_ctx *ctx);

/* Re-evaluate forces, tensions and energy at the current u (no tangent):
 * after a failed solve, sys.T/q/dl may belong to a rejected trial. */
int ps_solver_evaluate(ps_solver *s, ps_ctx *ctx);

/* Intact arms on the yield surface in the current state. */
ps_int ps_solver_count_yielding(const ps_solver *s);

/* What a solver has done since its creation: counts and times. Filled by
 * ps_solver_get_stats in one call; the reports take it as it is. */
typedef struct ps_solver_stats {
  ps_int newton_iterations;   /* Newton iterations of all solves */
  ps_int factorisations;      /* of the tangent (chosen backend + UMFPACK) */
  ps_int n_fallback;          /* UMFPACK fallbacks */
  ps_int solves;              /* direct solves */
  ps_int pcg_iterations, pcg_failures, pcg_skipped;
  ps_int majorant_factorisations, majorant_failures; /* opts.majorant */
  ps_int shifted_steps;       /* Newton directions from a shifted tangent */
  ps_int cg_truncated;        /* from CG truncated at negative curvature */
  ps_int stagnated;           /* Newton solves ended as stagnated */
  ps_int handovers;           /* adaptive CG solves that went on with the
                                 fixed rule at max_iterations */
  ps_int line_search_cuts;    /* backtracking steps of the line search */
  ps_int n_free;              /* free dofs */
  int threads;                /* threads of the run's CG */
  double serial_share;        /* share of a preconditioner solve on one
                                 thread alone (the majorant's factor, else
                                 the tangent's) */
  double nnz_tangent;         /* nonzeros of the free tangent (upper) */
  double nnz_factor, flops_factor; /* of the last factorisation */
  double nnz_majorant_factor;
  double t_assembly, t_analyze, t_factor, t_solve, t_majorant_factor;
  double t_cg;                /* wall seconds in CG (products and
                                 preconditioner solves) */
} ps_solver_stats;

/* Fill *st with the solver's statistics so far. */
void ps_solver_get_stats(const ps_solver *s, ps_solver_stats *st);

/* Read-only views of the current state (valid until the next call that
 * changes it): load factor; displacements [n_dof], m; arm tensions T,
 * unit directions q [n_arm * dim] and elongations dl [n_arm], m, of the
 * last evaluation; the arm states (yielding, broken, plastic strains). */
double ps_solver_lambda(const ps_solver *s);
const double *ps_solver_u(const ps_solver *s);
const double *ps_solver_arm_tension(const ps_solver *s);
const double *ps_solver_arm_direction(const ps_solver *s);
const double *ps_solver_arm_elongation(const ps_solver *s);
const ps_arm_state *ps_solver_arm_state(const ps_solver *s);
/* How the last Newton solve ended: enum ps_newton_reason, and its
 * relative residual. */
int ps_solver_last_reason(const ps_solver *s);
double ps_solver_last_residual(const ps_solver *s);

/* A short sentence for an enum ps_newton_reason, for messages ("line
 * search failed"); "unknown reason" for any other value. */
const char *ps_newton_reason_text(int reason);

#endif
