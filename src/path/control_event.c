/* control_event.c: event control, for arms that break. Each increment
 * ends where the next arm reaches its breaking criterion: the largest
 * relative excess g (ps_solver_max_excess: s / s0 - 1 for a critical
 * stretch, eps_p r0 / delta - 1 for Eq. 118) of the equilibrium state is
 * in (0, event_tolerance]. Those arms break at the start of the next
 * increment (ps_path_iterate, without re-equilibrating), which solves
 * first at the same load and then looks for the load of the next event:
 * below it when the network that is left cannot carry that load (the load
 * factor falls while the crack grows: a snap-back), above it otherwise.
 * This is the sequentially linear analysis of Rots, Belletti &
 * Invernizzi (2008) event by event, with a Newton solve at each trial load
 * so that plasticity and large rotations are carried too. Every state of
 * the path is an equilibrium with no arm past its criterion by more than
 * event_tolerance, and every arm breaks at its criterion, not past it.
 *
 * The event's load is a root of g(lambda), each g from a Newton solve from
 * the committed state. Where the arms are elastic in small strain g + 1 is
 * proportional to lambda, so the first guess lambda (1 + tol/2) / (1 + g)
 * from one solve lands within the tolerance at the next; where it does
 * not, regula falsi (the Illinois variant) between the largest load with
 * g <= 0 and the smallest with g > tol, a failed solve counting as one
 * past. An increment that meets no arm's criterion within load_step is an
 * ordinary one. */
#include "ps_path.h"

#include <math.h>

/* trial solves per increment before the event is taken where it was last
 * bracketed */
#define PS_EVENT_MAX_SOLVES 40

typedef struct event_state {
  double dl;      /* the largest rise of the load factor in one increment
                     (load_step, halved by cuts, doubled back after
                     accepted increments) */
  int pending;    /* 1: the last increment ended at an event; its arms
                     broke at the start of this one */
  int solves;     /* trial solves of the last increment */
  int good_in_a_row;
} event_state;

static void event_init(void *state, const ps_path_opts *o) {
  event_state *c = state;
  c->dl = o->load_step;
  c->pending = 0;
  c->solves = 0;
  c->good_in_a_row = 2;
}

static double event_cut(void *state, const ps_path_opts *o) {
  event_state *c = state;
  (void)o;
  c->dl *= 0.5;
  c->good_in_a_row = 0;
  return c->dl;
}

static void event_accept(void *state, ps_int broken_total, const ps_path_opts *o) {
  event_state *c = state;
  (void)broken_total;
  if (++c->good_in_a_row >= 2) c->dl = fmin(2.0 * c->dl, o->load_step);
}

/* The first trial up from a settled state at l0 with largest excess g0:
 * the proportional guess, within dl and max_load. */
static double guess_up(const event_state *c, double l0, double g0, double aim,
                       const ps_path_opts *o) {
  double dl = c->dl;
  if (l0 > 0 && 1.0 + g0 > 0) dl = fmin(dl, l0 * ((1.0 + aim) / (1.0 + g0) - 1.0));
  if (!(dl > 0)) dl = c->dl;
  return fmin(l0 + dl, o->max_load);
}

static int event_step(void *state, ps_solver *s, const ps_path_opts *o, double *lambda,
                      ps_ctx *ctx) {
  event_state *c = state;
  const double tol = o->event_tolerance, aim = 0.5 * tol;
  const double l0 = ps_solver_lambda(s);
  /* the bracket: lo with g <= 0 (known unless the last increment ended at
   * an event: the arms just broken may leave the state at l0 past the
   * criterion), hi with g > tol (INFINITY: a failed solve) */
  double lo = l0, flo = ps_solver_max_excess(s) - aim, hi = INFINITY, fhi = INFINITY;
  int have_lo = !c->pending, last_side = 0, at_commit = 1;
  double l = c->pending ? l0 : guess_up(c, l0, flo + aim, aim, o);
  int pending = c->pending;
  c->pending = 0;
  c->solves = 0;
  for (;;) {
    if (!at_commit) PS_CHECK(ps_solver_reject(s, ctx));
    int status = ps_solver_step(s, l, ctx);
    c->solves++;
    if (status < 0) return status;
    at_commit = status == PS_DIVERGED; /* a failed solve is back at the commit */
    double g = status == PS_OK ? ps_solver_max_excess(s) : INFINITY;
    if (status == PS_OK && g <= tol && (g > 0 || !isfinite(hi))) {
      /* an event; or, with none bracketed, an admissible state: the
       * re-equilibration after breaking, or a rise that met no criterion */
      c->pending = g > 0;
      ps_log(ctx, 2, "    %s at load factor %.8g after %d solves (largest excess %.3g)\n",
             g > 0 ? "event" : pending ? "re-equilibrated" : "no event", l, c->solves, g);
      *lambda = l;
      return PS_OK;
    }
    if (g > 0) { /* past: the new hi; Illinois halves a lo kept twice */
      hi = l;
      fhi = g - aim;
      if (last_side == 1) flo *= 0.5;
      last_side = 1;
    } else {
      lo = l;
      flo = g - aim;
      have_lo = 1;
      if (last_side == -1 && isfinite(fhi)) fhi *= 0.5;
      last_side = -1;
    }
    int resolved = have_lo && hi - lo <= 1e-12 * fmax(fabs(hi), 1.0);
    if (resolved || c->solves >= PS_EVENT_MAX_SOLVES) {
      /* g jumps across the bracket (an arm's criterion reached through a
       * kink of the path): take the state just past it, whose arms break
       * beyond the tolerance */
      if (!isfinite(fhi)) {
        *lambda = l0;
        return PS_DIVERGED;
      }
      if (!at_commit) PS_CHECK(ps_solver_reject(s, ctx));
      status = ps_solver_step(s, hi, ctx);
      c->solves++;
      if (status != PS_OK) {
        *lambda = l0;
        return status;
      }
      c->pending = 1;
      ps_log(ctx, 1, "    event at load factor %.8g not resolved to path.event_tolerance "
                     "%.3g (largest excess %.3g after %d solves): breaking there\n",
             hi, tol, ps_solver_max_excess(s), c->solves);
      *lambda = hi;
      return PS_OK;
    }
    if (have_lo && isfinite(fhi))
      l = lo + (hi - lo) * (-flo) / (fhi - flo);
    else if (have_lo)
      l = 0.5 * (lo + hi);
    else if (isfinite(fhi)) /* no admissible state yet: proportional from hi */
      l = hi * (1.0 + aim) / (1.0 + fhi + aim);
    else
      l = 0.5 * hi;
    if (have_lo && !(l > lo && l < hi)) l = 0.5 * (lo + hi);
    if (!have_lo && !(l < hi)) l = 0.5 * hi;
  }
}

static const ps_step_control_type event_type = {"event",      sizeof(event_state), event_init,
                                                NULL, event_cut,           event_accept,
                                                event_step, NULL, NULL};

const ps_step_control_type *const ps_step_control_event = &event_type;
