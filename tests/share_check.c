/* share_check.c: a distributed model's evaluation on MPI ranks (step 3
 * of doc/design-distributed.md), run by t990_petsc.sh as `mpiexec -n P
 * tests/share_check CASE` (P = 1, 2, 3). Every rank sets up the whole
 * case (as today) and evaluates the whole model once for reference; then
 * it builds its own share (ps_share of part `rank` of ps_partition_curve,
 * ghosts out to ps_model_share_horizons), fills its ghosts' displacements
 * from their owners through the halo (ps_halo over ps_parallel_comm) and
 * evaluates the share with the run's comm in its context, so that the
 * energy, the dissipation and the counts are summed over the ranks by
 * the solver's own reductions. Checked on every rank:
 *  - the halo brings every ghost exactly its owner's values;
 *  - the forces at owned dofs equal the whole model's (1e-12 of the
 *    largest: the same terms in another order);
 *  - the energy and the plastic dissipation summed over the ranks equal
 *    the whole model's (1e-12 relative), the yielding arms and the arms
 *    past the criterion exactly.
 * The displacements: a strain of 0.004 along x with a shear and noise
 * (past yield in the fibre model, past a critical stretch of 1e-3). */
#include "common.h"
#include "linsolve/ps_linsolve.h"
#include "nonlinear/problem_pd.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int fail(int rank, const char *what, const ps_ctx *ctx) {
  printf("share_check: rank %d: %s failed: %s\n", rank, what, ctx ? ctx->msg : "");
  return 1;
}

/* forces, energy, counts of the model `type` on (P, net) at u */
typedef struct evaluation {
  ps_pd *pd;
  double *f, energy, dissipation;
  ps_int yielding, past;
} evaluation;

static int evaluate(evaluation *e, const ps_particles *P, const ps_network *net,
                    const ps_model_type *type, const ps_material *mat,
                    const unsigned char *own_arm, const unsigned char *own_particle,
                    const double *u, ps_ctx *ctx) {
  ps_int nd = P->n * P->dim;
  unsigned char *fixed = calloc((size_t)nd, 1);
  e->f = calloc((size_t)nd, sizeof *e->f);
  if (!fixed || !e->f || ps_pd_create(&e->pd, P, net, type, mat, fixed, 0, 0, ctx)) return 1;
  free(fixed);
  e->pd->model.own_arm = own_arm;
  e->pd->model.own_particle = own_particle;
  ps_nl_problem pr = ps_pd_problem(e->pd);
  if (pr.ops->evaluate(e->pd, u, e->f, &e->energy, 1, ctx)) return 1;
  e->yielding = ps_pd_count_yielding(e->pd);
  e->past = ps_comm_count(ctx->comm, ps_model_count_past(&e->pd->model, &e->pd->st));
  e->dissipation = ps_pd_dissipation(e->pd, NULL);
  return 0;
}

int main(int argc, char **argv) {
  ps_ctx ctx;
  ps_comm comm;
  ps_case cs;
  ps_problem pb;
  ps_partition pt;
  ps_share sh;
  tc_mpi_share(argc, argv, "share_check", &comm, &cs, &pb, &pt, &sh, &ctx);
  const int rank = comm.rank, P_ranks = comm.size;
  const ps_particles *P = &pb.P;
  const int d = P->dim;
  const ps_model_type *type = ps_model_type_find(pb.cs.model);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 990);
  double *u = malloc((size_t)(P->n * d) * sizeof *u), strain = 0.004;
  for (ps_int a = 0; a < P->n; a++) {
    const double *X = &P->x[a * d];
    for (int k = 0; k < d; k++)
      u[a * d + k] = (k == 0 ? strain * X[0] + 0.3 * strain * X[1] : -0.2 * strain * X[k]) +
                     0.1 * strain * P->h[a] * (2 * gsl_rng_uniform(rng) - 1);
  }
  evaluation whole = {0}, mine = {0};
  if (evaluate(&whole, P, &pb.net, type, &pb.mat, NULL, NULL, u, &ctx))
    return fail(rank, "the whole model's evaluation", &ctx);

  const int h = ps_model_share_horizons(type, &pb.mat);
  ps_int nl = sh.P.n, ng = nl - sh.n_owned;
  int *owner = malloc(((size_t)ng + 1) * sizeof *owner);
  double *ul = malloc((size_t)(nl * d) * sizeof *ul);
  for (ps_int k = 0; k < ng; k++) owner[k] = pt.part_of[sh.global[sh.n_owned + k]];
  for (ps_int a = 0; a < nl; a++)
    for (int k = 0; k < d; k++) ul[a * d + k] = a < sh.n_owned ? u[sh.global[a] * d + k] : NAN;
  ps_halo halo;
  ctx.comm = &comm;
  if (ps_halo_create(&halo, &comm, nl, sh.n_owned, sh.global, owner, &ctx) ||
      ps_halo_exchange(&halo, &comm, ul, d, &ctx))
    return fail(rank, "the halo", &ctx);
  ps_int bad_ghosts = 0;
  for (ps_int a = sh.n_owned; a < nl; a++)
    for (int k = 0; k < d; k++) bad_ghosts += ul[a * d + k] != u[sh.global[a] * d + k];
  if (evaluate(&mine, &sh.P, &sh.net, type, &pb.mat, sh.own_arm, sh.own_particle, ul, &ctx))
    return fail(rank, "the share's evaluation", &ctx);
  double df = 0, fmax_ = 0;
  for (ps_int j = 0; j < P->n * d; j++) fmax_ = fmax(fmax_, fabs(whole.f[j]));
  for (ps_int a = 0; a < sh.n_owned; a++)
    for (int k = 0; k < d; k++)
      df = fmax(df, fabs(mine.f[a * d + k] - whole.f[sh.global[a] * d + k]));
  ps_comm_max(&comm, &df, 1);
  bad_ghosts = ps_comm_count(&comm, bad_ghosts);
  double dE = fabs(mine.energy - whole.energy) / fabs(whole.energy);
  double dD = whole.dissipation != 0
                  ? fabs(mine.dissipation - whole.dissipation) / fabs(whole.dissipation)
                  : fabs(mine.dissipation);
  int ok = bad_ghosts == 0 && df <= 1e-12 * fmax_ && dE <= 1e-12 && dD <= 1e-12 &&
           mine.yielding == whole.yielding && mine.past == whole.past;
  printf("share_check: rank %d of %d: %s (%lld owned, %lld ghosts out to %d horizons; ghosts "
         "wrong %lld; forces %.1e of the largest; energy %.1e, dissipation %.1e; yielding "
         "%lld of %lld, past %lld of %lld)\n",
         rank, P_ranks, ok ? "ok" : "FAILED", (long long)sh.n_owned, (long long)ng, h,
         (long long)bad_ghosts, df / fmax_, dE, dD, (long long)mine.yielding,
         (long long)whole.yielding, (long long)mine.past, (long long)whole.past);
  ps_halo_free(&halo);
  ps_pd_free(mine.pd);
  ps_pd_free(whole.pd);
  free(mine.f);
  free(whole.f);
  free(owner);
  free(ul);
  free(u);
  gsl_rng_free(rng);
  tc_mpi_share_end(&cs, &pb, &pt, &sh);
  return !ok;
}
