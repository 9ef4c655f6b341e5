/* t250_linsolve.c: one conformance suite over every linear-solver backend
 * (CHOLMOD supernodal, CHOLMOD simplicial, UMFPACK), on the tangent of a
 * small supported plane-strain network:
 *  - each solves K x = b to a relative residual below 1e-10 (a direct
 *    solve of a matrix with condition ~1e4..1e6: round-off ~1e-12);
 *  - the three solutions agree to 1e-9;
 *  - CG preconditioned by the exact factor converges in one iteration,
 *    and by the factor of a perturbed matrix in a few;
 *  - a matrix made indefinite at a known dof is reported: CHOLMOD returns
 *    PS_NOT_POSDEF with that column (mapped back through its fill-reducing
 *    permutation), and UMFPACK still solves it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common.h"

static double rel_residual(const ps_csc *A, const double *x, const double *b) {
  double *Ax = calloc((size_t)A->n, sizeof *Ax), num = 0, den = 0;
  ps_csc_symv(A, x, Ax);
  for (ps_int k = 0; k < A->n; k++) {
    num += (Ax[k] - b[k]) * (Ax[k] - b[k]);
    den += b[k] * b[k];
  }
  free(Ax);
  return sqrt(num / den);
}

static double dot_n(ps_int n, const double *a, const double *b) {
  double s = 0;
  for (ps_int k = 0; k < n; k++) s += a[k] * b[k];
  return s;
}

/* |x - ref| / |ref| */
static double rel_diff(ps_int n, const double *x, const double *ref) {
  double num = 0, den = 0;
  for (ps_int k = 0; k < n; k++) {
    num += (x[k] - ref[k]) * (x[k] - ref[k]);
    den += ref[k] * ref[k];
  }
  return sqrt(num / den);
}

int main(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_particles P;
  ps_network net;
  ps_int counts[3] = {14, 10, 1};
  if (ps_geom_box(&P, 2, counts, 1e-3, "hex", 0.2, 3, &ctx)) abort();
  tc_network(&P, 5.1, NULL, 0, &net);
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  ps_model model;
  ps_arm_state st;
  ps_system sys;
  ps_int nd = 2 * P.n;
  unsigned char *fixed = calloc((size_t)nd, 1);
  for (ps_int a = 0; a < P.n; a++)
    if (P.x[2 * a] < 2.5e-3) fixed[2 * a] = fixed[2 * a + 1] = 1; /* clamp the left */
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f), energy;
  ps_model_create(&model, ps_model_fibre, &P, &net, &mat, &ctx);
  ps_arm_state_alloc(&st, net.n_arm, &ctx);
  if (ps_system_create(&sys, &net, fixed, &ctx)) abort();
  for (ps_int a = 0; a < P.n; a++) u[2 * a] = 1e-3 * P.x[2 * a]; /* some tension */
  ps_system_eval(&sys, &model, &st, P.x, u, f, &energy, 1, &ctx);
  ps_csc *A = &sys.A;
  ps_int n = A->n;
  double *b = calloc((size_t)n, sizeof *b), *x[3], *work = calloc((size_t)(4 * n), sizeof *work);
  for (ps_int k = 0; k < n; k++) b[k] = sin(0.37 * k) + 0.1;
  const ps_linsolve_type *types[3] = {ps_linsolve_cholmod, ps_linsolve_cholmod_simplicial,
                                      ps_linsolve_umfpack};
  ps_linsolve ls[3];
  for (int t = 0; t < 3; t++) {
    x[t] = calloc((size_t)n, sizeof *x[t]);
    ps_int bad;
    int s1 = ps_linsolve_create(&ls[t], types[t], &ctx);
    int s2 = s1 ? s1 : ps_linsolve_factor(&ls[t], A, &bad, &ctx);
    int s3 = s2 ? s2 : ps_linsolve_solve(&ls[t], b, x[t], &ctx);
    ps_check(s3 == PS_OK, "%s: factor and solve (%lld dofs, %lld nonzeros)", types[t]->name,
             (long long)n, (long long)A->p[n]);
    ps_check_le(rel_residual(A, x[t], b), 1e-10, types[t]->name);
  }
  for (int t = 1; t < 3; t++) {
    char what[96];
    snprintf(what, sizeof what, "%s agrees with cholmod (rel. difference)", types[t]->name);
    ps_check_le(rel_diff(n, x[t], x[0]), 1e-9, what);
  }
  /* CG with the exact factor: one iteration; with a perturbed matrix's
   * factor (diagonal scaled by 1.05): a few */
  int its;
  ps_operator op = ps_csc_operator(A);
  double *y = calloc((size_t)n, sizeof *y);
  int s = ps_linsolve_pcg(&ls[0], &op, b, y, 1e-8, 25, work, &its, &ctx);
  ps_check(s == PS_OK && its <= 2, "CG preconditioned by the exact factor: %d iteration(s)",
           its);
  /* the factor in single precision as CG's preconditioner: z = M^-1 b
   * differs from the double solve by float round-off (6e-8) amplified by
   * the conditioning (measured 2e-7 here; 1e-5 leaves a factor 50), but
   * must differ (the float path is taken), must be symmetric (the same
   * rounded L forward and backward: p.M^-1 q = q.M^-1 p to float
   * round-off) and CG with it must still reach 1e-8 in a few iterations */
  double *z = calloc((size_t)n, sizeof *z), *q = calloc((size_t)n, sizeof *q),
         *zq = calloc((size_t)n, sizeof *zq);
  ps_check(ls[0].type->precondition != NULL, "cholmod has a single-precision preconditioner");
  if (ls[0].type->precondition) {
    /* the first single_after (PS_SINGLE_AFTER) calls after a
     * factorisation solve in double: exactly the double solve. (This
     * factor has one supernode of 142 columns, solved by strsv, and
     * narrower ones with inverted diagonal blocks: both paths of
     * chol_precondition.) */
    ls[0].single_precision = 1;
    double d0 = 0;
    for (int i = 0; i < PS_SINGLE_AFTER; i++) ps_linsolve_precondition(&ls[0], b, z, &ctx);
    for (ps_int k = 0; k < n; k++) d0 = fmax(d0, fabs(z[k] - x[0][k]));
    ps_check(d0 == 0.0, "the first %d preconditioner solves are the double solve",
             PS_SINGLE_AFTER);
    ps_linsolve_precondition(&ls[0], b, z, &ctx);
    double dz = rel_diff(n, z, x[0]);
    ps_check(dz > 1e-12 && dz <= 1e-5,
             "single-precision preconditioner vs the double solve: rel. difference %.2e "
             "in (1e-12, 1e-5]", dz);
    for (ps_int k = 0; k < n; k++) q[k] = cos(1.3 * k);
    ps_linsolve_precondition(&ls[0], q, zq, &ctx);
    double bMq = dot_n(n, b, zq), qMb = dot_n(n, q, z);
    ps_check_le(fabs(bMq - qMb) / fabs(bMq), 1e-5,
                "single-precision preconditioner symmetric: |b.M^-1 q - q.M^-1 b| / |b.M^-1 q|");
    s = ps_linsolve_pcg(&ls[0], &op, b, y, 1e-8, 25, work, &its, &ctx);
    ps_check(s == PS_OK && its <= 4 && rel_residual(A, y, b) <= 1e-8,
             "CG with the exact factor in single precision: %d iterations to 1e-8", its);
    /* single_after = 0 (the majorant's factors): float from the first
     * solve after a factorisation */
    ps_int bad0;
    ls[0].single_after = 0;
    ps_linsolve_factor(&ls[0], A, &bad0, &ctx);
    ps_linsolve_precondition(&ls[0], b, zq, &ctx);
    ps_check(rel_diff(n, zq, z) == 0.0 && rel_diff(n, zq, x[0]) > 1e-12,
             "with single_after = 0 the first solve after a factorisation is in single "
             "precision (the same as before: %.2e)", rel_diff(n, zq, z));
    /* two threads (ps_team): the two parts of the elimination tree at
     * once must give exactly the same numbers as one thread, and the
     * split must be a real one (both parts, a top that is not all) */
    ps_team *team = NULL;
    ps_check(ps_team_create(&team, 2, &ctx) == PS_OK && ps_team_size(team) == 2,
             "a team of 2 threads");
    ls[0].team = team;
    ps_linsolve_precondition(&ls[0], b, q, &ctx);
    ls[0].team = NULL;
    ps_check(rel_diff(n, q, zq) == 0.0,
             "the preconditioner solve on 2 threads is the 1-thread solve to the bit "
             "(difference %.2e)", rel_diff(n, q, zq));
    double share = ls[0].stats.serial_share;
    ps_check(share > 0.0 && share < 1.0,
             "the elimination tree splits: one thread alone does %.1f%% of a solve "
             "(in (0, 100%%): this small factor's top supernode has 142 of its 236 columns)",
             100 * share);
    /* the matrix-free product in its two parts on two threads: the same
     * to the bit as on one */
    {
      double *p1 = calloc((size_t)nd, sizeof *p1), *p2 = calloc((size_t)nd, sizeof *p2),
             *xv = calloc((size_t)nd, sizeof *xv);
      for (ps_int j = 0; j < nd; j++) xv[j] = sin(0.71 * j);
      ps_system_apply(&sys, xv, p1);
      sys.team = team;
      ps_system_apply(&sys, xv, p2);
      sys.team = NULL;
      double dmax = 0, pmax = 0;
      for (ps_int j = 0; j < nd; j++) {
        dmax = fmax(dmax, fabs(p2[j] - p1[j]));
        pmax = fmax(pmax, fabs(p1[j]));
      }
      ps_check(dmax == 0.0 && pmax > 0.0,
               "the matrix-free product on 2 threads is the 1-thread product to the bit");
      free(p1);
      free(p2);
      free(xv);
    }
    ps_team_free(team);
    /* four parts (solver.parts 4): the tree in four subtrees below a top,
     * the product and the evaluation's forces in four shares; on a team
     * of 4 threads the same to the bit as on one (and, the sums being in
     * another order, near the two parts' numbers) */
    {
      ps_team *team4 = NULL;
      ps_check(ps_team_create(&team4, 4, &ctx) == PS_OK && ps_team_size(team4) == 4,
               "a team of 4 threads");
      double *z4 = calloc((size_t)n, sizeof *z4), *z1 = calloc((size_t)n, sizeof *z1);
      ls[0].parts = 4;
      ps_linsolve_precondition(&ls[0], b, z1, &ctx);
      ls[0].team = team4;
      ps_linsolve_precondition(&ls[0], b, z4, &ctx);
      ls[0].team = NULL;
      ps_check(rel_diff(n, z4, z1) == 0.0 && rel_diff(n, z1, zq) <= 1e-5,
               "the preconditioner in 4 parts: 4 threads give the 1-thread solve to the bit "
               "(%.2e), near the 2 parts' one (%.2e)", rel_diff(n, z4, z1), rel_diff(n, z1, zq));
      double share4 = ls[0].stats.serial_share;
      ps_check(share4 > 0.0 && share4 < 1.0,
               "the elimination tree splits in 4: one thread alone does %.1f%% of a solve",
               100 * share4);
      ls[0].parts = PS_PARTS_DEFAULT;
      ps_check(ps_system_set_parts(&sys, 4, &ctx) == PS_OK && sys.parts == 4,
               "the system in 4 parts");
      double *p1 = calloc((size_t)nd, sizeof *p1), *p4 = calloc((size_t)nd, sizeof *p4),
             *f1 = calloc((size_t)nd, sizeof *f1), *f4 = calloc((size_t)nd, sizeof *f4),
             *xv = calloc((size_t)nd, sizeof *xv), e1, e4;
      for (ps_int j = 0; j < nd; j++) xv[j] = sin(0.71 * j);
      ps_system_eval(&sys, &model, &st, P.x, u, f1, &e1, PS_EVAL_OPERATOR, &ctx);
      ps_system_apply(&sys, xv, p1);
      sys.team = team4;
      ps_system_eval(&sys, &model, &st, P.x, u, f4, &e4, PS_EVAL_OPERATOR, &ctx);
      ps_system_apply(&sys, xv, p4);
      sys.team = NULL;
      int same = e1 == e4;
      for (ps_int j = 0; j < nd; j++) same = same && p1[j] == p4[j] && f1[j] == f4[j];
      ps_check(same, "the forces and the matrix-free product in 4 parts: 4 threads give the "
                     "1-thread numbers to the bit");
      ps_check(ps_system_set_parts(&sys, 0, &ctx) == PS_ERR_INPUT &&
                   ps_system_set_parts(&sys, PS_PARTS_MAX + 1, &ctx) == PS_ERR_INPUT &&
                   sys.parts == 4,
               "parts outside 1 .. PS_PARTS_MAX refused, the system keeps its parts");
      ps_check(ps_system_set_parts(&sys, PS_PARTS_DEFAULT, &ctx) == PS_OK, "back to 2 parts");
      free(p1);
      free(p4);
      free(f1);
      free(f4);
      free(xv);
      free(z1);
      free(z4);
      ps_team_free(team4);
    }
    ls[0].single_after = PS_SINGLE_AFTER;
    ls[0].single_precision = 0;
  }
  free(z);
  free(q);
  free(zq);
  double *x_save = malloc((size_t)A->p[n] * sizeof *x_save);
  memcpy(x_save, A->x, (size_t)A->p[n] * sizeof *x_save);
  for (ps_int j = 0; j < n; j++) A->x[A->p[j + 1] - 1] *= 1.05; /* the diagonal is last */
  ps_int bad;
  ps_linsolve_factor(&ls[0], A, &bad, &ctx);
  memcpy(A->x, x_save, (size_t)A->p[n] * sizeof *x_save);
  s = ps_linsolve_pcg(&ls[0], &op, b, y, 1e-8, 25, work, &its, &ctx);
  ps_check(s == PS_OK && its > 1 && its <= 20 && rel_residual(A, y, b) <= 1e-8,
           "CG preconditioned by a nearby factor: %d iterations", its);
  /* mildly indefinite, A - 1.5 lambda_min I (lambda_min by inverse
   * iteration with the exact factor): CG with the nearby factor first
   * makes progress along the positive directions, then meets the one
   * negative direction; the iterate it returns is still a descent
   * direction, b.x > 0 */
  {
    double *v = calloc((size_t)n, sizeof *v), *w = calloc((size_t)n, sizeof *w), lmin = 0;
    for (ps_int k = 0; k < n; k++) v[k] = 1.0 + 0.1 * sin(0.9 * k);
    for (int i = 0; i < 60; i++) { /* v <- A^-1 v / |.| */
      ps_linsolve_solve(&ls[1], v, w, &ctx);
      double nw = sqrt(dot_n(n, w, w));
      for (ps_int k = 0; k < n; k++) v[k] = w[k] / nw;
    }
    ps_csc_symv(A, v, w);
    lmin = dot_n(n, v, w); /* Rayleigh quotient, |v| = 1 */
    for (ps_int j = 0; j < n; j++) A->x[A->p[j + 1] - 1] -= 1.5 * lmin;
    s = ps_linsolve_pcg(&ls[0], &op, b, y, 1e-8, 50, work, &its, &ctx);
    double bx = dot_n(n, b, y);
    ps_check(s == PS_NOT_POSDEF && its >= 1 && bx > 0,
             "CG on A - 1.5 lambda_min I (lambda_min %.3g): negative curvature after %d "
             "iteration(s), descent b.x = %.3g > 0", lmin, its, bx);
    memcpy(A->x, x_save, (size_t)A->p[n] * sizeof *x_save);
    free(v);
    free(w);
  }
  /* indefinite: a large negative diagonal at a known free dof */
  ps_int jbad = n / 3;
  A->x[A->p[jbad + 1] - 1] = -1e3 * fabs(A->x[A->p[jbad + 1] - 1]);
  /* CG on it with a positive definite preconditioner (the nearby
   * factor) meets negative curvature: PS_NOT_POSDEF, and the truncated
   * iterate is a descent direction (b.x > 0: the energy, whose gradient
   * is -b, decreases along x), for a load at the bad dof and a smooth one */
  for (int rhs = 0; rhs < 2; rhs++) {
    double *bb = calloc((size_t)n, sizeof *bb);
    for (ps_int k = 0; k < n; k++) bb[k] = rhs ? b[k] * (k != jbad) : (k == jbad);
    s = ps_linsolve_pcg(&ls[0], &op, bb, y, 1e-8, 25, work, &its, &ctx);
    double bx = dot_n(n, bb, y);
    ps_check(s == PS_NOT_POSDEF && bx > 0,
             "CG on an indefinite matrix (%s load): negative curvature after %d "
             "iteration(s), status %d, descent b.x = %.3g > 0",
             rhs ? "smooth" : "point", its, s, bx);
    free(bb);
  }
  s = ps_linsolve_factor(&ls[0], A, &bad, &ctx);
  ps_check(s == PS_NOT_POSDEF, "cholmod reports an indefinite matrix (status %d)", s);
  /* columns eliminated before the bad dof do not see its value, so the
   * first non-positive pivot is the bad dof's own: CHOLMOD's L->minor, a
   * column of the permuted matrix, must map back to it */
  ps_check(bad == jbad, "cholmod names the indefinite dof %lld (got %lld)", (long long)jbad,
           (long long)bad);
  s = ps_linsolve_factor(&ls[2], A, &bad, &ctx);
  if (s == PS_OK) s = ps_linsolve_solve(&ls[2], b, y, &ctx);
  ps_check(s == PS_OK && rel_residual(A, y, b) < 1e-9,
           "umfpack solves the indefinite matrix (residual %.2e)", rel_residual(A, y, b));
  /* GMRES on this indefinite matrix, right-preconditioned by the
   * positive definite factor of it shifted by 10% of its diagonal (of the
   * dof made indefinite: by its original value, which the shift makes
   * positive): converges in a few iterations, the true residual with it
   * (1e-10 asked, 1e-9 checked: the least-squares estimate and the true
   * residual differ by round-off); one iteration is not enough and says
   * so */
  {
    double *diag = calloc((size_t)n, sizeof *diag);
    for (ps_int k = 0; k < n; k++) {
      double *a = &A->x[A->p[k + 1] - 1];
      diag[k] = *a;
      *a = k == jbad ? -1e-3 * diag[k] : 1.1 * diag[k];
    }
    s = ps_linsolve_factor(&ls[0], A, &bad, &ctx);
    for (ps_int k = 0; k < n; k++) A->x[A->p[k + 1] - 1] = diag[k];
    ps_operator op2 = ps_csc_operator(A);
    int g_its = 0, g1 = 0;
    int sg = s ? s : ps_linsolve_gmres(&ls[0], &op2, b, y, 1e-10, 40, &g_its, &ctx);
    double res = rel_residual(A, y, b);
    ps_check(sg == PS_OK && g_its > 1 && g_its < 40 && res < 1e-9,
             "GMRES on the indefinite matrix with the factor of a shifted one: %d "
             "iterations, residual %.2e", g_its, res);
    sg = ps_linsolve_gmres(&ls[0], &op2, b, y, 1e-10, 1, &g1, &ctx);
    ps_check(sg == PS_DIVERGED && g1 == 1, "GMRES stopped at its iteration cap says so "
             "(status %d)", sg);
    free(diag);
  }
  for (int t = 0; t < 3; t++) {
    ps_linsolve_destroy(&ls[t]);
    free(x[t]);
  }
  free(x_save);
  free(y);
  free(b);
  free(work);
  free(u);
  free(f);
  free(fixed);
  ps_system_free(&sys);
  ps_arm_state_free(&st);
  ps_model_free(&model);
  ps_network_free(&net);
  ps_particles_free(&P);
  return ps_check_summary();
}
