/* stall.c: how a path that cannot go on is classified and explained: a
 * Newton stall below path.min_step, a re-equilibration after breaking
 * that failed (an unstable fracture when the load fell below its peak,
 * otherwise a stall), and what was seen and what can help. */
#include "ps_path.h"

#include <math.h>
#include <stdio.h>

int ps_path_failed_attempt_is_fracture(ps_int broken_total, double sig, double peak) {
  return broken_total > 0 && isfinite(peak) && sig < peak;
}

/* 1 when the material has a breaking criterion */
static int model_breaks(const ps_path *p) { return ps_material_breaks(p->pb.mat); }

/* 1 when the last converged increments' boundary stresses fell */
static int load_falling(const ps_path *p) {
  const int nr = (int)(sizeof p->recent / sizeof p->recent[0]);
  int n = p->n_recent < nr ? p->n_recent : nr;
  if (n < 2) return 0;
  for (int k = nr - n + 1; k < nr; k++)
    if (!(p->recent[k] < p->recent[k - 1])) return 0;
  return 1;
}

/* What a Newton stall showed and what can help, from what the run knows:
 * arms broken or not, the load falling, an indefinite tangent (negative
 * curvature in CG, shifted steps, non-positive pivots). *softens = 1 when
 * the model itself softens (the load fell with an indefinite tangent and
 * no arm broken): then smaller steps or another factorisation cannot help. */
static void stall_advice(const ps_path *p, char *buf, size_t len, int *softens) {
  const ps_material *m = p->pb.mat;
  const ps_model_type *type = p->pb.model;
  ps_solver_stats st;
  ps_solver_get_stats(p->s, &st);
  ps_int indefinite = st.cg_truncated + st.shifted_steps + st.n_fallback;
  int falling = load_falling(p), breaks = model_breaks(p);
  char arms[64];
  if (p->broken_total > 0)
    snprintf(arms, sizeof arms, "%lld arms had broken", (long long)p->broken_total);
  else if (breaks)
    snprintf(arms, sizeof arms, "no arm had broken");
  else if (type == ps_model_fibre)
    snprintf(arms, sizeof arms, "no arm can break (delta is infinite)");
  else
    snprintf(arms, sizeof arms, "no arm can break (no material.fracture)");
  *softens = falling && indefinite > 0 && p->broken_total == 0;
  size_t l = (size_t)snprintf(buf, len, "Seen: %s%s%s.", arms,
                              falling ? "; the boundary stress was falling over the last "
                                        "converged increments" : "",
                              indefinite > 0 ? "; the tangent turned indefinite" : "");
  if (l >= len) return;
  if (!isfinite(ps_solver_last_residual(p->s))) {
    snprintf(buf + l, len - l, " The residual is not finite: the forces overflow; check "
                               "material.E and the units of the case");
    return;
  }
  if (!*softens) {
    snprintf(buf + l, len - l, " Try %s or solver.linear: umfpack",
             p->o.n_steps > 0 ? "closer path.steps" : "a smaller path.load_step");
    return;
  }
  if (type == ps_model_fibre &&
      m->plane == PS_PLANE_STRESS && m->nu < 1.0 / 3.0 && m->yield_rule == PS_YIELD_TOTAL)
    l += (size_t)snprintf(buf + l, len - l,
                          " The model itself softens: the fibre model in plane stress with "
                          "nu = %g < 1/3 under yield_rule total turns its family coefficient "
                          "negative as arms yield; use material.plane: strain, "
                          "material.yield_rule: deviatoric, or nu >= 1/3.", m->nu);
  else
    l += (size_t)snprintf(buf + l, len - l,
                          " The model itself softens (the load fell with no arm broken): "
                          "end the path before this load (path.max_load) or change the "
                          "material.");
  if (l < len)
    snprintf(buf + l, len - l, " %s or solver.linear: umfpack will not help",
             p->o.n_steps > 0 ? "Closer path.steps" : "A smaller path.load_step");
}

void ps_path_newton_stalled(ps_path *p, double target) {
  double res = ps_solver_last_residual(p->s);
  char advice[700], res_e[32] = "n/a", res_g[32] = "n/a";
  int softens;
  stall_advice(p, advice, sizeof advice, &softens);
  if (isfinite(res)) {
    snprintf(res_e, sizeof res_e, "%.3e", res);
    snprintf(res_g, sizeof res_g, "%.2e", res);
  }
  p->end = PS_PATH_STALLED;
  snprintf(p->message, sizeof p->message,
           "%s: Newton diverged at load factor %.6g (%s; the increment is below "
           "path.min_step = %g; last relative residual %s). %s",
           p->pb.name, target, ps_newton_reason_text(ps_solver_last_reason(p->s)),
           p->o.min_step, res_e, advice);
  snprintf(p->stop_reason, sizeof p->stop_reason,
           "Newton stalled at load factor %.6g (increments below path.min_step did not "
           "converge, last residual %s) %s",
           target, res_g,
           p->broken_total > 0 ? "before the crack ran"
           : softens           ? "as the model softened, no arm broken"
           : model_breaks(p)   ? "before any arm broke"
                               : "(no arm can break)");
}

void ps_path_reequilibration_failed(ps_path *p, double sig) {
  double lambda = ps_solver_lambda(p->s);
  /* a crack that runs at fixed displacement sheds load; a failed attempt
   * carrying at least the peak stress shows no fracture, only a solve
   * that failed (counted like a Newton stall: sigma_failure is then a
   * lower bound). The same rule reclassifies older runs on --resume. */
  if (ps_path_failed_attempt_is_fracture(p->broken_total, sig, p->peak)) {
    p->end = PS_PATH_FRACTURED;
    snprintf(p->stop_reason, sizeof p->stop_reason,
             "re-equilibration after breaking arms did not converge at load factor "
             "%.5g: the crack ran unstably (outputs show the last attempt)", lambda);
    return;
  }
  p->end = PS_PATH_STALLED;
  snprintf(p->message, sizeof p->message,
           "%s: re-equilibration after breaking arms did not converge at load "
           "factor %.6g with the boundary stress not below its peak (the crack had "
           "not run; last relative residual %.3e). Try a smaller "
           "path.load_step_after_break",
           p->pb.name, lambda, ps_solver_last_residual(p->s));
  snprintf(p->stop_reason, sizeof p->stop_reason,
           "re-equilibration after breaking arms did not converge at load factor "
           "%.5g with the load not below its peak: stalled before the crack ran", lambda);
}
