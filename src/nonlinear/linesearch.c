/* linesearch.c: the backtracking line search of linesearch.h (Armijo's
 * test, quadratic interpolation of the cut, the slopes' trapezoid where
 * the merit function's change is below its round-off). */
#include "linesearch.h"

#include <math.h>

void ps_linesearch_opts_default(ps_linesearch_opts *o) {
  o->backtrack = 1;
  o->max_tries = 16;
  o->armijo = 1e-4;
  o->resolution = PS_ENERGY_RESOLUTION;
  o->cut_min = 0.1;
  o->cut_max = 0.5;
}

void ps_linesearch_init(ps_linesearch *ls, const ps_linesearch_opts *o) {
  ls->opts = *o;
  ls->reason = PS_LINESEARCH_NO_STEP;
  ls->step = 0.0;
  ls->value = 0.0;
  ls->cuts = 0;
}

/* The next trial after rejecting alpha: the minimiser of the quadratic q
 * with q(0) = 0, q'(0) = dphi0, q(alpha) = dphi, kept in [cut_min alpha,
 * cut_max alpha]; cut_max alpha after a trial that is not finite. */
static double cut(const ps_linesearch_opts *o, int finite, double alpha, double dphi,
                  double dphi0) {
  double next = o->cut_max * alpha;
  if (finite) {
    double denom = 2.0 * (dphi - dphi0 * alpha);
    if (denom > 0) next = -dphi0 * alpha * alpha / denom;
    if (next < o->cut_min * alpha) next = o->cut_min * alpha;
    if (next > o->cut_max * alpha) next = o->cut_max * alpha;
  }
  return next;
}

int ps_linesearch_search(ps_linesearch *ls, const ps_merit *phi, double phi0,
                         double dphi0, ps_ctx *ctx) {
  const ps_linesearch_opts *o = &ls->opts;
  double alpha = 1.0;
  ls->reason = PS_LINESEARCH_NO_STEP;
  ls->cuts = 0;
  for (int i = 0; i < o->max_tries; i++) {
    double value = phi0;
    int status = phi->value(phi->data, alpha, &value, ctx);
    if (status < 0 && status != PS_ERR_SOLVER) return status;
    int finite = status == PS_OK && isfinite(value);
    ls->step = alpha;
    if (finite && !o->backtrack) {
      ls->value = value;
      ls->reason = PS_LINESEARCH_ACCEPTED;
      return PS_OK;
    }
    double dphi = value - phi0;
    if (finite && fabs(dphi) <= o->resolution * fabs(phi0))
      dphi = 0.5 * alpha * (dphi0 + phi->slope(phi->data)); /* trapezoid */
    if (finite && dphi <= o->armijo * alpha * dphi0) { /* Armijo */
      ls->value = value;
      ls->reason = PS_LINESEARCH_ACCEPTED;
      return PS_OK;
    }
    alpha = cut(o, finite, alpha, dphi, dphi0);
    ls->cuts++;
  }
  return PS_OK;
}

const char *ps_linesearch_reason_text(int reason) {
  switch (reason) {
  case PS_LINESEARCH_ACCEPTED: return "accepted";
  case PS_LINESEARCH_NO_STEP: return "no acceptable step";
  }
  return "unknown reason";
}
