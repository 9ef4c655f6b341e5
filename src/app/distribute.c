/* distribute.c: the distributed layout of `mpiexec -n P peristatic run`
 * (doc/design-distributed.md): which cases it takes today, and each
 * process's part of a problem: its share of the particles and arms
 * (ghosts out to the model's reach), the rows of the whole system its
 * own dofs give PETSc, and its boundary conditions and named groups. */
#include "ps_app.h"

#include <stdlib.h>
#include <string.h>

int ps_problem_distributable(const ps_problem *pb, int ranks, char *why, size_t len) {
  const ps_case *cs = &pb->cs;
  const ps_model_type *type = ps_model_type_find(cs->model);
  const char *no = NULL;
  if (strcmp(cs->solver.linear, "petsc") != 0)
    no = "solver.linear is not petsc";
  else if (!type)
    no = "its model is unknown";
  else if (pb->P.n < ranks)
    no = "it has fewer particles than processes";
  if (why) snprintf(why, len, "%s", no ? no : "");
  return no == NULL;
}

void ps_problem_part_free(ps_problem_part *pa) {
  if (!pa) return;
  free(pa->local.fixed);
  free(pa->local.ubar);
  free(pa->local.measure);
  free(pa->local.fext);
  free(pa->local.group_ptr);
  free(pa->local.group_particle);
  free(pa->rows);
  free(pa->owner);
  free(pa->given_k);
  free(pa->given_side);
  ps_share_free(&pa->sh);
  ps_partition_free(&pa->pt);
  memset(pa, 0, sizeof *pa);
}

/* the share's boundary conditions and named groups into pa->local */
static int local_loading(ps_problem_part *pa, const ps_problem *pb, ps_ctx *ctx) {
  ps_problem *lp = &pa->local;
  const ps_share *sh = &pa->sh;
  const int d = pb->P.dim;
  const ps_int nl = sh->P.n;
  lp->fixed = ps_calloc((size_t)(nl * d) + 1, 1, ctx);
  lp->ubar = ps_calloc((size_t)(nl * d) + 1, sizeof *lp->ubar, ctx);
  lp->measure = ps_calloc((size_t)(nl * d) + 1, sizeof *lp->measure, ctx);
  lp->fext = pb->fext ? ps_calloc((size_t)(nl * d) + 1, sizeof *lp->fext, ctx) : NULL;
  lp->group_ptr = ps_calloc((size_t)pb->n_groups + 1, sizeof *lp->group_ptr, ctx);
  if (!lp->fixed || !lp->ubar || !lp->measure || (pb->fext && !lp->fext) || !lp->group_ptr)
    return PS_ERR_NOMEM;
  for (ps_int a = 0; a < nl; a++)
    for (int k = 0; k < d; k++) {
      ps_int g = sh->global[a] * d + k, j = a * d + k;
      lp->fixed[j] = pb->fixed[g];
      lp->ubar[j] = pb->ubar[g];
      lp->measure[j] = pb->measure[g];
      /* the loads of own particles only: each is applied once */
      if (lp->fext) lp->fext[j] = a < sh->n_owned ? pb->fext[g] : 0.0;
    }
  /* the named groups' own particles (their reactions are summed over the
   * processes); the local numbers of the owned particles by global number */
  ps_int n_own = 0;
  for (int g = 0; g < pb->n_groups; g++)
    for (ps_int i = pb->group_ptr[g]; i < pb->group_ptr[g + 1]; i++)
      n_own += pa->pt.part_of[pb->group_particle[i]] == sh->part;
  lp->group_particle = ps_calloc((size_t)n_own + 1, sizeof *lp->group_particle, ctx);
  ps_int *local_of = ps_calloc((size_t)pb->P.n + 1, sizeof *local_of, ctx);
  if (!lp->group_particle || !local_of) {
    free(local_of);
    return PS_ERR_NOMEM;
  }
  for (ps_int a = 0; a < sh->n_owned; a++) local_of[sh->global[a]] = a;
  ps_int k = 0;
  for (int g = 0; g < pb->n_groups; g++) {
    lp->group_ptr[g] = k;
    for (ps_int i = pb->group_ptr[g]; i < pb->group_ptr[g + 1]; i++) {
      ps_int a = pb->group_particle[i];
      if (pa->pt.part_of[a] == sh->part) lp->group_particle[k++] = local_of[a];
    }
  }
  lp->group_ptr[pb->n_groups] = k;
  free(local_of);
  return PS_OK;
}

/* The whole model's constants for the share's arms where they read the
 * whole cloud (ps_model_whole_constants: the fibre and state moduli
 * correction) into pa->given: the whole network and model built here,
 * on every process alike, and freed once the share's constants are
 * taken from them. */
static int whole_constants(ps_problem_part *pa, const ps_problem *pb, ps_ctx *ctx) {
  const ps_model_type *type = ps_model_type_find(pb->cs.model);
  if (!type || !ps_model_whole_constants(type, &pb->mat)) return PS_OK;
  ps_network net;
  ps_model whole;
  memset(&net, 0, sizeof net);
  memset(&whole, 0, sizeof whole);
  int status = ps_network_build(&net, &pb->P, &pb->kernel, pb->cracks, pb->n_cracks, ctx);
  if (status == PS_OK) status = ps_model_create(&whole, type, &pb->P, &net, &pb->mat, ctx);
  if (status == PS_OK)
    status = ps_model_share_constants(&whole, &pa->sh.net, pa->sh.global, &pa->given_k,
                                      &pa->given_side, ctx);
  ps_model_free(&whole);
  ps_network_free(&net);
  pa->given = (ps_model_given){pa->given_k, pa->given_side};
  return status;
}

int ps_problem_part_create(ps_problem_part *pa, const ps_problem *pb, const ps_comm *comm,
                           ps_ctx *ctx) {
  int status = PS_OK;
  memset(pa, 0, sizeof *pa);
  const int d = pb->P.dim;
  status = ps_partition_curve(&pa->pt, &pb->P, comm->size, ctx);
  if (status == PS_OK) status = ps_problem_share(pb, &pa->pt, comm->rank, &pa->sh, ctx);
  if (status == PS_OK)
    status = ps_share_global_rows(&pa->sh, &pa->pt, d, &pa->rows, &pa->row0, ctx);
  if (status == PS_OK) status = local_loading(pa, pb, ctx);
  if (status == PS_OK) status = whole_constants(pa, pb, ctx);
  if (status == PS_OK && !(pa->owner = ps_calloc((size_t)pa->sh.P.n + 1, sizeof *pa->owner, ctx)))
    status = PS_ERR_NOMEM;
  for (ps_int a = 0; status == PS_OK && a < pa->sh.P.n; a++)
    pa->owner[a] = pa->pt.part_of[pa->sh.global[a]];
  /* every process stops alike (the others would wait in a collective) */
  if (ps_comm_any(comm, status < 0) && status >= 0)
    status = ps_error(ctx, PS_ERR_INPUT, "another process could not build its share");
  if (status < 0) {
    ps_problem_part_free(pa);
    return status;
  }
  /* the share as a problem: pb's case, material and measures, the
   * share's particles and network (borrowed), its own loading */
  ps_problem *lp = &pa->local;
  lp->cs = pb->cs; /* borrowed: never ps_problem_free'd */
  lp->P = pa->sh.P;
  lp->kernel = pb->kernel;
  lp->net = pa->sh.net;
  lp->mat = pb->mat;
  lp->c = pb->c;
  lp->measure_length = pb->measure_length;
  lp->n_groups = pb->n_groups;
  lp->group_bc = pb->group_bc;
  lp->threads = pb->threads;
  lp->t_network = pb->t_network;
  lp->checkpoint = pb->checkpoint; /* each process its share's checkpoint */
  lp->restart = pb->restart;
  pa->solver_share = (ps_solver_share){.own_arm = pa->sh.own_arm,
                                       .own_particle = pa->sh.own_particle,
                                       .global_row = pa->rows,
                                       .n_global = pb->P.n * d,
                                       .row0 = pa->row0,
                                       .n_rows = pa->sh.n_owned * d,
                                       .global = pa->sh.global,
                                       .owner = pa->owner,
                                       .given = pa->given_side || pa->given_k ? &pa->given
                                                                              : NULL};
  pa->piece = (ps_report_piece){comm, pa->sh.n_owned, pa->sh.global, pa->sh.own_arm};
  ps_int own = 0;
  for (ps_int i = 0; i < pa->sh.net.n_arm; i++) own += pa->sh.own_arm[i];
  pa->arms = ps_comm_count(comm, own);
  return PS_OK;
}
