/* linesearch.h: backtracking line search on a one-dimensional merit
 * function phi(alpha), alpha >= 0 (Newton: phi(alpha) = E(u + alpha du),
 * the energy along the Newton direction du, and phi'(alpha) = f(u +
 * alpha du) . du). It needs nothing from the solver: the caller passes
 * phi(0), phi'(0) and a callback that evaluates phi at a trial step.
 *
 * The rule. From alpha = 1, at most opts.max_tries trials:
 *   - the trial is finite when the callback returns PS_OK and a finite
 *     phi(alpha); PS_ERR_SOLVER counts as not finite, any other negative
 *     status is returned as it is;
 *   - with opts.backtrack = 0 the first finite trial is accepted;
 *   - dphi = phi(alpha) - phi(0); where |dphi| <= opts.resolution |phi(0)|
 *     it is below the round-off of phi (a sum over all arms) and the
 *     trapezoid rule on the slopes stands in:
 *       dphi = alpha/2 (phi'(0) + phi'(alpha)),
 *     exact for a quadratic phi and free of cancellation;
 *   - accepted when finite and dphi <= opts.armijo alpha phi'(0) (Armijo);
 *   - otherwise the next trial is the minimiser of the quadratic through
 *     phi(0), phi'(0) and dphi,
 *       alpha' = -phi'(0) alpha^2 / (2 (dphi - phi'(0) alpha))
 *     (where the denominator is positive, else opts.cut_max alpha), kept
 *     in [opts.cut_min alpha, opts.cut_max alpha]; after a trial that is
 *     not finite, alpha' = opts.cut_max alpha.
 * Each rejected trial counts as one cut. The rule does not test that
 * phi'(0) < 0: along a direction that is not a descent one Armijo's test
 * fails at every step length (above the resolution) and the search ends
 * without a step. */
#ifndef PS_LINESEARCH_H
#define PS_LINESEARCH_H

#include "../util/ps_util.h"

/* Relative round-off of the stored energy below which a step is judged by
 * the slopes (the default of ps_linesearch_opts.resolution). */
#define PS_ENERGY_RESOLUTION 1e-10

/* The merit function. value: *phi = phi(alpha); returns PS_OK,
 * PS_ERR_SOLVER (phi is not defined at alpha: a trial that is not finite)
 * or another negative status (fatal: the search returns it). slope:
 * phi'(alpha) at the alpha of the last call of value, which returned
 * PS_OK; called only then. data: the caller's, passed to both. */
typedef struct ps_merit {
  int (*value)(void *data, double alpha, double *phi, ps_ctx *ctx);
  double (*slope)(void *data);
  void *data;
} ps_merit;

typedef struct ps_linesearch_opts {
  int backtrack;      /* 1: the rule above; 0: the first finite trial */
  int max_tries;      /* trials per search (default 16) */
  double armijo;      /* sufficient-decrease constant c1 (default 1e-4) */
  double resolution;  /* default PS_ENERGY_RESOLUTION */
  double cut_min, cut_max; /* bounds of a cut alpha'/alpha (0.1, 0.5) */
} ps_linesearch_opts;

/* How a search ended. */
enum ps_linesearch_reason {
  PS_LINESEARCH_ACCEPTED = 0, /* step and value hold the accepted trial */
  PS_LINESEARCH_NO_STEP = 1   /* max_tries trials, none acceptable */
};

typedef struct ps_linesearch {
  ps_linesearch_opts opts;
  int reason;     /* enum ps_linesearch_reason of the last search */
  double step;    /* the accepted alpha (else the last one tried) */
  double value;   /* phi(step) when accepted */
  int cuts;       /* rejected trials of the last search */
} ps_linesearch;

/* backtrack 1, 16 tries, Armijo 1e-4, resolution PS_ENERGY_RESOLUTION,
 * cuts in [0.1, 0.5]. */
void ps_linesearch_opts_default(ps_linesearch_opts *o);

/* Set up a search object with the options (copied). */
void ps_linesearch_init(ps_linesearch *ls, const ps_linesearch_opts *o);

/* Search along alpha from phi(0) = phi0 with slope phi'(0) = dphi0.
 * Returns PS_OK (ls->reason says whether a step was accepted, ls->cuts
 * how many trials were rejected) or a fatal status of phi->value. */
int ps_linesearch_search(ps_linesearch *ls, const ps_merit *phi, double phi0,
                         double dphi0, ps_ctx *ctx);

/* "accepted" or "no acceptable step"; "unknown reason" for other values. */
const char *ps_linesearch_reason_text(int reason);

#endif
