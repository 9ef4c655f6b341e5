/* kdtree.c: a static k-d tree (median splits on the widest axis, leaves of
 * up to 8 points) for radius and k-nearest queries. Fast whatever the
 * spread of particle sizes, since it adapts to point density. */
#include "ps_geom.h"

#include <math.h>
#include <stdlib.h>

#define LEAF 8

typedef struct node {
  ps_int lo, hi;    /* points perm[lo..hi) */
  int axis;         /* split axis, -1 for a leaf */
  double split;     /* split coordinate */
  ps_int left, right;
  double bmin[3], bmax[3]; /* bounding box */
} node;

struct ps_kdtree {
  const double *x;
  ps_int n;
  int dim;
  ps_int *perm;
  node *nodes;
  ps_int n_nodes;
};

static double coord(const ps_kdtree *t, ps_int i, int k) {
  return t->x[t->perm[i] * t->dim + k];
}

/* nth_element on perm[lo..hi) by axis: quickselect. */
static void select_k(ps_kdtree *t, ps_int lo, ps_int hi, ps_int k, int axis) {
  while (hi - lo > 1) {
    ps_int mid = lo + (hi - lo) / 2;
    double pivot = coord(t, mid, axis);
    ps_int i = lo, j = hi - 1;
    while (i <= j) {
      while (coord(t, i, axis) < pivot) i++;
      while (coord(t, j, axis) > pivot) j--;
      if (i <= j) {
        ps_int s = t->perm[i];
        t->perm[i] = t->perm[j];
        t->perm[j] = s;
        i++;
        j--;
      }
    }
    if (k <= j)
      hi = j + 1;
    else if (k >= i)
      lo = i;
    else
      return;
  }
}

static ps_int build(ps_kdtree *t, ps_int lo, ps_int hi) {
  ps_int id = t->n_nodes++;
  node *nd = &t->nodes[id];
  nd->lo = lo;
  nd->hi = hi;
  for (int k = 0; k < t->dim; k++) {
    nd->bmin[k] = INFINITY;
    nd->bmax[k] = -INFINITY;
  }
  for (ps_int i = lo; i < hi; i++)
    for (int k = 0; k < t->dim; k++) {
      double c = coord(t, i, k);
      if (c < nd->bmin[k]) nd->bmin[k] = c;
      if (c > nd->bmax[k]) nd->bmax[k] = c;
    }
  if (hi - lo <= LEAF) {
    nd->axis = -1;
    return id;
  }
  int axis = 0;
  for (int k = 1; k < t->dim; k++)
    if (nd->bmax[k] - nd->bmin[k] > nd->bmax[axis] - nd->bmin[axis]) axis = k;
  ps_int mid = lo + (hi - lo) / 2;
  select_k(t, lo, hi, mid, axis);
  double split = coord(t, mid, axis);
  ps_int l = build(t, lo, mid);
  ps_int r = build(t, mid, hi);
  nd = &t->nodes[id]; /* (array not reallocated, but keep it clear) */
  nd->axis = axis;
  nd->split = split;
  nd->left = l;
  nd->right = r;
  return id;
}

int ps_kdtree_build(ps_kdtree **tree, const double *x, ps_int n, int dim,
                    ps_ctx *ctx) {
  ps_kdtree *t = ps_calloc(1, sizeof *t, ctx);
  if (!t) return PS_ERR_NOMEM;
  t->x = x;
  t->n = n;
  t->dim = dim;
  t->perm = ps_calloc((size_t)n, sizeof *t->perm, ctx);
  t->nodes = ps_calloc((size_t)(2 * (n / (LEAF / 2) + 1) + 8), sizeof *t->nodes, ctx);
  if (!t->perm || !t->nodes) {
    ps_kdtree_free(&t);
    return PS_ERR_NOMEM;
  }
  for (ps_int i = 0; i < n; i++) t->perm[i] = i;
  if (n > 0) build(t, 0, n);
  *tree = t;
  return PS_OK;
}

void ps_kdtree_free(ps_kdtree **tree) {
  if (!tree || !*tree) return;
  free((*tree)->perm);
  free((*tree)->nodes);
  free(*tree);
  *tree = NULL;
}

/* squared distance from q to the node's bounding box */
static double box_d2(const ps_kdtree *t, const node *nd, const double *q) {
  double s = 0.0;
  for (int k = 0; k < t->dim; k++) {
    double d = 0.0;
    if (q[k] < nd->bmin[k])
      d = nd->bmin[k] - q[k];
    else if (q[k] > nd->bmax[k])
      d = q[k] - nd->bmax[k];
    s += d * d;
  }
  return s;
}

static double pt_d2(const ps_kdtree *t, ps_int i, const double *q) {
  const double *p = &t->x[i * t->dim];
  double s = 0.0;
  for (int k = 0; k < t->dim; k++) s += (p[k] - q[k]) * (p[k] - q[k]);
  return s;
}

int ps_kdtree_radius(const ps_kdtree *t, const double *q, double radius,
                     ps_int **out, ps_int *cap, ps_int *count, ps_ctx *ctx) {
  ps_int stack[128];
  int sp = 0;
  double r2 = radius * radius;
  *count = 0;
  if (t->n == 0) return PS_OK;
  stack[sp++] = 0;
  while (sp > 0) {
    const node *nd = &t->nodes[stack[--sp]];
    if (box_d2(t, nd, q) >= r2) continue;
    if (nd->axis < 0) {
      for (ps_int i = nd->lo; i < nd->hi; i++) {
        ps_int p = t->perm[i];
        if (pt_d2(t, p, q) < r2) {
          if (*count >= *cap) {
            ps_int nc = *cap ? 2 * *cap : 64;
            PS_CHECK(ps_realloc((void **)out, (size_t)nc, sizeof **out, ctx));
            *cap = nc;
          }
          (*out)[(*count)++] = p;
        }
      }
    } else {
      stack[sp++] = nd->left;
      stack[sp++] = nd->right;
    }
  }
  return PS_OK;
}

/* squared distance from q to the farthest corner of the node's box */
static double box_far_d2(const ps_kdtree *t, const node *nd, const double *q) {
  double s = 0.0;
  for (int k = 0; k < t->dim; k++) {
    double d = fmax(fabs(q[k] - nd->bmin[k]), fabs(nd->bmax[k] - q[k]));
    s += d * d;
  }
  return s;
}

ps_int ps_kdtree_count(const ps_kdtree *t, const double *q, double radius, ps_int cap) {
  ps_int stack[128], count = 0;
  int sp = 0;
  double r2 = radius * radius;
  if (t->n == 0 || !(radius > 0)) return 0;
  stack[sp++] = 0;
  while (sp > 0 && count < cap) {
    const node *nd = &t->nodes[stack[--sp]];
    if (box_d2(t, nd, q) >= r2) continue;
    if (box_far_d2(t, nd, q) < r2) { /* the whole box is inside the ball */
      count += nd->hi - nd->lo;
    } else if (nd->axis < 0) {
      for (ps_int i = nd->lo; i < nd->hi; i++) count += pt_d2(t, t->perm[i], q) < r2;
    } else {
      stack[sp++] = nd->left;
      stack[sp++] = nd->right;
    }
  }
  return count < cap ? count : cap;
}

int ps_kdtree_knn(const ps_kdtree *t, ps_int i, int k, ps_int *idx,
                  double *dist) {
  const double *q = &t->x[i * t->dim];
  int found = 0;
  ps_int stack[128];
  int sp = 0;
  for (int j = 0; j < k; j++) dist[j] = INFINITY; /* squared while searching */
  if (t->n == 0) return 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const node *nd = &t->nodes[stack[--sp]];
    double worst = found < k ? INFINITY : dist[k - 1];
    if (box_d2(t, nd, q) >= worst) continue;
    if (nd->axis < 0) {
      for (ps_int m = nd->lo; m < nd->hi; m++) {
        ps_int p = t->perm[m];
        if (p == i) continue;
        double d2 = pt_d2(t, p, q);
        if (found == k && d2 >= dist[k - 1]) continue;
        int j = found < k ? found++ : k - 1;
        while (j > 0 && dist[j - 1] > d2) {
          dist[j] = dist[j - 1];
          idx[j] = idx[j - 1];
          j--;
        }
        dist[j] = d2;
        idx[j] = p;
      }
    } else {
      /* visit the nearer child last so it is popped first */
      double dq = q[nd->axis] - nd->split;
      if (dq < 0) {
        stack[sp++] = nd->right;
        stack[sp++] = nd->left;
      } else {
        stack[sp++] = nd->left;
        stack[sp++] = nd->right;
      }
    }
  }
  for (int j = 0; j < found; j++) dist[j] = sqrt(dist[j]);
  return found;
}
