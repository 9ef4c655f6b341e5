/* t755_share.c: a process's share of a distributed model (ps_share and
 * the ownership masks of ps_model; step 3 of doc/design-distributed.md),
 * checked serially. For each case and 1, 2, 3 and 5 parts, every part's
 * share (its owned particles, their ghosts out to the model's
 * ps_model_share_horizons, the network on them) is evaluated at the whole
 * model's displacements (a strain past yield and the breaking criterion,
 * plus noise: each local
 * particle takes its global particle's u), and compared with the whole
 * model evaluated once:
 *  (a) the forces at owned dofs equal the whole model's, to 1e-12 of the
 *      largest force (the same terms summed in another order);
 *  (b) the tangent times a random vector, at owned dofs, equals the whole
 *      model's likewise: each owned row of K is complete;
 *  (c) the shares' energies (owned arms and particles only) sum to the
 *      whole energy, 1e-12 relative;
 *  (d) the yielding arms, the arms past the breaking criterion and the
 *      plastic dissipation of the shares sum to the whole model's (the
 *      counts exactly, the dissipation to 1e-12);
 *  (e) every arm of the whole network is owned by exactly one share (the
 *      owned arms of the shares sum to its arms).
 * The ghosts a share needs (ps_model_share_horizons) are checked too:
 * with one horizon less, the forces at owned dofs are off (by more than
 * 1e-9 of the largest, for 5 parts).
 * With the fibre and state moduli correction, whose weights balance over
 * the whole cloud, each share takes the whole model's constants
 * (ps_model_share_constants) and (a)-(d) hold as well.
 * Cases: the small disk (fibre, total and deviatoric readings, and with
 * the moduli correction; a crack),
 * the notched PMB (bond, no surface correction: one horizon), the edge
 * crack (bond with the surface correction: two), the notched state plate
 * (two; with the moduli correction too) and three-body plate (partial volumes and the surface correction:
 * three), the 3D tension block (fibre, two). */
#include "check.h"
#include "common.h"
#include "nonlinear/problem_pd.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "t755: %s failed: %s\n", what, ctx->msg);
  printf("FAIL: %s\n", what);
  exit(2);
}

/* a model's evaluation at u: forces, energy, K x for x[n_dof] (every dof
 * free), the counts and the dissipation */
typedef struct result {
  double *f, *Kx, energy, dissipation;
  ps_int yielding, past;
} result;

static ps_pd *evaluate(const ps_particles *P, const ps_network *net, const ps_model_type *type,
                       const ps_material *mat, const ps_model_given *given,
                       const unsigned char *own_arm, const unsigned char *own_particle,
                       const double *u, const double *x, result *r, ps_ctx *ctx) {
  ps_int nd = P->n * P->dim;
  unsigned char *fixed = calloc((size_t)nd, 1);
  ps_pd *pd;
  if (ps_pd_create_given(&pd, P, net, type, mat, given, fixed, 0, 0, ctx))
    die_ctx("ps_pd_create", ctx);
  free(fixed);
  pd->model.own_arm = own_arm;
  pd->model.own_particle = own_particle;
  ps_nl_problem pr = ps_pd_problem(pd);
  r->f = calloc((size_t)nd, sizeof *r->f);
  r->Kx = calloc((size_t)nd, sizeof *r->Kx);
  double *xf = calloc((size_t)nd, sizeof *xf), *yf = calloc((size_t)nd, sizeof *yf);
  if (pr.ops->evaluate(pd, u, r->f, &r->energy, 1, ctx)) die_ctx("evaluate", ctx);
  for (ps_int k = 0; k < pr.n_free; k++) xf[k] = x[pr.dof_of_free[k]];
  pr.ops->apply(pd, xf, yf);
  for (ps_int k = 0; k < pr.n_free; k++) r->Kx[pr.dof_of_free[k]] = yf[k];
  r->yielding = ps_pd_count_yielding(pd);
  r->past = ps_model_count_past(&pd->model, &pd->st);
  r->dissipation = ps_pd_dissipation(pd, NULL);
  free(xf);
  free(yf);
  return pd;
}

static void result_free(result *r) {
  free(r->f);
  free(r->Kx);
}

/* the 1..parts shares of the whole problem pb with ghosts out to hops arms,
 * each evaluated at u (K times x): the largest differences from `whole` at
 * owned dofs and the sums of the shares' energies, dissipations, counts */
typedef struct share_sum {
  double df, dk, E, D;
  ps_int yielding, past, owned_arms;
} share_sum;

static share_sum shares(const ps_particles *P, const ps_problem *pb, const ps_model_type *type,
                        int hops, int parts, const double *u, const double *x,
                        const result *whole, const ps_model *whole_model, ps_ctx *ctx) {
  const int d = P->dim;
  share_sum r = {0};
  ps_partition pt;
  if (ps_partition_curve(&pt, P, parts, ctx)) die_ctx("ps_partition_curve", ctx);
  for (int p = 0; p < parts; p++) {
    ps_share sh;
    if (ps_share_build(&sh, P, &pt, p, hops, &pb->kernel, pb->cracks, pb->n_cracks, ctx))
      die_ctx("ps_share_build", ctx);
    ps_int nl = sh.P.n;
    double *ul = malloc((size_t)(nl * d) * sizeof *ul), *xl = malloc((size_t)(nl * d) * sizeof *xl);
    for (ps_int a = 0; a < nl; a++)
      for (int k = 0; k < d; k++) {
        ul[a * d + k] = u[sh.global[a] * d + k];
        xl[a * d + k] = x[sh.global[a] * d + k];
      }
    /* constants that read the whole cloud: the whole model's */
    double *gk = NULL, *gs = NULL;
    if (ps_model_whole_constants(type, &pb->mat) &&
        ps_model_share_constants(whole_model, &sh.net, sh.global, &gk, &gs, ctx))
      die_ctx("ps_model_share_constants", ctx);
    ps_model_given given = {gk, gs};
    result loc;
    ps_pd *pdl = evaluate(&sh.P, &sh.net, type, &pb->mat, gk || gs ? &given : NULL,
                          sh.own_arm, sh.own_particle, ul, xl, &loc, ctx);
    free(gk);
    free(gs);
    for (ps_int a = 0; a < sh.n_owned; a++)
      for (int k = 0; k < d; k++) {
        ps_int g = sh.global[a] * d + k;
        r.df = fmax(r.df, fabs(loc.f[a * d + k] - whole->f[g]));
        r.dk = fmax(r.dk, fabs(loc.Kx[a * d + k] - whole->Kx[g]));
      }
    r.E += loc.energy;
    r.D += loc.dissipation;
    r.yielding += loc.yielding;
    r.past += loc.past;
    for (ps_int i = 0; i < sh.net.n_arm; i++) r.owned_arms += sh.own_arm[i];
    result_free(&loc);
    ps_pd_free(pdl);
    free(ul);
    free(xl);
    ps_share_free(&sh);
  }
  ps_partition_free(&pt);
  return r;
}

/* the case file `name` with the material line `extra` (or none) */
static void check_case(const char *name, const char *extra, double strain, int want_h) {
  const char *srcdir = getenv("srcdir") ? getenv("srcdir") : ".";
  char path[1024], tmp[256];
  snprintf(path, sizeof path, "%s/data/cases/%s.yaml", srcdir, name);
  if (extra) { /* the case with `extra` after its material: line */
    snprintf(tmp, sizeof tmp, "t755-%s.yaml", name);
    FILE *in = fopen(path, "r"), *out = fopen(tmp, "w");
    char line[1024];
    if (!in || !out) {
      printf("FAIL: cannot copy %s\n", path);
      exit(2);
    }
    while (fgets(line, sizeof line, in)) {
      fputs(line, out);
      if (!strcmp(line, "material:\n")) fprintf(out, "  %s\n", extra);
    }
    fclose(in);
    fclose(out);
    snprintf(path, sizeof path, "%s", tmp);
  }
  ps_case cs;
  ps_problem pb;
  ps_ctx ctx;
  tc_setup_case_file(path, &cs, &pb, &ctx);
  const ps_particles *P = &pb.P;
  const int d = P->dim;
  const ps_int nd = P->n * d;
  const ps_model_type *type = ps_model_type_find(pb.cs.model);
  /* u: a uniaxial strain along x of `strain` and a shear, plus noise of a
   * tenth of it times the spacing; x: random */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 755);
  double *u = malloc((size_t)nd * sizeof *u), *x = malloc((size_t)nd * sizeof *x);
  for (ps_int a = 0; a < P->n; a++)
    for (int k = 0; k < d; k++) {
      const double *X = &P->x[a * d];
      u[a * d + k] = (k == 0 ? strain * X[0] + 0.3 * strain * X[1] : -0.2 * strain * X[k]) +
                     0.1 * strain * P->h[a] * (2 * gsl_rng_uniform(rng) - 1);
      x[a * d + k] = 2 * gsl_rng_uniform(rng) - 1;
    }
  result whole;
  ps_pd *pdw = evaluate(P, &pb.net, type, &pb.mat, NULL, NULL, NULL, u, x, &whole, &ctx);
  double fmax_ = 0, kmax = 0;
  for (ps_int j = 0; j < nd; j++) {
    fmax_ = fmax(fmax_, fabs(whole.f[j]));
    kmax = fmax(kmax, fabs(whole.Kx[j]));
  }
  const int h = ps_model_share_horizons(type, &pb.mat);
  const char *m = extra ? extra : pb.cs.model;
  ps_check(h == want_h, "%s (%s): a share needs ghosts out to %d horizons (want %d)", name, m,
           h, want_h);
  const int parts_list[] = {1, 2, 3, 5};
  for (size_t t = 0; t < sizeof parts_list / sizeof *parts_list; t++) {
    share_sum r = shares(P, &pb, type, h, parts_list[t], u, x, &whole,
                         &pdw->model, &ctx);
    int parts = parts_list[t];
    if (parts == 1 || parts == 5)
      printf("  %s (%s), %d parts: forces %.1e, K x %.1e of the largest; energy %.1e, "
             "dissipation %.3g of %.3g; yielding %lld of %lld, past %lld of %lld\n",
             name, m, parts, r.df / fmax_, r.dk / kmax,
             fabs(r.E - whole.energy) / fabs(whole.energy), r.D, whole.dissipation,
             (long long)r.yielding, (long long)whole.yielding, (long long)r.past,
             (long long)whole.past);
    ps_check(r.df <= 1e-12 * fmax_ && r.dk <= 1e-12 * kmax,
             "%s (%s), %d parts: forces and K x at owned dofs as the whole model's "
             "(%.1e, %.1e of the largest)", name, m, parts, r.df / fmax_, r.dk / kmax);
    ps_check(fabs(r.E - whole.energy) <= 1e-12 * fabs(whole.energy) &&
                 fabs(r.D - whole.dissipation) <= 1e-12 * fabs(whole.dissipation),
             "%s (%s), %d parts: the shares' energies and dissipations sum to the whole's",
             name, m, parts);
    ps_check(r.yielding == whole.yielding && r.past == whole.past &&
                 r.owned_arms == pb.net.n_arm,
             "%s (%s), %d parts: yielding arms %lld, arms past the criterion %lld, owned arms "
             "%lld as the whole's (%lld, %lld, %lld)", name, m, parts, (long long)r.yielding,
             (long long)r.past, (long long)r.owned_arms, (long long)whole.yielding,
             (long long)whole.past, (long long)pb.net.n_arm);
  }
  if (h > 1) { /* one horizon less: the ghosts matter */
    share_sum r = shares(P, &pb, type, h - 1, 5, u, x, &whole,
                         &pdw->model, &ctx);
    ps_check(r.df > 1e-9 * fmax_, "%s (%s), 5 parts, ghosts out to %d horizons only: forces "
             "off by %.1e of the largest", name, m, h - 1, r.df / fmax_);
  }
  result_free(&whole);
  ps_pd_free(pdw);
  free(u);
  free(x);
  gsl_rng_free(rng);
  ps_problem_free(&pb);
  ps_case_free(&cs);
}

int main(void) {
  check_case("small-disk", NULL, 0.004, 2);
  check_case("small-disk", "yield_rule: deviatoric", 0.004, 2);
  check_case("notched-plate-pmb", NULL, 0.002, 1);
  check_case("edge-crack-bond", NULL, 0.002, 2);
  check_case("notched-plate-state", NULL, 0.002, 2);
  check_case("notched-plate-threebody", NULL, 0.002, 3);
  check_case("tension-block-3d", NULL, 0.004, 2);
  /* the moduli correction of the fibre and state models balances its
   * weights over the whole cloud: no reach is local, a share takes the
   * whole model's (ps_model_share_constants) */
  check_case("small-disk", "surface_correction: true", 0.004, 2);
  check_case("notched-plate-state", "surface_correction: true", 0.002, 2);
  ps_material mat = tc_material(0.3, PS_PLANE_STRAIN);
  ps_check(!ps_model_whole_constants(ps_model_fibre, &mat) &&
               !ps_model_whole_constants(ps_model_bond, &mat),
           "fibre and bond without the correction: constants local");
  mat.surface_correction = 1;
  ps_check(ps_model_whole_constants(ps_model_fibre, &mat) &&
               ps_model_whole_constants(ps_model_state, &mat) &&
               !ps_model_whole_constants(ps_model_bond, &mat),
           "fibre and state with the moduli correction: constants from the whole (not bond)");
  return ps_check_summary();
}
