/* ps_network.h: the arm network of Olsson et al. (2021): neighbour search
 * with the arm rule r < alpha max(h_a, h_b), pre-crack cuts, the kernel of
 * Eq. 112 normalised by Eq. 54, and the arm weights of Eq. 70
 * A_ab = -(m_a m_b / rho_a^2) dW_ab/dr = -V_a V_b f'(r/h_a) / h_a^(N+1)
 * (uniform density, m = rho V). */
#ifndef PS_NETWORK_H
#define PS_NETWORK_H

#include "../geom/ps_geom.h"

/* The polynomial kernel of Eq. 112: f(u) = (1 - u^2/alpha^2)^k / Z for
 * u <= alpha, 0 beyond, with Z such that int f(u) 2(N-1) pi u^(N-1) du = 1
 * (Eq. 54). */
typedef struct ps_kernel {
  int dim;      /* N */
  int k;        /* exponent (paper: 2) */
  double alpha; /* horizon in units of h (paper: 5.1) */
  double Z;     /* normalisation of Eq. 112 */
} ps_kernel;

/* Set up the kernel; Z by GSL adaptive quadrature of Eq. 112's denominator.
 * Returns PS_OK, or PS_ERR_INPUT for alpha <= 0, k < 1 or dim not 2/3. */
int ps_kernel_init(ps_kernel *K, int dim, int k, double alpha, ps_ctx *ctx);
/* Closed form of Z for k = 2 (Eq. 113 without its stray C):
 * 2 (N-1) pi alpha^N (1/N - 2/(N+2) + 1/(N+4)). */
double ps_kernel_Z_k2(int dim, double alpha);
/* f(u) and f'(u) = df/du of Eq. 112. */
double ps_kernel_f(const ps_kernel *K, double u);
double ps_kernel_df(const ps_kernel *K, double u);

/* A straight pre-crack: arms whose segment crosses it are not created. */
typedef struct ps_crack {
  double p0[3], p1[3]; /* end points (2D: a segment; 3D: not yet supported) */
} ps_crack;

/* The arm network. Arm i joins particles a[i] < b[i]. Each particle's
 * family (the arms incident to it) is stored CSR-wise: fam_arm[fam_ptr[p]
 * .. fam_ptr[p+1]) are arm indices, in increasing order of the other end. */
typedef struct ps_network {
  int dim;
  ps_int n_particle, n_arm;
  ps_int *a, *b;     /* end particles */
  double *r0;        /* reference length, m */
  double *A_ab;      /* weight of a's side (m^(N-1)), may be 0 */
  double *A_ba;      /* weight of b's side */
  ps_int *fam_ptr;   /* [n_particle + 1] */
  ps_int *fam_arm;   /* [2 n_arm] */
  ps_int *n_arm0;    /* arms per particle at creation (damage, Eq. 119) */
  double max_h_ratio;/* largest h / smallest h */
} ps_network;

/* Build the network: arms r < alpha max(h_a, h_b), none crossing a crack
 * segment, weights of Eq. 70 from the kernel. Returns PS_OK, PS_ERR_INPUT
 * (a particle left without arms, a non-positive size or volume),
 * PS_ERR_NOMEM. */
int ps_network_build(ps_network *net, const ps_particles *p,
                     const ps_kernel *K, const ps_crack *cracks, int n_cracks,
                     ps_ctx *ctx);
void ps_network_free(ps_network *net);

/* Is segment x->y crossing the crack (2D)? Exposed for the tests. */
int ps_crack_cuts(const ps_crack *cr, const double *x, const double *y);

#endif
