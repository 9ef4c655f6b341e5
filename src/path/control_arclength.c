/* control_arclength.c: arc-length control (Riks/Crisfield): each
 * increment is one ps_solver_arclength_step of arc length ds (in units of
 * the load factor of the first, elastic, response), so the load factor
 * may rise, stay or fall and the path passes limit points; ds adapts to
 * the Newton iterations of the last increment and halves on a failure.
 * Load control (control_load.c) stays the default (path.control). */
#include "ps_path.h"

#include <math.h>

typedef struct arc_state {
  double ds;          /* the arc length of the next attempt */
  double ds_max;      /* arc_length_max, or load_step */
  int good_in_a_row;  /* accepted increments since the last cut */
  int its;            /* Newton iterations of the last successful attempt */
  ps_int broken_seen; /* arms broken at the last accept */
} arc_state;

static void arc_init(void *state, const ps_path_opts *o) {
  arc_state *c = state;
  c->ds = o->load_step;
  c->ds_max = o->arc_length_max > 0 ? o->arc_length_max : o->load_step;
  if (c->ds > c->ds_max) c->ds = c->ds_max;
  c->good_in_a_row = 2;
  c->its = 0;
  c->broken_seen = 0;
}

static double arc_cut(void *state, const ps_path_opts *o) {
  arc_state *c = state;
  (void)o;
  c->ds *= 0.5;
  c->good_in_a_row = 0;
  return c->ds;
}

static void arc_accept(void *state, ps_int broken_total, const ps_path_opts *o) {
  arc_state *c = state;
  double want = o->arc_length_iterations > 0 ? o->arc_length_iterations : 5;
  double factor = sqrt(want / (c->its > 1 ? c->its : 1));
  if (factor > 2) factor = 2;
  if (factor < 0.5) factor = 0.5;
  if (c->good_in_a_row < 2 && factor > 1) factor = 1; /* no growth right after a cut */
  c->good_in_a_row++;
  c->ds = fmin(c->ds * factor, c->ds_max);
  if (broken_total > c->broken_seen) {
    c->ds_max = fmin(c->ds_max, o->load_step_after_break);
    c->ds = fmin(c->ds, o->load_step_after_break);
    c->broken_seen = broken_total;
  }
}

static int arc_step(void *state, ps_solver *s, const ps_path_opts *o, double *lambda,
                    ps_ctx *ctx) {
  arc_state *c = state;
  ps_solver_stats st0, st1;
  ps_solver_get_stats(s, &st0);
  int status = ps_solver_arclength_step(s, c->ds, o->arc_length_psi, ctx);
  ps_solver_get_stats(s, &st1);
  c->its = (int)(st1.newton_iterations - st0.newton_iterations);
  *lambda = ps_solver_lambda(s);
  return status;
}

static const ps_step_control_type arc_type = {"arc_length", sizeof(arc_state), arc_init,
                                              NULL,   arc_cut,           arc_accept,
                                              arc_step, NULL, NULL};

const ps_step_control_type *const ps_step_control_arc_length = &arc_type;

const ps_step_control_type *ps_step_control_find(int control) {
  return control == PS_CONTROL_ARC_LENGTH    ? ps_step_control_arc_length
         : control == PS_CONTROL_DISSIPATION ? ps_step_control_dissipation
         : control == PS_CONTROL_EVENT       ? ps_step_control_event
                                             : ps_step_control_load;
}
