/* path.c: the load path as init / iterate / test: one increment per
 * iterate (attempts cut by the step controller: a target load factor for
 * ps_solver_step, or the controller's own step, as arc-length's; the
 * commit, the breaking rounds), the peak of the settled states, and the
 * stop rules; the default options (ps_path_opts.h). */
#include "ps_path.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ps_path_opts_default(ps_path_opts *o) {
  o->load_step = 0.02;
  o->load_step_after_break = 0.005;
  o->max_load = 5.0;
  o->max_increments = 2000;
  o->min_step = 1e-6;
  o->stop_crack_tip = 9.0;
  o->stop_tip_advance = 0.0;
  o->stop_load_drop = 0.5;
  o->max_break_rounds = 100000;
  o->control = PS_CONTROL_LOAD;
  o->arc_length_max = 0.0;
  o->arc_length_psi = 0.0;
  o->arc_length_iterations = 5;
  o->max_arms_per_step = 0;
  o->dissipation_step = 0.0;
  o->dissipation_max = 0.0;
  o->event_tolerance = 1e-3;
  o->steps = NULL;
  o->n_steps = 0;
}

int ps_path_init(ps_path *p, ps_solver *s, const ps_path_problem *pb, const ps_path_opts *o,
                 const ps_step_control_type *control, ps_ctx *ctx) {
  memset(p, 0, sizeof *p);
  p->s = s;
  p->pb = *pb;
  p->o = *o;
  p->control = control;
  p->peak = -INFINITY;
  p->resumable = 1;
  p->control_state = ps_calloc(1, control->size, ctx);
  if (!p->control_state) return PS_ERR_NOMEM;
  control->init(p->control_state, &p->o);
  return PS_OK;
}

void ps_path_free(ps_path *p) {
  ps_solver_snapshot_free(&p->settled_state);
  free(p->control_state);
  p->control_state = NULL;
}

int ps_path_state_list(ps_path *p, ps_state_list *l, ps_ctx *ctx) {
#define PS_ITEM(field) PS_CHECK(ps_state_add(l, "path." #field, &p->field, sizeof p->field, ctx))
  PS_ITEM(peak);
  PS_ITEM(lambda_peak);
  PS_ITEM(crack_tip);
  PS_ITEM(increments);
  PS_ITEM(step_cuts);
  PS_ITEM(gentle_rounds);
  PS_ITEM(broken_total);
  PS_ITEM(lambda_max);
  PS_ITEM(last);
  PS_ITEM(tip_start);
  PS_ITEM(recent);
  PS_ITEM(n_recent);
#undef PS_ITEM
  char name[PS_STATE_NAME];
  snprintf(name, sizeof name, "path.control.%s", p->control->name);
  return ps_state_add(l, name, p->control_state, p->control->size, ctx);
}

/* Asks problem.interrupted; when it says stop, the path ends here. */
static int check_interrupt(ps_path *p) {
  char why[96] = "interrupted";
  if (!p->pb.interrupted) return 0;
  /* every process ends where any was interrupted */
  double w = p->pb.interrupted(p->pb.interrupted_data, why, sizeof why);
  ps_comm_max(ps_solver_comm(p->s), &w, 1);
  int v = (int)w;
  if (!v) return 0;
  p->interrupted = v;
  p->end = PS_PATH_INTERRUPTED;
  snprintf(p->stop_reason, sizeof p->stop_reason, "%s at load factor %.6g", why,
           ps_solver_lambda(p->s));
  return 1;
}

ps_int ps_path_load_phase_arms(const ps_path *p) {
  return p->control->load_phase_arms ? p->control->load_phase_arms(p->control_state, &p->o)
                                     : 0;
}

/* 1 when the increments break arms in rounds at their load (load
 * control, a controller's load phase) */
static int rounds_at_load(const ps_path *p) {
  return p->o.control == PS_CONTROL_LOAD || ps_path_load_phase_arms(p) > 0;
}

/* Attempts at the controller's targets until Newton converges: returns
 * PS_OK with *its0 = the Newton iterations before the successful attempt,
 * or PS_OK with p->end set (a stall below min_step, an interruption
 * between attempts), or a fatal status. */
static int attempt(ps_path *p, ps_int *its0, ps_ctx *ctx) {
  ps_solver *s = p->s;
  for (;;) {
    ps_solver_stats st;
    double target;
    int status;
    ps_solver_get_stats(s, &st);
    *its0 = st.newton_iterations;
    if (p->control->step) {
      status = p->control->step(p->control_state, s, &p->o, &target, ctx);
    } else {
      target = p->control->target(p->control_state, ps_solver_lambda(s), &p->o);
      status = ps_solver_step(s, target, ctx);
    }
    if (status < 0) return status;
    ps_int past = 0;
    int loading = ps_path_load_phase_arms(p) > 0;
    if (status == PS_OK && !rounds_at_load(p) && p->o.max_arms_per_step > 0 &&
        (past = ps_solver_count_past_criterion(s)) > p->o.max_arms_per_step)
      PS_CHECK(ps_solver_reject(s, ctx)); /* too many arms at once: a shorter increment */
    else if (status != PS_DIVERGED)
      return PS_OK;
    p->step_cuts++;
    double dl = p->control->cut(p->control_state, &p->o);
    if (loading && ps_path_load_phase_arms(p) == 0)
      ps_log(ctx, 1, "  step %d: Newton did not converge at load factor %.6g (%s): the "
                     "%s controller goes on from load factor %.6g\n",
             (int)(p->increments + 1), target,
             ps_newton_reason_text(ps_solver_last_reason(s)), p->control->name,
             ps_solver_lambda(s));
    else if (past)
      ps_log(ctx, 1, "  step %d: %lld arms past the criterion at load factor %.6g "
                     "(path.max_arms_per_step %d); cutting the increment to %.4g\n",
             (int)(p->increments + 1), (long long)past, target, p->o.max_arms_per_step, dl);
    else
      ps_log(ctx, 1, "  step %d: Newton did not converge at load factor %.6g (%s, "
                     "residual %.2e); cutting the increment to %.4g\n",
             (int)(p->increments + 1), target,
             ps_newton_reason_text(ps_solver_last_reason(s)), ps_solver_last_residual(s), dl);
    if (dl < p->o.min_step) {
      /* the path ends here: an error for `run` (after the summary is
       * written to the partial output), a result for the sweep */
      ps_path_newton_stalled(p, target);
      return PS_OK;
    }
    if (check_interrupt(p)) return PS_OK;
  }
}

/* The rounds at one load ended the controller's load phase (p->unstable,
 * after nb arms broke; limit: the phase's arms): the load-controlled path
 * has passed its stable part. Back to the settled state of
 * p->settled_state, and the controller's own steps from there. Returns
 * PS_OK or fatal. */
static int end_load_phase(ps_path *p, ps_int nb, ps_int limit, ps_ctx *ctx) {
  char why[96];
  if (p->unstable == PS_UNSTABLE_ARMS)
    snprintf(why, sizeof why, "%lld arms broken at that load, more than %lld", (long long)nb,
             (long long)limit);
  else
    snprintf(why, sizeof why, "%s after %lld arms broke",
             p->unstable == PS_UNSTABLE_STOP_RULE ? "a stop rule met" : "a breaking round failed",
             (long long)nb);
  p->unstable = 0;
  double lambda = ps_solver_lambda(p->s);
  int st = ps_solver_snapshot_restore(p->s, &p->settled_state, ctx);
  if (st < 0) return st;
  p->control->leave_load_phase(p->control_state, &p->o);
  ps_log(ctx, 1, "  step %d: the crack runs at load factor %.6g (%s): the %s controller goes "
                 "on from load factor %.6g\n",
         (int)(p->increments + 1), lambda, why, p->control->name, ps_solver_lambda(p->s));
  return PS_OK;
}

int ps_path_iterate(ps_path *p, ps_ctx *ctx) {
  ps_solver *s = p->s;
  ps_int its0, nb;
  int settle, settled = 0;
  if (p->end) return PS_OK;
  p->resumable = 0;
  p->rounds_interrupted = 0;
  if (p->o.control == PS_CONTROL_EVENT) {
    /* the arms of the last increment's event break; the controller's
     * first solve is at that load */
    PS_CHECK(ps_solver_break_in_place(p->s, 0, &nb, ctx));
    p->broken_total += nb;
  } else if (!rounds_at_load(p)) {
    /* the last increment's arms past the criterion break; one
     * re-equilibration at that load (Newton with its line search) puts
     * the next constrained step's start back in equilibrium, where the
     * forces of arms that broke carrying load (fibre: T_y) left it far
     * off; when that fails, the step starts from the broken state */
    int st = ps_solver_break_round(p->s, 0, &nb, ctx);
    if (st < 0) return st;
    if (st == PS_DIVERGED) {
      ps_solver_restore(p->s);
      PS_CHECK(ps_solver_evaluate(p->s, ctx));
      PS_CHECK(ps_solver_break_in_place(p->s, 0, &nb, ctx));
    }
    p->broken_total += nb;
  }
  /* a load phase keeps the settled state it starts from, to come back to
   * when the crack runs at the increment's load */
  if (ps_path_load_phase_arms(p) > 0) PS_CHECK(ps_solver_snapshot_take(s, &p->settled_state, ctx));
again:
  PS_CHECK(attempt(p, &its0, ctx));
  if (p->end) return PS_OK;
  ps_solver_commit(s);
  p->tip_start = ps_path_crack_tip(p);
  if (rounds_at_load(p)) {
    ps_int limit = ps_path_load_phase_arms(p);
    PS_CHECK(ps_path_break_rounds(p, its0, &nb, &settle, &settled, ctx));
    if (p->unstable) {
      PS_CHECK(end_load_phase(p, nb, limit, ctx));
      goto again;
    }
  } else {
    /* path control: the converged state is the increment's; the arms
     * past the criterion break at the start of the next one, whose
     * constraint chooses the load of the next equilibrium (no rounds at
     * this load, which would snap through). The peak is that of these
     * converged states, some with arms past the criterion that break only
     * at the next increment's start (doc/path-following.md) */
    nb = 0;
    settle = PS_OK;
    settled = 1;
  }
  p->broken_total += nb;
  p->control->accept(p->control_state, p->broken_total, &p->o);
  int converged = settle == PS_OK;
  if (!converged) /* make T, q, dl those of u (a rejected trial may linger) */
    PS_CHECK(ps_solver_evaluate(s, ctx));
  ps_solver_stats st;
  ps_solver_get_stats(s, &st);
  ps_path_increment *last = &p->last;
  last->step = ++p->increments;
  last->lambda = ps_solver_lambda(s);
  last->sigma = ps_path_boundary_stress(p);
  last->tip = ps_path_crack_tip(p);
  last->residual = ps_solver_last_residual(s);
  last->converged = converged;
  last->newton_iterations = (int)(st.newton_iterations - its0);
  last->yielding = ps_solver_count_yielding(s);
  /* only a state that is converged and settled (no arm left past delta;
   * the rounds may end early once the crack has run) sets the peak */
  if (converged && settled && last->sigma > p->peak) {
    p->peak = last->sigma;
    p->lambda_peak = last->lambda;
  }
  if (converged && last->lambda > p->lambda_max) {
    p->lambda_max = last->lambda;
    /* arc-length without a boundary-stress measure: the peak's load
     * factor is that of the largest load factor */
    if (p->o.control != PS_CONTROL_LOAD && !(p->pb.measure_length > 0) && settled)
      p->lambda_peak = last->lambda;
  }
  if (converged) {
    const int nr = (int)(sizeof p->recent / sizeof p->recent[0]);
    memmove(p->recent, p->recent + 1, (size_t)(nr - 1) * sizeof *p->recent);
    p->recent[nr - 1] = last->sigma;
    p->n_recent++;
    p->crack_tip = last->tip;
  } else {
    ps_path_reequilibration_failed(p, last->sigma);
  }
  p->resumable = !p->end && !p->rounds_interrupted;
  return PS_OK;
}

/* The stop rules after a settled increment; 1 when the path ends here. */
static int stop_rule(ps_path *p) {
  const ps_path_opts *o = &p->o;
  const ps_path_increment *last = &p->last;
  double tip = last->tip, c = p->pb.c;
  if (last->converged && c > 0 && o->stop_tip_advance > 0 &&
      tip - p->tip_start >= o->stop_tip_advance) {
    p->end = PS_PATH_FRACTURED;
    snprintf(p->stop_reason, sizeof p->stop_reason,
             "the crack tip advanced %.3g c at one load (from %.4g c to %.4g c): it "
             "runs unstably", tip - p->tip_start, p->tip_start, tip);
    return 1;
  }
  if (c > 0 && tip >= o->stop_crack_tip) {
    p->end = PS_PATH_FRACTURED;
    snprintf(p->stop_reason, sizeof p->stop_reason, "crack tip passed %.3g c from the centre",
             o->stop_crack_tip);
    return 1;
  }
  if (p->broken_total > 0 && last->sigma < o->stop_load_drop * p->peak) {
    p->end = PS_PATH_FRACTURED;
    snprintf(p->stop_reason, sizeof p->stop_reason,
             "boundary stress fell below %.3g of its peak", o->stop_load_drop);
    return 1;
  }
  if (o->control != PS_CONTROL_LOAD && p->lambda_max > 0 &&
      last->lambda < o->stop_load_drop * p->lambda_max) {
    p->end = p->broken_total ? PS_PATH_FRACTURED : PS_PATH_LOAD_DROP;
    snprintf(p->stop_reason, sizeof p->stop_reason,
             "past the peak the load factor fell below %.3g of its largest value "
             "%.6g, %s", o->stop_load_drop, p->lambda_max,
             p->broken_total ? "arms broken" : "no arm broken");
    return 1;
  }
  if (last->lambda >= o->max_load) { /* exact: the target snaps to max_load */
    p->end = PS_PATH_MAX_LOAD;
    snprintf(p->stop_reason, sizeof p->stop_reason, "%s = %g reached: %s",
             o->n_steps > 0 ? "the last of path.steps" : "path.max_load", o->max_load,
             p->broken_total ? "arms broke but the crack did not run" : "no fracture");
    return 1;
  }
  return 0;
}

int ps_path_test(ps_path *p) {
  if (p->end) return p->end;
  if (check_interrupt(p)) return p->end;
  if (p->increments > 0 && stop_rule(p)) return p->end;
  if (p->increments >= p->o.max_increments) {
    p->end = PS_PATH_MAX_INCREMENTS;
    snprintf(p->stop_reason, sizeof p->stop_reason, "max_increments reached (%d)",
             p->o.max_increments);
  }
  return p->end;
}
