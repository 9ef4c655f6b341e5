/* state.c: ordinary state-based linear elastic peridynamics with the
 * dilatation / deviatoric split of the supplement to the elasto-plastic
 * animation paper (../shared/papers/pd-elastoplastic-animation-
 * supplement.md, Eq. 26-47), in arm-length space. With e_i = l_i - xi_i the
 * elongation of arm i (ends a, b) and kv_i = w(xi) v(xi) V_a V_b (influence
 * w = delta/xi, partial volume v of Li & Hao Eq. A.2):
 *   theta_a = (d / V_a) sum_{i in family(a)} kv_i e_i       (Eq. 27)
 *   Psi     = sum_a V_a a theta_a^2 + sum_i 2 b kv_i e_i^2  (Eq. 26 summed)
 *   T_i     = dPsi/de_i = 4 b kv_i e_i + 2 a d kv_i (theta_a + theta_b)
 * and the tangent D_i = 4 b kv_i plus, per particle a, the rank-one term
 * 2 a V_a g g^T with g_i = d kv_i / V_a over a's family. The constants
 * (Eq. 39, 46, 47 in 3D; the same derivation in 2D):
 *   3D: a = (K - 5G/3)/2, b = 15G / (2 pi delta^5), d = 9 / (4 pi delta^4)
 *   2D: a = (K - 2G)/2,   b = 6G / (pi delta^4),    d = 2 / (pi delta^3)
 * (2D per unit thickness, K the 2D bulk modulus of Eq. 80/81). With full
 * volumes v = 1 within the horizon and 0 beyond. On a point cloud the
 * cells differ: a's dilatation weighs b with v_a, the share of b's cell
 * (size dx_b = V_b^(1/N)) in a's horizon, and b's weighs a with v_b, so
 *   theta_a = (d / V_a) sum_{i in family(a)} ks_{i,a} e_i,
 *   T_i = 4 b kv_i e_i + 2 a d (ks_{i,a} theta_a + ks_{i,b} theta_b),
 * ks_{i,a} = w v_a V_a V_b (m->arm_side), while the deviatoric term,
 * counted once from each end, has kv_i = w (v_a + v_b)/2 V_a V_b. On a
 * lattice v_a = v_b and m->arm_side is NULL: the formulas above, bit for
 * bit. An arm breaks for good
 * when its stretch e/xi passes s0 (breaking.c); a broken arm leaves the
 * dilatation sums. theta is kept in m->epsbar (the dilatation).
 * With the moduli correction (material.surface_correction: true; off by
 * default; ps_moduli.h, doc/moduli.md) each end's half-arm weights get
 * factors from its family: phi (degree 4) on the deviatoric part, whose
 * half-arm weights ks xi^2 must have the fourth moment G V_a/(2b) I_4, and
 * psi (degree 2) on the dilatation, whose ks xi must have the second
 * moment V_a/d delta; then kv_i = (ks_{i,a} phi_a + ks_{i,b} phi_b)/2 and
 * m->arm_side = ks psi (always allocated), and every particle's stiffness
 * under homogeneous strain is the continuum's; on clouds both sets of
 * factors also balance the arm forces under it in the interior
 * (ps_moduli_balance: the homogeneous state is an equilibrium), and the
 * phi balance the surface layer, with the psi part's force held (a partly
 * matched family near a surface, such as a 3D edge's, which cannot carry
 * the isotropic moments, gets psi and phi matched under its surface
 * states only). */
#include "ps_model.h"
#include "ps_moduli.h"

#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>

typedef struct {
  double a, b, d;
} state_constants;

static state_constants constants(const ps_material *mat, int N) {
  state_constants c;
  double delta = mat->horizon, G = mat->G, K = mat->K;
  if (N == 3) {
    c.a = 0.5 * (K - 5.0 * G / 3.0);
    c.b = 15.0 * G / (2.0 * M_PI * pow(delta, 5));
    c.d = 9.0 / (4.0 * M_PI * pow(delta, 4));
  } else {
    c.a = 0.5 * (K - 2.0 * G);
    c.b = 6.0 * G / (M_PI * pow(delta, 4));
    c.d = 2.0 / (M_PI * pow(delta, 3));
  }
  return c;
}

/* The moduli correction (see the top): from the uncorrected half-arm
 * weights ks (m->arm_side, or arm_k on both sides) to the corrected arm_k
 * and arm_side. */
static int state_correct(ps_model *m, const ps_particles *P, ps_ctx *ctx) {
  const ps_network *net = m->net;
  state_constants c = constants(&m->mat, net->dim);
  ps_int na = net->n_arm, np = net->n_particle;
  double *ks = ps_calloc((size_t)(2 * na), sizeof *ks, ctx);
  double *w = ps_calloc((size_t)(2 * na), sizeof *w, ctx);
  double *phi = ps_calloc((size_t)(2 * na), sizeof *phi, ctx);
  double *t = ps_calloc((size_t)np, sizeof *t, ctx);
  double *kf = ps_calloc((size_t)(2 * na), sizeof *kf, ctx);
  double *fix = ps_calloc((size_t)(2 * na), sizeof *fix, ctx);
  const double *side = m->arm_side; /* NULL: both sides are arm_k */
  if (!m->arm_side) m->arm_side = ps_calloc((size_t)(2 * na), sizeof *m->arm_side, ctx);
  int status = PS_ERR_NOMEM;
  if (!ks || !w || !phi || !t || !kf || !fix || !m->arm_side) goto done;
  for (ps_int k = 0; k < 2 * na; k++) {
    ps_int i = k < na ? k : k - na;
    ks[k] = side ? side[k] : m->arm_k[i];
  }
  /* the dilatation first: weights ks xi, second moment V_a/d delta; its
   * arm force 2 a d (ks'_a + ks'_b) tr eps is balanced in the interior by
   * the first moment of ks'_a + ks'_b, ks' = ks psi; a partly matched
   * family near a surface (a 3D edge; in 2D a few near corners) gets the
   * dilatation right under the surface's states only (energy_only: the
   * surface's force is balanced with the phi below) */
  for (ps_int h = 0; h < 2 * na; h++) {
    w[h] = ks[h] * net->r0[h < na ? h : h - na];
    kf[h] = ks[h];
  }
  for (ps_int a = 0; a < np; a++) t[a] = P->volume[a] / c.d;
  ps_moduli_surface sd = {m->mat.K, m->mat.G, 0.0, NULL, 1};
  status = ps_moduli_balance(P, net, 2, w, kf, t, &sd, phi, NULL, ctx);
  if (status != PS_OK) goto done;
  for (ps_int h = 0; h < 2 * na; h++) m->arm_side[h] = ks[h] * phi[h];
  /* then the deviatoric part: weights ks xi^2, fourth moment G V_a/(2b)
   * I_4; its arm force 4 b kv e, e = xi n.eps.n, is balanced in the
   * interior by the third moment of kv xi = (ks_a phi_a + ks_b phi_b) xi /
   * 2, and in the surface layer together with the dilatation's force, in
   * units of 2b: (a d / b)(ks'_a + ks'_b) tr eps n (kfix) */
  for (ps_int h = 0; h < 2 * na; h++) {
    double xi = net->r0[h < na ? h : h - na];
    w[h] = ks[h] * xi * xi;
    kf[h] = ks[h] * xi;
    fix[h] = c.a * c.d / c.b * m->arm_side[h];
  }
  for (ps_int a = 0; a < np; a++) t[a] = m->mat.G * P->volume[a] / (2.0 * c.b);
  ps_moduli_surface sf = {m->mat.K, m->mat.G, 0.0, fix, 0};
  status = ps_moduli_balance(P, net, 4, w, kf, t, &sf, phi, NULL, ctx);
  if (status != PS_OK) goto done;
  for (ps_int i = 0; i < na; i++) m->arm_k[i] = 0.5 * (ks[i] * phi[i] + ks[na + i] * phi[na + i]);
done:
  free(fix);
  free(kf);
  free(ks);
  free(w);
  free(phi);
  free(t);
  return status;
}

static int state_prepare(ps_model *m, const ps_particles *P, ps_ctx *ctx) {
  const ps_network *net = m->net;
  const ps_material *mat = &m->mat;
  PS_CHECK(ps_lattice_model_check(mat, net->dim, P, "state", ctx));
  double delta = mat->horizon, dx = mat->spacing;
  ps_int na = net->n_arm;
  m->arm_k = ps_calloc((size_t)na, sizeof *m->arm_k, ctx);
  if (!m->arm_k) return PS_ERR_NOMEM;
  if (dx > 0 || mat->full_volumes) { /* one cell size, or none */
    for (ps_int i = 0; i < na; i++) {
      double xi = net->r0[i];
      double v =
          mat->full_volumes ? (xi <= delta ? 1.0 : 0.0) : ps_partial_volume(xi, delta, dx);
      double w = mat->full_volumes || xi < delta + 0.5 * dx ? delta / xi * v : 0.0;
      m->arm_k[i] = w * P->volume[net->a[i]] * P->volume[net->b[i]];
    }
  } else { /* a cloud with partial volumes: each end weighs the other's cell */
    m->arm_side = ps_calloc((size_t)(2 * na), sizeof *m->arm_side, ctx);
    if (!m->arm_side) return PS_ERR_NOMEM;
    for (ps_int i = 0; i < na; i++) {
      double xi = net->r0[i], va, vb;
      double VV = P->volume[net->a[i]] * P->volume[net->b[i]];
      ps_arm_partial_volumes(mat, P, net, i, &va, &vb);
      m->arm_k[i] = delta / xi * (0.5 * (va + vb)) * VV;
      m->arm_side[i] = delta / xi * va * VV;
      m->arm_side[na + i] = delta / xi * vb * VV;
    }
  }
  for (ps_int a = 0; a < net->n_particle; a++) m->R[a] = P->volume[a]; /* V_a */
  if (ps_moduli_correction_on(mat) && m->given) { /* a share's: the whole model's */
    PS_CHECK(ps_model_take_given(m, ctx));
  } else if (ps_moduli_correction_on(mat)) {
    PS_CHECK(state_correct(m, P, ctx));
  }
  return ps_model_fracture_prepare(m, NULL, ctx);
}

static int state_evaluate(const ps_model *m, const double *dl, ps_arm_state *st, double *T,
                          double *energy, ps_arm_tangent *tan, ps_ctx *ctx) {
  (void)ctx;
  const ps_network *net = m->net;
  state_constants c = constants(&m->mat, net->dim);
  const double *V = m->R, *kv = m->arm_k, *side = m->arm_side;
  ps_int na = net->n_arm;
  double *theta = m->epsbar, psi = 0.0;
  for (ps_int a = 0; a < net->n_particle; a++) {
    double s = 0.0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k];
      if (!st->broken[i]) s += (side ? side[net->a[i] == a ? i : na + i] : kv[i]) * dl[i];
    }
    theta[a] = c.d * s / V[a];
    if (ps_model_owns_particle(m, a)) psi += V[a] * c.a * theta[a] * theta[a];
    if (tan) tan->c[a] = 2.0 * c.a * V[a];
  }
  for (ps_int i = 0; i < net->n_arm; i++) {
    st->eps_p_trial[i] = st->eps_p[i];
    st->yielding[i] = 0;
    st->stretch[i] = dl[i] / net->r0[i];
    if (st->broken[i]) {
      T[i] = 0.0;
      if (tan) tan->D[i] = 0.0;
      continue;
    }
    if (side)
      T[i] = 4.0 * c.b * kv[i] * dl[i] +
             2.0 * c.a * c.d * (side[i] * theta[net->a[i]] + side[na + i] * theta[net->b[i]]);
    else
      T[i] = 4.0 * c.b * kv[i] * dl[i] +
             2.0 * c.a * c.d * kv[i] * (theta[net->a[i]] + theta[net->b[i]]);
    if (ps_model_owns_arm(m, i)) psi += 2.0 * c.b * kv[i] * dl[i] * dl[i];
    if (tan) tan->D[i] = 4.0 * c.b * kv[i];
  }
  if (tan)
    for (ps_int a = 0; a < net->n_particle; a++)
      for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
        ps_int i = net->fam_arm[k];
        double ks = side ? side[net->a[i] == a ? i : na + i] : kv[i];
        tan->w[k] = st->broken[i] ? 0.0 : c.d * ks / V[a];
      }
  *energy = psi;
  return PS_OK;
}

/* The energy arm i holds at the last evaluate: what the stored energy
 * loses when the arm alone leaves it at fixed displacements, its
 * deviatoric term 2 b kv e^2 and, at each end a, V_a a (theta_a^2 -
 * theta_a'^2) with theta_a' = theta_a - d ks_a e / V_a (the dilatation
 * without the arm; 0 in 2D at nu = 1/3, where a = 0). Arms broken in the
 * same pass are each counted against the dilatation before the pass. */
static double state_arm_energy(const ps_model *m, const ps_arm_state *st, ps_int i) {
  const ps_network *net = m->net;
  state_constants c = constants(&m->mat, net->dim);
  ps_int na = net->n_arm, end[2] = {net->a[i], net->b[i]};
  double e = st->stretch[i] * net->r0[i], w = 2.0 * c.b * m->arm_k[i] * e * e;
  for (int j = 0; j < 2; j++) {
    double ks = m->arm_side ? m->arm_side[j ? na + i : i] : m->arm_k[i];
    double V = m->R[end[j]], th = m->epsbar[end[j]], dth = c.d * ks * e / V;
    w += V * c.a * (th * th - (th - dth) * (th - dth));
  }
  return w;
}

static const ps_model_type state_type = {.name = "state",
                                         .evaluate = state_evaluate,
                                         .break_excess = ps_model_stretch_excess,
                                         .break_local = 1,
                                         .arm_energy = state_arm_energy,
                                         .prepare = state_prepare,
                                         .family_coupling = 1,
                                         .lattice = 1,
                                         .reach_extra_spacings = 0.5};
const ps_model_type *const ps_model_state = &state_type;
