/* umfpack.c: UMFPACK backend (LU with partial pivoting, 64-bit indices) for
 * tangents that are indefinite. The symmetric upper-triangle input is
 * expanded once to a full pattern with a map back to the upper entries, so
 * each factorisation is a gather plus umfpack_dl_numeric; the symbolic
 * analysis runs once per pattern. */
#include "ps_linsolve.h"

#include <stdlib.h>
#include <umfpack.h>

typedef struct {
  ps_int n;
  ps_int *Ap, *Ai, *map; /* full pattern; map: full entry -> upper entry */
  double *Ax;
  void *symbolic, *numeric;
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
} umf_state;

static int umf_create(void **state, const struct ps_linsolve *ls, ps_ctx *ctx) {
  (void)ls;
  umf_state *s = ps_calloc(1, sizeof *s, ctx);
  if (!s) return PS_ERR_NOMEM;
  umfpack_dl_defaults(s->control);
  s->control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;
  *state = s;
  return PS_OK;
}

static void umf_free_arrays(umf_state *s) {
  free(s->Ap);
  free(s->Ai);
  free(s->map);
  free(s->Ax);
  s->Ap = s->Ai = s->map = NULL;
  s->Ax = NULL;
  if (s->numeric) umfpack_dl_free_numeric(&s->numeric);
  if (s->symbolic) umfpack_dl_free_symbolic(&s->symbolic);
}

/* The status for a failed UMFPACK call `what` that returned rc:
 * PS_ERR_NOMEM when it ran out of memory, PS_ERR_SOLVER otherwise. */
static int umf_failed(int rc, const char *what, ps_ctx *ctx) {
  if (rc == UMFPACK_ERROR_out_of_memory)
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory in UMFPACK's %s (status %d)", what, rc);
  return ps_error(ctx, PS_ERR_SOLVER, "UMFPACK %s failed (status %d)", what, rc);
}

static int umf_analyze(void *state, const ps_csc *A, ps_linsolve_stats *st,
                       ps_ctx *ctx) {
  umf_state *s = state;
  double t = ps_wtime();
  umf_free_arrays(s);
  ps_int n = A->n;
  s->n = n;
  PS_CHECK(ps_csc_expand(A, 0, n, &s->Ap, &s->Ai, &s->map, ctx));
  ps_int nf = s->Ap[n];
  if (!(s->Ax = ps_calloc((size_t)nf + 1, sizeof *s->Ax, ctx))) return PS_ERR_NOMEM;
  for (ps_int k = 0; k < nf; k++) s->Ax[k] = 1.0;
  int rc = umfpack_dl_symbolic(n, n, s->Ap, s->Ai, s->Ax, &s->symbolic,
                               s->control, s->info);
  if (rc != UMFPACK_OK)
    return umf_failed(rc, "symbolic analysis", ctx);
  st->t_analyze += ps_wtime() - t;
  st->n_analyze++;
  return PS_OK;
}

static int umf_factor(void *state, const ps_csc *A, ps_int *bad_col,
                      ps_linsolve_stats *st, ps_ctx *ctx) {
  umf_state *s = state;
  double t = ps_wtime();
  *bad_col = -1;
  for (ps_int k = 0; k < s->Ap[s->n]; k++) s->Ax[k] = A->x[s->map[k]];
  if (s->numeric) umfpack_dl_free_numeric(&s->numeric);
  int rc = umfpack_dl_numeric(s->Ap, s->Ai, s->Ax, s->symbolic, &s->numeric,
                              s->control, s->info);
  st->t_factor += ps_wtime() - t;
  st->n_factor++;
  st->flops_factor = s->info[UMFPACK_FLOPS];
  st->nnz_factor = s->info[UMFPACK_LNZ] + s->info[UMFPACK_UNZ];
  if (rc == UMFPACK_WARNING_singular_matrix) return PS_SINGULAR;
  if (rc != UMFPACK_OK)
    return umf_failed(rc, "factorisation", ctx);
  /* reciprocal condition estimate: treat as singular below round-off */
  if (s->info[UMFPACK_RCOND] < 1e-15) return PS_SINGULAR;
  return PS_OK;
}

static int umf_solve(void *state, const double *b, double *x,
                     ps_linsolve_stats *st, ps_ctx *ctx) {
  umf_state *s = state;
  double t = ps_wtime();
  int rc = umfpack_dl_solve(UMFPACK_A, s->Ap, s->Ai, s->Ax, x, b, s->numeric,
                            s->control, s->info);
  if (rc != UMFPACK_OK)
    return umf_failed(rc, "solve", ctx);
  st->t_solve += ps_wtime() - t;
  st->n_solve++;
  return PS_OK;
}

static void umf_destroy(void **state) {
  umf_state *s = *state;
  if (!s) return;
  umf_free_arrays(s);
  free(s);
  *state = NULL;
}

static const ps_linsolve_type umf_type = {"umfpack", umf_create, umf_analyze,
                                          umf_factor, umf_solve, NULL, umf_destroy, 0};
const ps_linsolve_type *const ps_linsolve_umfpack = &umf_type;
