/* ps_nl_problem.h: the narrow interface between the nonlinear solver
 * (Newton in newton.c, the direction strategy in direction.c) and the
 * problem it solves. The solver sees displacements u[n_dof] of which the
 * free ones (dof_of_free) are unknowns and the others (fixed) prescribed;
 * it never sees a model, an arm or an assembly. The peridynamic problem
 * (model + system + arm states) implements it in problem_pd.c; a unit
 * test can implement it by hand (t210: a 2-dof energy).
 *
 * Statuses as everywhere (ps_util.h): PS_OK, positive recoverable,
 * negative fatal. */
#ifndef PS_NL_PROBLEM_H
#define PS_NL_PROBLEM_H

#include <stddef.h>

#include "../linsolve/ps_linsolve.h"

typedef struct ps_nl_problem_ops {
  /* f[n_dof] = the forces at u[n_dof] (the residual at free dofs, the
   * reactions at prescribed ones) and *energy = the energy whose gradient
   * they are; with want_tangent also the tangent K at u, which apply,
   * assemble and changed then refer to until the next call with it (a
   * call without it leaves that tangent alone). Returns PS_OK,
   * PS_ERR_SOLVER (u outside the domain: f or the energy not finite), or
   * fatal. */
  int (*evaluate)(void *prob, const double *u, double *f, double *energy,
                  int want_tangent, ps_ctx *ctx);
  /* y[n_free] = K_ff x[n_free] for the tangent of the last evaluation
   * with one (matrix-free or by the assembled matrix: the problem's
   * choice). Not reentrant. */
  void (*apply)(void *prob, const double *x, double *y);
  /* *A = K_ff of that tangent (majorant 0) or a majorant P_ff >= K_ff
   * (majorant 1, only where has_majorant), as the upper triangle of a
   * symmetric CSC matrix for a factorisation. The matrix is the
   * problem's: the caller may change its values until the next call (the
   * shift does, and restores them). Returns PS_OK or fatal. */
  int (*assemble)(void *prob, int majorant, ps_csc **A, ps_ctx *ctx);
  /* record the state that makes the tangent change between evaluations
   * (peridynamics: the arms' yielding/broken flags), at a new factor */
  void (*mark)(void *prob);
  /* how many parts of that state differ from the last mark, counting up
   * to limit (limit <= 0: all); a factor of an older tangent is a worse
   * preconditioner the more did */
  ps_int (*changed)(void *prob, ps_int limit);
  /* the name of free dof k for messages ("particle 12 (x = .., y = ..),
   * dof y") into buf[len] */
  void (*dof_name)(void *prob, ps_int k, char *buf, size_t len);
} ps_nl_problem_ops;

/* A problem: its operations, their first argument, and its dofs (owned
 * by the problem, fixed for its life). */
typedef struct ps_nl_problem {
  const ps_nl_problem_ops *ops;
  void *data;
  ps_int n_dof, n_free;
  const ps_int *dof_of_free;    /* [n_free] */
  const unsigned char *fixed;   /* [n_dof] 1: prescribed */
  int has_majorant;             /* assemble(.., 1, ..) is available */
  const ps_comm *comm;          /* the processes the dofs are spread over
                                   (ps_util.h; NULL: one): every norm and
                                   dot product of the solver sums over it */
  const unsigned char *owned;   /* [n_dof] 1: this process's dof, counted in
                                   the norms and dot products (a share of a
                                   distributed problem also holds ghost
                                   dofs, free or prescribed, whose values
                                   are their owners'); NULL: every dof */
  const unsigned char *owned_free; /* [n_free] owned of each free dof (the
                                   dot products of CG and GMRES); NULL:
                                   every free dof */
} ps_nl_problem;

#endif
