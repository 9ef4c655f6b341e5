/* ps_assembly.h: the discrete system of an arm network: dof map and
 * prescribed dofs, residual (internal forces), energy, and the consistent
 * tangent stiffness
 *   K = sum_arms [ D q q^T + (T/l)(I - q q^T) ] (x) [[1,-1],[-1,1]]
 *     + sum_a c_a g_a g_a^T,   g_a = sum_{i in family a} w_{a,i} dl_i/dy
 * on a fixed sparsity pattern (two horizons wide: every pair of particles
 * that share a family), computed once per network, so the symbolic
 * factorisation runs once. Broken arms stay in the pattern as zeros.
 * The same K is also applied without assembling it (ps_system_apply: arm
 * terms plus the rank-one family terms, O(arms + family members) per
 * product), which is what CG uses; the matrix is assembled only to be
 * factored (ps_system_assemble).
 * Files: pattern.c (create, free: dof map, pattern, slot maps),
 * evaluate.c (ps_system_eval), assemble.c (ps_system_assemble),
 * operator.c (apply, apply_free, operator, coupling), majorant.c
 * (ps_system_assemble_majorant); assembly_internal.h is theirs alone. */
#ifndef PS_ASSEMBLY_H
#define PS_ASSEMBLY_H

#include "../linsolve/ps_linsolve.h"
#include "../model/ps_model.h"

/* The arm length the models see is rounded at zero,
 *   l = sqrt(|y_b - y_a|^2 + (e r0)^2),  dl = l - sqrt(r0^2 + (e r0)^2),
 * e = PS_ARM_LENGTH_ROUNDING: |y_b - y_a| is not differentiable where two
 * particles meet, and a perfectly plastic arm crushed to zero length at a
 * crack tip (its tension, from the mean strain of its particles, still
 * pulling them together) put Newton's minimiser on that cone point, where
 * no line search makes progress (doc/model.md). The gradient of l is q =
 * (y_b - y_a)/l and its Hessian (I - q q^T)/l, the form the tangent has
 * anyway, so nothing else changes; dl is zero in the reference state, and
 * the stiffness of an arm of length r0 changes by the factor
 * 1/(1 + e^2) (1e-8). */
#define PS_ARM_LENGTH_ROUNDING 1e-4

/* dof of particle a, direction k: a * dim + k. */
typedef struct ps_system {
  const ps_network *net;
  int dim;
  ps_int n_dof;             /* dim * n_particle */
  unsigned char *fixed;     /* [n_dof] 1: prescribed displacement */
  ps_int n_free;
  ps_int *free_of_dof;      /* [n_dof] index among free dofs, or -1 */
  ps_int *dof_of_free;      /* [n_free] */

  /* particle-block pattern, both triangles: column Q holds the particles
   * bidx[bptr[Q] .. bptr[Q+1]) (sorted). Values of all dofs, dof CSC: the
   * entry (P*dim + al, Q*dim + be) with P = bidx[bptr[Q] + k] sits at
   *   Kfull[dim*dim*bptr[Q] + be*dim*len_Q + k*dim + al]. */
  ps_int *bptr, *bidx;
  double *Kfull;
  ps_int *slot_ab;          /* [n_arm] position of block (a, b) in column b */
  ps_int *slot_ba;          /* [n_arm] position of block (b, a) in column a */
  ps_int *slot_diag;        /* [n_particle] position of block (a, a) */
  ps_int *fam_slot_ptr;     /* [n_particle + 1] */
  ps_int *fam_slot;         /* per family, |M|^2 block positions, M = {a} u
                               family, in sorted particle order */
  ps_int *fam_members_ptr;  /* [n_particle + 1] */
  ps_int *fam_members;      /* sorted members of each M_a */
  ps_int *fam_member_arm;   /* arm joining a to that member (-1 for a) */

  ps_csc A;                 /* free-free upper triangle (for linsolve) */
  ps_int *A_src;            /* [nnz(A)] position in Kfull */

  /* per-arm work: current length l, elongation dl, direction q (from a
   * to b; the gradient of l, |q| = |y_b - y_a| / l <= 1), tension T, all
   * of the rounded length of PS_ARM_LENGTH_ROUNDING */
  double *l, *dl, *q, *T;
  double *l0;               /* [n_arm] the rounded reference length
                               sqrt(r0^2 + (e r0)^2), fixed per network */
  /* the arm geometry l, dl, q (and th, r) above is that of positions
   * X_geom + u_geom when geom_valid: an evaluation at the same X and u
   * (bit for bit) takes it as it is instead of computing it again, which
   * gives the same numbers (a Newton iteration evaluates its tangent at
   * the point its line search has just evaluated; a breaking round its
   * forces where the last round converged). Never for models with arm
   * rotations, whose evaluation overwrites q with the force's direction.
   * Whoever writes l, dl or q otherwise sets geom_valid = 0. */
  double *u_geom;           /* [n_dof] */
  const double *X_geom;
  int geom_valid;
  /* the tangent of the last evaluation with one (PS_EVAL_OPERATOR or
   * PS_EVAL_TANGENT), kept through later evaluations of forces alone:
   * the model's stiffnesses tan, and the arm geometry tq (directions,
   * [dim n_arm]) and tTl (T/l, N/m^2 per unit thickness in 2D; 0 for a
   * broken arm), the loose particles and their spring (N/m); the family
   * gradients are in G. A particle is loose in the directions its intact
   * arms do not span (all of them once every arm has broken; the one
   * across a line of collinear arms), and a fragment's particles where
   * its determinate support acts (evaluate.c): free_body[a] is the number
   * of those directions (0: held; at most dim), free_proj the sum of n
   * n^T over them, the spring's direction matrix. */
  ps_arm_tangent tan;
  double *tq, *tTl;
  unsigned char *free_body; /* [n_particle] */
  double *free_proj;        /* [dim dim n_particle], column-major blocks */
  ps_int *group, *group_size, *group_pick; /* work of the loose groups:
                               [n_particle] x 2, [2 n_particle] */
  double *group_far;        /* [n_particle] */
  ps_int loose_max;         /* the most particles with free_body != 0, and */
  ps_int fragments_max;     /* the most fragments supported, at one
                               evaluation with a tangent so far */
  double spring;
  int assembled;            /* Kfull and A hold that tangent */
  double *xw, *yw;          /* [n_dof] work of the matrix-free product */
  int parts;                /* the parts of the loops over arms and
                               particles (ps_util.h; PS_PARTS_DEFAULT, or
                               ps_system_set_parts): the results depend on
                               it, not on the team */
  double *yw_part;          /* [(parts - 1) n_dof] the product's parts
                               1 .. parts - 1's outputs */
  double *f_part;           /* [(parts - 1) n_dof] ps_system_eval's parts
                               1 .. parts - 1's forces */
  ps_team *team;            /* threads for the product (not owned; NULL:
                               one; the results do not depend on it) */
  double *G[2];             /* the family gradients g_a of the tangent
                               (both rank-one terms), [dim x |M_a|] at
                               dim * fam_members_ptr[a]; G[1] allocated
                               when a model has a second term */
  int family_coupling;      /* 1: two-horizon pattern with the family
                               terms; 0: arms only (one horizon) */
  /* models with arm rotations (ps_model_type.rotations, threebody; 2D),
   * allocated by the first evaluation of such a model, else NULL: per
   * arm the rotation th = atan2(n x y, n . y) from the reference
   * direction n to the current (unrounded) arm vector y, the moment M =
   * dPsi/dth, r = dth/dy_b = (z x y)/|y|^2 [2 n_arm]; the tangent's
   * copies tr, tM (tan.Dr the model's rotational stiffnesses). The arm's
   * force is not central: dPsi/dy_b = T q + M r = -dPsi/dy_a. For such a
   * model, T and q above hold that force after ps_system_eval, for the
   * consumers of forces (post: PD stress, boundary stress, J): q its unit
   * direction, T >= 0 its length, T q = dPsi/dy_b (for central models T q
   * is that force already). */
  double *th, *M, *r, *tr, *tM;
} ps_system;

/* Build the dof map and the pattern for a network and a prescribed-dof
 * mask (copied), with room for the models' rank-one family terms (the
 * two-horizon stencil). Returns PS_OK, PS_ERR_NOMEM, PS_ERR_INPUT (no
 * free dof). */
int ps_system_create(ps_system *sys, const ps_network *net,
                     const unsigned char *fixed, ps_ctx *ctx);
/* The same; family_coupling = 0 builds the one-horizon pattern of the
 * arms alone, for models without family terms (ps_model_type
 * family_coupling = 0): 3-4x fewer nonzeros. */
int ps_system_create_pattern(ps_system *sys, const ps_network *net,
                             const unsigned char *fixed, int family_coupling,
                             ps_ctx *ctx);
void ps_system_free(ps_system *sys);

/* The items of the last evaluation for a checkpoint (ps_state_list,
 * ps_util.h), named "sys." + field: per arm l, dl, q, T, the tangent's
 * data (the model's stiffnesses, tq, tTl, the family gradients G, free
 * bodies and spring) and the rotation arrays of a model with arm
 * rotations, so that the tangent a restored system applies, assembles
 * and couples is the one it had, whatever evaluations led to it. A
 * family gradient not yet allocated is allocated here (it is read only
 * where its coefficient is nonzero). After the items are read back the
 * caller marks the system not assembled (sys->assembled = 0): the matrix
 * is assembled again from the restored data when it is needed. Returns
 * PS_OK, PS_ERR_NOMEM or ps_state_add's status. */
int ps_system_state_list(ps_system *sys, ps_state_list *l, ps_ctx *ctx);

/* Split the loops of evaluations and products into `parts` parts
 * (1 .. PS_PARTS_MAX; a new system has PS_PARTS_DEFAULT), reallocating
 * the parts' outputs. The numbers depend on the parts (the order of the
 * sums over arms), never on the team. PS_OK, PS_ERR_INPUT (out of range)
 * or PS_ERR_NOMEM (the system keeps its parts). */
int ps_system_set_parts(ps_system *sys, int parts, ps_ctx *ctx);

/* What ps_system_eval computes besides the forces and the energy. */
enum ps_eval_want {
  PS_EVAL_FORCES = 0,   /* nothing else */
  PS_EVAL_TANGENT = 1,  /* the tangent, assembled into Kfull and A */
  PS_EVAL_OPERATOR = 2  /* the tangent's data only: ps_system_apply uses it
                           matrix-free, ps_system_assemble assembles it
                           when a factorisation needs the matrix */
};

/* Evaluate at displacements u[n_dof] (positions y = X + u): arm lengths,
 * tensions (model), internal forces f[n_dof] = dPsi/dy (at free dofs the
 * residual, at prescribed dofs the reactions), *energy; and the tangent as
 * `want` (enum ps_eval_want) says. Returns PS_OK, PS_ERR_SOLVER if an arm
 * length is not finite (names the particles),
 * PS_ERR_INPUT if the model has family terms and the pattern none, or if
 * a system evaluated with a model with arm rotations is handed another. */
int ps_system_eval(ps_system *sys, const ps_model *model, ps_arm_state *st,
                   const double *X, const double *u, double *f,
                   double *energy, int want, ps_ctx *ctx);

/* Assemble the tangent of the last evaluation with one into Kfull and A
 * (nothing to do after PS_EVAL_TANGENT). Returns PS_OK (a model with
 * family terms on a pattern without them is caught by ps_system_eval). */
int ps_system_assemble(ps_system *sys, ps_ctx *ctx);

/* The first particle (lowest index) that the last evaluation with a
 * tangent found loose in a direction along which it can move (its arms
 * do not hold it there, or it lies in a piece with no prescribed dof
 * while another piece has one: free_body, with a component on a free
 * dof): the dof of its free component most along those directions (for
 * ps_system_dof_name), or -1 when every particle is held. Only the
 * particles `only` marks when it is not NULL (a share's owned ones). */
ps_int ps_system_first_loose(const ps_system *sys, const unsigned char *only);

/* y[n_dof] = K x[n_dof] with the tangent K of the last evaluation with one
 * (all dofs, the loose particles' springs included), matrix-free: arm terms
 * and rank-one family terms, O(arms + family members), without the
 * two-horizon matrix (doc/performance.md). In sys->parts parts on
 * sys->team's threads; the parts' sums go through sys->yw_part, so two
 * calls on one system must not run at the same time. */
void ps_system_apply(const ps_system *sys, const double *x, double *y);

/* y[n_free] = K_ff x[n_free], matrix-free (as ps_system_apply); equals
 * A x with A assembled from the same tangent. Uses sys->xw, sys->yw. */
void ps_system_apply_free(ps_system *sys, const double *x, double *y);

/* ps_system_apply_free as an operator for ps_linsolve_pcg. */
ps_operator ps_system_operator(ps_system *sys);

/* A one-horizon majorant of the last tangent of K, for preconditioning:
 * into pre (a system on the same network and dofs, created with
 * family_coupling = 0), the arm terms of K with each positive family term
 * c g g^T replaced by arm stiffnesses that bound it from above by
 * Cauchy-Schwarz,
 *   c (sum_k w_k dl_k)^2 <= c (sum_k |w_k| r0_k) sum_k |w_k| dl_k^2 / r0_k,
 * and negative family terms dropped, so that x^T K x <= x^T pre x for all
 * x: the eigenvalues of pre^-1 K lie in (0, 1] when K is positive
 * definite, and for the elastic fibre model in [min(r, 1/r), 1] with
 * r = G(N+2)/(NK) (0.8 for nu = 0.3 in plane strain; doc/performance.md).
 * Needs K evaluated with the tangent (either want; K need not be
 * assembled). pre's tangent arm stiffnesses pre->tan.D receive the
 * majorant's (pre is never evaluated itself); its Kfull and A the matrix.
 * Returns PS_OK, PS_ERR_INPUT when the systems do not match. */
int ps_system_assemble_majorant(ps_system *pre, const ps_system *K, ps_ctx *ctx);

/* out[n_free] = K_fp du_p: the coupling of prescribed increments du[n_dof]
 * (free entries ignored) into the free rows, with the tangent of the last
 * evaluation with one (matrix-free). Uses sys->xw, sys->yw. */
void ps_system_coupling(ps_system *sys, const double *du, double *out);

/* Name of a dof for messages: "particle 1234 (x = .., y = ..), dof y". */
void ps_system_dof_name(const ps_system *sys, const double *X, ps_int dof,
                        char *buf, size_t len);

#endif
