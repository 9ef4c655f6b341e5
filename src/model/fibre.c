/* fibre.c: the virtual-fibre model of Olsson, Ander & Williams (2021).
 *   S_a(q_ab) = G(N+2)(eps_ab - eps_p_ab) + (N K - G(N+2)) epsbar_a  (Eq. 110)
 *   T_ab      = A_ab S_a + A_ba S_b                                  (Eq. 70)
 *   epsbar_a  = sum_b A_ab r0_ab eps_ab / sum_b A_ab r0_ab  (intact arms)
 * (the energy-consistent mean strain of MODEL-NOTES), with the stored
 * (incremental) energy
 *   Psi = sum_arms (A_ab + A_ba) r0 psi(eps - eps_p_n)
 *       + sum_a 1/2 (N K - G(N+2)) R_a epsbar_a^2,   R_a = sum_b A_ab r0_ab
 * where psi(e) = G(N+2) e^2/2 for |e| <= eps_y and G(N+2)(eps_y |e| -
 * eps_y^2/2) beyond (perfect plasticity, Eq. 111, backward Euler from the
 * committed eps_p_n). dPsi/dl_ab = T_ab exactly, so the tangent is
 * symmetric. Breaking (Eq. 118): eps_p r0 > delta, tension only.
 * With the moduli correction (material.surface_correction: true; off by
 * default, the paper's model; ps_moduli.h, doc/moduli.md) every half-arm
 * weight A_ab becomes A_ab phi_a(n_ab), phi from the fourth moment of a's
 * family (weights A_ab r0, target V_a/(N+2) I_4, so that a's stiffness
 * under any homogeneous strain is the continuum's 2G I + (K - 2G/N) 1 1)
 * and, on clouds, with the arms' forces under it balanced in the
 * interior (ps_moduli_balance: the homogeneous state is an equilibrium),
 * and in the layer along free surfaces under the states with no traction
 * on them:
 * the formulas above with the corrected weights, kept in m->arm_side
 * ([i] A'_ab, [n_arm + i] A'_ba); NULL: the network's A_ab, A_ba. */
#include "ps_model.h"
#include "ps_moduli.h"

#include <math.h>
#include <stdlib.h>

/* the half-arm weights of arm i: a's side (A_ab), b's side (A_ba), the
 * corrected ones when the model has them */
static inline double w_ab(const ps_model *m, ps_int i) {
  return m->arm_side ? m->arm_side[i] : m->net->A_ab[i];
}
static inline double w_ba(const ps_model *m, ps_int i) {
  return m->arm_side ? m->arm_side[m->net->n_arm + i] : m->net->A_ba[i];
}

/* weight of particle p's side of arm i */
static inline double side_weight(const ps_model *m, ps_int i, ps_int p) {
  return m->net->a[i] == p ? w_ab(m, i) : w_ba(m, i);
}

/* R_a = sum_b A_ab r0 and the mean strain epsbar_a over a's intact arms,
 * into m->R and m->epsbar, for particles [a0, a1) */
static void mean_strains_range(const ps_model *m, const double *dl, const ps_arm_state *st,
                               ps_int a0, ps_int a1) {
  const ps_network *net = m->net;
  for (ps_int a = a0; a < a1; a++) {
    double Ra = 0.0, num = 0.0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k];
      if (st->broken[i]) continue;
      double Ar = side_weight(m, i, a) * net->r0[i];
      Ra += Ar;
      num += Ar * dl[i] / net->r0[i];
    }
    m->R[a] = Ra;
    m->epsbar[a] = Ra > 0 ? num / Ra : 0.0;
  }
}

static void mean_strains(const ps_model *m, const double *dl, const ps_arm_state *st) {
  mean_strains_range(m, dl, st, 0, m->net->n_particle);
}

static int fibre_evaluate_deviatoric(const ps_model *m, const double *dl, ps_arm_state *st,
                                     double *T, double *energy, ps_arm_tangent *tan);

/* one evaluate of the (default) fibre model, split into the model's
 * parts: particles, then arms */
typedef struct {
  const ps_model *m;
  const double *dl;
  ps_arm_state *st;
  double *T;
  ps_arm_tangent *tan;
  int parts;                    /* m->parts, at least 1 */
  double psi[PS_PARTS_MAX];     /* each part's energy: its particles' terms */
  double psi_arm[PS_PARTS_MAX]; /* and its arms' */
} fibre_job;

/* particles [a0, a1) of one part: R_a and epsbar_a, their energy
 * 1/2 (N K - G(N+2)) R_a epsbar_a^2, and the tangent's family terms: c_a
 * = (N K - G(N+2)) / R_a with the side weights w of a's intact arms */
static void fibre_particles(void *arg, int part) {
  fibre_job *j = arg;
  const ps_model *m = j->m;
  const ps_network *net = m->net;
  ps_int a0, a1;
  ps_part_range(net->n_particle, part, j->parts, &a0, &a1);
  double Kc = net->dim * m->mat.K - m->mat.G * (net->dim + 2), psi = 0.0;
  mean_strains_range(m, j->dl, j->st, a0, a1);
  for (ps_int a = a0; a < a1; a++) {
    double R = m->R[a], eb = m->epsbar[a];
    if (ps_model_owns_particle(m, a)) psi += 0.5 * Kc * R * eb * eb;
    if (!j->tan) continue;
    j->tan->c[a] = R > 0 ? Kc / R : 0.0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k];
      j->tan->w[k] = j->st->broken[i] ? 0.0 : side_weight(m, i, a);
    }
  }
  j->psi[part] = psi;
}

/* arms [i0, i1) of one part: the return mapping (Eq. 111), the tension
 * (Eq. 110, 70), the arm's energy and stiffness */
static void fibre_arms(void *arg, int part) {
  fibre_job *j = arg;
  const ps_model *m = j->m;
  const ps_network *net = m->net;
  const ps_material *mat = &m->mat;
  ps_arm_state *st = j->st;
  ps_arm_tangent *tan = j->tan;
  int N = net->dim;
  double Gc = mat->G * (N + 2);      /* G(N+2) */
  double Kc = N * mat->K - Gc;       /* N K - G(N+2) */
  double ey = mat->yield_strain, psi = 0.0;
  int plastic = mat->plastic;
  const double *eb = m->epsbar;
  ps_int i0, i1;
  ps_part_range(net->n_arm, part, j->parts, &i0, &i1);
  for (ps_int i = i0; i < i1; i++) {
    if (st->broken[i]) {
      j->T[i] = 0.0;
      st->eps_p_trial[i] = st->eps_p[i];
      st->yielding[i] = 0;
      if (tan) tan->D[i] = 0.0;
      continue;
    }
    double r0 = net->r0[i];
    double eps = j->dl[i] / r0;
    double e = eps - st->eps_p[i]; /* trial elastic strain */
    double ee = e;                 /* returned elastic strain */
    int yielding = 0;
    /* Eq. 111. An arm left on the yield surface by the last commit (a
     * re-equilibration after breaking starts there) counts as yielding:
     * psi is C1 at eps_y, so only the tangent differs, and the plastic one
     * needs fewer Newton iterations (doc/performance.md) */
    const int own = ps_model_owns_arm(m, i);
    if (plastic && fabs(e) > ey * (1.0 - 1e-9)) {
      ee = e > 0 ? ey : -ey;
      yielding = 1;
      if (own) psi += (w_ab(m, i) + w_ba(m, i)) * r0 * Gc * (ey * fabs(e) - 0.5 * ey * ey);
    } else if (own) {
      psi += (w_ab(m, i) + w_ba(m, i)) * r0 * 0.5 * Gc * e * e;
    }
    st->eps_p_trial[i] = eps - ee;
    st->yielding[i] = (unsigned char)yielding;
    double Sa = Gc * ee + Kc * eb[net->a[i]]; /* Eq. 110 */
    double Sb = Gc * ee + Kc * eb[net->b[i]];
    j->T[i] = w_ab(m, i) * Sa + w_ba(m, i) * Sb; /* Eq. 70 */
    if (tan) tan->D[i] = yielding ? 0.0 : Gc * (w_ab(m, i) + w_ba(m, i)) / r0;
  }
  j->psi_arm[part] = psi;
}

static int fibre_evaluate(const ps_model *m, const double *dl, ps_arm_state *st,
                          double *T, double *energy, ps_arm_tangent *tan,
                          ps_ctx *ctx) {
  (void)ctx;
  if (m->mat.yield_rule == PS_YIELD_DEVIATORIC)
    return fibre_evaluate_deviatoric(m, dl, st, T, energy, tan);
  fibre_job j = {m, dl, st, T, tan, m->parts > 1 ? m->parts : 1, {0}, {0}};
  ps_team_run(m->team, j.parts, fibre_particles, &j); /* the arms need every epsbar */
  ps_team_run(m->team, j.parts, fibre_arms, &j);
  double psi = 0.0;
  for (int p = 0; p < j.parts; p++) psi += j.psi[p];
  for (int p = 0; p < j.parts; p++) psi += j.psi_arm[p];
  *energy = psi;
  return PS_OK;
}

/* The deviatoric reading of MODEL-NOTES: per half-arm (a's side with
 * epsbar_a, b's with epsbar_b) the elastic strain e = eps - epsbar - eps_p
 * is held at +-eps_y (perfect plasticity, backward Euler from the
 * committed eps_p of that side), and the energy
 *   Psi = sum_arms r0 (A_ab psi(e_a) + A_ba psi(e_b))
 *       + sum_a 1/2 N K R_a epsbar_a^2,   psi(e) = G(N+2) e^2 / 2 (elastic)
 * gives S_a = psi'(e_a) - m_a + N K epsbar_a with m_a the weighted mean of
 * psi' over a's family (zero while elastic: Eq. 110 again). Plastic strain
 * carries no volume. Tangent: diagonal (A_ab psi''_a + A_ba psi''_b)/r0
 * plus, per particle, (1/R)[C w w^T - u w^T - w u^T] with w the side
 * weights, u = w psi'', C = sum w r0 psi''/R + N K, written as two
 * rank-one terms C/R (w - u/C)(w - u/C)^T - 1/(R C) u u^T. */
static int fibre_evaluate_deviatoric(const ps_model *m, const double *dl, ps_arm_state *st,
                                     double *T, double *energy, ps_arm_tangent *tan) {
  const ps_network *net = m->net;
  const ps_material *mat = &m->mat;
  int N = net->dim;
  ps_int na = net->n_arm, np = net->n_particle;
  double Gc = mat->G * (N + 2), NK = N * mat->K, ey = mat->yield_strain;
  double *R = m->R, *eb = m->epsbar;
  double *dpsi = m->work, *d2psi = m->work + 2 * na; /* [2 na] each: side a, b */
  double *mean = m->work + 4 * na, *cmean = mean + np; /* [np] each */
  double psi = 0.0;
  mean_strains(m, dl, st);
  for (ps_int a = 0; a < np; a++)
    if (ps_model_owns_particle(m, a)) psi += 0.5 * NK * R[a] * eb[a] * eb[a];
  /* return mapping per half-arm */
  for (ps_int i = 0; i < na; i++) {
    st->yielding[i] = 0;
    for (int side = 0; side < 2; side++) {
      ps_int j = side * na + i;
      if (st->broken[i]) {
        st->eps_p_trial[j] = st->eps_p[j];
        dpsi[j] = d2psi[j] = 0.0;
        continue;
      }
      double r0 = net->r0[i], eps = dl[i] / r0;
      double e = eps - eb[side ? net->b[i] : net->a[i]] - st->eps_p[j], ee = e;
      double Aw = side ? w_ba(m, i) : w_ab(m, i);
      int y = mat->plastic && fabs(e) > ey;
      const int own = ps_model_owns_arm(m, i);
      if (y) {
        ee = e > 0 ? ey : -ey;
        if (own) psi += Aw * r0 * Gc * (ey * fabs(e) - 0.5 * ey * ey);
      } else if (own) {
        psi += Aw * r0 * 0.5 * Gc * e * e;
      }
      st->eps_p_trial[j] = st->eps_p[j] + (e - ee);
      st->yielding[i] |= (unsigned char)y;
      dpsi[j] = Gc * ee;
      d2psi[j] = y ? 0.0 : Gc;
    }
  }
  /* family means of psi' and psi'' (weights A r0) */
  for (ps_int a = 0; a < np; a++) {
    double s1 = 0.0, s2 = 0.0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k], j = (net->a[i] == a ? 0 : na) + i;
      if (st->broken[i]) continue;
      double Ar = side_weight(m, i, a) * net->r0[i];
      s1 += Ar * dpsi[j];
      s2 += Ar * d2psi[j];
    }
    mean[a] = R[a] > 0 ? s1 / R[a] : 0.0;
    cmean[a] = R[a] > 0 ? s2 / R[a] : 0.0;
  }
  for (ps_int i = 0; i < na; i++) {
    if (st->broken[i]) {
      T[i] = 0.0;
      if (tan) tan->D[i] = 0.0;
      continue;
    }
    ps_int a = net->a[i], b = net->b[i];
    double Sa = dpsi[i] - mean[a] + NK * eb[a], Sb = dpsi[na + i] - mean[b] + NK * eb[b];
    T[i] = w_ab(m, i) * Sa + w_ba(m, i) * Sb;
    if (tan) tan->D[i] = (w_ab(m, i) * d2psi[i] + w_ba(m, i) * d2psi[na + i]) / net->r0[i];
  }
  if (tan)
    for (ps_int a = 0; a < np; a++) {
      double C = cmean[a] + NK;
      tan->c[a] = R[a] > 0 ? C / R[a] : 0.0;
      tan->c2[a] = R[a] > 0 ? -1.0 / (R[a] * C) : 0.0;
      for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
        ps_int i = net->fam_arm[k], j = (net->a[i] == a ? 0 : na) + i;
        double w = st->broken[i] ? 0.0 : side_weight(m, i, a), u = w * d2psi[j];
        tan->w[k] = w - u / C;
        tan->w2[k] = u;
      }
    }
  *energy = psi;
  return PS_OK;
}

/* The moduli correction (ps_moduli.h): the corrected half-arm weights
 * A phi into m->arm_side. Half-arm weights A r0 (the arm energy's, and
 * the mean strain's), fourth moment matched to V_a/(N+2) I_4: then R_a =
 * N V_a and the mean strain's second moment V_a delta follow (traces). */
static int fibre_correct(ps_model *m, const ps_particles *P, ps_ctx *ctx) {
  const ps_network *net = m->net;
  ps_int na = net->n_arm, np = net->n_particle;
  if (!P)
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.surface_correction: the fibre model's correction needs the "
                    "particles");
  double *w = ps_calloc((size_t)(2 * na), sizeof *w, ctx);
  double *k = ps_calloc((size_t)(2 * na), sizeof *k, ctx);
  double *t = ps_calloc((size_t)np, sizeof *t, ctx);
  m->arm_side = ps_calloc((size_t)(2 * na), sizeof *m->arm_side, ctx);
  int status = PS_ERR_NOMEM;
  if (w && k && t && m->arm_side) {
    for (ps_int i = 0; i < na; i++) {
      k[i] = net->A_ab[i];
      k[na + i] = net->A_ba[i];
      w[i] = net->A_ab[i] * net->r0[i];
      w[na + i] = net->A_ba[i] * net->r0[i];
    }
    for (ps_int a = 0; a < np; a++) t[a] = P->volume[a] / (net->dim + 2);
    int N = net->dim;
    double Gc = m->mat.G * (N + 2), Kc = N * m->mat.K - Gc;
    ps_moduli_surface sf = {m->mat.K, m->mat.G, Kc / (N * Gc), NULL, 0};
    /* and the surface layer (3D edges: matched under their surface states) */
    status = ps_moduli_balance(P, net, 4, w, k, t, &sf, m->arm_side, NULL, ctx);
    for (ps_int i = 0; status == PS_OK && i < na; i++) {
      m->arm_side[i] *= net->A_ab[i];
      m->arm_side[na + i] *= net->A_ba[i];
    }
  }
  free(w);
  free(k);
  free(t);
  return status;
}

static int fibre_prepare(ps_model *m, const ps_particles *P, ps_ctx *ctx) {
  if (ps_moduli_correction_on(&m->mat) && m->given) { /* a share's: the whole model's */
    PS_CHECK(ps_model_take_given(m, ctx));
  } else if (ps_moduli_correction_on(&m->mat)) {
    PS_CHECK(fibre_correct(m, P, ctx));
  }
  if (m->mat.yield_rule != PS_YIELD_DEVIATORIC) return PS_OK;
  /* the deviatoric rule's scratch: psi', psi'' per half-arm, family means */
  m->work = ps_calloc((size_t)(4 * m->net->n_arm + 2 * m->net->n_particle),
                      sizeof *m->work, ctx);
  return m->work ? PS_OK : PS_ERR_NOMEM;
}

/* How far an intact arm is past Eq. 118, relative to delta: an elongation
 * measure below over delta, less one (it breaks when positive; -1 for a
 * broken arm). material.break_rule:
 *   elongation (default): eps_p r0, the arm's own plastic elongation (a
 *     plastic strain delta / r0 at breaking: shorter arms need more, the
 *     paper's necking argument, section 8);
 *   strain: eps_p L with L = material.break_length the same for every
 *     arm, i.e. eps_p against the critical plastic strain delta / L,
 *     scaled by L so that an arm of length L gets the elongation rule's
 *     number exactly;
 *   toughness: eps_p sqrt(r0 L), i.e. eps_p r0 against delta sqrt(r0 /
 *     L), scaled by sqrt(L / r0) (again the elongation rule's number when
 *     r0 = L). An arm of length r0 at a crack tip spans a crack-face
 *     opening ~ K sqrt(r0) / E (elastic), so a limit elongation ~ sqrt(r0)
 *     is a fixed K whatever the arm length: the scaling s0 ~ 1 /
 *     sqrt(horizon) of a critical stretch from G_c (Silling & Askari
 *     2005), arm by arm (doc/griffith.md). */
static double fibre_break_excess(const ps_model *m, const ps_arm_state *st, ps_int i) {
  if (st->broken[i]) return -1.0;
  double ep = ps_arm_plastic_strain(st, i, m->mat.yield_rule), d = m->mat.delta;
  if (m->mat.break_rule == PS_BREAK_STRAIN) return (ep * m->mat.break_length - d) / d;
  if (m->mat.break_rule == PS_BREAK_TOUGHNESS)
    return (ep * sqrt(m->net->r0[i] * m->mat.break_length) - d) / d;
  return (ep * m->net->r0[i] - d) / d;
}

/* The plastic work of the step, G(N+2) eps_y |eps_p - eps_p,n| A r0 per
 * (half-)arm that flowed (the incremental energy less the stored one).
 * Its derivative, the rate of further flow, is exact for the total
 * reading, G(N+2) eps_y (A_ab + A_ba) sign(e) for an arm on the yield
 * surface; for the deviatoric reading the flow of a half-arm also moves
 * with its family's mean strain, which dD leaves out (dissipation control
 * refuses that reading). A broken arm dissipates nothing more. */
static double fibre_arm_dissipation(const ps_model *m, const ps_arm_state *c,
                                    const ps_arm_state *st, ps_int i, double dl, double *dD) {
  const ps_network *net = m->net;
  const ps_material *mat = &m->mat;
  double Gey = mat->G * (net->dim + 2) * mat->yield_strain, r0 = net->r0[i], D = 0.0;
  ps_int na = net->n_arm;
  *dD = 0.0;
  if (!mat->plastic || st->broken[i]) return 0.0;
  D += w_ab(m, i) * r0 * Gey * fabs(st->eps_p_trial[i] - c->eps_p[i]);
  if (mat->yield_rule == PS_YIELD_DEVIATORIC) {
    D += w_ba(m, i) * r0 * Gey * fabs(st->eps_p_trial[na + i] - c->eps_p[na + i]);
    return D;
  }
  D += w_ba(m, i) * r0 * Gey * fabs(st->eps_p_trial[i] - c->eps_p[i]);
  if (st->yielding[i]) {
    double e = dl / r0 - c->eps_p[i];
    *dD = (w_ab(m, i) + w_ba(m, i)) * Gey * (e > 0 ? 1.0 : -1.0);
  }
  return D;
}

/* only plastic flow dissipates (fibre_arm_dissipation) */
static int fibre_dissipates(const ps_model *m) { return m->mat.plastic; }

static const ps_model_type fibre_type = {.name = "fibre",
                                         .evaluate = fibre_evaluate,
                                         .arm_dissipation = fibre_arm_dissipation,
                                         .dissipates = fibre_dissipates,
                                         .break_excess = fibre_break_excess,
                                         .break_local = 1,
                                         .prepare = fibre_prepare,
                                         .family_coupling = 1,
                                         .lattice = 0,
                                         .reach_extra_spacings = 0.0};
const ps_model_type *const ps_model_fibre = &fibre_type;
