/* breaking.c: the control flow of fracture (Eq. 118) at one load: rounds
 * of breaking and re-equilibration until no arm is past delta, a failed
 * round retried with the worst half of its arms down to one, an early end
 * once the crack has run. The rule itself (which arms are past delta) is
 * the model's; one round is ps_solver_break_round. */
#include "ps_path.h"

#include <math.h>

/* both: this process's arms' share (post.c), then the run's */
double ps_path_boundary_stress(const ps_path *p) {
  double s = ps_post_boundary_stress(p->pb.net, ps_solver_arm_tension(p->s),
                                     ps_solver_arm_direction(p->s), p->pb.measure,
                                     p->pb.measure_length, ps_solver_own_arm(p->s));
  return ps_comm_sum1(ps_solver_comm(p->s), s);
}

double ps_path_crack_tip(const ps_path *p) {
  if (!(p->pb.c > 0)) return 0.0;
  double tip = ps_post_crack_tip(p->pb.P, p->pb.net, ps_solver_arm_state(p->s), p->pb.c,
                                 ps_solver_own_arm(p->s));
  ps_comm_max(ps_solver_comm(p->s), &tip, 1);
  return tip;
}

/* One breaking round; when its re-equilibration fails, go back and break
 * fewer arms, the worst first, halving down to one: only if one arm cannot
 * be broken and re-equilibrated does the round stay failed. */
static int round_with_retries(ps_path *p, ps_int *n_broken, ps_ctx *ctx) {
  double tol = p->o.round_tolerance;
  int settle = ps_solver_break_round_to(p->s, p->o.max_arms_per_round, tol, n_broken, ctx);
  while (settle == PS_DIVERGED && *n_broken > 1) {
    ps_int limit = *n_broken / 2;
    ps_solver_restore(p->s);
    ps_log(ctx, 2, "    re-equilibration failed: breaking the worst %lld arms only\n",
           (long long)limit);
    settle = ps_solver_break_round_to(p->s, limit, tol, n_broken, ctx);
    p->gentle_rounds++;
  }
  return settle;
}

/* 1 when the state after a round shows the crack has run: the stop rules
 * will end the path, so the rounds end here */
static int crack_has_run(const ps_path *p) {
  const ps_path_opts *o = &p->o;
  double sr = ps_path_boundary_stress(p);
  double tr = ps_path_crack_tip(p);
  return sr < o->stop_load_drop * fmax(p->peak, sr) ||
         (p->pb.c > 0 && tr >= o->stop_crack_tip) ||
         (p->pb.c > 0 && o->stop_tip_advance > 0 && tr - p->tip_start >= o->stop_tip_advance);
}

/* path.round_tolerance: the state of the last round, converged to the
 * looser tolerance, solved again to solver.tolerance (*loose = 0).
 * Returns PS_OK, PS_DIVERGED or fatal. */
static int tighten(ps_path *p, int *loose, ps_ctx *ctx) {
  if (!*loose) return PS_OK;
  *loose = 0;
  return ps_solver_resettle(p->s, ctx);
}

int ps_path_break_rounds(ps_path *p, ps_int its0, ps_int *n_broken, int *settle,
                         int *settled, ps_ctx *ctx) {
  int rounds = 0;
  int loose = 0; /* the last commit is a round's, converged to
                    path.round_tolerance only */
  double t_note = ps_wtime(); /* long increments print a line every 10 s */
  *n_broken = 0;
  for (;;) {
    ps_int nr;
    *settle = round_with_retries(p, &nr, ctx);
    if (*settle < 0) return *settle;
    *n_broken += nr;
    ps_int limit = ps_path_load_phase_arms(p);
    if (limit > 0 && nr > 0) { /* the controller's load phase ends (ps_path_iterate) */
      p->unstable = *settle != PS_OK       ? PS_UNSTABLE_ROUND_FAILED
                    : *n_broken > limit    ? PS_UNSTABLE_ARMS
                    : crack_has_run(p)     ? PS_UNSTABLE_STOP_RULE
                                           : 0;
      if (p->unstable) return PS_OK;
    }
    if (*settle == PS_OK && nr > 0 && p->o.round_tolerance > 0) loose = 1;
    if (*settle == PS_OK && nr == 0 && loose) {
      /* nothing past the criterion in the loose state: the equilibrium to
       * solver.tolerance decides, and the rounds go on from it if arms
       * are past the criterion there */
      *settle = tighten(p, &loose, ctx);
      if (*settle < 0) return *settle;
      if (*settle == PS_OK && ps_solver_count_past_criterion(p->s) > 0) continue;
    }
    *settled = *settle == PS_OK && nr == 0; /* no arm left past delta */
    if (*settle != PS_OK || nr == 0) return PS_OK;
    if (p->pb.interrupted &&
        ps_comm_any(ps_solver_comm(p->s), p->pb.interrupted(p->pb.interrupted_data, NULL, 0))) {
      p->rounds_interrupted = 1;
      *settle = tighten(p, &loose, ctx);
      return *settle < 0 ? *settle : PS_OK;
    }
    if (ps_wtime() - t_note > 10.0) {
      ps_solver_stats st;
      ps_solver_get_stats(p->s, &st);
      t_note = ps_wtime();
      ps_log(ctx, 1, "         ... load factor %.5f: breaking round %d, %lld arms broken "
                     "so far, %lld Newton iterations\n",
             ps_solver_lambda(p->s), rounds + 1, (long long)(p->broken_total + *n_broken),
             (long long)(st.newton_iterations - its0));
    }
    if (crack_has_run(p)) { /* the stop rules end the run */
      *settle = tighten(p, &loose, ctx);
      return *settle < 0 ? *settle : PS_OK;
    }
    if (++rounds >= p->o.max_break_rounds)
      return ps_error(ctx, PS_ERR_SOLVER,
                      "%s: arms still breaking after %d re-equilibrations at load "
                      "factor %.6g (path.max_break_rounds)",
                      p->pb.name, rounds, ps_solver_lambda(p->s));
  }
}
