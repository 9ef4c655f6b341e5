/* geom.c: particle clouds: boxes and lattices, the elliptic crack disk of
 * Eq. 114, the analytical field of Eq. 116, sizes by Eq. 115 and Eq. 44. */
#include "ps_geom.h"

#include <complex.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_ellint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int ps_particles_alloc(ps_particles *p, int dim, ps_int n, ps_ctx *ctx) {
  memset(p, 0, sizeof *p);
  if (dim != 2 && dim != 3)
    return ps_error(ctx, PS_ERR_INPUT, "dimension must be 2 or 3 (got %d)", dim);
  if (n <= 0)
    return ps_error(ctx, PS_ERR_INPUT, "a cloud needs at least one particle");
  p->dim = dim;
  p->n = n;
  p->x = ps_calloc((size_t)(n * dim), sizeof *p->x, ctx);
  p->volume = ps_calloc((size_t)n, sizeof *p->volume, ctx);
  p->h = ps_calloc((size_t)n, sizeof *p->h, ctx);
  p->block = ps_calloc((size_t)n, sizeof *p->block, ctx);
  if (!p->x || !p->volume || !p->h || !p->block) {
    ps_particles_free(p);
    return PS_ERR_NOMEM;
  }
  return PS_OK;
}

/* particle a of src into place j of dst (dst may be src, j <= a): its
 * position, volume, size and block, and the disk's zones and a cloud's
 * lines where both clouds have them */
static void copy_particle(ps_particles *dst, ps_int j, const ps_particles *src, ps_int a) {
  int d = src->dim;
  for (int k = 0; k < d; k++) dst->x[j * d + k] = src->x[a * d + k];
  dst->volume[j] = src->volume[a];
  dst->h[j] = src->h[a];
  dst->block[j] = src->block[a];
  if (dst->zone_xi && src->zone_xi) dst->zone_xi[j] = src->zone_xi[a];
  if (dst->in_boundary_zone && src->in_boundary_zone)
    dst->in_boundary_zone[j] = src->in_boundary_zone[a];
  if (dst->line && src->line) dst->line[j] = src->line[a];
}

int ps_particles_subset(ps_particles *out, const ps_particles *P, const ps_int *ids, ps_int n,
                        ps_ctx *ctx) {
  PS_CHECK(ps_particles_alloc(out, P->dim, n, ctx));
  for (ps_int j = 0; j < n; j++) copy_particle(out, j, P, ids[j]);
  return PS_OK;
}

int ps_geom_cut_holes(ps_particles *p, const double (*holes)[4], int n, ps_ctx *ctx) {
  if (n == 0) return PS_OK;
  int dim = p->dim;
  if (dim != 2 && dim != 3) return ps_error(ctx, PS_ERR_INPUT, "holes: dimension %d", dim);
  ps_int m = 0;
  for (ps_int a = 0; a < p->n; a++) {
    const double *x = &p->x[a * dim];
    int inside = 0;
    for (int i = 0; i < n && !inside; i++) {
      const double *h = holes[i]; /* centre h[0..dim), radius h[dim] */
      if (dim == 2)
        inside = hypot(x[0] - h[0], x[1] - h[1]) < h[2];
      else
        inside = sqrt((x[0] - h[0]) * (x[0] - h[0]) + (x[1] - h[1]) * (x[1] - h[1]) +
                      (x[2] - h[2]) * (x[2] - h[2])) < h[3];
    }
    if (inside) continue;
    copy_particle(p, m++, p, a);
  }
  if (m == 0) return ps_error(ctx, PS_ERR_INPUT, "the holes remove every particle");
  p->n = m;
  return PS_OK;
}

void ps_particles_free(ps_particles *p) {
  free(p->x);
  free(p->volume);
  free(p->h);
  free(p->block);
  free(p->zone_xi);
  free(p->in_boundary_zone);
  free(p->source);
  free(p->line);
  memset(p, 0, sizeof *p);
}

const char *ps_particle_where(const ps_particles *p, ps_int a, char *buf, size_t len) {
  if (p->source && p->line && p->line_is_element)
    snprintf(buf, len, "%s: element %lld: particle %lld", p->source,
             (long long)p->line[a], (long long)a);
  else if (p->source && p->line)
    snprintf(buf, len, "%s:%lld: particle %lld", p->source, (long long)p->line[a],
             (long long)a);
  else
    snprintf(buf, len, "particle %lld", (long long)a);
  return buf;
}

const char *ps_particle_at(const ps_particles *p, ps_int a, char *buf, size_t len) {
  const double *x = &p->x[a * p->dim];
  if (p->dim == 3)
    snprintf(buf, len, "(%g, %g, %g)", x[0], x[1], x[2]);
  else
    snprintf(buf, len, "(%g, %g)", x[0], x[1]);
  return buf;
}

int ps_error_coincide(ps_ctx *ctx, const ps_particles *p, ps_int a, ps_int b) {
  if (a > b) {
    ps_int t = a;
    a = b;
    b = t;
  }
  char at[200];
  ps_particle_at(p, b, at, sizeof at);
  if (p->source && p->line && p->line_is_element)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: particles %lld and %lld coincide (at %s): the centroids of "
                    "elements %lld and %lld (overlapping elements?)",
                    p->source, (long long)a, (long long)b, at, (long long)p->line[a],
                    (long long)p->line[b]);
  if (p->source && p->line)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s:%lld: particles %lld and %lld coincide (at %s), the first at "
                    "line %lld: remove one",
                    p->source, (long long)p->line[b], (long long)a, (long long)b, at,
                    (long long)p->line[a]);
  return ps_error(ctx, PS_ERR_INPUT,
                  "particles %lld and %lld coincide (at %s): closer than %g of their "
                  "size (coordinates too large for their spacing?)",
                  (long long)a, (long long)b, at, PS_COINCIDE);
}

int ps_particles_check(const ps_particles *p, ps_ctx *ctx) {
  char w[1200];
  for (ps_int a = 0; a < p->n; a++)
    for (int k = 0; k < p->dim; k++)
      if (!isfinite(p->x[a * p->dim + k]))
        return ps_error(ctx, PS_ERR_INPUT, "%s: coordinate %c is not finite (%g)",
                        ps_particle_where(p, a, w, sizeof w), "xyz"[k],
                        p->x[a * p->dim + k]);
  return PS_OK;
}

double ps_geom_row_spacing(const char *lattice, double d) {
  return strcmp(lattice, "hex") == 0 ? d * sqrt(3.0) / 2.0 : d;
}

int ps_geom_box(ps_particles *p, int dim, const ps_int counts[3], double d,
                const char *lattice, double jitter, unsigned long seed,
                ps_ctx *ctx) {
  int hex = 0;
  if (strcmp(lattice, "hex") == 0)
    hex = 1;
  else if (strcmp(lattice, "square") != 0)
    return ps_error(ctx, PS_ERR_INPUT,
                    "lattice must be \"square\" or \"hex\" (got \"%s\")", lattice);
  if (hex && dim != 2)
    return ps_error(ctx, PS_ERR_INPUT, "the hex lattice is 2D only");
  if (!(d > 0))
    return ps_error(ctx, PS_ERR_INPUT, "spacing must be > 0 (got %g)", d);
  if (!(jitter >= 0 && jitter < 0.5))
    return ps_error(ctx, PS_ERR_INPUT, "jitter must be in [0, 0.5) (got %g)", jitter);
  ps_int n = 1;
  for (int k = 0; k < dim; k++) {
    if (counts[k] < 1)
      return ps_error(ctx, PS_ERR_INPUT, "particle count along axis %d must be >= 1", k);
    if (counts[k] > ((ps_int)1 << 40) / n)
      return ps_error(ctx, PS_ERR_INPUT, "too many particles (counts along axis %d)", k);
    n *= counts[k];
  }
  PS_CHECK(ps_particles_alloc(p, dim, n, ctx));
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  if (!rng) {
    ps_particles_free(p);
    return ps_error(ctx, PS_ERR_NOMEM, "cannot allocate RNG");
  }
  gsl_rng_set(rng, seed);
  double dy = ps_geom_row_spacing(lattice, d);
  double vol = hex ? d * dy : pow(d, dim);
  ps_int a = 0;
  ps_int nz = dim == 3 ? counts[2] : 1;
  for (ps_int kz = 0; kz < nz; kz++)
    for (ps_int j = 0; j < counts[1]; j++)
      for (ps_int i = 0; i < counts[0]; i++, a++) {
        double *x = &p->x[a * dim];
        x[0] = (i + 0.5) * d + (hex && (j % 2) ? 0.5 * d : 0.0);
        x[1] = (j + 0.5) * dy;
        if (dim == 3) x[2] = (kz + 0.5) * d;
        if (jitter > 0)
          for (int k = 0; k < dim; k++)
            x[k] += jitter * d * (2.0 * gsl_rng_uniform(rng) - 1.0);
        p->volume[a] = vol;
      }
  gsl_rng_free(rng);
  return PS_OK;
}

void ps_disk_params_default(ps_disk_params *dp) {
  dp->c = 1.0 / 24.0;
  dp->n_eta = 20;
  dp->n_xi = 40;
  dp->per_zone = 5;
  dp->xi_min = -M_PI;
  dp->xi_max = M_PI;
  dp->jitter = 0.1;
  dp->seed = 11;
  dp->refine_tips = 1;
  dp->refine_radius = 0.0;
}

/* the split of sub-cell (ci, cj) of the disk: refine_tips when its centre
 * (without jitter) lies within refine_radius of a tip, else 1 */
static int disk_split(const ps_disk_params *dp, ps_int ci, ps_int cj, double dxi, double deta) {
  if (dp->refine_tips <= 1 || !(dp->refine_radius > 0)) return 1;
  double xi = dp->xi_min + (ci + 0.5) * dxi, eta = (cj + 0.5) * deta;
  double x = dp->c * cosh(xi) * cos(eta), y = dp->c * sinh(xi) * sin(eta);
  double r = fmin(hypot(x - dp->c, y), hypot(x + dp->c, y));
  return r < dp->refine_radius ? dp->refine_tips : 1;
}

double ps_geom_disk_count(const ps_disk_params *dp) {
  int m = dp->per_zone;
  double n = (double)dp->n_eta * dp->n_xi * m * m;
  if (dp->refine_tips <= 1 || !(dp->refine_radius > 0)) return n;
  double dxi = (dp->xi_max - dp->xi_min) / ((double)dp->n_xi * m);
  double deta = M_PI / ((double)dp->n_eta * m);
  for (ps_int ci = 0; ci < (ps_int)dp->n_xi * m; ci++)
    for (ps_int cj = 0; cj < (ps_int)dp->n_eta * m; cj++) {
      int k = disk_split(dp, ci, cj, dxi, deta);
      n += (double)k * k - 1.0;
    }
  return n;
}

/* int sinh^2 and int sin^2 (antiderivatives) */
static double Ish2(double t) { return 0.25 * sinh(2 * t) - 0.5 * t; }
static double Isn2(double t) { return 0.5 * t - 0.25 * sin(2 * t); }

int ps_geom_disk(ps_particles *p, const ps_disk_params *dp, ps_ctx *ctx) {
  if (!(dp->c > 0))
    return ps_error(ctx, PS_ERR_INPUT, "disk.c must be > 0 (got %g)", dp->c);
  if (dp->n_eta < 1 || dp->n_xi < 3 || dp->per_zone < 1)
    return ps_error(ctx, PS_ERR_INPUT,
                    "disk needs n_eta >= 1, n_xi >= 3, per_zone >= 1");
  if (!(dp->xi_min < 0 && dp->xi_max > 0))
    return ps_error(ctx, PS_ERR_INPUT,
                    "disk xi range must contain 0 (the crack): got (%g, %g)",
                    dp->xi_min, dp->xi_max);
  if (!(dp->jitter >= 0 && dp->jitter < 0.5))
    return ps_error(ctx, PS_ERR_INPUT, "disk.jitter must be in [0, 0.5) (got %g)",
                    dp->jitter);
  int m = dp->per_zone;
  if (dp->refine_tips < 1 || !(dp->refine_radius >= 0))
    return ps_error(ctx, PS_ERR_INPUT,
                    "disk: refine_tips must be >= 1 and refine_radius >= 0 (got %d, %g)",
                    dp->refine_tips, dp->refine_radius);
  if ((double)dp->n_eta * dp->n_xi * m * m * dp->refine_tips * dp->refine_tips >
      (double)((ps_int)1 << 40))
    return ps_error(ctx, PS_ERR_INPUT, "disk: too many particles");
  {
    /* the crack (xi = 0) must fall on a sub-cell boundary, else a row of
     * particles straddles it (or sits on it and bridges the crack) */
    double cells = -dp->xi_min / ((dp->xi_max - dp->xi_min) / ((double)dp->n_xi * m));
    if (fabs(cells - floor(cells + 0.5)) > 1e-9)
      return ps_error(ctx, PS_ERR_INPUT,
                      "disk: xi = 0 (the crack) must lie on a sub-cell boundary: with "
                      "xi in (%g, %g), n_xi * per_zone = %.0f puts it %.3g cells from "
                      "xi_min (use an even n_xi * per_zone for a symmetric range)",
                      dp->xi_min, dp->xi_max, (double)dp->n_xi * m, cells);
  }
  ps_int n = (ps_int)ps_geom_disk_count(dp);
  PS_CHECK(ps_particles_alloc(p, 2, n, ctx));
  p->zone_xi = ps_calloc((size_t)n, sizeof *p->zone_xi, ctx);
  p->in_boundary_zone = ps_calloc((size_t)n, 1, ctx);
  if (!p->zone_xi || !p->in_boundary_zone) {
    ps_particles_free(p);
    return PS_ERR_NOMEM;
  }
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937), *rng2 = gsl_rng_alloc(gsl_rng_mt19937);
  if (!rng || !rng2) {
    if (rng) gsl_rng_free(rng);
    if (rng2) gsl_rng_free(rng2);
    ps_particles_free(p);
    return ps_error(ctx, PS_ERR_NOMEM, "cannot allocate RNG");
  }
  gsl_rng_set(rng, dp->seed);
  gsl_rng_set(rng2, dp->seed + 1);
  double dxi = (dp->xi_max - dp->xi_min) / ((double)dp->n_xi * m);
  double deta = M_PI / ((double)dp->n_eta * m);
  double c2 = dp->c * dp->c;
  ps_int a = 0;
  for (int zi = 0; zi < dp->n_xi; zi++)
    for (int zj = 0; zj < dp->n_eta; zj++)
      for (int si = 0; si < m; si++)
        for (int sj = 0; sj < m; sj++) {
          ps_int ci = (ps_int)zi * m + si, cj = (ps_int)zj * m + sj;
          int k = disk_split(dp, ci, cj, dxi, deta);
          double hxi = dxi / k, heta = deta / k, r1 = 0.0, r2 = 0.0;
          if (dp->jitter > 0) { /* the sub-cell's draws, refined or not, so
                                   that the unrefined cells are the
                                   unrefined disk's */
            r1 = gsl_rng_uniform(rng);
            r2 = gsl_rng_uniform(rng);
          }
          for (int ki = 0; ki < k; ki++)
            for (int kj = 0; kj < k; kj++, a++) {
              double xi0 = dp->xi_min + ci * dxi + ki * hxi, eta0 = cj * deta + kj * heta;
              double xi = xi0 + 0.5 * hxi, eta = eta0 + 0.5 * heta;
              if (dp->jitter > 0) {
                if (k > 1) { /* the refined cells' own stream */
                  r1 = gsl_rng_uniform(rng2);
                  r2 = gsl_rng_uniform(rng2);
                }
                xi += dp->jitter * hxi * (2.0 * r1 - 1.0);
                eta += dp->jitter * heta * (2.0 * r2 - 1.0);
              }
              p->x[2 * a] = dp->c * cosh(xi) * cos(eta);
              p->x[2 * a + 1] = dp->c * sinh(xi) * sin(eta);
              /* exact area of the cell: c^2 int int (sinh^2 xi + sin^2 eta) */
              p->volume[a] = c2 * ((Ish2(xi0 + hxi) - Ish2(xi0)) * heta +
                                   (Isn2(eta0 + heta) - Isn2(eta0)) * hxi);
              p->zone_xi[a] = zi;
              p->in_boundary_zone[a] = (zi == 0 || zi == dp->n_xi - 1);
            }
        }
  gsl_rng_free(rng);
  gsl_rng_free(rng2);
  return PS_OK;
}

void ps_geom_elliptic_coords(double x, double y, double c, double *xi,
                             double *eta) {
  double complex z = cacosh((x + I * y) / c); /* Re >= 0, Im in [-pi, pi] */
  *xi = creal(z);
  *eta = cimag(z);
}

void ps_geom_eq116(double x, double y, double c, double S, double G,
                   double kappa, double *u, double *v) {
  double xi, eta;
  ps_geom_elliptic_coords(x, y, c, &xi, &eta);
  double sh = sinh(xi), ch = cosh(xi), sn = sin(eta), cs = cos(eta);
  double den = ch * ch - cs * cs;
  double fac = kappa - (den > 0 ? (sh * sh - sn * sn) / den : -1.0);
  double pre = S * c / (4.0 * G);
  /* u - i v = pre (sinh xi cos eta - i cosh xi sin eta) fac */
  *u = pre * sh * cs * fac;
  *v = pre * ch * sn * fac;
}

double ps_geom_ellipse_perimeter(double c, double xi) {
  double a = c * cosh(xi);
  double e = 1.0 / cosh(xi); /* eccentricity: foci at +-c */
  gsl_sf_result r;
  if (gsl_sf_ellint_Ecomp_e(e, GSL_PREC_DOUBLE, &r) != GSL_SUCCESS) return NAN;
  return 4.0 * a * r.val;
}

int ps_geom_sizes_eq115(ps_particles *p, int n_nearest, ps_ctx *ctx) {
  if (n_nearest < 1 || n_nearest > 64)
    return ps_error(ctx, PS_ERR_INPUT, "size_neighbours must be in 1..64 (got %d)",
                    n_nearest);
  if (p->n < n_nearest + 1)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s%sEq. 115 with n = %d needs at least %d particles (have %lld)",
                    p->source ? p->source : "", p->source ? ": " : "", n_nearest,
                    n_nearest + 1, (long long)p->n);
  PS_CHECK(ps_particles_check(p, ctx));
  ps_kdtree *t = NULL;
  PS_CHECK(ps_kdtree_build(&t, p->x, p->n, p->dim, ctx));
  ps_int idx[64];
  double dist[64];
  int k = n_nearest;
  int status = PS_OK;
  for (ps_int a = 0; a < p->n; a++) {
    int f = ps_kdtree_knn(t, a, k, idx, dist);
    double s = 0.0;
    for (int j = 0; j < f; j++) s += dist[j];
    /* the nearest closer than PS_COINCIDE of the size it would give */
    if (!(dist[0] > PS_COINCIDE * s / (2.0 * k))) {
      status = ps_error_coincide(ctx, p, a, idx[0]);
      break;
    }
    p->h[a] = s / (2.0 * k); /* Eq. 115 */
  }
  ps_kdtree_free(&t);
  return status;
}

void ps_geom_sizes_eq44(ps_particles *p) {
  int N = p->dim;
  for (ps_int a = 0; a < p->n; a++)
    p->h[a] = pow(N * p->volume[a] / (2.0 * (N - 1) * M_PI), 1.0 / N);
}
