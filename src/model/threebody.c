/* threebody.c: the three-body (bond stretch + bond shear) model of Li &
 * Hao (2023), Int J Fract 239:211-232, 2D, in the form of
 * doc/design-threebody.md. What is published and what is ours:
 *  - [pub] the three-body idea, the "bond shear form" under small
 *    deformation and failure by a micropotential criterion (the abstract);
 *    the partial volumes (Eq. A.2) and the energy-based surface correction
 *    (Eq. A.3-A.6). The paper's own potential is not available to us.
 *  - [derived, design note sec. 1-2, checked by its prototype] everything
 *    else: the energy, the constants, the kinematics, forces and tangent.
 * Arm i (ends a, b), reference length xi, direction n, current vector y:
 *   s_i = dl_i / xi_i (rounded length of the assembly, as bond.c),
 *   theta_i = atan2(n x y, n . y)  (finite rotation of the arm),
 *   k_ai = v_a R xi V_a V_b  (a's half-arm weight; v_a the partial volume
 *          of b's cell in a's horizon, R the surface correction; on a
 *          lattice k_ai = k_bi = k_i),
 *   rho_a = atan2(sum k sin theta, sum k cos theta) over a's intact arms,
 *   g_ai = wrap(theta_i - rho_a) - <wrap(theta - rho_a)>_k  (the arm's
 *          rotation relative to the k-weighted mean rotation of a's family),
 *   Psi = sum_i [ 1/2 c k_i s_i^2 + 1/4 kappa (k_ai g_ai^2 + k_bi g_bi^2) ],
 * k_i = (k_ai + k_bi)/2. Since g is relative to the weighted mean, the
 * shear energy of a family is a sum over its pairs of arms of the squared
 * change of the angle between them: a three-body potential [derived].
 * Forces: T_i = dPsi/dl_i = c k_i s_i / xi_i, M_i = dPsi/dtheta_i =
 * 1/2 kappa (k_ai g_ai + k_bi g_bi) (no term through the mean: it is the
 * minimiser). Tangent: D_i = c k_i / xi^2, Dr_i = 1/2 kappa (k_ai + k_bi),
 * and per particle a the rank-one term -kappa/(2 S_a) (sum k_ai dtheta_i)^2
 * on the rotations, S_a = sum k_ai.
 * Constants [derived]: matching 1/2 eps:C:eps under homogeneous strain,
 *   c = 12 K beta / (pi delta^3),  kappa = 12 (G - lambda) beta / (pi delta^3)
 * (plane stress: c = 6E/(pi delta^3 (1 - nu)) beta, kappa = 6E(1 - 3nu) /
 * (pi delta^3 (1 - nu^2)) beta; plane strain: c = 6E/(pi delta^3 (1 + nu)
 * (1 - 2nu)) beta, kappa = 6E(1 - 4nu)/(pi delta^3 (1 + nu)(1 - 2nu)) beta),
 * K, G, lambda the 2D moduli. beta [derived, our choice] = (2 pi delta^3
 * / 3) / sum_b v(xi_b) xi_b V_b over the offsets of an interior particle
 * of the ideal lattice (square or hex, told apart by the cell volume);
 * beta = 1 on a point cloud. kappa < 0 (nu > 1/3 plane stress, > 1/4
 * plane strain) is refused, and so is 3D.
 * Surface correction [Eq. A.3-A.6, adapted]: W_k(a) = 1/4 sum_b v_a V_b xi
 * [c n_k^4 + kappa (n_k t_k - m_ak)^2] (m_ak the weighted family mean of
 * n_k t_k, t = z x n), W_inf = the same sum for an interior particle of
 * the ideal lattice (on a cloud the continuum's, 1/2 C11), so R = 1 in
 * the bulk and beta survives; Eq. A.5-A.6 as bond.c.
 * Breaking [form derived]: the arm micropotential w_i = R xi [1/2 c s^2 +
 * 1/4 kappa (v_a g_a^2 + v_b g_b^2)/v] passes w_c in tension (s > 0): the
 * model writes st->stretch[i] = s_eq = sqrt(s^2 + kappa (k_a g_a^2 + k_b
 * g_b^2) / (2 c k)) for s > 0 (else s), so that 1/2 c R xi s_eq^2 = w_i
 * and breaking.c's stretch excess with the per-arm s0 of w_c applies
 * unchanged; w_c = 3 G_c / (2 delta^3) from a fracture energy. */
#include "ps_model.h"

#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>

double ps_threebody_max_poisson(int plane) {
  return plane == PS_PLANE_STRESS ? 1.0 / 3.0 : 0.25;
}

int ps_threebody_poisson_check(double nu, int plane, ps_ctx *ctx) {
  if (nu <= ps_threebody_max_poisson(plane) + 1e-3) return PS_OK;
  int stress = plane == PS_PLANE_STRESS;
  return ps_error(ctx, PS_ERR_INPUT,
                  "material.nu = %g: the threebody model needs a non-negative bond-shear "
                  "stiffness, nu <= 1/3 in plane stress and nu <= 1/4 in plane strain "
                  "(kappa = %s would be negative; this case is plane %s); use model state "
                  "for this nu",
                  nu,
                  stress ? "6E(1-3nu)/(pi delta^3 (1-nu^2))"
                         : "6E(1-4nu)/(pi delta^3 (1+nu)(1-2nu))",
                  stress ? "stress" : "strain");
}

int ps_threebody_fracture_check(int fracture, ps_ctx *ctx) {
  if (fracture != PS_FRACTURE_STRETCH) return PS_OK;
  return ps_error(ctx, PS_ERR_INPUT,
                  "material.fracture: the threebody model breaks by its arm micropotential "
                  "(stretch and shear energy; Li & Hao 2023): give critical_micropotential "
                  "or fracture_energy (criterion energy), not a critical stretch");
}

/* c and kappa without beta: 12 K / (pi d^3), 12 (G - lambda) / (pi d^3),
 * lambda = K - G in 2D; kappa < 0 within the tolerance on nu is 0 */
static void continuum_constants(const ps_material *mat, double *c, double *kap) {
  double d3 = M_PI * pow(mat->horizon, 3);
  double lambda = mat->K - mat->G;
  *c = 12.0 * mat->K / d3;
  *kap = 12.0 * (mat->G - lambda) / d3;
  if (*kap < 0) *kap = 0.0;
}

/* w(x) = x - 2 pi round(x / 2 pi), in (-pi, pi] */
static double wrap(double x) { return x - 2.0 * M_PI * floor((x + M_PI) / (2.0 * M_PI)); }

/* partial volume of an arm of length xi (full: 1 within the horizon) */
static double arm_volume(const ps_material *mat, double xi, double dx, int full) {
  if (full) return xi <= mat->horizon * (1 + 1e-9) ? 1.0 : 0.0;
  return ps_partial_volume(xi, mat->horizon, dx);
}

/* The ideal lattice's sums for an interior particle: *S = sum v xi V,
 * Wk[k] = 1/4 sum v V xi [c n_k^4 + kappa n_k^2 t_k^2]; hex or square,
 * spacing dx */
static void lattice_sums(const ps_material *mat, int hex, double dx, double c, double kap,
                         double *S, double *Wk) {
  double delta = mat->horizon, V = hex ? 0.5 * sqrt(3.0) * dx * dx : dx * dx;
  int J = (int)ceil((delta + dx) / (hex ? 0.5 * sqrt(3.0) * dx : dx)) + 1;
  *S = Wk[0] = Wk[1] = 0.0;
  for (int j = -J; j <= J; j++)
    for (int i = -J - J; i <= J + J; i++) {
      double ox = hex ? (i + 0.5 * j) * dx : i * dx, oy = hex ? 0.5 * sqrt(3.0) * j * dx : j * dx;
      double xi = sqrt(ox * ox + oy * oy);
      if (xi == 0.0) continue;
      double v = arm_volume(mat, xi, dx, mat->full_volumes);
      if (v <= 0) continue;
      double nx = ox / xi, ny = oy / xi, nt = nx * ny; /* |n_k t_k| */
      *S += v * xi * V;
      Wk[0] += 0.25 * v * V * xi * (c * nx * nx * nx * nx + kap * nt * nt);
      Wk[1] += 0.25 * v * V * xi * (c * ny * ny * ny * ny + kap * nt * nt);
    }
}

/* work layout: [0] c, [1] kappa, then S[np], rho[np], mean[np] */
static int tb_prepare(ps_model *m, const ps_particles *P, ps_ctx *ctx) {
  const ps_network *net = m->net;
  ps_material *mat = &m->mat;
  if (net->dim != 2)
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.model threebody is 2D only (geometry.dim is %d): its "
                    "finite-rotation form has no 3D counterpart here "
                    "(doc/design-threebody.md, decision 4)", net->dim);
  PS_CHECK(ps_lattice_model_check(mat, 2, P, "threebody", ctx));
  PS_CHECK(ps_threebody_poisson_check(mat->nu, mat->plane, ctx));
  PS_CHECK(ps_threebody_fracture_check(mat->fracture, ctx));
  double c, kap, dx = mat->spacing;
  continuum_constants(mat, &c, &kap);
  /* beta and W_inf from the ideal lattice (a box lattice: mat->spacing >
   * 0; square or hex from the cell volume), or 1 and the continuum's
   * 1/2 C11 on a cloud */
  double beta = 1.0, Winf[2];
  if (dx > 0) {
    int hex = fabs(P->volume[0] / (dx * dx) - 0.5 * sqrt(3.0)) < 1e-6;
    double S, Wk[2];
    lattice_sums(mat, hex, dx, c, kap, &S, Wk);
    beta = 2.0 * M_PI * pow(mat->horizon, 3) / 3.0 / S;
    Winf[0] = beta * Wk[0];
    Winf[1] = beta * Wk[1];
  } else {
    Winf[0] = Winf[1] = pow(mat->horizon, 3) / 12.0 * (0.75 * M_PI * c + 0.25 * M_PI * kap);
  }
  c *= beta;
  kap *= beta;
  ps_int na = net->n_arm, np = net->n_particle;
  int cloud_pv = !(dx > 0) && !mat->full_volumes;
  m->arm_k = ps_calloc((size_t)na, sizeof *m->arm_k, ctx);
  m->work = ps_calloc((size_t)(2 + 3 * np), sizeof *m->work, ctx);
  double *ks = ps_calloc((size_t)(2 * na), sizeof *ks, ctx); /* uncorrected k_a, k_b */
  double *Wk = ps_calloc((size_t)(4 * np), sizeof *Wk, ctx); /* W_k(a), m_ak sums */
  double *cxi = ps_calloc((size_t)na, sizeof *cxi, ctx);
  if (cloud_pv) m->arm_side = ps_calloc((size_t)(2 * na), sizeof *m->arm_side, ctx);
  if (!m->arm_k || !m->work || !ks || !Wk || !cxi || (cloud_pv && !m->arm_side)) {
    free(ks);
    free(Wk);
    free(cxi);
    return PS_ERR_NOMEM;
  }
  m->work[0] = c;
  m->work[1] = kap;
  for (ps_int i = 0; i < na; i++) {
    ps_int a = net->a[i], b = net->b[i];
    double xi = net->r0[i], va, vb;
    if (mat->full_volumes)
      va = vb = arm_volume(mat, xi, dx, 1);
    else
      ps_arm_partial_volumes(mat, P, net, i, &va, &vb);
    double VV = P->volume[a] * P->volume[b];
    ks[i] = va * xi * VV;
    ks[na + i] = vb * xi * VV;
  }
  /* surface correction (Eq. A.3 adapted): W_k(a) under unit uniaxial
   * strain along k, with the family mean m_ak of n_k t_k */
  if (mat->surface_correction) {
    double *msum = &Wk[2 * np]; /* [np] sum k n_x n_y, [np] sum k (from a's side) */
    for (ps_int i = 0; i < na; i++) {
      ps_int a = net->a[i], b = net->b[i];
      double xi = net->r0[i];
      double nx = (P->x[2 * b] - P->x[2 * a]) / xi, ny = (P->x[2 * b + 1] - P->x[2 * a + 1]) / xi;
      msum[a] += ks[i] * nx * ny;
      msum[np + a] += ks[i];
      msum[b] += ks[na + i] * nx * ny;
      msum[np + b] += ks[na + i];
    }
    for (ps_int i = 0; i < na; i++) {
      ps_int a = net->a[i], b = net->b[i];
      double xi = net->r0[i];
      double nx = (P->x[2 * b] - P->x[2 * a]) / xi, ny = (P->x[2 * b + 1] - P->x[2 * a + 1]) / xi;
      double nt = nx * ny; /* n_x t_x = -nt, n_y t_y = +nt */
      for (int e = 0; e < 2; e++) {
        ps_int p = e == 0 ? a : b;
        double kk = e == 0 ? ks[i] : ks[na + i];
        double mean = msum[np + p] > 0 ? msum[p] / msum[np + p] : 0.0;
        double gx = -nt + mean, gy = nt - mean; /* n_k t_k - m_ak, m_ax = -mean */
        /* 1/4 sum_b v V_b xi [...] = 1/(4 V_a) sum k [...] */
        Wk[2 * p] += 0.25 * kk / P->volume[p] * (c * nx * nx * nx * nx + kap * gx * gx);
        Wk[2 * p + 1] += 0.25 * kk / P->volume[p] * (c * ny * ny * ny * ny + kap * gy * gy);
      }
    }
  }
  for (ps_int i = 0; i < na; i++) {
    ps_int a = net->a[i], b = net->b[i];
    double xi = net->r0[i], R = 1.0;
    if (mat->surface_correction && ks[i] + ks[na + i] > 0) {
      double s = 0.0;
      for (int k = 0; k < 2; k++) { /* Eq. A.5 and A.6 */
        double ga = Wk[2 * a + k] > 0 ? Winf[k] / Wk[2 * a + k] : 1.0;
        double gb = Wk[2 * b + k] > 0 ? Winf[k] / Wk[2 * b + k] : 1.0;
        double n = (P->x[2 * b + k] - P->x[2 * a + k]) / xi, g = 0.5 * (ga + gb);
        s += (n / g) * (n / g);
      }
      R = 1.0 / sqrt(s);
    }
    m->arm_k[i] = 0.5 * (ks[i] + ks[na + i]) * R;
    if (m->arm_side) {
      m->arm_side[i] = ks[i] * R;
      m->arm_side[na + i] = ks[na + i] * R;
    }
    cxi[i] = m->arm_k[i] > 0 ? c * R : 0.0;
  }
  free(ks);
  free(Wk);
  int status = ps_model_fracture_prepare(m, cxi, ctx);
  free(cxi);
  return status;
}

static int tb_evaluate_rot(const ps_model *m, const double *dl, const double *th,
                           ps_arm_state *st, double *T, double *M, double *energy,
                           ps_arm_tangent *tan, ps_ctx *ctx) {
  (void)ctx;
  const ps_network *net = m->net;
  ps_int na = net->n_arm, np = net->n_particle;
  const double *k = m->arm_k, *side = m->arm_side;
  double c = m->work[0], kap = m->work[1];
  double *S = &m->work[2], *rho = &m->work[2 + np], *mean = &m->work[2 + 2 * np];
  for (ps_int a = 0; a < np; a++) {
    double sw = 0.0, cs = 0.0, sn = 0.0;
    for (ps_int f = net->fam_ptr[a]; f < net->fam_ptr[a + 1]; f++) {
      ps_int i = net->fam_arm[f];
      if (st->broken[i]) continue;
      double w = side ? side[net->a[i] == a ? i : na + i] : k[i];
      sw += w;
      cs += w * cos(th[i]);
      sn += w * sin(th[i]);
    }
    S[a] = sw;
    rho[a] = sw > 0 ? atan2(sn, cs) : 0.0;
    double ms = 0.0;
    for (ps_int f = net->fam_ptr[a]; f < net->fam_ptr[a + 1] && sw > 0; f++) {
      ps_int i = net->fam_arm[f];
      if (st->broken[i]) continue;
      double w = side ? side[net->a[i] == a ? i : na + i] : k[i];
      ms += w * wrap(th[i] - rho[a]);
    }
    mean[a] = sw > 0 ? ms / sw : 0.0;
    m->epsbar[a] = rho[a] + mean[a]; /* the neighbourhood's rotation */
    if (tan) tan->c[a] = sw > 0 && kap > 0 ? -0.5 * kap / sw : 0.0;
  }
  double psi = 0.0;
  for (ps_int i = 0; i < na; i++) {
    double xi = net->r0[i], s = dl[i] / xi;
    st->eps_p_trial[i] = st->eps_p[i];
    st->yielding[i] = 0;
    st->stretch[i] = s;
    if (st->broken[i] || !(k[i] > 0)) {
      T[i] = M[i] = 0.0;
      if (tan) tan->D[i] = tan->Dr[i] = 0.0;
      continue;
    }
    ps_int a = net->a[i], b = net->b[i];
    double ka = side ? side[i] : k[i], kb = side ? side[na + i] : k[i];
    double ga = wrap(th[i] - rho[a]) - mean[a], gb = wrap(th[i] - rho[b]) - mean[b];
    double shear = ka * ga * ga + kb * gb * gb;
    T[i] = c * k[i] * s / xi;
    M[i] = 0.5 * kap * (ka * ga + kb * gb);
    if (ps_model_owns_arm(m, i)) psi += 0.5 * c * k[i] * s * s + 0.25 * kap * shear;
    if (s > 0) st->stretch[i] = sqrt(s * s + 0.5 * kap * shear / (c * k[i]));
    if (tan) {
      tan->D[i] = c * k[i] / (xi * xi);
      tan->Dr[i] = 0.5 * kap * (ka + kb);
    }
  }
  if (tan) {
    for (ps_int a = 0; a < np; a++) {
      tan->c2[a] = 0.0;
      for (ps_int f = net->fam_ptr[a]; f < net->fam_ptr[a + 1]; f++) {
        ps_int i = net->fam_arm[f];
        tan->w[f] = st->broken[i] ? 0.0 : side ? side[net->a[i] == a ? i : na + i] : k[i];
        tan->w2[f] = 0.0;
      }
    }
    tan->rot[0] = 1;
    tan->rot[1] = 0;
  }
  *energy = psi;
  return PS_OK;
}

/* the length-only entry point: a model with rotations is evaluated by
 * evaluate_rot (the assembly does); refuse a caller that has no angles */
static int tb_evaluate(const ps_model *m, const double *dl, ps_arm_state *st, double *T,
                       double *energy, ps_arm_tangent *tan, ps_ctx *ctx) {
  (void)m, (void)dl, (void)st, (void)T, (void)energy, (void)tan;
  return ps_error(ctx, PS_ERR_INPUT,
                  "the threebody model needs the arm rotations: evaluate it through "
                  "the assembly (ps_model_type.evaluate_rot)");
}

/* the arm's stored energy v V_a V_b w_i at the last evaluate: 1/2 c k
 * s_eq^2 (s_eq = st->stretch, the micropotential's equivalent stretch in
 * tension; arms break in tension only) */
static double tb_arm_energy(const ps_model *m, const ps_arm_state *st, ps_int i) {
  double s = st->stretch[i];
  return 0.5 * m->work[0] * m->arm_k[i] * s * s;
}

static const ps_model_type threebody_type = {.name = "threebody",
                                             .evaluate = tb_evaluate,
                                             .break_excess = ps_model_stretch_excess,
                                             .arm_energy = tb_arm_energy,
                                             .prepare = tb_prepare,
                                             .family_coupling = 1,
                                             .lattice = 1,
                                             .reach_extra_spacings = 0.5,
                                             .rotations = 1,
                                             .evaluate_rot = tb_evaluate_rot};
const ps_model_type *const ps_model_threebody = &threebody_type;
