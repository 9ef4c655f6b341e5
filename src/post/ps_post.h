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
 * net->a to net->b). */
double ps_post_boundary_stress(const ps_network *net, const double *T,
                               const double *q, const double *m,
                               double length);

/* Crack tip distance from the origin: the largest distance of a broken
 * arm's midpoint (reference configuration) from (0, 0), in units of c;
 * 1 when no arm is broken (the initial tips are at +-c). */
double ps_post_crack_tip(const ps_particles *P, const ps_network *net,
                         const ps_arm_state *st, double c);

/* The peridynamic stress tensor of Fallah et al. (2020), Eq. 24:
 *   sigma_a = 1/(2 V_a) sum_b F_ab (x) (X_b - X_a),
 * F_ab = T_ab q_ab the force of arm ab on a (q from a to b in the current
 * configuration), X the reference positions. Works for any central-force
 * model. sigma[a*dim*dim + i*dim + j], Pa. Accurate one horizon away from
 * free surfaces and cracks (skin effect; Fallah et al. section 4). */
void ps_post_stress_tensor(const ps_particles *P, const ps_network *net,
                           const double *T, const double *q, double *sigma);

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
