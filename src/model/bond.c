/* bond.c: bond-based peridynamics as in Fallah et al. (2020), section 2:
 * the pairwise force of an arm (bond) of reference length xi is
 *   T = c(xi) s V_a V_b v R,   s = (l - xi) / xi,
 * with the conical micromodulus of Eq. 7, c(xi) = c0 (1 - xi/delta) for
 * xi <= delta (0 beyond), c0 from equating the isotropic-expansion energy
 * with the continuum's (2D: c0 = 48 K / (pi delta^3), which is Eq. 7's
 * 24 E / (pi delta^3 (1 - nu)) in plane stress; 3D: 90 K / (pi delta^4)),
 * or the constant micromodulus of the PMB model (Silling & Askari 2005)
 * from the same energy (2D: c = 12 K / (pi delta^3), 9 E / (pi delta^3)
 * in plane stress, as Peridigm's plane-stress option with t = 1; 3D:
 * 18 K / (pi delta^4)); the partial volume v of Li & Hao (2023) Eq. A.2
 * for bonds near the horizon (or v = 1 within it: full volumes), and the
 * energy-based surface correction R of their Eq. A.3-A.6 (optional).
 * Forces are per unit thickness in 2D (V_a are areas), so c is Eq. 7
 * with t = 1. On a point cloud the cells differ: v(xi) is the share of
 * the neighbour b's cell (size dx_b = V_b^(1/N)) in a's horizon, v_a,
 * and that of a's cell in b's horizon, v_b; the bond's energy, counted
 * once from each end, is that of v = (v_a + v_b) / 2, and W_k(a) of the
 * correction (Eq. A.3) sums b with v_a (a's own horizon). On a lattice
 * v_a = v_b = v, bit for bit. The stored energy is sum 1/2 k dl^2 with
 * k = c V_a V_b v R / xi, so dT/dl = k: no family coupling. An arm
 * breaks for good when its stretch passes s0, or its micropotential w =
 * 1/2 c R s^2 xi passes w_c (breaking.c). Bond-based PD fixes Poisson's
 * ratio: 1/3 in plane stress, 1/4 in plane strain and 3D. The arms of
 * the constant micromodulus end at the horizon too (as Peridigm's), so
 * its partial volumes only thin the outer half cell inside it. With
 * material.fracture.softening_ratio r > 1 an arm past s0 softens instead
 * of breaking (see soft_arm below), which dissipation control needs. */
#include "ps_model.h"

#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>

/* bond-based PD has a single material constant: nu = 1/3 in plane
 * stress, 1/4 in plane strain and 3D */
static double bond_fixed_poisson(int dim, int plane) {
  return dim == 2 && plane == PS_PLANE_STRESS ? 1.0 / 3.0 : 0.25;
}

static int bond_prepare(ps_model *m, const ps_particles *P, ps_ctx *ctx) {
  const ps_network *net = m->net;
  const ps_material *mat = &m->mat;
  int N = net->dim;
  double delta = mat->horizon;
  PS_CHECK(ps_lattice_model_check(mat, N, P, "bond", ctx));
  PS_CHECK(ps_model_poisson_check(m->type, mat->nu, N, mat->plane, ctx));
  int conical = mat->micromodulus == PS_MICRO_CONICAL;
  double c0 = N == 2 ? (conical ? 48.0 : 12.0) * mat->K / (M_PI * pow(delta, 3))
                     : (conical ? 90.0 : 18.0) * mat->K / (M_PI * pow(delta, 4));
  ps_int na = net->n_arm, np = net->n_particle;
  m->arm_k = ps_calloc((size_t)na, sizeof *m->arm_k, ctx);
  double *Wk = ps_calloc((size_t)np * N, sizeof *Wk, ctx);
  double *cxi = ps_calloc((size_t)na, sizeof *cxi, ctx); /* c(xi) R, breaking */
  if (!m->arm_k || !Wk || !cxi) {
    free(Wk);
    free(cxi);
    return PS_ERR_NOMEM;
  }
  /* uncorrected bond constants c(xi) v, and (Eq. A.3) each particle's
   * energy density under the unit uniaxial strain along axis k, up to the
   * common factor eps0^2: W_k(a) = 1/4 sum_b c v_a xi n_k^4 V_b */
  for (ps_int i = 0; i < na; i++) {
    ps_int a = net->a[i], b = net->b[i];
    double xi = net->r0[i];
    double c = conical ? c0 * (1.0 - xi / delta) : c0;
    double va = 1.0, vb = 1.0;
    if (!mat->full_volumes) ps_arm_partial_volumes(mat, P, net, i, &va, &vb);
    double v = 0.5 * (va + vb); /* = va on a lattice, exactly */
    /* every arm of the network is within the horizon (up to round-off:
     * ps_model_lattice_reach, ps_model_cloud_reach); the cone is 0 at its
     * edge */
    int in = !conical || xi < delta;
    double cv = in ? c * v : 0.0, cva = in ? c * va : 0.0, cvb = in ? c * vb : 0.0;
    m->arm_k[i] = cv;
    for (int k = 0; k < N; k++) {
      double n = (P->x[b * N + k] - P->x[a * N + k]) / xi, n4 = n * n * n * n;
      Wk[a * N + k] += 0.25 * cva * xi * n4 * P->volume[b];
      Wk[b * N + k] += 0.25 * cvb * xi * n4 * P->volume[a];
    }
  }
  /* the continuum's value (Eq. A.4): 1/2 C11 with C11 of the plane /
   * solid, so that W_inf / W_k(a) also removes the lattice-sum error */
  double E = mat->E, nu = mat->nu;
  double C11 = (N == 2 && mat->plane == PS_PLANE_STRESS)
                   ? E / (1.0 - nu * nu)
                   : E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  double Winf = 0.5 * C11;
  for (ps_int i = 0; i < na; i++) {
    ps_int a = net->a[i], b = net->b[i];
    double xi = net->r0[i], R = 1.0;
    if (mat->surface_correction && m->arm_k[i] > 0) {
      double s = 0.0;
      for (int k = 0; k < N; k++) { /* Eq. A.5 and A.6 on the unit direction */
        double ga = Wk[a * N + k] > 0 ? Winf / Wk[a * N + k] : 1.0;
        double gb = Wk[b * N + k] > 0 ? Winf / Wk[b * N + k] : 1.0;
        double n = (P->x[b * N + k] - P->x[a * N + k]) / xi, g = 0.5 * (ga + gb);
        s += (n / g) * (n / g);
      }
      R = 1.0 / sqrt(s);
    }
    double c = conical ? c0 * (1.0 - xi / delta) : c0;
    cxi[i] = m->arm_k[i] > 0 ? c * R : 0.0;
    m->arm_k[i] *= R * P->volume[a] * P->volume[b] / xi;
  }
  free(Wk);
  int status = ps_model_fracture_prepare(m, cxi, ctx);
  free(cxi);
  return status;
}

/* The softening arm (material.softening_ratio r > 1): in tension its
 * envelope rises as k dl up to dl0 = s0 r0, then falls linearly to zero at
 * dl1 = r dl0, T_env = k dl0 (dl1 - dl) / (dl1 - dl0); below its largest
 * elongation kappa (committed in eps_p[i]) it follows the secant T_env(kappa)
 * / kappa (damage, unloading to the origin); in compression k dl. The
 * incremental energy (the potential of T at the committed kappa) is the
 * stored energy 1/2 T dl plus the step's dissipation (arm_dissipation).
 * The tangent of a softening arm that loads is its negative slope only
 * when it was loading at the previous evaluation too (st->yielding), else
 * its secant T/dl: with the slope alone the arms at the crack tip switched
 * between loading and unloading from one Newton iterate to the next
 * without end, with the secant alone Newton converged only linearly. */
typedef struct soft_arm {
  double k, dl0, dl1;
} soft_arm;

static soft_arm soft_of(const ps_model *m, ps_int i) {
  soft_arm a = {m->arm_k[i], m->arm_s0[i] * m->net->r0[i], 0.0};
  a.dl1 = m->mat.softening_ratio * a.dl0;
  return a;
}

static double soft_envelope(const soft_arm *a, double x) {
  if (x <= a->dl0) return a->k * x;
  if (x >= a->dl1) return 0.0;
  return a->k * a->dl0 * (a->dl1 - x) / (a->dl1 - a->dl0);
}

/* int_x0^x1 T_env, x0 <= x1 */
static double soft_work(const soft_arm *a, double x0, double x1) {
  double w = 0.0, lo = x0;
  if (lo < a->dl0) {
    double hi = fmin(x1, a->dl0);
    w += 0.5 * a->k * (hi * hi - lo * lo);
    lo = hi;
  }
  double hi = fmin(x1, a->dl1);
  if (hi > lo)
    w += a->k * a->dl0 / (a->dl1 - a->dl0) * (a->dl1 * (hi - lo) - 0.5 * (hi * hi - lo * lo));
  return w;
}

/* energy dissipated by an arm whose largest elongation is kappa */
static double soft_dissipated(const soft_arm *a, double kappa) {
  if (kappa <= a->dl0) return 0.0;
  if (kappa >= a->dl1) return 0.5 * a->k * a->dl0 * a->dl1;
  return 0.5 * a->dl0 * (a->k * kappa - soft_envelope(a, kappa));
}

/* T, dT/ddl and the incremental energy of a softening arm at dl from the
 * committed largest elongation kc; *kappa gets the new one */
static double soft_evaluate(const soft_arm *a, double dl, double kc, int was_loading, double *D,
                            double *phi, double *kappa) {
  double kref = fmax(kc, a->dl0); /* below dl0 the secant is k */
  double sec = soft_envelope(a, kref) / kref;
  *kappa = fmax(kc, dl);
  if (dl <= 0.0) {
    *D = a->k;
    *phi = 0.5 * a->k * dl * dl;
    return a->k * dl;
  }
  if (dl <= kref) {
    *D = sec;
    *phi = 0.5 * sec * dl * dl;
    return sec * dl;
  }
  *phi = 0.5 * sec * kref * kref + soft_work(a, kref, dl);
  /* the slope when the arm was loading at the last evaluation too, else
   * the secant: see the comment above */
  *D = was_loading && dl < a->dl1 ? -a->k * a->dl0 / (a->dl1 - a->dl0) : soft_envelope(a, dl) / dl;
  return soft_envelope(a, dl);
}

static int bond_evaluate(const ps_model *m, const double *dl, ps_arm_state *st,
                         double *T, double *energy, ps_arm_tangent *tan, ps_ctx *ctx) {
  (void)ctx;
  const ps_network *net = m->net;
  const int soft = m->mat.softening_ratio > 1.0 && m->arm_s0;
  double psi = 0.0;
  if (!soft) /* linear arms: the loop below without its branches */
    for (ps_int i = 0; i < net->n_arm; i++) {
      double k = st->broken[i] ? 0.0 : m->arm_k[i];
      st->stretch[i] = dl[i] / net->r0[i];
      st->eps_p_trial[i] = st->eps_p[i];
      st->yielding[i] = 0;
      T[i] = k * dl[i];
      if (ps_model_owns_arm(m, i)) psi += 0.5 * k * dl[i] * dl[i];
      if (tan) tan->D[i] = k;
    }
  for (ps_int i = 0; soft && i < net->n_arm; i++) {
    double k = st->broken[i] ? 0.0 : m->arm_k[i], D = k;
    int was_loading = st->yielding[i];
    st->stretch[i] = dl[i] / net->r0[i];
    st->eps_p_trial[i] = st->eps_p[i];
    st->yielding[i] = 0;
    if (k > 0 && isfinite(m->arm_s0[i])) {
      soft_arm a = soft_of(m, i);
      double phi;
      T[i] = soft_evaluate(&a, dl[i], st->eps_p[i], was_loading, &D, &phi,
                           &st->eps_p_trial[i]);
      /* loading on the softening branch: counted with the yielding arms */
      st->yielding[i] = dl[i] > 0 && dl[i] >= st->eps_p[i] && st->eps_p_trial[i] > a.dl0;
      if (ps_model_owns_arm(m, i)) psi += phi;
    } else {
      T[i] = k * dl[i];
      if (ps_model_owns_arm(m, i)) psi += 0.5 * k * dl[i] * dl[i];
    }
    if (tan) tan->D[i] = D;
  }
  if (tan) {
    for (ps_int a = 0; a < net->n_particle; a++) tan->c[a] = 0.0;
    for (ps_int k = 0; k < 2 * net->n_arm; k++) tan->w[k] = 0.0;
  }
  *energy = psi;
  return PS_OK;
}

/* the stored energy at the stretch of the last evaluate: 1/2 k dl^2, or
 * 1/2 T dl on the secant of a softening arm */
static double bond_arm_energy(const ps_model *m, const ps_arm_state *st, ps_int i) {
  double dl = st->stretch[i] * m->net->r0[i];
  if (m->mat.softening_ratio > 1.0 && m->arm_s0 && isfinite(m->arm_s0[i]) && dl > 0) {
    soft_arm a = soft_of(m, i);
    double kref = fmax(st->eps_p_trial[i], a.dl0);
    return 0.5 * soft_envelope(&a, kref) / kref * dl * dl;
  }
  return 0.5 * m->arm_k[i] * dl * dl;
}

/* softening arms: breaking at dl1 (their force is zero there), else the
 * stretch criterion */
static double bond_break_excess(const ps_model *m, const ps_arm_state *st, ps_int i) {
  if (m->mat.softening_ratio > 1.0 && m->arm_s0) {
    if (st->broken[i] || !isfinite(m->arm_s0[i])) return -1.0;
    soft_arm a = soft_of(m, i);
    return st->eps_p_trial[i] / a.dl1 - 1.0 + 1e-12; /* at dl1 exactly: broken */
  }
  return ps_model_stretch_excess(m, st, i);
}

static double bond_arm_dissipation(const ps_model *m, const ps_arm_state *c,
                                   const ps_arm_state *st, ps_int i, double dl, double *dD) {
  *dD = 0.0;
  if (!(m->mat.softening_ratio > 1.0) || !m->arm_s0 || !isfinite(m->arm_s0[i]) ||
      !(m->arm_k[i] > 0))
    return 0.0;
  soft_arm a = soft_of(m, i);
  double kc = c->eps_p[i], kt = st->eps_p_trial[i];
  if (!st->broken[i] && dl >= kc && dl > a.dl0 && dl < a.dl1)
    *dD = 0.5 * a.k * a.dl0 * a.dl1 / (a.dl1 - a.dl0);
  return soft_dissipated(&a, kt) - soft_dissipated(&a, kc);
}

/* only softening arms dissipate (bond_arm_dissipation) */
static int bond_dissipates(const ps_model *m) {
  return m->mat.softening_ratio > 1.0 && m->arm_s0;
}

static const ps_model_type bond_type = {.name = "bond",
                                        .evaluate = bond_evaluate,
                                        .break_excess = bond_break_excess,
                                        .break_local = 1,
                                        .arm_energy = bond_arm_energy,
                                        .arm_dissipation = bond_arm_dissipation,
                                        .dissipates = bond_dissipates,
                                        .prepare = bond_prepare,
                                        .family_coupling = 0,
                                        .lattice = 1,
                                        .reach_extra_spacings = 0.0,
                                        .fixed_poisson = bond_fixed_poisson};
const ps_model_type *const ps_model_bond = &bond_type;
