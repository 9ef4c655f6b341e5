/* ps_moduli.h: the moduli correction of the fibre and state models
 * (issue 19; doc/moduli.md): per-particle factors on the half-arms, computed
 * from the particle's energy under homogeneous strain, so that every
 * particle's stiffness is the continuum's, in the bulk of any lattice or
 * cloud and at its surfaces.
 *
 * Under a homogeneous strain eps an arm of direction n has the strain
 * n.eps.n, so a particle's energy is a quadratic form in eps whose arm part
 * is the fourth moment M4 = sum_b w_b n n n n of its half-arm weights w
 * (and whose family part, the fibre model's mean strain or the state
 * model's dilatation, is a second moment M2 = sum_b w_b n n). The energies
 * of the N(N+1)/2 independent homogeneous strain states are the
 * components of these moments; the continuum's are isotropic, t I_p (I_2 =
 * delta_ij, I_4 = delta_ij delta_kl + delta_ik delta_jl + delta_il
 * delta_jk). ps_moduli_factors gives each half-arm of particle a the factor
 *   phi_b = 1 + sum_alpha lambda_alpha n_b^alpha   (|alpha| = p, p = 2 or 4)
 * of least change sum_b w_b (phi_b - 1)^2 that makes the moment the
 * isotropic target: sum_b w_b phi_b n_b^(x)p = t_a I_p (a linear system of
 * 3 or 5 unknowns in 2D, 6 or 15 in 3D, the monomials of degree p). One
 * scalar per arm could only rescale the energy direction by direction
 * (Li & Hao Eq. A.3-A.6, bond.c); the degree-p form also removes the
 * cubic anisotropy of a square or cubic lattice (C66 against
 * (C11 - C12)/2), which a scalar per particle cannot.
 *
 * A family whose arms cannot carry the isotropic moment with positive
 * factors (a corner, a particle with few arms) gets the least change cut
 * back so that no factor falls below the floor, phi_b >= floor (a partial
 * match, counted in ps_moduli_stats); a family whose moment matrix is
 * singular keeps phi = 1.
 *
 * The switch: material.surface_correction, a tri-state in ps_material (< 0
 * unset, 0 off, 1 on). The fibre and state models apply this correction
 * only when it is 1 (their default, unset, is the uncorrected model: the
 * paper's Griffith reproduction); the bond and three-body models read any
 * non-zero value as their own Li & Hao correction, as before. */
#ifndef PS_MODULI_H
#define PS_MODULI_H

#include "ps_model.h"

/* The lowest half-arm factor the correction gives (see above). */
#define PS_MODULI_FLOOR 0.1

/* What the correction did, for reports and tests. */
typedef struct ps_moduli_stats {
  ps_int n_matched; /* particles whose moment is the target (to round-off) */
  ps_int n_partial; /* particles whose change was cut back at the floor */
  ps_int n_singular;/* particles whose moment matrix is singular: phi = 1 */
  double phi_min, phi_max; /* over the half-arms with w > 0 */
  ps_int n_balanced; /* particles whose force moment is balanced
                        (ps_moduli_balance) */
  ps_int n_surface;  /* particles near a surface in the second stage:
                        their forces under its traction-free states are
                        balanced (with energy_only: their factors are
                        matched under those states) */
  int balance_passes;/* solves made; negative: the balance was given up
                        and the local factors kept */
  ps_int balance_iterations; /* CG iterations of those solves (3D) */
} ps_moduli_stats;

/* 1 when the fibre or state model applies the moduli correction:
 * mat->surface_correction == 1 (set in the case; unset is < 0). */
int ps_moduli_correction_on(const ps_material *mat);

/* The factors of the half-arms: w[2 n_arm] the uncorrected half-arm
 * weights ([i] end a's side of arm i, [n_arm + i] end b's; >= 0), order 2
 * or 4, target[n_particle] the scale t_a of the isotropic moment t_a I_p;
 * out phi[2 n_arm] (same layout; 1 where w = 0) and, when stats != NULL,
 * the counts above. The directions are the reference ones, P->x. Returns
 * PS_OK or PS_ERR_INPUT (order not 2 or 4, dim not 2 or 3). */
int ps_moduli_factors(const ps_particles *P, const ps_network *net, int order,
                      const double *w, const double *target, double *phi,
                      ps_moduli_stats *stats, ps_ctx *ctx);

/* ps_moduli_balance puts a particle on the surface (a free face, a hole
 * or a crack) when the first moment of its half-arm weights, |sum_b w_b
 * n_b|, exceeds this share of their sum sum_b w_b: the outermost row of a
 * square lattice has about 0.55 and the next 0.2 (fibre, alpha 5.1), the
 * interior of a square lattice jittered by 0.2 spacings stays below 0.14. */
#define PS_MODULI_SURFACE 0.3

/* The factors of ps_moduli_factors made to balance the forces as well.
 * For a model whose arm force under a homogeneous strain eps is, order 4,
 * s_ab f(n.eps.n, tr eps) n, or, order 2, s_ab g(tr eps) n, with the
 * arm's stiffness s_ab = k_ab phi_ab + k_ba phi_ba (the fibre model,
 * order 4: k = A; the state model, order 4 for its deviatoric part: k =
 * ks xi, order 2 for its dilatation: k = ks), once every energy moment is
 * matched (so that the mean strain or the dilatation is tr eps / N or tr
 * eps everywhere). On an irregular cloud the sum of these forces at a
 * particle is not zero, so the homogeneous state is not an equilibrium:
 * the network relaxes and is softer than its particles' energies say
 * (doc/moduli.md). Here the factors of the matched particles are the
 * least change sum w (phi - 1)^2 such that every matched particle's
 * energy moment is its target and every balanced particle c (matched,
 * with no particle on the surface, PS_MODULI_SURFACE, within two arms)
 * has a zero moment of degree order - 1, sum_b s_cb n^(x)(order - 1) = 0
 * (order 4: the third moment, whose trace is the first), so that the
 * force vanishes for every eps. That is one sparse symmetric positive
 * definite system over all particles (its Lagrange multipliers, 9 a
 * particle in 2D, 25 in 3D at order 4), factored by CHOLMOD in 2D and
 * solved by conjugate gradients in 3D, where the factor is too large (CG
 * preconditioned by each particle's diagonal block, to a relative
 * residual of 1e-13). Factors below the floor are held at it and the
 * system solved again (an active set, at most 8 solves). The local
 * factors are kept, with stats->balance_passes 0, where they balance
 * every balanced particle already (a lattice: bit for bit); with
 * balance_passes < 0 where the system is singular (or CG does not
 * converge in 20,000 iterations), does not fit in memory, its solution is
 * inaccurate (a constraint off by more than 1e-8) or 8 solves leave a
 * factor below the floor (a warning on ctx->log says so). The force
 * rows are scaled by the mean arm length (a power of two), so the result
 * does not depend on the unit of length. The factors of unmatched
 * particles are ps_moduli_factors'. w, k: [2 n_arm] half-arm weights as
 * ps_moduli_factors' w; order and target as there; out phi. Returns
 * PS_OK, PS_ERR_INPUT (order not 2 or 4, dim not 2 or 3), PS_ERR_NOMEM or
 * a fatal status of the linear solver. */
/* The surface conditions of ps_moduli_balance (NULL: none): the model's
 * N-dimensional moduli K, G (mat->K, mat->G) and beta, its arm force
 * under a homogeneous strain eps being s (n.eps.n + beta tr eps) n (the
 * fibre model: beta = (NK - G(N+2)) / (N G (N+2))). With them, after the
 * interior, a second stage balances the layer a free surface cuts: every
 * matched particle with a surface particle (PS_MODULI_SURFACE) among
 * itself and its neighbours gets N force rows for each stress state with
 * no traction on the nearby faces (normals: the principal directions of
 * the surface particles' first moments; 1 state at a 2D face, 3 at a 3D
 * face, 1 along an edge, none at a corner), so that the homogeneous
 * states the continuum holds in equilibrium there are equilibria of the
 * network too; the deep interior (balanced particles with balanced
 * neighbours only) and the arms that reach it keep the first stage's
 * factors. A partly matched particle near a surface (a 3D edge, whose
 * quarter-space family cannot carry the isotropic moment above the floor)
 * gets these force rows too, and instead of the moment only the
 * conditions its states see, per state e: order 4, its half-arm virial
 * stress the continuum's (N(N+1)/2 rows, with the kfix part's) and,
 * without kfix, its mean strain tr e / N (1 row more); order 2, its
 * second moment under e, sum_b w phi n.e.n = t tr e (the state model's
 * dilatation, 1 row); one whose rows are dependent or span the whole
 * moment (three states at a 3D face) stays out. A direction is normal to
 * the nearby faces when the surface particles' normals put more than a
 * quarter of the largest eigenvalue, or a tenth of the trace, of sum u
 * u^T on it (at a corner all N are). */
typedef struct ps_moduli_surface {
  double K, G, beta;
  /* [2 n_arm] or NULL: half-arm stiffnesses (in k's units) of a part of
   * the arm force that these factors do not change, (kfix_ab + kfix_ba)
   * tr eps n under eps, added to the surface rows (the state model's
   * dilatation, balanced by its own factors before); with it the
   * restricted rows of a partly matched particle are its half-arm virial
   * stress only, the fixed part's included */
  const double *kfix;
  /* 1: no force rows at the surface; only the partly matched particles
   * near it join the stage, with their restricted rows (the state
   * model's dilatation, order 2, whose surface force the deviatoric
   * stage carries through kfix) */
  int energy_only;
} ps_moduli_surface;

int ps_moduli_balance(const ps_particles *P, const ps_network *net, int order,
                      const double *w, const double *k, const double *target,
                      const ps_moduli_surface *surf, double *phi, ps_moduli_stats *stats,
                      ps_ctx *ctx);

#endif
