/* post.c: damage, boundary stress, crack tip, strain fit, RMS error, line
 * fit. */
#include "ps_post.h"

#include <gsl/gsl_fit.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit.h>
#include <math.h>
#include <string.h>

void ps_post_damage(const ps_network *net, const ps_arm_state *st,
                    double *phi) {
  for (ps_int a = 0; a < net->n_particle; a++) {
    ps_int intact = 0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++)
      intact += !st->broken[net->fam_arm[k]];
    phi[a] = net->n_arm0[a] ? 1.0 - (double)intact / (double)net->n_arm0[a] : 0.0;
  }
}

static int measured(const double *m, ps_int a, int d) {
  for (int k = 0; k < d; k++)
    if (m[a * d + k] != 0.0) return 1;
  return 0;
}

double ps_post_boundary_stress(const ps_network *net, const double *T,
                               const double *q, const double *m,
                               double length) {
  int d = net->dim;
  double s = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (T[i] == 0.0) continue;
    ps_int a = net->a[i], b = net->b[i];
    int ma = measured(m, a, d), mb = measured(m, b, d);
    if (ma == mb) continue;
    /* zone particle z, interior particle o: the arm pulls o towards z */
    ps_int z = ma ? a : b;
    double sgn = ma ? -1.0 : 1.0; /* e_{o->z} = -q if z = a, +q if z = b */
    double proj = 0;
    for (int k = 0; k < d; k++) proj += sgn * q[i * d + k] * m[z * d + k];
    s += T[i] * proj;
  }
  return length > 0 ? s / length : 0.0;
}

double ps_post_crack_tip(const ps_particles *P, const ps_network *net,
                         const ps_arm_state *st, double c) {
  double tip = 1.0;
  int d = P->dim;
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (!st->broken[i]) continue;
    double r2 = 0;
    for (int k = 0; k < d; k++) {
      double m = 0.5 * (P->x[net->a[i] * d + k] + P->x[net->b[i] * d + k]);
      r2 += m * m;
    }
    double r = sqrt(r2) / c;
    if (r > tip) tip = r;
  }
  return tip;
}

void ps_post_stress_tensor(const ps_particles *P, const ps_network *net,
                           const double *T, const double *q, double *sigma) {
  int d = P->dim;
  memset(sigma, 0, (size_t)(P->n * d * d) * sizeof *sigma);
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (T[i] == 0.0) continue;
    ps_int a = net->a[i], b = net->b[i];
    /* F_ab (x) (X_b - X_a) is the same for both ends: (-F) (x) (-dX) */
    for (int r = 0; r < d; r++)
      for (int c = 0; c < d; c++) {
        double v = T[i] * q[i * d + r] * (P->x[b * d + c] - P->x[a * d + c]);
        sigma[a * d * d + r * d + c] += v;
        sigma[b * d * d + r * d + c] += v;
      }
  }
  for (ps_int a = 0; a < P->n; a++)
    for (int k = 0; k < d * d; k++) sigma[a * d * d + k] /= 2.0 * P->volume[a];
}

void ps_post_displacement_gradient(const ps_particles *P, const ps_network *net,
                                   const ps_arm_state *st, const double *u, double *H) {
  int d = P->dim;
  gsl_error_handler_t *old = gsl_set_error_handler_off(); /* a singular M gives H = 0 */
  for (ps_int a = 0; a < P->n; a++) {
    double M[9] = {0}, B[9] = {0}; /* M = sum w dX dX^T, B = sum w dU dX^T */
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k];
      if (st && st->broken[i]) continue;
      ps_int b = net->a[i] == a ? net->b[i] : net->a[i];
      double w = 1.0 / (net->r0[i] * net->r0[i]), dX[3], dU[3];
      for (int j = 0; j < d; j++) {
        dX[j] = P->x[b * d + j] - P->x[a * d + j];
        dU[j] = u[b * d + j] - u[a * d + j];
      }
      for (int r = 0; r < d; r++)
        for (int c = 0; c < d; c++) {
          M[r * d + c] += w * dX[r] * dX[c];
          B[r * d + c] += w * dU[r] * dX[c];
        }
    }
    /* H M = B, M symmetric: solve M h_r = b_r for each row r of H */
    double *Ha = &H[a * d * d];
    memset(Ha, 0, (size_t)(d * d) * sizeof *Ha);
    gsl_matrix_view Mv = gsl_matrix_view_array(M, (size_t)d, (size_t)d);
    int bad = gsl_linalg_cholesky_decomp1(&Mv.matrix) != 0;
    for (int r = 0; r < d && !bad; r++) {
      gsl_vector_view bv = gsl_vector_view_array(&B[r * d], (size_t)d);
      gsl_vector_view hv = gsl_vector_view_array(&Ha[r * d], (size_t)d);
      bad = gsl_linalg_cholesky_solve(&Mv.matrix, &bv.vector, &hv.vector) != 0;
    }
    if (bad) memset(Ha, 0, (size_t)(d * d) * sizeof *Ha);
  }
  gsl_set_error_handler(old);
}

/* 2D strain energy density sigma_ij u_i,j / 2 of particle a */
static double energy_density_2d(const double *sigma, const double *H, ps_int a) {
  const double *s = &sigma[4 * a], *h = &H[4 * a];
  return 0.5 * (s[0] * h[0] + s[1] * h[1] + s[2] * h[2] + s[3] * h[3]);
}

/* distance from the tip in the max norm (square contours) */
static double rho_tip(const ps_particles *P, ps_int a, const double *tip) {
  return fmax(fabs(P->x[2 * a] - tip[0]), fabs(P->x[2 * a + 1] - tip[1]));
}

double ps_post_j_domain(const ps_particles *P, const double *sigma, const double *H,
                        const double *tip, double l_in, double l_out) {
  double J = 0.0, w = l_out - l_in;
  for (ps_int a = 0; a < P->n; a++) {
    double dx = P->x[2 * a] - tip[0], dy = P->x[2 * a + 1] - tip[1];
    double rho = rho_tip(P, a, tip);
    if (rho <= l_in || rho >= l_out) continue; /* grad q = 0 */
    double gq[2] = {0, 0}; /* q = (l_out - rho) / w */
    if (fabs(dx) >= fabs(dy))
      gq[0] = -(dx > 0 ? 1.0 : -1.0) / w;
    else
      gq[1] = -(dy > 0 ? 1.0 : -1.0) / w;
    const double *s = &sigma[4 * a], *h = &H[4 * a]; /* h[j*2 + k] = du_j/dx_k */
    double W = energy_density_2d(sigma, H, a);
    for (int i = 0; i < 2; i++) {
      double t = s[i * 2 + 0] * h[0 * 2 + 0] + s[i * 2 + 1] * h[1 * 2 + 0]; /* sigma_ij u_j,1 */
      if (i == 0) t -= W;
      J += t * gq[i] * P->volume[a];
    }
  }
  return J;
}

double ps_post_j_contour(const ps_particles *P, const ps_network *net, const double *T,
                         const double *q, const double *sigma, const double *H,
                         const double *tip, double l, double dx) {
  double Jw = 0.0, Jt = 0.0;
  for (ps_int a = 0; a < P->n; a++) { /* W n_x ds on the vertical sides */
    double ax = fabs(P->x[2 * a] - tip[0]), ay = fabs(P->x[2 * a + 1] - tip[1]);
    if (fabs(ax - l) >= dx || ay >= l) continue;
    double W = energy_density_2d(sigma, H, a);
    /* hat weight: 1/2 each for the two columns beside a contour between
     * them, 1 for a column on the contour */
    double hat = 1.0 - fabs(ax - l) / dx;
    Jw += hat * W * (P->x[2 * a] > tip[0] ? 1.0 : -1.0) * dx;
  }
  for (ps_int i = 0; i < net->n_arm; i++) { /* arms across the contour */
    if (T[i] == 0.0) continue;
    ps_int a = net->a[i], b = net->b[i];
    double ra = rho_tip(P, a, tip), rb = rho_tip(P, b, tip);
    if ((ra < l) == (rb < l)) continue;
    ps_int k = ra < l ? a : b, m = ra < l ? b : a;
    double sg = k == a ? 1.0 : -1.0; /* q runs a -> b: the force on k is T q_km */
    for (int j = 0; j < 2; j++)
      Jt += sg * T[i] * q[2 * i + j] * 0.5 * (H[4 * k + 2 * j] + H[4 * m + 2 * j]);
  }
  return Jw - Jt;
}

int ps_post_fit_strain(const ps_particles *P, const double *u,
                       const unsigned char *mask, double *eps, ps_ctx *ctx) {
  int d = P->dim;
  ps_int m = 0;
  for (ps_int a = 0; a < P->n; a++) m += mask[a] != 0;
  if (m < d + 1)
    return ps_error(ctx, PS_ERR_INPUT, "strain fit needs >= %d particles (got %lld)",
                    d + 1, (long long)m);
  gsl_matrix *X = gsl_matrix_alloc((size_t)m, (size_t)d + 1);
  gsl_vector *y = gsl_vector_alloc((size_t)m), *c = gsl_vector_alloc((size_t)d + 1);
  gsl_matrix *cov = gsl_matrix_alloc((size_t)d + 1, (size_t)d + 1);
  gsl_multifit_linear_workspace *w = gsl_multifit_linear_alloc((size_t)m, (size_t)d + 1);
  if (!X || !y || !c || !cov || !w) {
    gsl_matrix_free(X);
    gsl_vector_free(y);
    gsl_vector_free(c);
    gsl_matrix_free(cov);
    if (w) gsl_multifit_linear_free(w);
    return ps_error(ctx, PS_ERR_NOMEM, "strain fit: out of memory");
  }
  double H[9];
  ps_int r = 0;
  for (ps_int a = 0; a < P->n; a++) {
    if (!mask[a]) continue;
    gsl_matrix_set(X, (size_t)r, 0, 1.0);
    for (int k = 0; k < d; k++) gsl_matrix_set(X, (size_t)r, (size_t)k + 1, P->x[a * d + k]);
    r++;
  }
  for (int i = 0; i < d; i++) {
    r = 0;
    for (ps_int a = 0; a < P->n; a++)
      if (mask[a]) gsl_vector_set(y, (size_t)r++, u[a * d + i]);
    double chisq;
    gsl_multifit_linear(X, y, c, cov, &chisq, w);
    for (int j = 0; j < d; j++) H[i * d + j] = gsl_vector_get(c, (size_t)j + 1);
  }
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) eps[i * d + j] = 0.5 * (H[i * d + j] + H[j * d + i]);
  gsl_matrix_free(X);
  gsl_vector_free(y);
  gsl_vector_free(c);
  gsl_matrix_free(cov);
  gsl_multifit_linear_free(w);
  return PS_OK;
}

double ps_post_rms_error(int dim, ps_int n, const double *u,
                         const double *u_ref, const unsigned char *mask) {
  double num = 0, den = 0;
  for (ps_int a = 0; a < n; a++) {
    if (mask && !mask[a]) continue;
    for (int k = 0; k < dim; k++) {
      double e = u[a * dim + k] - u_ref[a * dim + k];
      num += e * e;
      den += u_ref[a * dim + k] * u_ref[a * dim + k];
    }
  }
  return den > 0 ? sqrt(num / den) : sqrt(num);
}

int ps_post_line_fit(const double *x, const double *y, int n, double *slope,
                     double *intercept, double *r2, ps_ctx *ctx) {
  if (n < 2)
    return ps_error(ctx, PS_ERR_INPUT, "a line fit needs at least 2 points (got %d)", n);
  double c0, c1, cov00, cov01, cov11, sumsq;
  gsl_fit_linear(x, 1, y, 1, (size_t)n, &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  double mean = 0, tss = 0;
  for (int i = 0; i < n; i++) mean += y[i] / n;
  for (int i = 0; i < n; i++) tss += (y[i] - mean) * (y[i] - mean);
  *slope = c1;
  *intercept = c0;
  *r2 = tss > 0 ? 1.0 - sumsq / tss : 1.0;
  return PS_OK;
}
