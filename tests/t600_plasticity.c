/* t600_plasticity.c: the per-arm return mapping (Eq. 111) and breaking
 * (Eq. 118) of the fibre model on a single arm, against hand-computed
 * values: loading past yield, elastic unloading keeping the plastic
 * strain, reverse yielding in compression, breaking exactly when eps_p r0
 * passes delta and never in compression. Exact arithmetic up to round-off
 * (rel 1e-12). material.break_rule strain (eps_p > delta / L, L fixed):
 * the same single arm against hand values (an arm shorter than L breaks at
 * a smaller plastic elongation than delta, a longer one at a larger);
 * break_rule toughness (eps_p r0 > delta sqrt(r0 / L)) likewise; and on
 * an equilateral triangle, all arms of length L, the same excess (to
 * round-off) and the same arms broken as the elongation rule, also when
 * only the worst arm of a round breaks (max_count 1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common.h"

int main(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_particles P;
  ps_particles_alloc(&P, 2, 2, &ctx);
  double r0 = 1.0e-3;
  P.x[2] = r0 * 0.6;
  P.x[3] = r0 * 0.8;
  P.volume[0] = P.volume[1] = 1e-6;
  P.h[0] = 0.4e-3;
  P.h[1] = 0.7e-3; /* different sizes: A_ab != A_ba */
  ps_kernel K;
  ps_kernel_init(&K, 2, 2, 5.1, &ctx);
  ps_network net;
  if (ps_network_build(&net, &P, &K, NULL, 0, &ctx) || net.n_arm != 1) {
    ps_check(0, "single-arm network: %s", ctx.msg);
    return ps_check_summary();
  }
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  mat.plastic = 1;
  double ey = mat.yield_strain;
  ps_model m;
  ps_model_create(&m, ps_model_fibre, &P, &net, &mat, &ctx);
  ps_arm_state st;
  ps_arm_state_alloc(&st, 1, &ctx);
  double Gc = 4 * mat.G, Kc = 2 * mat.K - Gc, A = net.A_ab[0] + net.A_ba[0];
  double T, E, dl;
  /* a single arm: epsbar_a = epsbar_b = eps, so T = A (Gc (eps - eps_p) + Kc eps) */
  dl = 2.5 * ey * r0; /* load past yield */
  m.type->evaluate(&m, &dl, &st, &T, &E, NULL, &ctx);
  ps_check(st.yielding[0] == 1, "loading to 2.5 eps_y yields");
  ps_check_rel(st.eps_p_trial[0], 1.5 * ey, 1e-12, "plastic strain after loading");
  ps_check_rel(T, A * (Gc * ey + Kc * 2.5 * ey), 1e-12, "tension on the yield surface");
  st.eps_p[0] = st.eps_p_trial[0]; /* commit */
  dl = 1.7 * ey * r0;               /* unload elastically */
  m.type->evaluate(&m, &dl, &st, &T, &E, NULL, &ctx);
  ps_check(st.yielding[0] == 0, "unloading to 1.7 eps_y is elastic");
  ps_check_rel(st.eps_p_trial[0], 1.5 * ey, 1e-12, "unloading keeps the plastic strain");
  ps_check_rel(T, A * (Gc * 0.2 * ey + Kc * 1.7 * ey), 1e-12, "tension after unloading");
  dl = -1.0 * ey * r0; /* reverse: e = -2.5 eps_y, yields in compression */
  m.type->evaluate(&m, &dl, &st, &T, &E, NULL, &ctx);
  ps_check(st.yielding[0] == 1, "reverse loading to -eps_y yields in compression");
  ps_check(st.eps_p_trial[0] == 0.0 || fabs(st.eps_p_trial[0]) < 1e-18,
           "reverse yielding: plastic strain eps + eps_y = %.3g (0)", st.eps_p_trial[0]);

  /* breaking, Eq. 118: committed eps_p r0 = 1.5 eps_y r0 */
  st.eps_p[0] = 1.5 * ey;
  double lim = 1.5 * ey * r0;
  m.mat.delta = lim * (1 + 1e-9);
  ps_int nb = -1;
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 0 && !st.broken[0],
           "no break while eps_p r0 < delta");
  m.mat.delta = lim * (1 - 1e-9);
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 1 && st.broken[0],
           "breaks once eps_p r0 > delta");
  dl = 3 * ey * r0;
  m.type->evaluate(&m, &dl, &st, &T, &E, NULL, &ctx);
  ps_check(T == 0.0 && E == 0.0, "a broken arm carries nothing (T = %g, energy = %g)", T, E);
  st.broken[0] = 0;
  st.eps_p[0] = -40 * ey; /* large plastic shortening */
  m.mat.delta = 1e-12;
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 0,
           "never breaks in compression");

  /* break_rule strain, L = 2 r0: breaks when eps_p > delta / L, i.e. at
   * eps_p r0 = delta r0 / L = delta / 2 for this arm */
  m.mat.break_rule = PS_BREAK_STRAIN;
  m.mat.break_length = 2 * r0;
  st.eps_p[0] = 1.5 * ey; /* plastic elongation 1.5 eps_y r0 */
  m.mat.delta = 1.5 * ey * 2 * r0 * (1 + 1e-9);
  ps_check_rel(m.type->break_excess(&m, &st, 0),
               (1.5 * ey * 2 * r0 - m.mat.delta) / m.mat.delta, 1e-12,
               "strain rule: excess eps_p L / delta - 1");
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 0 && !st.broken[0],
           "strain rule: no break while eps_p < delta / L");
  m.mat.delta = 1.5 * ey * 2 * r0 * (1 - 1e-9); /* twice the arm's plastic elongation */
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 1 && st.broken[0],
           "strain rule: breaks once eps_p > delta / L (eps_p r0 = delta / 2: the elongation "
           "rule would not break it)");
  st.broken[0] = 0;
  m.mat.break_length = 0.5 * r0; /* an arm longer than L: eps_p r0 = 2 delta needed */
  m.mat.delta = 1.5 * ey * r0 * (1 - 1e-9);
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 0 && !st.broken[0],
           "strain rule: an arm longer than L survives eps_p r0 > delta");
  st.eps_p[0] = -40 * ey;
  m.mat.delta = 1e-12;
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 0,
           "strain rule: never breaks in compression");
  /* break_rule toughness, L = 4 r0: breaks when eps_p r0 > delta sqrt(r0 / L)
   * = delta / 2 */
  m.mat.break_rule = PS_BREAK_TOUGHNESS;
  m.mat.break_length = 4 * r0;
  st.eps_p[0] = 1.5 * ey;
  m.mat.delta = 2 * 1.5 * ey * r0 * (1 + 1e-9);
  ps_check_rel(m.type->break_excess(&m, &st, 0),
               (1.5 * ey * 2 * r0 - m.mat.delta) / m.mat.delta, 1e-12,
               "toughness rule: excess eps_p sqrt(r0 L) / delta - 1");
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 0 && !st.broken[0],
           "toughness rule: no break while eps_p r0 < delta sqrt(r0 / L)");
  m.mat.delta = 2 * 1.5 * ey * r0 * (1 - 1e-9);
  ps_check(ps_model_break_arms(&m, &st, 0, &nb, &ctx) == PS_OK && nb == 1 && st.broken[0],
           "toughness rule: breaks once eps_p r0 > delta sqrt(r0 / L)");
  ps_arm_state_free(&st);
  ps_model_free(&m);
  ps_network_free(&net);
  ps_particles_free(&P);

  /* an equilateral triangle of side L: every arm has the reference
   * length, so the two rules must agree arm for arm */
  ps_particles_alloc(&P, 2, 3, &ctx);
  double L = 1.0e-3;
  P.x[2] = L;
  P.x[4] = 0.5 * L;
  P.x[5] = 0.5 * sqrt(3.0) * L;
  for (int a = 0; a < 3; a++) {
    P.volume[a] = 1e-6;
    P.h[a] = 0.5e-3;
  }
  if (ps_network_build(&net, &P, &K, NULL, 0, &ctx) || net.n_arm != 3) {
    ps_check(0, "triangle network: %s", ctx.msg);
    return ps_check_summary();
  }
  ps_model_create(&m, ps_model_fibre, &P, &net, &mat, &ctx);
  ps_arm_state se, ss;
  ps_arm_state_alloc(&se, 3, &ctx);
  ps_arm_state_alloc(&ss, 3, &ctx);
  double eps_p[3] = {2.0 * ey, 0.7 * ey, 3.1 * ey};
  m.mat.delta = 1.5 * ey * L;
  m.mat.break_length = L;
  int same = 1;
  for (ps_int i = 0; i < 3; i++) {
    se.eps_p[i] = ss.eps_p[i] = eps_p[i];
    same &= fabs(net.r0[i] - L) <= 1e-12 * L;
    m.mat.break_rule = PS_BREAK_ELONGATION;
    double xe = m.type->break_excess(&m, &se, i);
    m.mat.break_rule = PS_BREAK_STRAIN;
    double xs = m.type->break_excess(&m, &ss, i);
    ps_check(fabs(xs - xe) <= 1e-12 * fabs(xe),
             "triangle arm %d: the strain rule's excess is the elongation rule's (%.17g, "
             "%.17g)", (int)i, xs, xe);
    m.mat.break_rule = PS_BREAK_TOUGHNESS;
    double xt = m.type->break_excess(&m, &ss, i);
    ps_check(fabs(xt - xe) <= 1e-12 * fabs(xe),
             "triangle arm %d: the toughness rule's excess is the elongation rule's (%.17g, "
             "%.17g)", (int)i, xt, xe);
  }
  ps_check(same, "the triangle's arms have the reference length");
  /* one arm per round, the worst first: arm 2, then arm 0, then none */
  for (int round = 0; round < 3; round++) {
    ps_int ne = -1, ns = -1;
    m.mat.break_rule = PS_BREAK_ELONGATION;
    ps_model_break_arms(&m, &se, 1, &ne, &ctx);
    m.mat.break_rule = PS_BREAK_STRAIN;
    ps_model_break_arms(&m, &ss, 1, &ns, &ctx);
    ps_check(ne == ns && !memcmp(se.broken, ss.broken, 3),
             "round %d: the same arms broken (%d, %d)", round, (int)ne, (int)ns);
  }
  ps_check(se.broken[0] && !se.broken[1] && se.broken[2], "arms 0 and 2 broken, 1 intact");
  ps_arm_state_free(&se);
  ps_arm_state_free(&ss);
  ps_model_free(&m);
  ps_network_free(&net);
  ps_particles_free(&P);
  return ps_check_summary();
}
