/* control_load.c: load control, the step controller of today's runs: the
 * load factor grows by a nominal increment, halved when Newton fails and
 * doubled back after two good increments in a row. */
#include "ps_path.h"

#include <math.h>

typedef struct load_state {
  double dl_nominal; /* load_step, or load_step_after_break once arms broke */
  double dl;         /* the increment of the next attempt */
  int good_in_a_row; /* accepted increments since the last cut */
} load_state;

static void load_init(void *state, const ps_path_opts *o) {
  load_state *c = state;
  c->dl_nominal = c->dl = o->load_step;
  c->good_in_a_row = 0;
}

static double load_target(void *state, double lambda, const ps_path_opts *o) {
  const load_state *c = state;
  double target = lambda + c->dl;
  if (target > o->max_load - 1e-9 * c->dl) target = o->max_load; /* no sliver */
  return target;
}

static double load_cut(void *state, const ps_path_opts *o) {
  load_state *c = state;
  (void)o;
  c->dl *= 0.5;
  c->good_in_a_row = 0;
  return c->dl;
}

static void load_accept(void *state, ps_int broken_total, const ps_path_opts *o) {
  load_state *c = state;
  if (broken_total > 0) c->dl_nominal = fmin(c->dl_nominal, o->load_step_after_break);
  if (++c->good_in_a_row >= 2 && c->dl < c->dl_nominal) c->dl = fmin(2 * c->dl, c->dl_nominal);
  if (c->dl > c->dl_nominal) c->dl = c->dl_nominal;
}

static const ps_step_control_type load_type = {
    "load", sizeof(load_state), load_init, load_target, load_cut, load_accept, NULL};

const ps_step_control_type *const ps_step_control_load = &load_type;
