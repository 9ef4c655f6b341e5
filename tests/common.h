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
 * aborts on failure. */
void tc_solve(ps_solver *s, const ps_particles *P, const ps_network *net,
              const ps_material *mat, const unsigned char *fixed,
              const double *ubar, double lambda);

/* Distance from x to the nearest face of the box [lo, hi] (dim axes). */
double tc_dist_to_box_face(const double *x, const double *lo, const double *hi,
                           int dim);

#endif
