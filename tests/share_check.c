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
 *    past the criterion exactly;
 *  - all of that again after both commit that state and evaluate at 1.5
 *    times the displacements: the ghosts' committed plastic strains are their
 *    owners' (the deviatoric yield rule's half-arms read their family's
 *    mean strain: t990 runs it with that rule too).
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

/* the yielding arms, the arms past the criterion and the plastic
 * dissipation of e's last evaluation, summed over the ranks */
static void counts(evaluation *e) {
  e->yielding = ps_pd_count_yielding(e->pd);
  e->past = ps_comm_count(e->pd->comm, ps_model_count_past(&e->pd->model, &e->pd->st));
  e->dissipation = ps_pd_dissipation(e->pd, NULL);
}

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
  counts(e);
  return 0;
}

/* 1 when the share's evaluation `mine` is the whole model's at its owned
 * dofs (1e-12 of the largest force), and its energy, dissipation and
 * counts summed over the ranks are the whole's; a line about it */
static int compare(const evaluation *mine, const evaluation *whole, const ps_share *sh,
                   const ps_particles *P, const ps_comm *comm, const char *which, int h) {
  const int d = P->dim;
  double df = 0, fmax_ = 0;
  for (ps_int j = 0; j < P->n * d; j++) fmax_ = fmax(fmax_, fabs(whole->f[j]));
  for (ps_int a = 0; a < sh->n_owned; a++)
    for (int k = 0; k < d; k++)
      df = fmax(df, fabs(mine->f[a * d + k] - whole->f[sh->global[a] * d + k]));
  ps_comm_max(comm, &df, 1);
  double dE = fabs(mine->energy - whole->energy) / fabs(whole->energy);
  double dD = whole->dissipation != 0
                  ? fabs(mine->dissipation - whole->dissipation) / fabs(whole->dissipation)
                  : fabs(mine->dissipation);
  int ok = df <= 1e-12 * fmax_ && dE <= 1e-12 && dD <= 1e-12 &&
           mine->yielding == whole->yielding && mine->past == whole->past;
  printf("share_check: rank %d of %d: %s evaluation %s (%lld owned, %lld ghosts out to %d "
         "horizons; forces %.1e of the largest; energy %.1e, dissipation %.1e; yielding "
         "%lld of %lld, past %lld of %lld)\n",
         comm->rank, comm->size, which, ok ? "ok" : "FAILED", (long long)sh->n_owned,
         (long long)(sh->P.n - sh->n_owned), h, df / fmax_, dE, dD, (long long)mine->yielding,
         (long long)whole->yielding, (long long)mine->past, (long long)whole->past);
  return ok;
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
  bad_ghosts = ps_comm_count(&comm, bad_ghosts);
  if (bad_ghosts)
    printf("share_check: rank %d of %d: %lld ghost values are not their owners'\n", rank,
           P_ranks, (long long)bad_ghosts);
  int ok = bad_ghosts == 0 && compare(&mine, &whole, &sh, P, &comm, "first", h);
  /* the second evaluation from the state the first committed (the
   * ghosts' plastic strains, the deviatoric reading's half-arms, as the
   * owners'): the displacements 1.5 times, the yielding arms flowing on
   * from their committed plastic strains */
  for (ps_int j = 0; j < P->n * d; j++) u[j] *= 1.5;
  for (ps_int j = 0; j < nl * d; j++) ul[j] *= 1.5;
  ps_pd_commit(whole.pd);
  ps_pd_commit(mine.pd);
  ps_nl_problem pw = ps_pd_problem(whole.pd), pm = ps_pd_problem(mine.pd);
  if (pw.ops->evaluate(whole.pd, u, whole.f, &whole.energy, 1, &ctx) ||
      pm.ops->evaluate(mine.pd, ul, mine.f, &mine.energy, 1, &ctx))
    return fail(rank, "the evaluation after the commit", &ctx);
  counts(&whole);
  counts(&mine);
  ok = compare(&mine, &whole, &sh, P, &comm, "after the commit", h) && ok;
  if (ok) printf("share_check: rank %d of %d: ok (both evaluations)\n", rank, P_ranks);
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
