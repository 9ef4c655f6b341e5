/* solve_check.c: Newton on a distributed model (step 3 of
 * doc/design-distributed.md), run by t990_petsc.sh as `mpiexec -n P
 * tests/solve_check CASE` (P = 1, 2, 3). Every rank sets up the whole
 * case and solves it serially with CHOLMOD for reference (two load
 * increments, to load factors 0.6 and 1.1 of the case's loading: the
 * small disk yields in the second); then it builds its own share
 * (ps_share, ghosts out to ps_model_share_horizons), a solver on it
 * (ps_solver_create_share: the share's arms and dofs, the rows of the
 * whole system its owned dofs give PETSc, MUMPS's factor of the whole
 * system for each Newton system, every norm and energy summed over the
 * ranks) and takes the same two increments, both Newton solves to a
 * relative residual of 1e-11. Checked on every rank after each: the
 * owned particles' displacements within 1e-8 of the largest displacement
 * of the serial solution (the bound), the
 * ghosts' displacements as their owners' (the same bound), and the
 * yielding arms over the ranks as the serial count. Then an arc-length
 * and a dissipation-controlled step on both, the load factor and the
 * displacements as the serial ones'. */
#include "common.h"
#include "linsolve/ps_linsolve.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(int rank, const char *what, const ps_ctx *ctx) {
  printf("solve_check: rank %d: %s failed: %s\n", rank, what, ctx ? ctx->msg : "");
  return 1;
}

int main(int argc, char **argv) {
  ps_ctx ctx, dctx;
  ps_comm comm;
  ps_case cs;
  ps_problem pb;
  ps_partition pt;
  ps_share sh;
  tc_mpi_share(argc, argv, "solve_check", &comm, &cs, &pb, &pt, &sh, &ctx);
  const int rank = comm.rank;
  const ps_particles *P = &pb.P;
  const int d = P->dim;
  const ps_model_type *type = ps_model_type_find(pb.cs.model);
  ps_solver_opts o = pb.cs.solver;
  o.threads = 1;
  /* Newton to 1e-11 in both: near the yield kink the tangent is soft,
   * and displacements converged to 1e-8 in the residual differ by 6e-8
   * between two solvers (as between CHOLMOD and PETSc on one rank) */
  o.tolerance = 1e-11;
  snprintf(o.linear, sizeof o.linear, "cholmod");
  ps_solver *whole = NULL;
  if (ps_solver_create(&whole, P, &pb.net, type, &pb.mat, pb.fixed, pb.ubar, &o, &ctx))
    return fail(rank, "the serial solver", &ctx);
  if (pb.fext) ps_solver_set_forces(whole, pb.fext);

  /* the share's solver */
  ps_int *rows = NULL, row0 = 0;
  if (ps_share_global_rows(&sh, &pt, d, &rows, &row0, &ctx)) return fail(rank, "the rows", &ctx);
  ps_int nl = sh.P.n;
  unsigned char *fixed = calloc((size_t)(nl * d) + 1, 1);
  double *ubar = calloc((size_t)(nl * d) + 1, sizeof *ubar);
  double *fext = pb.fext ? calloc((size_t)(nl * d) + 1, sizeof *fext) : NULL;
  for (ps_int a = 0; a < nl; a++)
    for (int k = 0; k < d; k++) {
      ps_int g = sh.global[a] * d + k;
      fixed[a * d + k] = pb.fixed[g];
      ubar[a * d + k] = pb.ubar[g];
      if (fext) fext[a * d + k] = a < sh.n_owned ? pb.fext[g] : 0.0; /* once */
    }
  ps_solver_share share = {sh.own_arm, sh.own_particle, rows, P->n * d, row0, sh.n_owned * d,
                           sh.global};
  ps_solver_opts od = o;
  snprintf(od.linear, sizeof od.linear, "petsc");
  od.reuse_factor = 0;
  od.majorant = 0;
  dctx = ctx;
  dctx.comm = &comm;
  ps_solver *s = NULL, *rep = NULL;
  if (ps_solver_create_share(&s, &sh.P, &sh.net, type, &pb.mat, fixed, ubar, &od, &share, &dctx))
    return fail(rank, "the share's solver", &dctx);
  if (fext) ps_solver_set_forces(s, fext);
  /* and today's way for the timings: the whole model on every rank, the
   * same PETSc solves (SOLVE_CHECK_REPLICATED=1) */
  const int timed_rep = getenv("SOLVE_CHECK_REPLICATED") != NULL;
  if (timed_rep) {
    if (ps_solver_create(&rep, P, &pb.net, type, &pb.mat, pb.fixed, pb.ubar, &od, &ctx))
      return fail(rank, "the replicated solver", &ctx);
    if (pb.fext) ps_solver_set_forces(rep, pb.fext);
  }

  const double lambdas[] = {0.6, 1.1};
  int ok = 1;
  for (int step = 0; step < 2; step++) {
    /* wall seconds of each solve (the distributed one's: the slowest
     * rank's, from a common start), for bench/distributed.sh */
    double t = ps_wtime();
    if (ps_solver_step(whole, lambdas[step], &ctx)) return fail(rank, "the serial step", &ctx);
    ps_solver_commit(whole);
    double t_serial = ps_wtime() - t;
    ps_comm_sum1(&comm, 0.0); /* (all ranks here) */
    t = ps_wtime();
    if (ps_solver_step(s, lambdas[step], &dctx))
      return fail(rank, "the distributed step", &dctx);
    ps_solver_commit(s);
    double t_dist = ps_wtime() - t, t_rep = 0;
    ps_comm_max(&comm, &t_dist, 1);
    if (timed_rep) {
      ps_comm_sum1(&comm, 0.0);
      t = ps_wtime();
      if (ps_solver_step(rep, lambdas[step], &ctx)) return fail(rank, "the replicated step", &ctx);
      ps_solver_commit(rep);
      t_rep = ps_wtime() - t;
      ps_comm_max(&comm, &t_rep, 1);
    }
    const double *u = ps_solver_u(whole), *ul = ps_solver_u(s);
    double umax = 0, du_own = 0, du_ghost = 0;
    for (ps_int j = 0; j < P->n * d; j++) umax = fmax(umax, fabs(u[j]));
    for (ps_int a = 0; a < nl; a++)
      for (int k = 0; k < d; k++) {
        double e = fabs(ul[a * d + k] - u[sh.global[a] * d + k]);
        if (a < sh.n_owned) du_own = fmax(du_own, e);
        else du_ghost = fmax(du_ghost, e);
      }
    ps_comm_max(&comm, &du_own, 1);
    ps_comm_max(&comm, &du_ghost, 1);
    ps_int y = ps_solver_count_yielding(s), yw = ps_solver_count_yielding(whole);
    int good = du_own <= 1e-8 * umax && du_ghost <= 1e-8 * umax && y == yw;
    ok &= good;
    ps_solver_stats st;
    ps_solver_get_stats(s, &st);
    printf("solve_check: rank %d of %d: load factor %g: %s (%lld owned, %lld ghosts; "
           "displacements off by %.1e (owned), %.1e (ghosts) of the largest; yielding %lld of "
           "%lld; %lld Newton iterations; %.3f s distributed, %.3f s replicated, %.3f s "
           "serial)\n",
           rank, comm.size, lambdas[step], good ? "ok" : "FAILED", (long long)sh.n_owned,
           (long long)(nl - sh.n_owned), du_own / umax, du_ghost / umax, (long long)y,
           (long long)yw, (long long)st.newton_iterations, t_dist, t_rep, t_serial);
  }
  /* path following on the share: an arc-length step (ds 0.05, psi 1),
   * then a dissipation-controlled one (tau: half the arc-length step's
   * dissipation, or 1e-9 J when it dissipated nothing), each as the
   * whole model's: the same status (the arc-length step converged), the
   * load factor within 1e-8 relative, the displacements within 1e-8 of
   * the largest */
  double tau = 0.0;
  for (int step = 0; step < 2; step++) {
    const char *what = step ? "dissipation" : "arc-length";
    int sw = step ? ps_solver_dissipation_step(whole, tau, &ctx)
                  : ps_solver_arclength_step(whole, 0.05, 1.0, &ctx);
    if (sw < 0) return fail(rank, "the serial path step", &ctx);
    int sd = step ? ps_solver_dissipation_step(s, tau, &dctx)
                  : ps_solver_arclength_step(s, 0.05, 1.0, &dctx);
    if (sd < 0) return fail(rank, "the distributed path step", &dctx);
    if (!step) {
      tau = 0.5 * ps_solver_step_dissipation(whole);
      if (!(tau > 0)) tau = 1e-9;
    }
    if (sw == PS_OK) ps_solver_commit(whole);
    if (sd == PS_OK) ps_solver_commit(s);
    const double *u = ps_solver_u(whole), *ul = ps_solver_u(s);
    double umax = 0, du = 0, lw = ps_solver_lambda(whole), ld = ps_solver_lambda(s);
    for (ps_int j = 0; j < P->n * d; j++) umax = fmax(umax, fabs(u[j]));
    for (ps_int a = 0; a < nl; a++)
      for (int k = 0; k < d; k++) du = fmax(du, fabs(ul[a * d + k] - u[sh.global[a] * d + k]));
    ps_comm_max(&comm, &du, 1);
    /* (a model that dissipates nothing, the elastic three-body plate,
     * fails the dissipation step on both alike, back at the commit) */
    int good = sd == sw && (step || sw == PS_OK) && fabs(ld - lw) <= 1e-8 * fabs(lw) &&
               du <= 1e-8 * umax;
    ok &= good;
    printf("solve_check: rank %d of %d: %s step: %s (status %d, serial %d; load factor "
           "%.10g, serial %.10g; displacements off by %.1e of the largest)\n",
           rank, comm.size, what, good ? "ok" : "FAILED", sd, sw, ld, lw, du / umax);
  }
  ps_solver_free(s);
  ps_solver_free(rep);
  ps_solver_free(whole);
  free(fixed);
  free(ubar);
  free(fext);
  free(rows);
  tc_mpi_share_end(&cs, &pb, &pt, &sh);
  return !ok;
}
