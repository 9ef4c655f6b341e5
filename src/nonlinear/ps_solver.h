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
 * breaking round, the arc-length step, statistics), newton.c (the Newton loop), direction.c,
 * linesearch.c, forcing.c; solver_impl.h holds the solver's struct and
 * declares what they share. The options are in ps_solver_opts.h. */
#ifndef PS_SOLVER_H
#define PS_SOLVER_H

#include "../assembly/ps_assembly.h"
#include "../linsolve/ps_linsolve.h"
#include "ps_solver_opts.h"
#include "ps_solver_stats.h"

/* Why a Newton solve ended (as PETSc's SNESConvergedReason). */
enum ps_newton_reason {
  PS_NEWTON_CONVERGED = 0,
  PS_NEWTON_MAX_ITER = 1,      /* not converged within max_iterations */
  PS_NEWTON_LINE_SEARCH = 2,   /* no acceptable step along the direction */
  PS_NEWTON_NOT_FINITE = 3,    /* NaN or inf in the residual */
  PS_NEWTON_SINGULAR = 4,      /* tangent singular, also for UMFPACK */
  PS_NEWTON_STAGNATED = 5,     /* line-search steps below PS_SMALL_STEP that
                                  together cut the residual by < 10%, for
                                  opts.max_small_steps iterations in a row */
  PS_NEWTON_NO_DISSIPATION = 6, /* dissipation control: the arms dissipate
                                   nothing along the step's direction */
  PS_NEWTON_NO_PROGRESS = 7     /* arc-length or dissipation step: the
                                   corrector's smallest residual, far from
                                   the tolerance, did not fall in
                                   PS_CORRECTOR_PATIENCE iterations */
};

/* iterations a constrained step's corrector may go on without lowering
 * its smallest residual, while that is above PS_CORRECTOR_FAR times the
 * Newton tolerance, before the step fails and is cut (solver.c) */
#define PS_CORRECTOR_PATIENCE 6
#define PS_CORRECTOR_FAR 1e3

/* a line-search step below this counts towards stagnation (newton.c) */
#define PS_SMALL_STEP 1e-2

/* The solver's state (solver_impl.h): created by ps_solver_create, read
 * through ps_solver_get_stats and the accessors below, freed by
 * ps_solver_free. */
typedef struct ps_solver ps_solver;

/* Create a solver for the network with the prescribed-dof mask `fixed` and
 * prescribed field ubar (both [n_dof], copied) into *s (allocated; free it
 * with ps_solver_free). The model type and material choose the
 * constitutive law; opts are copied, opts->linear names the backend
 * (ps_linsolve_type_find). Checks that the unloaded structure is
 * supported: the tangent at rest must be positive definite, otherwise
 * PS_ERR_INPUT names the loose particle and direction. Returns PS_OK,
 * PS_ERR_INPUT (also for an unknown opts->linear), PS_ERR_NOMEM,
 * PS_ERR_SOLVER; on failure *s is NULL. P and net are not copied: they
 * must outlive the solver. */
int ps_solver_create(ps_solver **s, const ps_particles *P,
                     const ps_network *net, const ps_model_type *type,
                     const ps_material *mat, const unsigned char *fixed,
                     const double *ubar, const ps_solver_opts *opts,
                     ps_ctx *ctx);
/* A share of a distributed model (ps_share, doc/design-distributed.md):
 * what the solver of one process needs beyond its particles and network. */
typedef struct ps_solver_share {
  const unsigned char *own_arm;      /* ps_share.own_arm (borrowed) */
  const unsigned char *own_particle; /* ps_share.own_particle (borrowed) */
  const ps_int *global_row; /* [n_dof] each local dof's row in the whole
                               system (ps_share_global_rows; borrowed) */
  ps_int n_global;          /* the whole model's dofs */
  ps_int row0, n_rows;      /* this process's rows: its owned dofs */
  const ps_int *global;     /* [P.n] each particle's number in the whole
                               model (ps_share.global; borrowed): names
                               the arms breaking chooses over the
                               processes (NULL: no breaking on several) */
  const int *owner;         /* [P.n] the process owning each particle
                               (borrowed): the arms' halo of criteria that
                               only an arm's owner judges (NULL: none) */
  const ps_model_given *given; /* the whole model's constants for the
                               share's arms where they read the whole
                               cloud (ps_model_whole_constants; borrowed,
                               read at creation), else NULL */
} ps_solver_share;

/* ps_solver_create on a share of a distributed model (share NULL: the
 * same as ps_solver_create): P, net, fixed and ubar are the share's
 * (owned particles, then ghosts), ctx->comm the run's processes (every
 * call is collective), opts must choose PETSc and no majorant (linear
 * petsc; majorant 0 where reuse_factor is 1: PS_ERR_INPUT otherwise).
 * The ghosts' displacements follow their owners' through the linear
 * solves (each process gets the whole solution at its free dofs); CG
 * with the old factor (reuse_factor) sums its dot products over the own
 * free dofs (its ghost entries of the preconditioned residual, and so of
 * its directions, are their owners', the residual's are not used).
 * External forces (ps_solver_set_forces) are the share's: only those at
 * owned dofs do work. Every step controller and breaking work on a share
 * as on the whole (their sums over the own dofs and arms, breaking
 * decided over the processes: doc/parallel.md). */
int ps_solver_create_share(ps_solver **s, const ps_particles *P, const ps_network *net,
                           const ps_model_type *type, const ps_material *mat,
                           const unsigned char *fixed, const double *ubar,
                           const ps_solver_opts *opts, const ps_solver_share *share,
                           ps_ctx *ctx);
/* Free the solver and all it owns; NULL is a no-op. */
void ps_solver_free(ps_solver *s);

/* Newton at the current prescribed values (and forces), from the current
 * u: u and the arm states' trial values end at the last accepted
 * iterate. Stops converged when ||r_free|| <= opts.tolerance ||r_fixed||
 * (or ||r_free|| when there are no reactions, or r_free = 0); fails at
 * max_iterations (under the adaptive forcing rule: it then hands over to
 * the fixed rule for max_iterations more), on a residual or energy that
 * is not finite, a singular tangent, a line search without a step, or
 * opts.max_small_steps steps in a row below PS_SMALL_STEP that cut the
 * residual by less than 10% together. Returns PS_OK (converged),
 * PS_DIVERGED (recoverable; ps_solver_last_reason says why) or a fatal
 * status; ps_solver_last_residual says where it ended. */
int ps_newton_solve(ps_solver *s, ps_ctx *ctx);

/* Move the load factor to `lambda` with a predictor and Newton. The
 * predictor extrapolates the last two converged load factors (secant)
 * when no arm broke in between, else it solves with the last factor
 * (tangent predictor). Returns PS_OK, PS_DIVERGED (state restored to
 * the last commit), or fatal. Does not commit. */
int ps_solver_step(ps_solver *s, double lambda, ps_ctx *ctx);

/* One increment of arc-length path following from the last commit (the
 * load factor follows from the constraint; Riks/Crisfield):
 *   r_free(u, lambda) = 0,  ||Du_f||^2 / U^2 + psi^2 Dlambda^2 = ds^2,
 * D from the committed state, U = ||K_ff^-1 q|| at the first call (q =
 * -dr_free/dlambda = fext_f - K_fp ubar_p), so that ds is in units of the
 * load factor of the first (elastic) response. Tangent predictor
 * (Dlambda v, v = K_ff^-1 q, its sign that of the last converged
 * increment's dot product with it), then Newton with two right-hand sides
 * per iteration (K_ff^-1 r_free and K_ff^-1 q by the direction strategy,
 * CG truncation off, CG to the fixed forcing rule of opts.cg_forcing),
 * the load factor's correction the root of the constraint's quadratic
 * whose increment turns least (the linearised constraint where the roots
 * are complex), no line search. Stops as ps_newton_solve (tolerance,
 * max_iterations), and fails early with PS_NEWTON_NO_PROGRESS (above).
 * Returns PS_OK (not
 * committed), PS_DIVERGED (state restored to the last commit;
 * ps_solver_last_reason says why), or fatal (PS_ERR_INPUT when the load
 * moves no free dof). */
int ps_solver_arclength_step(ps_solver *s, double ds, double psi, ps_ctx *ctx);

/* One increment of dissipation control from the last commit (Gutierrez
 * 2004; Verhoosel, Remmers & Gutierrez 2009): the load factor follows
 * from the constraint that the arms dissipate tau (J, per unit thickness
 * in 2D) in the step,
 *   r_free(u, lambda) = 0,  D(u, lambda) = tau,
 * D from the model's arm_dissipation (ps_pd_dissipation) relative to the
 * committed states, linearised with its exact gradient, so the load
 * factor may fall while the displacements grow (snap-back). Predictor and
 * Newton as ps_solver_arclength_step; converged when the residual meets
 * the tolerance and D is within 1e-2 tau. Returns PS_OK (not committed),
 * PS_DIVERGED (restored; ps_solver_last_reason PS_NEWTON_NO_DISSIPATION
 * when no arm dissipates along the step: elastic loading or unloading,
 * where dissipation control cannot set the load), or fatal. */
int ps_solver_dissipation_step(ps_solver *s, double tau, ps_ctx *ctx);

/* Energy the arms dissipated up to the last commit (0 for a model without
 * arm_dissipation), J; and that of the last evaluation from the last
 * commit (the step's). Broken arms' stored energy is apart
 * (ps_arm_state.broken_energy). */
double ps_solver_dissipated(const ps_solver *s);
double ps_solver_step_dissipation(const ps_solver *s);

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

/* Reject a converged but unwanted step (not committed): back to the last
 * commit's state and load factor, re-evaluated there. Returns PS_OK or
 * fatal. */
int ps_solver_reject(ps_solver *s, ps_ctx *ctx);

/* Intact arms past the model's breaking criterion in the last evaluation
 * (those the next breaking round would break). */
ps_int ps_solver_count_past_criterion(const ps_solver *s);

/* The largest relative excess over the breaking criterion of the intact
 * arms in the last evaluation (ps_model_max_excess: > 0 past it, 0 at
 * it; -1 with no criterion or no intact arm). */
double ps_solver_max_excess(const ps_solver *s);

/* One round of fracture: break the arms past the elongation limit (model
 * rule; with max_count > 0 only the max_count arms past it by the most)
 * and re-equilibrate at the same load; commits when converged. *n_broken
 * gets the number broken (0: the state is settled, nothing done). Returns
 * PS_OK, PS_DIVERGED (the re-equilibration failed: the state is that of
 * the failed attempt; ps_solver_restore goes back to before the round),
 * or fatal. */
int ps_solver_break_round(ps_solver *s, ps_int max_count, ps_int *n_broken,
                          ps_ctx *ctx);

/* ps_solver_break_round with the re-equilibration stopped once the
 * relative residual is below tolerance (used when above solver.tolerance:
 * path.round_tolerance; <= solver.tolerance: the solver's own). */
int ps_solver_break_round_to(ps_solver *s, ps_int max_count, double tolerance,
                             ps_int *n_broken, ps_ctx *ctx);

/* Newton at the load of the last commit, from its state, to
 * solver.tolerance; commits when converged (a state committed at a looser
 * tolerance made an equilibrium of it). Returns PS_OK, PS_DIVERGED (the
 * state is that of the failed attempt) or fatal. */
int ps_solver_resettle(ps_solver *s, ps_ctx *ctx);

/* Break the arms past the criterion (as ps_solver_break_round) without
 * re-equilibrating: the state, out of equilibrium by the broken arms'
 * forces, becomes the commit, from which the next path-following step
 * (arc-length, dissipation) starts; its constraint then chooses the load
 * at which equilibrium is found again. Returns PS_OK or fatal. */
int ps_solver_break_in_place(ps_solver *s, ps_int max_count, ps_int *n_broken, ps_ctx *ctx);

/* Re-evaluate forces, tensions and energy at the current u (no tangent):
 * after a failed solve, the arm tensions, directions and elongations may
 * belong to a rejected trial. */
int ps_solver_evaluate(ps_solver *s, ps_ctx *ctx);

/* The stored (elastic and plastic-incremental) energy Psi of the last
 * evaluation, J (per unit thickness in 2D): the merit energy plus the
 * load's potential, Psi = E + lambda fext . u, less the step's
 * dissipation where the model measures it (the merit energy is the
 * incremental potential: stored energy plus the step's dissipation). */
double ps_solver_stored_energy(const ps_solver *s);

/* Intact arms on the yield surface in the current state. */
ps_int ps_solver_count_yielding(const ps_solver *s);
/* the processes the solver's problem is spread over (ctx->comm at
 * create; NULL: one), for the global quantities of the layers above */
const ps_comm *ps_solver_comm(const ps_solver *s);
/* the arms this process owns (ps_model.own_arm; NULL: every arm) */
const unsigned char *ps_solver_own_arm(const ps_solver *s);

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
/* The force vector of the last evaluation [n_dof], N (per m of thickness
 * in 2D): at prescribed dofs the reactions (the force the supports exert
 * on the particle, the gradient of the stored energy), at free dofs the
 * residual r = f_int - lambda fext. */
const double *ps_solver_force(const ps_solver *s);
/* How the last Newton solve ended: enum ps_newton_reason, and its
 * relative residual. */
int ps_solver_last_reason(const ps_solver *s);
double ps_solver_last_residual(const ps_solver *s);

/* ---- checkpoints (src/io/checkpoint.c; doc/peristatic.md RESTART) ----
 *
 * A restarted run must repeat an uninterrupted one to the last bit, so a
 * checkpoint holds all the solver carries from one increment to the
 * next: displacements (the committed ones and the predictor's history),
 * load factors, both arm states (trial and committed), the last
 * evaluation's forces, energy and tangent data (the tangent predictor
 * and the next breaking round read them), the statistics, and the factor
 * the next directions reuse. That factor is not stored: the matrix it
 * was made of is (ps_solver_keep_factors), and the restored solver
 * factors it again with the same backend, which gives the same factor;
 * the backends' statistics are then put back as they were. */

/* Keep a copy of the matrix of every factor from now on (ps_linsolve
 * keep_matrix; costs the tangent's nonzeros in memory and a copy per
 * factorisation), so that ps_solver_factor_matrix can give it; the
 * factor made by ps_solver_create (at rest) is assembled again for it.
 * Call right after ps_solver_create, on the solver whose state will be
 * checkpointed and on the one that restores it. Returns PS_OK or
 * fatal. */
int ps_solver_keep_factors(ps_solver *s, ps_ctx *ctx);

/* Append the solver's state to l as ps_state_items (names "u", "st.eps_p",
 * "sys.T", ...): valid until the solver's next call. The same list of a
 * solver created for the same problem and options receives them back.
 * Returns PS_OK, PS_ERR_NOMEM or ps_state_add's status. */
int ps_solver_state_list(ps_solver *s, ps_state_list *l, ps_ctx *ctx);

/* A copy of the solver's state (the items of ps_solver_state_list less
 * its counters and statistics), to go back to after steps that are
 * rejected as a whole: the path's way back to its last settled state. */
typedef struct ps_solver_snapshot {
  unsigned char *data;
  size_t size, cap;
} ps_solver_snapshot;

/* Copy the solver's state into snap (zeroed at first; its buffer is
 * reused). Returns PS_OK or PS_ERR_NOMEM. */
int ps_solver_snapshot_take(ps_solver *s, ps_solver_snapshot *snap, ps_ctx *ctx);

/* Put the state of snap (taken from this solver) back, the counters
 * going on counting, and make a fresh factor of its tangent, as after a
 * failed step. Returns PS_OK, PS_SINGULAR (no factor: the next step
 * will say so), or fatal. */
int ps_solver_snapshot_restore(ps_solver *s, const ps_solver_snapshot *snap, ps_ctx *ctx);

/* Free snap's buffer. */
void ps_solver_snapshot_free(ps_solver_snapshot *snap);

/* The factor the next directions reuse: *which = 0 none, 1 the chosen
 * backend's, 2 the majorant's, 3 UMFPACK's, 4 LDL^T's, and *A the matrix
 * it was made of (NULL for none; the solver's, valid until its next
 * factorisation). PS_OK, or PS_ERR_INTERNAL without
 * ps_solver_keep_factors. */
int ps_solver_factor_matrix(const ps_solver *s, int *which, const ps_csc **A, ps_ctx *ctx);

/* After the items of ps_solver_state_list were read back into s: create
 * the linear solvers the checkpointed solver had made, factor A (the
 * matrix of ps_solver_factor_matrix, which = its *which) into the one
 * `which` names, make it the factor the next directions reuse and put
 * the backends' statistics back; the tangent is assembled again from the
 * restored data when a factorisation needs it. Returns PS_OK,
 * PS_ERR_INPUT (which out of range, A not on this solver's pattern, or A
 * no longer factors: not this solver's checkpoint), or fatal. */
int ps_solver_state_restored(ps_solver *s, int which, const ps_csc *A, ps_ctx *ctx);

/* A short sentence for an enum ps_newton_reason, for messages ("line
 * search failed"); "unknown reason" for any other value. */
const char *ps_newton_reason_text(int reason);

#endif
