/* linsolve.c: the generic solver object over a backend table. */
#include "ps_linsolve.h"

#include <string.h>

const ps_linsolve_type *ps_linsolve_type_find(const char *name) {
  const ps_linsolve_type *const all[] = {ps_linsolve_cholmod, ps_linsolve_umfpack};
  for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
    if (strcmp(all[i]->name, name) == 0) return all[i];
  return NULL;
}

int ps_linsolve_create(ps_linsolve *ls, const ps_linsolve_type *type,
                       ps_ctx *ctx) {
  memset(ls, 0, sizeof *ls);
  ls->type = type;
  return type->create(&ls->state, ctx);
}

void ps_linsolve_destroy(ps_linsolve *ls) {
  if (ls->type && ls->state) ls->type->destroy(&ls->state);
  memset(ls, 0, sizeof *ls);
}

int ps_linsolve_factor(ps_linsolve *ls, const ps_csc *A, ps_int *bad_col,
                       ps_ctx *ctx) {
  if (!ls->analysed) {
    PS_CHECK(ls->type->analyze(ls->state, A, &ls->stats, ctx));
    ls->analysed = 1;
  }
  return ls->type->factor(ls->state, A, bad_col, &ls->stats, ctx);
}

int ps_linsolve_solve(ps_linsolve *ls, const double *b, double *x,
                      ps_ctx *ctx) {
  return ls->type->solve(ls->state, b, x, &ls->stats, ctx);
}
