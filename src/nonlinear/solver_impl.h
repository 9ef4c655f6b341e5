/* solver_impl.h: what the files of src/nonlinear share and no other layer
 * sees: the evaluation of the system at a trial u, and the direction
 * strategy (direction.c) that Newton (newton.c) and the path steps
 * (solver.c) call. */
#ifndef PS_SOLVER_IMPL_H
#define PS_SOLVER_IMPL_H

#include "ps_solver.h"

/* f[n_dof] = f_int(u) - lambda fext and *energy = Psi(u) - lambda fext . u
 * at u[n_dof] (fext: ps_solver_set_forces, else 0); with tangent = 1 also
 * the tangent: its data only when CG applies it matrix-free
 * (opts.reuse_factor and opts.matrix_free), else assembled. Timed as
 * assembly. Returns the status of ps_system_eval. */
int ps_nl_eval(ps_solver *s, const double *u, double *f, double *energy, int tangent,
               ps_ctx *ctx);

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

#endif
