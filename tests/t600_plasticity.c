/* t600_plasticity.c: the per-arm return mapping (Eq. 111) and breaking
 * (Eq. 118) of the fibre model on a single arm, against hand-computed
 * values: loading past yield, elastic unloading keeping the plastic
 * strain, reverse yielding in compression, breaking exactly when eps_p r0
 * passes delta and never in compression. Exact arithmetic up to round-off
 * (rel 1e-12). */
#include <math.h>
#include <stdlib.h>

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
  ps_arm_state_free(&st);
  ps_model_free(&m);
  ps_network_free(&net);
  ps_particles_free(&P);
  return ps_check_summary();
}
