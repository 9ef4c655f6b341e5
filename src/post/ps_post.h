/* ps_post.h: quantities derived from a solved state: damage (Eq. 119, as
 * 1 - intact/initial arms), boundary stress from reactions, crack tip,
 * least-squares strain of a region, RMS error against a reference field,
 * and the Griffith line fit (GSL). */
#ifndef PS_POST_H
#define PS_POST_H

#include "../model/ps_model.h"

/* phi_a = 1 - (intact arms of a) / (arms of a at creation). */
void ps_post_damage(const ps_network *net, const ps_arm_state *st,
                    double *phi);

/* Boundary stress carried across the interface between the measured
 * particles (m nonzero) and the rest (the zone's reactions over the
 * interface length would also count its own hoop and corner forces; see
 * doc/model.md): the sum over arms a (measured) - b
 * (not) of T_ab (e_ba . m_a), e_ba the current unit vector from b to a,
 * divided by length. This is the normal force the boundary zone exerts on
 * the interior over the interface length. T and q as in ps_system (q from
 * net->a to net->b). own_arm: only the arms it marks (a process's share
 * of a distributed model, ps_model.own_arm); NULL: every arm. */
double ps_post_boundary_stress(const ps_network *net, const double *T,
                               const double *q, const double *m,
                               double length, const unsigned char *own_arm);

/* Crack tip distance from the origin: the largest distance of a broken
 * arm's midpoint (reference configuration) from (0, 0), in units of c;
 * 1 when no arm is broken (the initial tips are at +-c). own_arm: only
 * the arms it marks (as in ps_post_boundary_stress); NULL: every arm. */
double ps_post_crack_tip(const ps_particles *P, const ps_network *net,
                         const ps_arm_state *st, double c, const unsigned char *own_arm);

/* The peridynamic stress tensor of Fallah et al. (2020), Eq. 24:
 *   sigma_a = 1/(2 V_a) sum_b F_ab (x) (X_b - X_a),
 * F_ab = T_ab q_ab the force of arm ab on a (q from a to b in the current
 * configuration), X the reference positions. Works for any central-force
 * model. sigma[a*dim*dim + i*dim + j], Pa. Accurate one horizon away from
 * free surfaces and cracks (skin effect; Fallah et al. section 4). */
void ps_post_stress_tensor(const ps_particles *P, const ps_network *net,
                           const double *T, const double *q, double *sigma);

/* Displacement gradient per particle, H[a d^2 + j d + k] = du_j/dx_k: the
 * least-squares fit of u_b - u_a = H (X_b - X_a) over a's intact arms,
 * weights 1 / r0^2 (the nearest neighbours count most). Arms across a
 * crack do not exist, so at crack faces the fit is one-sided, as it must
 * be. A particle whose arms do not span the space gets H = 0. */
void ps_post_displacement_gradient(const ps_particles *P, const ps_network *net,
                                   const ps_arm_state *st, const double *u, double *H);

/* J-integral of a straight crack running along +x with its tip at tip[],
 * by the equivalent domain integral of Fallah et al. (2020), Eq. 39:
 *   J = sum_k (sigma_ij du_j/dx_1 - W delta_1i) dq/dx_i V_k,
 * sigma from Eq. 24 (ps_post_stress_tensor), du/dx from
 * ps_post_displacement_gradient, W = sigma_ij du_i/dx_j / 2 (linear
 * elasticity), and the trapezoidal weight q = 1 for rho <= l_in, 0 for
 * rho >= l_out, linear in between, rho = max(|x - x_tip|, |y - y_tip|)
 * (a square ring around the tip, Fallah Fig. 14). 2D; J in J/m^2 (N/m),
 * V_k areas per unit thickness. */
double ps_post_j_domain(const ps_particles *P, const double *sigma, const double *H,
                        const double *tip, double l_in, double l_out);

/* J-integral by the nonlocal contour form of Hu et al. as Fallah et al.
 * (2020) write it (Eq. 36): J = sum W n_x ds - sum F_km . (u_k,x +
 * u_m,x) / 2 over the square contour rho = max(|x - x_tip|, |y - y_tip|)
 * = l (crack along +x), the first sum over the particle rows on the two
 * vertical sides (W = sigma_ij u_i,j / 2 interpolated linearly between the
 * columns beside the contour, ds = dx), the second over the arms that cross the
 * contour, F_km = T q the force on the inner end k from the outer end m
 * (the traction of the outside on the inside; the mean of the two ends'
 * du/dx stands for du/dx on the contour). On a lattice put the contour
 * between particle rows (particles exactly on a horizontal side count as
 * outside). 2D; J in N/m. */
double ps_post_j_contour(const ps_particles *P, const ps_network *net, const double *T,
                         const double *q, const double *sigma, const double *H,
                         const double *tip, double l, double dx);

/* The crack-tip frame of a straight crack of any direction (2D): dir is
 * the unit vector e1 from the crack into the material ahead of the tip
 * (normalised here; NULL: +x), e2 = e1 turned by +90 degrees. The square
 * rings and contours below are aligned with e1, e2 (rho = max(|x1|,
 * |x2|), x1, x2 the local coordinates of x - tip); stresses, displacement
 * gradients and the gradient of q are taken in that frame (A' = R A R^T,
 * R with rows e1, e2). With dir = +x (or NULL) the numbers are those of
 * ps_post_j_domain / ps_post_j_contour to the bit. */
double ps_post_j_domain_dir(const ps_particles *P, const double *sigma, const double *H,
                            const double *tip, const double *dir, double l_in,
                            double l_out);
double ps_post_j_contour_dir(const ps_particles *P, const ps_network *net, const double *T,
                             const double *q, const double *sigma, const double *H,
                             const double *tip, const double *dir, double l, double dx);

/* The Williams near-tip fields of a crack along -x1 with K = 1 Pa sqrt(m)
 * (mode 1: K_I, 2: K_II) at local (x1, x2): stress sig[2i + j] (Pa) and
 * displacement gradient Hu[2j + k] = du_j/dx_k, mu = E / (2 (1 + nu)),
 * kappa = 3 - 4 nu (plane strain) or (3 - nu)/(1 + nu) (plane stress:
 * plane == PS_PLANE_STRESS). Anderson, Fracture Mechanics, Tables 2.1-2.2. */
void ps_post_williams(int mode, double x1, double x2, double E, double nu, int plane,
                      double *sig, double *Hu);

/* K_I, K_II (Pa sqrt(m)) of the tip by the interaction integral in its
 * domain form, in the crack-tip frame (same ring and q as
 * ps_post_j_domain_dir):
 *   I_m = sum_k (sigma_ij u^m_j,1 + sigma^m_ij u_j,1 - W_m delta_1i) q,_i V_k,
 *   W_m = (sigma_ij u^m_i,j + sigma^m_ij u_i,j) / 2,
 * the auxiliary field m the Williams field of mode m with K = 1
 * (ps_post_williams), sigma and u_,j as for J; K_I = E' I_1 / 2, K_II =
 * E' I_2 / 2, E' = E (plane stress) or E / (1 - nu^2) (plane strain).
 * Then J = (K_I^2 + K_II^2) / E' for a linear elastic field. K[0] = K_I,
 * K[1] = K_II. 2D. */
void ps_post_k_interaction(const ps_particles *P, const double *sigma, const double *H,
                           const double *tip, const double *dir, double l_in, double l_out,
                           double E, double nu, int plane, double *K);

/* Least-squares affine fit u(x) = u0 + H x over the particles with
 * mask[a] != 0; writes the symmetric strain eps[i*dim + j] = (H_ij + H_ji)/2.
 * Returns PS_OK, or PS_ERR_INPUT when fewer than dim + 1 particles are
 * selected. */
int ps_post_fit_strain(const ps_particles *P, const double *u,
                       const unsigned char *mask, double *eps, ps_ctx *ctx);

/* sqrt(sum |u - u_ref|^2 / sum |u_ref|^2) over particles with mask[a]. */
double ps_post_rms_error(int dim, ps_int n, const double *u,
                         const double *u_ref, const unsigned char *mask);

/* Least-squares line y = intercept + slope x (GSL gsl_fit_linear) and the
 * coefficient of determination R^2. Returns PS_OK or PS_ERR_INPUT (n < 2). */
int ps_post_line_fit(const double *x, const double *y, int n, double *slope,
                     double *intercept, double *r2, ps_ctx *ctx);

#endif
