/* partition.c: particles split into parts along a space-filling curve,
 * and the ghost particles of a part (ps_partition in ps_geom.h). The
 * first brick of the distributed model (doc/design-distributed.md): a
 * part is a compact piece of the body, found without MPI, the same on
 * every rank and in a serial test.
 *
 * The curve is Morton's (Z-order): the reference positions quantised to
 * 2^21 cells per axis of the cloud's bounding box (2^31 in 2D) and their
 * bits interleaved into one 64-bit key; particles sorted by key (ties by
 * particle number) and cut into parts of equal counts (the first n mod
 * parts parts one more). */
#include "ps_geom.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  uint64_t key;
  ps_int id;
} keyed;

static int by_key(const void *x, const void *y) {
  const keyed *a = x, *b = y;
  if (a->key != b->key) return a->key < b->key ? -1 : 1;
  return (a->id > b->id) - (a->id < b->id);
}

/* the bits of v (below 2^bits) spread to every dim-th bit from 0 */
static uint64_t spread(uint64_t v, int bits, int dim) {
  uint64_t out = 0;
  for (int i = 0; i < bits; i++) out |= ((v >> i) & 1u) << (i * dim);
  return out;
}

int ps_partition_curve(ps_partition *pt, const ps_particles *P, int parts, ps_ctx *ctx) {
  memset(pt, 0, sizeof *pt);
  if (parts < 1 || (ps_int)parts > (P->n > 0 ? P->n : 1))
    return ps_error(ctx, PS_ERR_INPUT, "cannot split %lld particles into %d parts",
                    (long long)P->n, parts);
  int d = P->dim, bits = d == 2 ? 31 : 21;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (ps_int a = 0; a < P->n; a++)
    for (int k = 0; k < d; k++) {
      lo[k] = fmin(lo[k], P->x[a * d + k]);
      hi[k] = fmax(hi[k], P->x[a * d + k]);
    }
  keyed *kv = ps_calloc((size_t)P->n + 1, sizeof *kv, ctx);
  pt->order = ps_calloc((size_t)P->n + 1, sizeof *pt->order, ctx);
  pt->start = ps_calloc((size_t)parts + 1, sizeof *pt->start, ctx);
  pt->part_of = ps_calloc((size_t)P->n + 1, sizeof *pt->part_of, ctx);
  if (!kv || !pt->order || !pt->start || !pt->part_of) {
    free(kv);
    ps_partition_free(pt);
    return PS_ERR_NOMEM;
  }
  const double cells = (double)((1ull << bits) - 1);
  for (ps_int a = 0; a < P->n; a++) {
    uint64_t key = 0;
    for (int k = 0; k < d; k++) {
      double w = hi[k] - lo[k], t = w > 0 ? (P->x[a * d + k] - lo[k]) / w : 0.0;
      uint64_t q = (uint64_t)(fmin(fmax(t, 0.0), 1.0) * cells);
      key |= spread(q, bits, d) << k;
    }
    kv[a].key = key;
    kv[a].id = a;
  }
  qsort(kv, (size_t)P->n, sizeof *kv, by_key);
  for (ps_int j = 0; j < P->n; j++) pt->order[j] = kv[j].id;
  free(kv);
  pt->parts = parts;
  pt->n = P->n;
  for (int p = 0; p <= parts; p++) {
    ps_int q = P->n / parts, r = P->n % parts;
    pt->start[p] = (ps_int)p * q + (p < r ? p : r);
  }
  for (int p = 0; p < parts; p++)
    for (ps_int j = pt->start[p]; j < pt->start[p + 1]; j++) pt->part_of[pt->order[j]] = p;
  return PS_OK;
}

/* the marked particles of parts other than `part`, in increasing number,
 * into *ghost (allocated here) and *n_ghost. PS_OK or PS_ERR_NOMEM. */
static int marked_ghosts(const ps_partition *pt, int part, const unsigned char *mark,
                         ps_int **ghost, ps_int *n_ghost, ps_ctx *ctx) {
  ps_int n = 0, w = 0;
  for (ps_int b = 0; b < pt->n; b++) n += mark[b] && pt->part_of[b] != part;
  ps_int *g = ps_calloc((size_t)n + 1, sizeof *g, ctx);
  if (!g) return PS_ERR_NOMEM;
  for (ps_int b = 0; b < pt->n; b++)
    if (mark[b] && pt->part_of[b] != part) g[w++] = b;
  *ghost = g;
  *n_ghost = n;
  return PS_OK;
}

int ps_partition_ghosts(const ps_partition *pt, const ps_particles *P, int part, double reach,
                        ps_int **ghost, ps_int *n_ghost, ps_ctx *ctx) {
  *ghost = NULL;
  *n_ghost = 0;
  if (part < 0 || part >= pt->parts || !(reach >= 0))
    return ps_error(ctx, PS_ERR_INPUT, "ghosts of part %d of %d within %g", part, pt->parts,
                    reach);
  ps_kdtree *tree = NULL;
  PS_CHECK(ps_kdtree_build(&tree, P->x, P->n, P->dim, ctx));
  unsigned char *mark = ps_calloc((size_t)P->n + 1, 1, ctx);
  ps_int *found = NULL, cap = 0, count = 0;
  int status = mark ? PS_OK : PS_ERR_NOMEM;
  for (ps_int j = pt->start[part]; j < pt->start[part + 1] && status == PS_OK; j++) {
    ps_int a = pt->order[j];
    status = ps_kdtree_radius(tree, &P->x[a * P->dim], reach, &found, &cap, &count, ctx);
    for (ps_int i = 0; status == PS_OK && i < count; i++) mark[found[i]] = 1;
  }
  if (status == PS_OK) status = marked_ghosts(pt, part, mark, ghost, n_ghost, ctx);
  free(found);
  free(mark);
  ps_kdtree_free(&tree);
  return status;
}

int ps_partition_ghost_hops(const ps_partition *pt, const ps_particles *P, int part, int hops,
                            double alpha, ps_int **ghost, ps_int *n_ghost, ps_ctx *ctx) {
  *ghost = NULL;
  *n_ghost = 0;
  if (part < 0 || part >= pt->parts || hops < 0 || !(alpha > 0))
    return ps_error(ctx, PS_ERR_INPUT, "ghosts of part %d of %d, %d hops, alpha %g", part,
                    pt->parts, hops, alpha);
  const int dim = P->dim;
  double hmax = 0.0;
  for (ps_int a = 0; a < P->n; a++) hmax = fmax(hmax, P->h[a]);
  ps_kdtree *tree = NULL;
  PS_CHECK(ps_kdtree_build(&tree, P->x, P->n, dim, ctx));
  unsigned char *mark = ps_calloc((size_t)P->n + 1, 1, ctx);
  ps_int *layer = ps_calloc((size_t)P->n + 1, sizeof *layer, ctx); /* this hop's, then the
                                                                      next's after it */
  ps_int *found = NULL, cap = 0, count = 0;
  int status = mark && layer ? PS_OK : PS_ERR_NOMEM;
  /* layer[l0, l1): the particles first reached at the last hop */
  ps_int l0 = 0, l1 = 0;
  for (ps_int j = pt->start[part]; status == PS_OK && j < pt->start[part + 1]; j++) {
    mark[pt->order[j]] = 1;
    layer[l1++] = pt->order[j];
  }
  for (int hop = 0; status == PS_OK && hop < hops; hop++) {
    ps_int end = l1;
    for (ps_int j = l0; status == PS_OK && j < end; j++) {
      ps_int a = layer[j];
      const double *xa = &P->x[a * dim];
      double ra = alpha * P->h[a];
      status = ps_kdtree_radius(tree, xa, alpha * hmax, &found, &cap, &count, ctx);
      for (ps_int i = 0; status == PS_OK && i < count; i++) {
        ps_int b = found[i];
        if (mark[b]) continue;
        double d2 = 0.0, rb = alpha * P->h[b];
        for (int k = 0; k < dim; k++) {
          double d = P->x[b * dim + k] - xa[k];
          d2 += d * d;
        }
        if (d2 < ra * ra || d2 < rb * rb) { /* an arm of the network (either end's query) */
          mark[b] = 1;
          layer[l1++] = b;
        }
      }
    }
    l0 = end;
  }
  if (status == PS_OK) status = marked_ghosts(pt, part, mark, ghost, n_ghost, ctx);
  free(found);
  free(mark);
  free(layer);
  ps_kdtree_free(&tree);
  return status;
}

void ps_partition_free(ps_partition *pt) {
  free(pt->order);
  free(pt->start);
  free(pt->part_of);
  memset(pt, 0, sizeof *pt);
}
