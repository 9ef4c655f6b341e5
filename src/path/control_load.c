/* control_load.c: load control, the step controller of today's runs: the
 * load factor grows by a nominal increment, halved when Newton fails and
 * doubled back after two good increments in a row. With path.steps the
 * targets are the listed load factors in turn: a failed attempt is halved
 * as above (the targets between two entries then lie where the halved
 * increments fall), and after two good increments the increment doubles
 * until it reaches the next entry again. */
#include "ps_path.h"

#include <math.h>

typedef struct load_state {
  double dl_nominal; /* load_step, or load_step_after_break once arms broke
                        (path.steps: INFINITY, the next entry bounds it) */
  double dl;         /* the increment of the next attempt */
  double tried;      /* the increment of the last attempt */
  int good_in_a_row; /* accepted increments since the last cut */
} load_state;

static void load_init(void *state, const ps_path_opts *o) {
  load_state *c = state;
  c->dl_nominal = c->dl = o->n_steps > 0 ? INFINITY : o->load_step;
  c->tried = 0.0;
  c->good_in_a_row = 0;
}

/* path.steps: the first entry above lambda (the last one past the list) */
static double next_entry(double lambda, const ps_path_opts *o) {
  for (int i = 0; i < o->n_steps; i++)
    if (o->steps[i] > lambda) return o->steps[i];
  return o->steps[o->n_steps - 1];
}

static double load_target(void *state, double lambda, const ps_path_opts *o) {
  load_state *c = state;
  double last = o->n_steps > 0 ? next_entry(lambda, o) : o->max_load;
  double target = lambda + c->dl;
  if (target > last - 1e-9 * c->dl) target = last; /* no sliver */
  c->tried = target - lambda;
  return target;
}

static double load_cut(void *state, const ps_path_opts *o) {
  load_state *c = state;
  (void)o;
  /* path.steps: half the increment tried (the whole way to an entry at
   * first); else half the nominal one */
  c->dl = 0.5 * (o->n_steps > 0 ? fmin(c->dl, c->tried) : c->dl);
  c->good_in_a_row = 0;
  return c->dl;
}

static void load_accept(void *state, ps_int broken_total, const ps_path_opts *o) {
  load_state *c = state;
  if (broken_total > 0 && o->n_steps == 0)
    c->dl_nominal = fmin(c->dl_nominal, o->load_step_after_break);
  if (++c->good_in_a_row >= 2 && c->dl < c->dl_nominal) c->dl = fmin(2 * c->dl, c->dl_nominal);
  if (c->dl > c->dl_nominal) c->dl = c->dl_nominal;
}

static const ps_step_control_type load_type = {
    "load", sizeof(load_state), load_init, load_target, load_cut, load_accept, NULL, NULL, NULL};

const ps_step_control_type *const ps_step_control_load = &load_type;
