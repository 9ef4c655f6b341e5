/* common.c: see common.h. */
#include "common.h"
#include "linsolve/ps_linsolve.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static void die(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "FAIL: %s: %s\n", what, ctx->msg);
  printf("FAIL: %s\n", what);
  exit(1);
}

void tc_network(ps_particles *P, double alpha, const ps_crack *cracks,
                int n_cracks, ps_network *net) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_kernel K;
  if (ps_geom_sizes_eq115(P, 5, &ctx)) die("sizes", &ctx);
  if (ps_kernel_init(&K, P->dim, 2, alpha, &ctx)) die("kernel", &ctx);
  if (ps_network_build(net, P, &K, cracks, n_cracks, &ctx)) die("network", &ctx);
}

void tc_setup_case_file(const char *yaml, ps_case *cs, ps_problem *pb, ps_ctx *ctx) {
  ps_ctx_init(ctx);
  ctx->verbosity = getenv("PS_TEST_VERBOSE") ? 1 : 0;
  ps_case_defaults(cs);
  if (ps_case_load(cs, yaml, ctx)) die(yaml, ctx);
  if (ps_problem_setup(pb, cs, ctx)) die("problem set-up", ctx);
}

ps_material tc_material(double nu, int plane) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_material m = {.E = 210e9, .nu = nu, .plane = plane, .yield_strain = 1.0 / 500,
                   .plastic = 0, .delta = INFINITY, .rho = 7800};
  if (ps_material_finish(&m, plane == PS_SOLID_3D ? 3 : 2, &ctx)) die("material", &ctx);
  return m;
}

ps_solver *tc_solve(const ps_particles *P, const ps_network *net, const ps_material *mat,
                     const unsigned char *fixed, const double *ubar, double lambda) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 2 : 0;
  ps_solver_opts o;
  ps_solver_opts_default(&o);
  o.tolerance = 1e-9;
  ps_solver *s;
  if (ps_solver_create(&s, P, net, ps_model_fibre, mat, fixed, ubar, &o, &ctx))
    die("solver create", &ctx);
  int st = ps_solver_step(s, lambda, &ctx);
  if (st != PS_OK) {
    fprintf(stderr, "newton reason %d, residual %g\n", ps_solver_last_reason(s),
            ps_solver_last_residual(s));
    die("solver step", &ctx);
  }
  return s;
}

void tc_evaluator_create(tc_evaluator *ev, const ps_network *net,
                         const ps_material *mat) {
  tc_evaluator_create_model(ev, ps_model_fibre, NULL, net, mat);
}

void tc_evaluator_create_model(tc_evaluator *ev, const ps_model_type *type,
                               const ps_particles *P, const ps_network *net,
                               const ps_material *mat) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_int nd = (ps_int)net->dim * net->n_particle;
  unsigned char *fixed = calloc((size_t)nd, 1);
  fixed[0] = 1; /* the system needs a free dof; nothing is solved here */
  if (ps_model_create(&ev->model, type, P, net, mat, &ctx) ||
      ps_arm_state_alloc(&ev->st, net->n_arm, &ctx) ||
      /* forces only (tc_eval): no room for the family terms' tangent */
      ps_system_create_pattern(&ev->sys, net, fixed, 0, &ctx))
    die("evaluator", &ctx);
  free(fixed);
  ev->f = calloc((size_t)nd, sizeof *ev->f);
}

void tc_eval(tc_evaluator *ev, const ps_particles *P, const double *u) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  double energy;
  if (ps_system_eval(&ev->sys, &ev->model, &ev->st, P->x, u, ev->f, &energy, 0, &ctx))
    die("evaluate", &ctx);
}

void tc_evaluator_free(tc_evaluator *ev) {
  ps_system_free(&ev->sys);
  ps_arm_state_free(&ev->st);
  ps_model_free(&ev->model);
  free(ev->f);
}

double tc_dist_to_box_face(const double *x, const double *lo, const double *hi,
                           int dim) {
  double d = INFINITY;
  for (int k = 0; k < dim; k++) {
    d = fmin(d, x[k] - lo[k]);
    d = fmin(d, hi[k] - x[k]);
  }
  return d;
}

ps_solver *tc_problem_solver(ps_problem *pb) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_solver *s = NULL;
  ps_solver_opts o = pb->cs.solver;
  o.threads = 1;
  if (ps_solver_create(&s, &pb->P, &pb->net, ps_model_type_find(pb->cs.model), &pb->mat,
                       pb->fixed, pb->ubar, &o, &ctx))
    die("solver", &ctx);
  if (pb->fext) ps_solver_set_forces(s, pb->fext);
  return s;
}

ps_path_problem tc_path_problem(ps_problem *pb, const char *name) {
  ps_path_problem pp = {.P = &pb->P,
                        .net = &pb->net,
                        .model = ps_model_type_find(pb->cs.model),
                        .mat = &pb->mat,
                        .measure = pb->measure,
                        .measure_length = pb->measure_length,
                        .c = pb->c,
                        .name = name};
  return pp;
}

void tc_mpi_share(int argc, char **argv, const char *prog, ps_comm *comm, ps_case *cs,
                  ps_problem *pb, ps_partition *pt, ps_share *sh, ps_ctx *ctx) {
  ps_ctx_init(ctx);
  if (argc != 2) {
    printf("%s: usage: %s CASE.yaml\n", prog, prog);
    exit(2);
  }
  if (ps_parallel_init(NULL, ctx) || ps_parallel_comm(comm, ctx)) {
    printf("%s: MPI: %s\n", prog, ctx->msg);
    exit(1);
  }
  tc_setup_case_file(argv[1], cs, pb, ctx);
  if (ps_partition_curve(pt, &pb->P, comm->size, ctx) ||
      ps_problem_share(pb, pt, comm->rank, sh, ctx)) {
    printf("%s: rank %d: the share: %s\n", prog, comm->rank, ctx->msg);
    exit(1);
  }
}

void tc_mpi_share_end(ps_case *cs, ps_problem *pb, ps_partition *pt, ps_share *sh) {
  ps_share_free(sh);
  ps_partition_free(pt);
  ps_problem_free(pb);
  ps_case_free(cs);
  ps_parallel_finalize();
}
