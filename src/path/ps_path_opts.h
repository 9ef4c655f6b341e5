/* ps_path_opts.h: the settings of the load path (the case's path.* keys),
 * apart from ps_path.h so that the case reader (src/io) can hold and fill
 * them without seeing the path layer. Depends on nothing but the C
 * library. */
#ifndef PS_PATH_OPTS_H
#define PS_PATH_OPTS_H

/* Settings of the load path; the load factor lambda is dimensionless. */
typedef struct ps_path_opts {
  double load_step;             /* nominal increment of the load factor
                                   (default 0.02) */
  double load_step_after_break; /* the nominal increment, if smaller, once an
                                   arm has broken (default 0.005) */
  double max_load;              /* last load factor (the last increment is
                                   shortened to land on it; default 5) */
  int max_increments;           /* increments at most (cuts do not count;
                                   default 2000) */
  double min_step;              /* the path stalls when a cut takes the
                                   increment below this (default 1e-6) */
  double stop_crack_tip;        /* disk: stop when the tip is this many c
                                   from the centre (default 9) */
  double stop_tip_advance;      /* disk: stop when the tip advances this many
                                   c within one increment; 0: off (default) */
  double stop_load_drop;        /* stop when, after breaking, the boundary
                                   stress falls below this fraction of its
                                   peak (default 0.5) */
  int max_break_rounds;         /* breaking rounds per increment before the
                                   path fails (PS_ERR_SOLVER; default
                                   100000: each round breaks at least one
                                   arm, and a crack that runs across a
                                   ligament at one load needs a round per
                                   few arms of it) */
  int max_arms_per_round;       /* a breaking round breaks at most this many
                                   arms, those past the criterion by the
                                   most, before re-equilibrating; 0: all of
                                   them (default) */
  double round_tolerance;       /* > 0: each breaking round's
                                   re-equilibration stops at this relative
                                   residual (if above solver.tolerance), and
                                   the state the rounds end in is solved
                                   again to solver.tolerance (and the rounds
                                   go on if arms are then past the
                                   criterion); 0: every round to
                                   solver.tolerance (default) */
  int control;                  /* the step controller: PS_CONTROL_LOAD
                                   (default), PS_CONTROL_ARC_LENGTH,
                                   PS_CONTROL_DISSIPATION or
                                   PS_CONTROL_EVENT */
  double arc_length_max;        /* arc-length: the largest arc length, in
                                   units of the load factor of the first
                                   (elastic) response; 0: load_step
                                   (default) */
  double arc_length_psi;        /* arc-length: the weight of the load
                                   factor in the constraint (0: cylindrical,
                                   the default; 1: spherical) */
  int arc_length_iterations;    /* arc-length: the Newton iterations per
                                   increment the arc length adapts to
                                   (default 5) */
  int max_arms_per_step;        /* arc-length and dissipation control: an
                                   increment after which more arms than
                                   this are past the criterion is cut, so
                                   that the path through fracture is a
                                   sequence of equilibrium states; 0: no
                                   cap (default) */
  double dissipation_step;      /* dissipation control: the first energy
                                   tau dissipated per increment, J (per m
                                   of thickness in 2D); 0: the dissipation
                                   of the arc-length increment in which it
                                   started (default) */
  double dissipation_max;       /* dissipation control: the largest tau, J;
                                   0: 1/50 of the largest stored energy so
                                   far (default) */
  int load_until_unstable;      /* dissipation control: load-controlled
                                   increments with breaking rounds (as
                                   PS_CONTROL_LOAD) while the path is
                                   stable; at the first load whose rounds
                                   break more than unstable_arms arms (the
                                   crack runs), or whose Newton fails, back
                                   to the last settled state and
                                   dissipation control from there. 0: no
                                   (default) */
  int unstable_arms;            /* with load_until_unstable: 0 (default):
                                   four times the most arms a settled load
                                   broke, at least 50 */
  double event_tolerance;       /* event control: an increment ends where
                                   the largest relative excess over the
                                   breaking criterion (break_excess) is in
                                   (0, event_tolerance] (default 1e-3) */
  double *steps;                /* load control: the load factors to reach
                                   in turn (path.steps: > 0, increasing;
                                   max_load is the last), or NULL (default:
                                   increments of load_step). Owned by the
                                   ps_case that holds these options
                                   (ps_case_free); a copy of the options
                                   borrows it */
  int n_steps;                  /* entries of steps (0: none) */
} ps_path_opts;

/* path.control */
enum ps_path_control {
  PS_CONTROL_LOAD = 0,
  PS_CONTROL_ARC_LENGTH = 1,
  PS_CONTROL_DISSIPATION = 2,
  PS_CONTROL_EVENT = 3
};

/* The defaults above, the only place they are written down (the case
 * reader starts from them). Defined in path.c. */
void ps_path_opts_default(ps_path_opts *o);

#endif
