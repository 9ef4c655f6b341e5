/* common.h: shared set-up for the physics tests: sizes (Eq. 115), kernel
 * (k = 2) and network on a cloud; a one-step elastic solve. */
#ifndef PS_TEST_COMMON_H
#define PS_TEST_COMMON_H

#include <gsl/gsl_math.h>

#include "app/ps_app.h"

/* Sizes by Eq. 115 (n = 5), kernel k = 2 with alpha, network with the
 * given cracks. Aborts with a message on failure (tests only). */
void tc_network(ps_particles *P, double alpha, const ps_crack *cracks,
                int n_cracks, ps_network *net);

/* Table 1 steel (E 210 GPa) with the given nu and plane; elastic arms. */
ps_material tc_material(double nu, int plane);

/* Create a solver and step the load factor to lambda (one increment);
 * aborts on failure. The caller frees the solver (ps_solver_free). */
ps_solver *tc_solve(const ps_particles *P, const ps_network *net, const ps_material *mat,
                     const unsigned char *fixed, const double *ubar, double lambda);

/* A model, arm state and system on a network with nothing prescribed:
 * enough to evaluate forces of a given displacement field. */
typedef struct tc_evaluator {
  ps_model model;
  ps_arm_state st;
  ps_system sys;
  double *f; /* [n_dof] internal forces of the last tc_eval */
} tc_evaluator;
void tc_evaluator_create(tc_evaluator *ev, const ps_network *net,
                         const ps_material *mat);
/* The same with a given model type on the particles P. */
void tc_evaluator_create_model(tc_evaluator *ev, const ps_model_type *type,
                               const ps_particles *P, const ps_network *net,
                               const ps_material *mat);
/* Internal forces (ev->f), tensions and directions (ev->sys) at u. */
void tc_eval(tc_evaluator *ev, const ps_particles *P, const double *u);
void tc_evaluator_free(tc_evaluator *ev);

/* The case file yaml read into *cs (defaults first) with a fresh *ctx
 * (verbose when PS_TEST_VERBOSE is set) and its problem set up in *pb;
 * exits on failure. */
void tc_setup_case_file(const char *yaml, ps_case *cs, ps_problem *pb, ps_ctx *ctx);

/* The MPI checks (tests/share_check.c, solve_check.c; t990 runs them): PETSc
 * and MPI up, *comm the run's ranks, the case file argv[1] set up in *cs
 * and *pb (ctx fresh), and this rank's share *sh of part rank of the
 * partition *pt (ps_problem_share). Exits 2 on a usage error, 1 on a
 * failure, naming `prog`. */
void tc_mpi_share(int argc, char **argv, const char *prog, ps_comm *comm, ps_case *cs,
                  ps_problem *pb, ps_partition *pt, ps_share *sh, ps_ctx *ctx);
/* What tc_mpi_share made, freed, and PETSc and MPI finalised. */
void tc_mpi_share_end(ps_case *cs, ps_problem *pb, ps_partition *pt, ps_share *sh);

/* Distance from x to the nearest face of the box [lo, hi] (dim axes). */
/* A solver of problem pb with its case's solver options on one thread
 * and its forces (exits on failure). */
ps_solver *tc_problem_solver(ps_problem *pb);
/* The path layer's view of problem pb, its runs named `name`. */
ps_path_problem tc_path_problem(ps_problem *pb, const char *name);

double tc_dist_to_box_face(const double *x, const double *lo, const double *hi,
                           int dim);

#endif
