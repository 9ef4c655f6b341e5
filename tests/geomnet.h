/* geomnet.h: helpers shared by the geometry and network tests (t100_kernel,
 * t105_geom, t110_network, t115_estimate). */
#ifndef PS_TEST_GEOMNET_H
#define PS_TEST_GEOMNET_H

#include "network/ps_network.h"

/* Print "<what> failed: <ctx->msg>" and exit with status 2 (a set-up
 * step of a test failed; not a check). */
void tg_die(const char *what, const ps_ctx *ctx) __attribute__((noreturn));

/* |x - y|^2 in dim dimensions, summed in coordinate order. */
double tg_d2(const double *x, const double *y, int dim);

/* A jittered (0.3) square-lattice box of nx x ny x nz particles of spacing
 * d (seed for the jitter) with Eq. 115 sizes (n = 5) scaled by the smooth
 * factor s = 1.2 + 0.6 sin(2 pi x / L) cos(pi y / H) in (0.6, 1.8),
 * volumes by s^dim (to keep V ~ h^N). */
void tg_make_box(ps_particles *P, int dim, ps_int nx, ps_int ny, ps_int nz, double d,
                 unsigned long seed, ps_ctx *ctx);

/* An arm as the pair of its particles (a < b), ordered by (a, b). */
typedef struct {
  ps_int a, b;
} tg_pair;
int tg_cmp_pair(const void *u, const void *v);

/* A test's own "does the arm x-y cross the crack(s) in arg?" */
typedef int (*tg_cut_fn)(const void *arg, const double *x, const double *y);

/* The brute-force arm list {a < b : r < alpha max(h_a, h_b), not cut}
 * (cut NULL: none cut), sorted by (a, b), in *n arms (malloc'd; the
 * caller frees it); *n_cut: the pairs within reach that cut removed. */
tg_pair *tg_brute_arms(const ps_particles *P, double alpha, tg_cut_fn cut, const void *arg,
                       ps_int *n, ps_int *n_cut);

#endif
