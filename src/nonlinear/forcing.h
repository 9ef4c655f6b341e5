/* forcing.h: the forcing rule of inexact Newton, the relative tolerance
 * eta_k to which CG solves the Newton system K du = -r at iteration k
 * (rel_k = |r_k| / |reactions|, the relative Newton residual):
 *
 *   adaptive (Eisenstat and Walker's choice 2, SIAM J. Sci. Comput. 17,
 *   1996): eta_0 = eta_max;
 *     e_k = gamma (rel_k / rel_k-1)^alpha, raised to gamma eta_k-1^alpha
 *     when that safeguard exceeds PS_EW_SAFEGUARD, then capped at eta_max;
 *     eta_k = e_k and the tolerance is max(rtol_min, eta_k);
 *   fixed: max(rtol_min, min(PS_CG_FORCING_MAX, c rel_k)); with c = 0
 *     always rtol_min (exact Newton), and no floor below.
 *
 * Both rules (but c = 0) then apply Kelley's floor against oversolving:
 * a full Newton step leaves the linear residual t rel_k (plus a quadratic
 * term), so t = PS_CG_OVERSOLVE tolerance / rel_k already reaches the
 * Newton tolerance; the CG tolerance is never below it. */
#ifndef PS_FORCING_H
#define PS_FORCING_H

/* the cap of the fixed rule */
#define PS_CG_FORCING_MAX 1e-2

/* Eisenstat-Walker choice 2: gamma, alpha and the safeguard's threshold */
#define PS_EW_GAMMA 0.9
#define PS_EW_ALPHA 2.0
#define PS_EW_SAFEGUARD 0.1

/* the default c of the fixed rule, also the rule an adaptive solve hands
 * over to at max_iterations (ps_newton_solve) */
#define PS_CG_FORCING_FIXED 100.0

/* the share of the Newton tolerance left to the linear residual of the
 * last CG solve (the floor above) */
#define PS_CG_OVERSOLVE 0.1

typedef struct ps_forcing {
  int adaptive;      /* 1: Eisenstat-Walker choice 2; 0: the fixed rule */
  double eta_max;    /* adaptive: the loosest tolerance and eta_0 */
  double c;          /* fixed: the factor c of c rel_k (0: exact Newton) */
  double rtol_min;   /* the tightest CG tolerance either rule asks for */
  double tolerance;  /* the Newton tolerance on rel (the floor) */
  int k;             /* calls of ps_forcing_next since init */
  double eta;        /* adaptive: the last eta_k */
  double rel_prev;   /* the last rel_k */
} ps_forcing;

/* Start a Newton solve's rule (k = 0, no history). */
void ps_forcing_init(ps_forcing *F, int adaptive, double eta_max, double c,
                     double rtol_min, double tolerance);

/* The CG tolerance of the next Newton iteration at the relative residual
 * rel > 0, by the rule in force; records rel (and eta_k) as history. */
double ps_forcing_next(ps_forcing *F, double rel);

/* From here on the fixed rule (the history is kept). */
void ps_forcing_handover(ps_forcing *F);

#endif
