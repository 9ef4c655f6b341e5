/* forcing.c: the CG forcing rule of inexact Newton (forcing.h): fixed,
 * or Eisenstat and Walker's adaptive choice 2, with Kelley's floor. */
#include "forcing.h"

#include <math.h>

void ps_forcing_init(ps_forcing *F, int adaptive, double eta_max, double c,
                     double rtol_min, double tolerance) {
  F->adaptive = adaptive;
  F->eta_max = eta_max;
  F->c = c;
  F->rtol_min = rtol_min;
  F->tolerance = tolerance;
  F->k = 0;
  F->eta = 0.0;
  F->rel_prev = 0.0;
}

void ps_forcing_handover(ps_forcing *F) { F->adaptive = 0; }

/* eta_k of choice 2 from rel_k and the history (eta_max at k = 0) */
static double choice2(const ps_forcing *F, double rel) {
  double e = F->eta_max;
  if (F->k > 0 && F->rel_prev > 0) {
    e = PS_EW_GAMMA * pow(rel / F->rel_prev, PS_EW_ALPHA);
    double guard = PS_EW_GAMMA * pow(F->eta, PS_EW_ALPHA);
    if (guard > PS_EW_SAFEGUARD) e = fmax(e, guard);
    e = fmin(e, F->eta_max);
  }
  return e;
}

double ps_forcing_next(ps_forcing *F, double rel) {
  double t;
  int kelley = 1; /* apply the floor */
  if (F->adaptive) {
    F->eta = choice2(F, rel);
    t = fmax(F->rtol_min, F->eta);
  } else {
    t = fmax(F->rtol_min, fmin(PS_CG_FORCING_MAX, F->c * rel));
    kelley = !(F->c <= 0); /* c = 0: exact Newton, rtol_min as it is */
  }
  F->k++;
  F->rel_prev = rel;
  return kelley ? fmax(t, PS_CG_OVERSOLVE * F->tolerance / rel) : t;
}
