/* network.c: kernel (Eq. 112/113, Eq. 54), neighbour search by k-d tree,
 * arm rule r < alpha max(h_a, h_b), pre-crack cuts (the test: crack.c),
 * weights (Eq. 70). */
#include "ps_network.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  int dim, k;
  double alpha;
} zpar;

static double z_integrand(double u, void *vp) {
  const zpar *zp = vp;
  double s = 1.0 - u * u / (zp->alpha * zp->alpha);
  return gsl_pow_int(s, zp->k) * 2.0 * (zp->dim - 1) * M_PI *
         gsl_pow_int(u, zp->dim - 1);
}

int ps_kernel_init(ps_kernel *K, int dim, int k, double alpha, ps_ctx *ctx) {
  if (dim != 2 && dim != 3)
    return ps_error(ctx, PS_ERR_INPUT, "kernel: dimension must be 2 or 3");
  if (!(alpha > 0))
    return ps_error(ctx, PS_ERR_INPUT, "kernel.alpha must be > 0 (got %g)", alpha);
  if (k < 1)
    return ps_error(ctx, PS_ERR_INPUT, "kernel.k must be >= 1 (got %d)", k);
  K->dim = dim;
  K->k = k;
  K->alpha = alpha;
  zpar zp = {dim, k, alpha};
  gsl_function F = {z_integrand, &zp};
  gsl_integration_workspace *w = gsl_integration_workspace_alloc(200);
  if (!w) return ps_error(ctx, PS_ERR_NOMEM, "kernel: no memory for quadrature");
  double res, err;
  int rc = gsl_integration_qag(&F, 0.0, alpha, 0.0, 1e-13, 200,
                               GSL_INTEG_GAUSS61, w, &res, &err);
  gsl_integration_workspace_free(w);
  if (rc != GSL_SUCCESS || !(res > 0) || !isfinite(res))
    return ps_error(ctx, PS_ERR_INPUT,
                    "kernel.alpha = %g, kernel.k = %d: the normalisation of Eq. 54 "
                    "(quadrature) failed (%s): alpha or k too large",
                    alpha, k, rc != GSL_SUCCESS ? gsl_strerror(rc) : "not a finite positive number");
  K->Z = res;
  return PS_OK;
}

double ps_kernel_Z_k2(int dim, double alpha) {
  double N = dim;
  return 2.0 * (N - 1) * M_PI * pow(alpha, N) *
         (1.0 / N - 2.0 / (N + 2) + 1.0 / (N + 4));
}

double ps_kernel_f(const ps_kernel *K, double u) {
  if (u >= K->alpha) return 0.0;
  double s = 1.0 - u * u / (K->alpha * K->alpha);
  return gsl_pow_int(s, K->k) / K->Z;
}

double ps_kernel_df(const ps_kernel *K, double u) {
  if (u >= K->alpha) return 0.0;
  double a2 = K->alpha * K->alpha;
  double s = 1.0 - u * u / a2;
  return K->k * gsl_pow_int(s, K->k - 1) * (-2.0 * u / a2) / K->Z;
}

typedef struct {
  ps_int a, b;
} pair;

static int cmp_pair(const void *u, const void *v) {
  const pair *p = u, *q = v;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return 0;
}

void ps_network_free(ps_network *net) {
  free(net->a);
  free(net->b);
  free(net->r0);
  free(net->A_ab);
  free(net->A_ba);
  free(net->fam_ptr);
  free(net->fam_arm);
  free(net->n_arm0);
  memset(net, 0, sizeof *net);
}

/* Sizes, volumes and coordinates must be finite, sizes and volumes > 0. */
static int check_particles(const ps_particles *p, double *hmin, double *hmax,
                           ps_ctx *ctx) {
  char w[1200];
  *hmin = INFINITY;
  *hmax = 0;
  PS_CHECK(ps_particles_check(p, ctx));
  for (ps_int a = 0; a < p->n; a++) {
    if (!(p->h[a] > 0) || !isfinite(p->h[a]))
      return ps_error(ctx, PS_ERR_INPUT, "%s: size h must be > 0 (got %g)",
                      ps_particle_where(p, a, w, sizeof w), p->h[a]);
    if (!(p->volume[a] > 0) || !isfinite(p->volume[a]))
      return ps_error(ctx, PS_ERR_INPUT, "%s: volume must be > 0 (got %g)",
                      ps_particle_where(p, a, w, sizeof w), p->volume[a]);
    if (p->h[a] < *hmin) *hmin = p->h[a];
    if (p->h[a] > *hmax) *hmax = p->h[a];
  }
  return PS_OK;
}

/* The arm candidates (a < b, sorted, unique) into *pairs[*np]: every
 * particle finds the others inside its own horizon alpha h_a; the union
 * of both directions gives the rule r < alpha max(h_a, h_b). Pairs whose
 * segment a crack cuts are left out. Each particle tests only the cracks
 * whose bounding box (ps_crack_bounds) meets its horizon's (a cut point
 * lies on both the arm, inside the horizon, and the crack), widened by a
 * margin far above round-off: the cracks left out cannot cut, so the
 * network is the same (16 holes, 1,040 segments: each particle tests a
 * few). */
static int collect_pairs(const ps_particles *p, const ps_kernel *K,
                         const ps_crack *cracks, int n_cracks, pair **pairs,
                         ps_int *np_out, ps_ctx *ctx) {
  int status = PS_OK, dim = p->dim;
  ps_kdtree *tree = NULL;
  ps_int *nb = NULL, cap = 0, cnt = 0, np = 0, pcap = 0;
  int *near = NULL, n_near = 0;
  if (n_cracks > 0) {
    near = ps_calloc((size_t)n_cracks, sizeof *near, ctx);
    if (!near) return PS_ERR_NOMEM;
  }
  PS_CHECK_GOTO(ps_kdtree_build(&tree, p->x, p->n, dim, ctx));
  for (ps_int a = 0; a < p->n; a++) {
    const double *xa = &p->x[a * dim];
    double R = K->alpha * p->h[a];
    PS_CHECK_GOTO(ps_kdtree_radius(tree, xa, R, &nb, &cap, &cnt, ctx));
    /* the cracks that may cut an arm of a */
    double Rm = 1.01 * R, lo[3], hi[3];
    for (int k = 0; k < dim; k++) Rm += 1e-9 * fabs(xa[k]);
    n_near = 0;
    for (int c = 0; c < n_cracks; c++) {
      ps_crack_bounds(&cracks[c], dim, lo, hi);
      int away = 0;
      for (int k = 0; k < dim && !away; k++)
        away = lo[k] > xa[k] + Rm || hi[k] < xa[k] - Rm;
      if (!away) near[n_near++] = c;
    }
    for (ps_int j = 0; j < cnt; j++) {
      ps_int b = nb[j];
      if (b == a) continue;
      int cut = 0;
      for (int c = 0; c < n_near && !cut; c++)
        cut = ps_crack_cuts(&cracks[near[c]], xa, &p->x[b * dim]);
      if (cut) continue;
      if (np >= pcap) {
        pcap = pcap ? 2 * pcap : 1024;
        PS_CHECK_GOTO(ps_realloc((void **)pairs, (size_t)pcap, sizeof **pairs, ctx));
      }
      (*pairs)[np].a = a < b ? a : b;
      (*pairs)[np].b = a < b ? b : a;
      np++;
    }
  }
  if (np > 0) qsort(*pairs, (size_t)np, sizeof **pairs, cmp_pair);
  ps_int na = 0;
  for (ps_int i = 0; i < np; i++)
    if (i == 0 || cmp_pair(&(*pairs)[i], &(*pairs)[i - 1]) != 0) (*pairs)[na++] = (*pairs)[i];
  *np_out = na;
cleanup:
  ps_kdtree_free(&tree);
  free(nb);
  free(near);
  return status;
}

/* The arms of the sorted pairs: lengths, weights (Eq. 70), family counts;
 * a pair closer than PS_COINCIDE max(h_a, h_b) (or not finite) is an
 * error naming it. */
static int fill_arms(ps_network *net, const ps_particles *p, const ps_kernel *K,
                     const pair *pairs, ps_ctx *ctx) {
  int dim = p->dim;
  double N1 = dim + 1;
  for (ps_int i = 0; i < net->n_arm; i++) {
    ps_int a = pairs[i].a, b = pairs[i].b;
    double r2 = 0, dmax = 0;
    for (int k = 0; k < dim; k++) {
      double d = p->x[b * dim + k] - p->x[a * dim + k];
      r2 += d * d;
      dmax = fmax(dmax, fabs(d));
    }
    double r = sqrt(r2);
    if (!isfinite(r2) && isfinite(dmax)) { /* the squares overflowed: scale */
      double s2 = 0;
      for (int k = 0; k < dim; k++) {
        double d = (p->x[b * dim + k] - p->x[a * dim + k]) / dmax;
        s2 += d * d;
      }
      r = dmax * sqrt(s2);
    }
    if (!isfinite(r) || !isfinite(dmax))
      return ps_error(ctx, PS_ERR_INPUT,
                      "particles %lld and %lld: their distance overflows (coordinates "
                      "beyond 1e150 m?)",
                      (long long)a, (long long)b);
    if (!(r > PS_COINCIDE * fmax(p->h[a], p->h[b])))
      return ps_error_coincide(ctx, p, a, b);
    net->a[i] = a;
    net->b[i] = b;
    net->r0[i] = r;
    /* A_ab = -V_a V_b f'(r/h_a)/h_a^(N+1): Eq. 70 with m = rho V */
    net->A_ab[i] = -p->volume[a] * p->volume[b] * ps_kernel_df(K, r / p->h[a]) /
                   pow(p->h[a], N1);
    net->A_ba[i] = -p->volume[a] * p->volume[b] * ps_kernel_df(K, r / p->h[b]) /
                   pow(p->h[b], N1);
    net->fam_ptr[a + 1]++;
    net->fam_ptr[b + 1]++;
  }
  return PS_OK;
}

/* Families: arms are sorted by (a, b), so for each particle the arms come
 * ordered by the other end once the "b-side" ones (other end a < b, in
 * increasing a) are placed first, then those where it is the a end. */
static int fill_families(ps_network *net, ps_ctx *ctx) {
  ps_int n = net->n_particle, na = net->n_arm;
  for (ps_int a = 0; a < n; a++) {
    net->n_arm0[a] = net->fam_ptr[a + 1];
    net->fam_ptr[a + 1] += net->fam_ptr[a];
  }
  ps_int *pos = ps_calloc((size_t)n, sizeof *pos, ctx);
  if (!pos) return PS_ERR_NOMEM;
  for (ps_int a = 0; a < n; a++) pos[a] = net->fam_ptr[a];
  for (ps_int i = 0; i < na; i++) net->fam_arm[pos[net->b[i]]++] = i;
  for (ps_int i = 0; i < na; i++) net->fam_arm[pos[net->a[i]]++] = i;
  free(pos);
  return PS_OK;
}

/* ps_network_build, the first n_checked particles required to have arms */
static int build(ps_network *net, const ps_particles *p, const ps_kernel *K,
                 const ps_crack *cracks, int n_cracks, ps_int n_checked, ps_ctx *ctx) {
  int status = PS_OK, dim = p->dim;
  pair *pairs = NULL;
  ps_int na = 0;
  double hmin, hmax;
  char w[1200];
  memset(net, 0, sizeof *net);
  if (K->dim != dim)
    return ps_error(ctx, PS_ERR_INPUT, "kernel dimension %d differs from the cloud's %d",
                    K->dim, dim);
  PS_CHECK(check_particles(p, &hmin, &hmax, ctx));
  PS_CHECK(ps_cracks_check(cracks, n_cracks, dim, ctx));
  PS_CHECK_GOTO(collect_pairs(p, K, cracks, n_cracks, &pairs, &na, ctx));
  if (na == 0) {
    status = ps_error(ctx, PS_ERR_INPUT,
                      "no arms: the horizon holds no neighbours; alpha too small or "
                      "particles too far apart (%lld particles, alpha %g, sizes h %g .. %g)",
                      (long long)p->n, K->alpha, hmin, hmax);
    goto cleanup;
  }
  net->dim = dim;
  net->n_particle = p->n;
  net->n_arm = na;
  net->max_h_ratio = hmax / hmin;
  net->a = ps_calloc((size_t)na, sizeof *net->a, ctx);
  net->b = ps_calloc((size_t)na, sizeof *net->b, ctx);
  net->r0 = ps_calloc((size_t)na, sizeof *net->r0, ctx);
  net->A_ab = ps_calloc((size_t)na, sizeof *net->A_ab, ctx);
  net->A_ba = ps_calloc((size_t)na, sizeof *net->A_ba, ctx);
  net->fam_ptr = ps_calloc((size_t)p->n + 1, sizeof *net->fam_ptr, ctx);
  net->fam_arm = ps_calloc((size_t)(2 * na), sizeof *net->fam_arm, ctx);
  net->n_arm0 = ps_calloc((size_t)p->n, sizeof *net->n_arm0, ctx);
  if (!net->a || !net->b || !net->r0 || !net->A_ab || !net->A_ba ||
      !net->fam_ptr || !net->fam_arm || !net->n_arm0) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  PS_CHECK_GOTO(fill_arms(net, p, K, pairs, ctx));
  PS_CHECK_GOTO(fill_families(net, ctx));
  for (ps_int a = 0; a < n_checked; a++)
    if (net->n_arm0[a] == 0) {
      char at[200];
      status = ps_error(ctx, PS_ERR_INPUT,
                        "%s at %s has no arms: it lies farther than alpha h from "
                        "every other particle",
                        ps_particle_where(p, a, w, sizeof w),
                        ps_particle_at(p, a, at, sizeof at));
      goto cleanup;
    }
cleanup:
  free(pairs);
  if (status < 0) ps_network_free(net);
  return status;
}

int ps_network_build(ps_network *net, const ps_particles *p,
                     const ps_kernel *K, const ps_crack *cracks, int n_cracks,
                     ps_ctx *ctx) {
  return build(net, p, K, cracks, n_cracks, p->n, ctx);
}

int ps_network_build_local(ps_network *net, const ps_particles *p, const ps_kernel *K,
                           const ps_crack *cracks, int n_cracks, ps_int n_owned,
                           ps_ctx *ctx) {
  return build(net, p, K, cracks, n_cracks, n_owned, ctx);
}
