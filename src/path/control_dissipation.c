/* control_dissipation.c: dissipation control (Gutierrez 2004; Verhoosel,
 * Remmers & Gutierrez 2009): arc-length increments while the arms only
 * store energy, and once an increment dissipates, increments of a fixed
 * dissipated energy tau (ps_solver_dissipation_step), whose load factor
 * may fall while the crack opens, so the path passes snap-backs where the
 * arc-length constraint on all displacements turns back. An increment in
 * which no arm dissipates (elastic loading or unloading) goes back to
 * arc-length for that increment. tau grows after quick increments, up to
 * dissipation_max, and halves on a failure. With path.load_until_unstable
 * the path starts as load control's (ps_step_control_load: increments of
 * the load factor, breaking rounds at each load) and switches to
 * dissipation control at the first failed load increment, or when the
 * path (ps_path_iterate) finds that the rounds at one load break more than
 * load_phase_arms arms: the crack runs at that load, the load-controlled
 * path has passed its stable part. */
#include "ps_path.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

/* tau grows by 1.5 after each accepted increment (not in the two after a
 * cut) up to its cap, and halves on a failure: the Newton iterations of a
 * dissipation increment depend little on tau (kinks of arms switching
 * between loading and unloading, not the step's size, set them), so the
 * failures and the cap set tau */
typedef struct diss_state {
  _Alignas(max_align_t) unsigned char arc[128]; /* the arc-length controller's state */
  _Alignas(max_align_t) unsigned char load[64]; /* the load controller's state */
  int loading;            /* 1: load-controlled increments (load_until_unstable) */
  ps_int most_at_load;    /* the most arms an accepted load increment broke */
  ps_int broken_last;     /* the arms broken before the last accepted increment */
  int dissipating;        /* 1: the next attempt is a dissipation step */
  double tau, tau_ref;    /* the next tau; the first one (cuts relative to it) */
  double tau_max;
  int good_in_a_row;
  double last_dissipation;/* of the last successful attempt, J */
  double stored;          /* the stored energy after it, J */
} diss_state;

static void diss_init(void *state, const ps_path_opts *o) {
  diss_state *c = state;
  assert(ps_step_control_arc_length->size <= sizeof c->arc);
  assert(ps_step_control_load->size <= sizeof c->load);
  ps_step_control_arc_length->init(c->arc, o);
  ps_step_control_load->init(c->load, o);
  c->loading = o->load_until_unstable;
  c->dissipating = 0;
  c->good_in_a_row = 2;
}

/* the first tau once an increment has dissipated last_dissipation */
static void start_dissipating(diss_state *c, const ps_path_opts *o) {
  c->dissipating = 1;
  c->tau_max = o->dissipation_max > 0 ? o->dissipation_max : 0.02 * c->stored;
  c->tau = o->dissipation_step > 0 ? o->dissipation_step : c->last_dissipation;
  if (!(c->tau_max > 0)) c->tau_max = c->tau;
  c->tau = fmin(c->tau, c->tau_max);
  c->tau_ref = c->tau;
  c->good_in_a_row = 2;
}

/* the end of the load phase: dissipation control from the last settled
 * state, its first tau from the last load increment's dissipation (arc
 * length first when that increment dissipated nothing) */
static void diss_leave_load_phase(void *state, const ps_path_opts *o) {
  diss_state *c = state;
  c->loading = 0;
  if (c->last_dissipation > 0) start_dissipating(c, o);
}

static ps_int diss_load_phase_arms(const void *state, const ps_path_opts *o) {
  const diss_state *c = state;
  if (!c->loading) return 0;
  if (o->unstable_arms > 0) return o->unstable_arms;
  return c->most_at_load > 12 ? 4 * c->most_at_load : 50;
}

static double diss_cut(void *state, const ps_path_opts *o) {
  diss_state *c = state;
  if (c->loading) { /* a failed load increment: a limit point, or the crack */
    diss_leave_load_phase(c, o);
    return 1.0;
  }
  if (!c->dissipating) return ps_step_control_arc_length->cut(c->arc, o);
  c->tau *= 0.5;
  c->good_in_a_row = 0;
  return c->tau / c->tau_ref; /* the path stalls below min_step of the first tau */
}

static void diss_accept(void *state, ps_int broken_total, const ps_path_opts *o) {
  diss_state *c = state;
  if (c->loading) {
    ps_step_control_load->accept(c->load, broken_total, o);
    if (broken_total - c->broken_last > c->most_at_load)
      c->most_at_load = broken_total - c->broken_last;
    c->broken_last = broken_total;
    return;
  }
  if (!c->dissipating) {
    ps_step_control_arc_length->accept(c->arc, broken_total, o);
    if (c->last_dissipation > 0) start_dissipating(c, o); /* dissipation started */
    return;
  }
  double factor = c->good_in_a_row < 2 ? 1.0 : 1.5; /* no growth right after a cut */
  c->good_in_a_row++;
  /* the default cap follows the stored energy (plasticity may start long
   * before the peak, where 1/50 of the energy then is far too small) */
  if (!(o->dissipation_max > 0)) c->tau_max = fmax(c->tau_max, 0.02 * c->stored);
  c->tau = fmin(c->tau * factor, c->tau_max);
}

static int diss_step(void *state, ps_solver *s, const ps_path_opts *o, double *lambda,
                     ps_ctx *ctx) {
  diss_state *c = state;
  int status;
  if (c->loading) {
    double target = ps_step_control_load->target(c->load, ps_solver_lambda(s), o);
    status = ps_solver_step(s, target, ctx);
  } else if (c->dissipating) {
    status = ps_solver_dissipation_step(s, c->tau, ctx);
    if (status == PS_DIVERGED && ps_solver_last_reason(s) == PS_NEWTON_NO_DISSIPATION) {
      ps_log(ctx, 2, "    no arm dissipates along the step: an arc-length increment\n");
      c->dissipating = 0;
    }
  }
  if (!c->loading && !c->dissipating)
    status = ps_step_control_arc_length->step(c->arc, s, o, lambda, ctx);
  *lambda = ps_solver_lambda(s);
  if (status == PS_OK) {
    c->last_dissipation = ps_solver_step_dissipation(s);
    c->stored = ps_solver_stored_energy(s);
  }
  return status;
}

static const ps_step_control_type diss_type = {
    "dissipation", sizeof(diss_state), diss_init,          NULL,
    diss_cut,      diss_accept,        diss_step,          diss_load_phase_arms,
    diss_leave_load_phase};

const ps_step_control_type *const ps_step_control_dissipation = &diss_type;
