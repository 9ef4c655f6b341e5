/* geomnet.c: helpers shared by the geometry and network tests (geomnet.h). */
#include "geomnet.h"

#include <gsl/gsl_math.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

void tg_die(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "%s failed: %s\n", what, ctx->msg);
  exit(2);
}

double tg_d2(const double *x, const double *y, int dim) {
  double s = 0.0;
  for (int k = 0; k < dim; k++) s += (x[k] - y[k]) * (x[k] - y[k]);
  return s;
}

void tg_make_box(ps_particles *P, int dim, ps_int nx, ps_int ny, ps_int nz, double d,
                 unsigned long seed, ps_ctx *ctx) {
  ps_int counts[3] = {nx, ny, nz};
  if (ps_geom_box(P, dim, counts, d, "square", 0.3, seed, ctx)) tg_die("ps_geom_box", ctx);
  if (ps_geom_sizes_eq115(P, 5, ctx)) tg_die("ps_geom_sizes_eq115", ctx);
  double L = nx * d, H = ny * d;
  for (ps_int a = 0; a < P->n; a++) {
    double x = P->x[a * dim], y = P->x[a * dim + 1];
    double s = 1.2 + 0.6 * sin(2.0 * M_PI * x / L) * cos(M_PI * y / H);
    P->h[a] *= s;
    P->volume[a] *= pow(s, dim);
  }
}

int tg_cmp_pair(const void *u, const void *v) {
  const tg_pair *p = u, *q = v;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return 0;
}

tg_pair *tg_brute_arms(const ps_particles *P, double alpha, tg_cut_fn cut, const void *arg,
                       ps_int *n, ps_int *n_cut) {
  ps_int cap = 1024, na = 0;
  tg_pair *arms = malloc((size_t)cap * sizeof *arms);
  int dim = P->dim;
  *n_cut = 0;
  for (ps_int a = 0; a < P->n; a++)
    for (ps_int b = a + 1; b < P->n; b++) {
      const double *x = &P->x[a * dim], *y = &P->x[b * dim];
      double r = sqrt(tg_d2(y, x, dim));
      double hm = P->h[a] > P->h[b] ? P->h[a] : P->h[b];
      if (!(r < alpha * hm)) continue;
      if (cut && cut(arg, x, y)) {
        (*n_cut)++;
        continue;
      }
      if (na == cap) {
        cap *= 2;
        arms = realloc(arms, (size_t)cap * sizeof *arms);
      }
      arms[na].a = a;
      arms[na].b = b;
      na++;
    }
  *n = na;
  return arms;
}
