/* ps_path.h: following the load path of one case on a solver: the
 * increments (predictor and Newton through ps_solver_step), the commit,
 * the rounds of arm breaking (Eq. 118) with their halving retries, the
 * stop rules, the peak, and whether the run fractured or stalled; in the
 * GSL style of init / iterate / test, with the choice of the next load
 * factor behind a replaceable step controller (ps_step_control_type).
 *
 *   ps_path p;
 *   PS_CHECK(ps_path_init(&p, solver, &problem, &opts,
 *                         ps_step_control_find(opts.control), ctx));
 *   while (ps_path_test(&p) == PS_PATH_CONTINUE) {
 *     PS_CHECK(ps_path_iterate(&p, ctx));     (one increment)
 *     ... print p.last, write history and fields ...
 *   }
 *   ... p.end, p.stop_reason, p.peak ...
 *   ps_path_free(&p);
 *
 * The path uses the solver only through ps_solver.h's functions and
 * accessors; it prints the lines about cut increments and long breaking
 * rounds (ps_log), the caller prints one line per increment. */
#ifndef PS_PATH_H
#define PS_PATH_H

#include "../post/ps_post.h"
#include "../nonlinear/ps_solver.h"
#include "ps_path_opts.h"

/* What the path measures on the solver's states and names in messages
 * (nothing owned). */
typedef struct ps_path_problem {
  const ps_particles *P;
  const ps_network *net;
  const ps_model_type *model;   /* the solver's model type */
  const ps_material *mat;       /* the solver's material (this run's delta) */
  const double *measure;        /* [n_dof] boundary-stress weights */
  double measure_length;        /* m (2D), m^2 (3D); 0: no measure */
  double c;                     /* disk: half crack length, m (crack tip in
                                   units of c); 0: no crack tip */
  const char *name;             /* the case file, first in messages */
  /* Interruption (e.g. by a signal): returns nonzero when the path must
   * end after the attempt under way, and then, when why != NULL, writes
   * a short reason ("interrupted by SIGINT") into why. NULL: never. */
  int (*interrupted)(void *data, char *why, size_t len);
  void *interrupted_data;
} ps_path_problem;

/* The step controller: the choice of the next load factor. The path calls
 * init once, then per attempt target; cut after an attempt that did not
 * converge (the solver is back at the last committed state); accept after
 * an increment was committed and its breaking rounds ended. An
 * implementation keeps its state in `size` bytes that the path allocates
 * (zeroed). Load control (ps_step_control_load) chooses the load factor
 * (target); arc-length control (ps_step_control_arc_length) makes the
 * attempt itself (step), the load factor following from its constraint.
 * ps_step_control_find maps path.control to one of them. */
typedef struct ps_step_control_type {
  const char *name;
  size_t size;
  void (*init)(void *state, const ps_path_opts *o);
  /* the load factor of the next attempt from the current one, lambda
   * (NULL for a controller with a step, whose load factor follows from
   * its constraint) */
  double (*target)(void *state, double lambda, const ps_path_opts *o);
  /* the attempt failed: the increment of the next one (the path stalls
   * when it is below o->min_step) */
  double (*cut)(void *state, const ps_path_opts *o);
  /* an increment was accepted; broken_total = arms broken so far */
  void (*accept)(void *state, ps_int broken_total, const ps_path_opts *o);
  /* optional: the attempt itself, for a controller whose load factor
   * follows from a constraint (NULL: target, then ps_solver_step). Sets
   * *lambda to the load factor reached (on failure: the one it started
   * from). Returns PS_OK, PS_DIVERGED (the solver is back at the last
   * commit) or a fatal status. */
  int (*step)(void *state, ps_solver *s, const ps_path_opts *o, double *lambda, ps_ctx *ctx);
  /* optional, for a controller whose path starts with load-controlled
   * increments and breaking rounds at each load (as load control's):
   * while it does, the number of arms whose breaking at one load ends
   * that phase (the crack runs), else 0 (NULL: never such a phase) */
  ps_int (*load_phase_arms)(const void *state, const ps_path_opts *o);
  /* optional, with load_phase_arms: end that phase; the solver is back at
   * the path's last settled state */
  void (*leave_load_phase)(void *state, const ps_path_opts *o);
} ps_step_control_type;

/* Load control: increments of load_step (min(load_step,
 * load_step_after_break) once an arm has broken), halved on each failed
 * attempt and doubled back towards the nominal one after two accepted
 * increments in a row; the target snaps to max_load. With path.steps
 * (o->n_steps > 0) the targets are the listed load factors in turn: a
 * failed attempt halves the increment tried, which doubles after two
 * accepted increments until the target is the next entry again. */
extern const ps_step_control_type *const ps_step_control_load;

/* Arc-length control (control_arclength.c; ps_solver_arclength_step):
 * increments of arc length ds, in units of the load factor of the first
 * (elastic) response, starting at load_step; after each accepted
 * increment ds is scaled by sqrt(arc_length_iterations / Newton
 * iterations), within [ds/2, 2 ds], not above arc_length_max (0:
 * load_step) and not up in the two increments after a cut; halved on
 * each failed attempt. Once an arm has broken, ds is at most
 * load_step_after_break for good. Breaking rounds stay at the load
 * factor of the increment, as under load control. */
extern const ps_step_control_type *const ps_step_control_arc_length;

/* Dissipation control (control_dissipation.c; ps_solver_dissipation_step):
 * arc-length increments (as ps_step_control_arc_length) until one
 * dissipates energy in the arms, then increments of dissipated energy
 * tau: the first dissipation_step (0: that increment's dissipation), at
 * most dissipation_max (0: 1/50 of the largest stored energy so far), adapted to
 * the Newton iterations as ds is, halved on a failure; an increment in
 * which no arm dissipates goes back to arc-length until one does again.
 * With load_until_unstable the path starts under load control instead
 * (load_phase_arms), and dissipation control starts where the crack runs
 * at one load or a load increment fails (the path goes back to the last
 * settled state first). Needs a model that measures its dissipation
 * (arm_dissipation: the fibre model, the bond model with
 * material.fracture.softening_ratio). */
extern const ps_step_control_type *const ps_step_control_dissipation;

/* Event control (control_event.c): each increment ends at the load factor
 * where the next arm reaches its breaking criterion (the largest relative
 * excess in (0, event_tolerance]), found by Newton solves from the
 * committed state at trial load factors (proportional guess, then regula
 * falsi); those arms break at the start of the next increment without
 * re-equilibrating, and its first solve is at the same load factor. The
 * load factor falls where the damaged network cannot carry it (a
 * snap-back). Increments that meet no criterion rise by at most
 * load_step (halved on a failure). */
extern const ps_step_control_type *const ps_step_control_event;

/* The controller of path.control (enum ps_path_control). */
const ps_step_control_type *ps_step_control_find(int control);

/* Why the rounds at one load ended a controller's load phase. */
enum ps_path_unstable {
  PS_UNSTABLE_ARMS = 1,         /* more arms broke than load_phase_arms */
  PS_UNSTABLE_STOP_RULE = 2,    /* the state met a stop rule (tip, load drop) */
  PS_UNSTABLE_ROUND_FAILED = 3  /* a round's re-equilibration failed */
};

/* How a path ended (ps_path_test). */
enum ps_path_end {
  PS_PATH_CONTINUE = 0,
  PS_PATH_FRACTURED = 1,      /* the crack ran: a stop rule (tip, tip
                                 advance, load drop), or a failed
                                 re-equilibration that shed load below the
                                 peak (an unstable fracture) */
  PS_PATH_STALLED = 2,        /* the solve failed before the crack ran:
                                 Newton below min_step, or a failed
                                 re-equilibration with the load not below
                                 its peak; p->message says what was seen
                                 and what can help */
  PS_PATH_MAX_LOAD = 3,       /* max_load reached */
  PS_PATH_MAX_INCREMENTS = 4, /* max_increments done */
  PS_PATH_INTERRUPTED = 5,    /* problem.interrupted said so */
  PS_PATH_LOAD_DROP = 6       /* arc-length or dissipation control: the
                                 load factor fell below stop_load_drop of
                                 its largest value with no arm broken
                                 (past a limit point; with arms broken
                                 it is PS_PATH_FRACTURED) */
};

/* The last increment, for the caller's progress line, history row and
 * fields (valid after ps_path_iterate). */
typedef struct ps_path_increment {
  ps_int step;                /* 1, 2, ... */
  double lambda;              /* load factor */
  double sigma;               /* boundary stress, Pa */
  double residual;            /* relative residual of the last solve */
  double tip;                 /* crack tip, c (0 without a crack) */
  int converged;              /* 0: the final re-equilibration failed */
  int newton_iterations;      /* of the increment, breaking rounds included */
  ps_int yielding;            /* intact arms on the yield surface */
} ps_path_increment;

typedef struct ps_path {
  /* the outcome so far (read only) */
  int end;                    /* enum ps_path_end, set by ps_path_test
                                 (stalls and failed re-equilibrations by
                                 ps_path_iterate) */
  char stop_reason[160];      /* why it ended */
  char message[2048];         /* a stall: the error text for a caller that
                                 treats it as one */
  int interrupted;            /* problem.interrupted's value, 0 if none */
  double peak;                /* peak boundary stress of the converged and
                                 settled states, Pa (-inf: none yet) */
  double lambda_peak;         /* load factor at the peak (0: none);
                                 under arc-length without a measure, the
                                 largest settled load factor */
  double crack_tip;           /* tip of the last converged state, c */
  ps_int increments, step_cuts;
  ps_int gentle_rounds;       /* breaking rounds retried with fewer arms */
  ps_int broken_total;        /* arms broken so far */
  double lambda_max;          /* largest load factor of the converged
                                 increments (0: none yet) */
  ps_path_increment last;
  int resumable;              /* 1: the solver is in the state the path
                                 left it in after the last complete
                                 increment (or at the start), from which
                                 the path goes on as if never stopped: a
                                 checkpoint may be taken; 0 after an end
                                 inside an increment (a stall, a failed
                                 re-equilibration, an interruption
                                 between attempts or breaking rounds) */

  /* private */
  ps_solver *s;
  ps_path_problem pb;
  ps_path_opts o;
  const ps_step_control_type *control;
  void *control_state;
  double tip_start;           /* crack tip before the last breaking rounds */
  ps_solver_snapshot settled_state; /* a load phase's last settled state */
  int unstable;               /* the rounds at one load ended the load
                                 phase: enum ps_path_unstable */
  double recent[3];           /* boundary stresses of the last converged
                                 increments, the newest last */
  int n_recent;
  int rounds_interrupted;     /* the last breaking rounds ended early on an
                                 interruption */
} ps_path;

/* Start a path on solver s at its current state (load factor 0). The
 * problem and options are copied (the arrays they point to are not).
 * Returns PS_OK or PS_ERR_NOMEM. */
int ps_path_init(ps_path *p, ps_solver *s, const ps_path_problem *pb, const ps_path_opts *o,
                 const ps_step_control_type *control, ps_ctx *ctx);

/* One increment: attempts at the controller's targets (a failed Newton
 * solve restores the last committed state and cuts the increment; below
 * min_step the path ends as stalled, and problem.interrupted is asked
 * between attempts), the commit, then the breaking rounds at that load
 * (ps_path_break_rounds). Fills p->last. A failed final re-equilibration
 * ends the path (fractured or stalled). Returns PS_OK (see p->end) or a
 * fatal status (PS_ERR_SOLVER when arms still break after
 * max_break_rounds rounds). */
int ps_path_iterate(ps_path *p, ps_ctx *ctx);

/* The stop rules, in this order: an end already reached; interruption;
 * after an increment the tip advance, the crack tip, the load drop, under
 * arc-length with no arm broken the load factor below stop_load_drop of
 * its largest value (PS_PATH_LOAD_DROP), and max_load (under arc-length
 * the last increment may pass it); then max_increments. Returns p->end (PS_PATH_CONTINUE to go
 * on) and sets p->stop_reason. */
int ps_path_test(ps_path *p);

void ps_path_free(ps_path *p);

/* Append the path's state to l for a checkpoint (ps_state_list,
 * ps_util.h; names "path." + field): the counts, the peak, the largest
 * load factor, the last increment, the recent boundary stresses and the
 * step controller's state; not how the path ended (a restored path tests
 * its stop rules again). Valid while p lives; the same list of a path
 * initialised for the same case receives them back. Returns PS_OK or
 * ps_state_add's status. */
int ps_path_state_list(ps_path *p, ps_state_list *l, ps_ctx *ctx);

/* Breaking rounds (Eq. 118) at the load of the last commit, until no arm
 * breaks: each breaks the arms past delta and re-equilibrates; when the
 * re-equilibration fails the round is retried from the last converged
 * state with the worst half of the arms, down to one. Stops early once
 * the crack has run (load below stop_load_drop of the peak, tip past
 * stop_crack_tip or advanced stop_tip_advance) or on interruption. its0 =
 * Newton iterations before the increment (for the progress note).
 * *n_broken = arms broken, *settle = the last round's status (PS_OK or
 * PS_DIVERGED), *settled = 1 when no arm is left past delta. Returns PS_OK
 * or a fatal status. In a controller's load phase (ps_path_load_phase_arms
 * > 0) a round that breaks arms and fails, breaks more than that many in
 * all, or meets the stop rules ends the rounds with p->unstable = 1: the
 * crack runs at this load. */
int ps_path_break_rounds(ps_path *p, ps_int its0, ps_int *n_broken, int *settle,
                         int *settled, ps_ctx *ctx);

/* The arms whose breaking at one load ends the controller's load phase
 * (ps_step_control_type load_phase_arms), 0 when it is not in one. */
ps_int ps_path_load_phase_arms(const ps_path *p);

/* Boundary stress (Pa) and crack tip (c; 0 without a crack) of the
 * solver's current state. */
double ps_path_boundary_stress(const ps_path *p);
double ps_path_crack_tip(const ps_path *p);

/* A re-equilibration that failed after arms broke counts as the crack
 * running only when arms broke and the failed attempt's boundary stress
 * fell below the peak of the settled states. */
int ps_path_failed_attempt_is_fracture(ps_int broken_total, double sig, double peak);

/* End the path (p->end, p->stop_reason, p->message) after a Newton stall
 * below min_step at load factor target, or after the final
 * re-equilibration failed with boundary stress sig (fractured when
 * ps_path_failed_attempt_is_fracture, else stalled). Used by
 * ps_path_iterate (stall.c). */
void ps_path_newton_stalled(ps_path *p, double target);
void ps_path_reequilibration_failed(ps_path *p, double sig);

#endif
