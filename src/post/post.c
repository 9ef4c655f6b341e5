/* post.c: damage, boundary stress, crack tip, PD stress tensor,
 * displacement gradient, J (domain and contour forms) and K_I, K_II (the
 * interaction integral) in the crack-tip frame, strain fit, RMS error,
 * line fit. */
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
                               double length, const unsigned char *own_arm) {
  int d = net->dim;
  double s = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (T[i] == 0.0 || (own_arm && !own_arm[i])) continue;
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
                         const ps_arm_state *st, double c, const unsigned char *own_arm) {
  double tip = 1.0;
  int d = P->dim;
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (!st->broken[i] || (own_arm && !own_arm[i])) continue;
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

/* The crack-tip frame: e1 = dir (unit, along the crack into the material
 * ahead of the tip), e2 = e1 rotated by +90 degrees; R has rows e1, e2. */
typedef struct tip_frame {
  double x0, y0, c, s; /* tip, e1 = (c, s) */
} tip_frame;

static tip_frame make_frame(const double *tip, const double *dir) {
  tip_frame f = {tip[0], tip[1], 1.0, 0.0};
  if (dir) {
    double n = hypot(dir[0], dir[1]);
    if (n > 0) {
      f.c = dir[0] / n;
      f.s = dir[1] / n;
    }
  }
  return f;
}

/* local coordinates of particle a: x1 = (x - tip) . e1, x2 = (x - tip) . e2 */
static void local_xy(const tip_frame *f, const ps_particles *P, ps_int a, double *x1,
                     double *x2) {
  double dx = P->x[2 * a] - f->x0, dy = P->x[2 * a + 1] - f->y0;
  *x1 = f->c * dx + f->s * dy;
  *x2 = -f->s * dx + f->c * dy;
}

/* a vector in the local frame: v' = R v */
static void local_vec(const tip_frame *f, const double *v, double *vl) {
  vl[0] = f->c * v[0] + f->s * v[1];
  vl[1] = -f->s * v[0] + f->c * v[1];
}

/* a 2x2 tensor (row-major) in the local frame: A' = R A R^T (sigma and
 * du_j/dx_k alike; the identity frame reproduces A exactly) */
static void local_tensor(const tip_frame *f, const double *A, double *Al) {
  const double R[4] = {f->c, f->s, -f->s, f->c};
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      Al[2 * i + j] = R[2 * i] * (A[0] * R[2 * j] + A[1] * R[2 * j + 1]) +
                      R[2 * i + 1] * (A[2] * R[2 * j] + A[3] * R[2 * j + 1]);
}

/* distance from the tip in the max norm of the local frame (square
 * contours aligned with the crack) */
static double rho_local(const tip_frame *f, const ps_particles *P, ps_int a) {
  double x1, x2;
  local_xy(f, P, a, &x1, &x2);
  return fmax(fabs(x1), fabs(x2));
}

/* the gradient of the trapezoidal q (1 for rho <= l_in, 0 for rho >=
 * l_out, linear in between) at local (x1, x2), in the local frame; 0 when
 * outside the ring */
static int q_gradient(double x1, double x2, double l_in, double l_out, double *gq) {
  double rho = fmax(fabs(x1), fabs(x2)), w = l_out - l_in;
  gq[0] = gq[1] = 0.0;
  if (rho <= l_in || rho >= l_out) return 0;
  if (fabs(x1) >= fabs(x2))
    gq[0] = -(x1 > 0 ? 1.0 : -1.0) / w;
  else
    gq[1] = -(x2 > 0 ? 1.0 : -1.0) / w;
  return 1;
}

double ps_post_j_domain_dir(const ps_particles *P, const double *sigma, const double *H,
                            const double *tip, const double *dir, double l_in,
                            double l_out) {
  tip_frame f = make_frame(tip, dir);
  double J = 0.0;
  for (ps_int a = 0; a < P->n; a++) {
    double x1, x2, gq[2], s[4], h[4]; /* h[j*2 + k] = du_j/dx_k, local */
    local_xy(&f, P, a, &x1, &x2);
    if (!q_gradient(x1, x2, l_in, l_out, gq)) continue;
    local_tensor(&f, &sigma[4 * a], s);
    local_tensor(&f, &H[4 * a], h);
    double W = energy_density_2d(sigma, H, a); /* invariant */
    for (int i = 0; i < 2; i++) {
      double t = s[i * 2 + 0] * h[0 * 2 + 0] + s[i * 2 + 1] * h[1 * 2 + 0]; /* sigma_ij u_j,1 */
      if (i == 0) t -= W;
      J += t * gq[i] * P->volume[a];
    }
  }
  return J;
}

double ps_post_j_domain(const ps_particles *P, const double *sigma, const double *H,
                        const double *tip, double l_in, double l_out) {
  return ps_post_j_domain_dir(P, sigma, H, tip, NULL, l_in, l_out);
}

double ps_post_j_contour_dir(const ps_particles *P, const ps_network *net, const double *T,
                             const double *q, const double *sigma, const double *H,
                             const double *tip, const double *dir, double l, double dx) {
  tip_frame f = make_frame(tip, dir);
  double Jw = 0.0, Jt = 0.0;
  for (ps_int a = 0; a < P->n; a++) { /* W n_1 ds on the sides x1 = +-l */
    double x1, x2;
    local_xy(&f, P, a, &x1, &x2);
    double ax = fabs(x1), ay = fabs(x2);
    if (fabs(ax - l) >= dx || ay >= l) continue;
    double W = energy_density_2d(sigma, H, a);
    /* hat weight: 1/2 each for the two columns beside a contour between
     * them, 1 for a column on the contour */
    double hat = 1.0 - fabs(ax - l) / dx;
    Jw += hat * W * (x1 > 0 ? 1.0 : -1.0) * dx;
  }
  for (ps_int i = 0; i < net->n_arm; i++) { /* arms across the contour */
    if (T[i] == 0.0) continue;
    ps_int a = net->a[i], b = net->b[i];
    double ra = rho_local(&f, P, a), rb = rho_local(&f, P, b);
    if ((ra < l) == (rb < l)) continue;
    ps_int k = ra < l ? a : b, m = ra < l ? b : a;
    double sg = k == a ? 1.0 : -1.0; /* q runs a -> b: the force on k is T q_km */
    double F[2], Fl[2], hk[4], hm[4];
    for (int j = 0; j < 2; j++) F[j] = sg * T[i] * q[2 * i + j];
    local_vec(&f, F, Fl);
    local_tensor(&f, &H[4 * k], hk);
    local_tensor(&f, &H[4 * m], hm);
    for (int j = 0; j < 2; j++) Jt += Fl[j] * 0.5 * (hk[2 * j] + hm[2 * j]);
  }
  return Jw - Jt;
}

double ps_post_j_contour(const ps_particles *P, const ps_network *net, const double *T,
                         const double *q, const double *sigma, const double *H,
                         const double *tip, double l, double dx) {
  return ps_post_j_contour_dir(P, net, T, q, sigma, H, tip, NULL, l, dx);
}

void ps_post_williams(int mode, double x1, double x2, double E, double nu, int plane,
                      double *sig, double *Hu) {
  double mu = E / (2.0 * (1.0 + nu));
  double kappa = plane == PS_PLANE_STRESS ? (3.0 - nu) / (1.0 + nu) : 3.0 - 4.0 * nu;
  double r = hypot(x1, x2), th = atan2(x2, x1);
  double c = cos(0.5 * th), s = sin(0.5 * th), c3 = cos(1.5 * th), s3 = sin(1.5 * th);
  double ct = cos(th), st = sin(th);
  double A = 1.0 / sqrt(2.0 * M_PI * r);      /* stresses, K = 1 */
  double C = 1.0 / (2.0 * mu * sqrt(2.0 * M_PI)); /* u = C sqrt(r) f(theta) */
  double f[2], fp[2]; /* f_j(theta) and df_j/dtheta */
  if (mode == 1) {
    sig[0] = A * c * (1.0 - s * s3);
    sig[3] = A * c * (1.0 + s * s3);
    sig[1] = sig[2] = A * s * c * c3;
    f[0] = C * c * (kappa - 1.0 + 2.0 * s * s);
    fp[0] = C * (-0.5 * s * (kappa - 1.0 + 2.0 * s * s) + 2.0 * s * c * c);
    f[1] = C * s * (kappa + 1.0 - 2.0 * c * c);
    fp[1] = C * (0.5 * c * (kappa + 1.0 - 2.0 * c * c) + 2.0 * s * s * c);
  } else {
    sig[0] = -A * s * (2.0 + c * c3);
    sig[3] = A * s * c * c3;
    sig[1] = sig[2] = A * c * (1.0 - s * s3);
    f[0] = C * s * (kappa + 1.0 + 2.0 * c * c);
    fp[0] = C * (0.5 * c * (kappa + 1.0 + 2.0 * c * c) - 2.0 * s * s * c);
    f[1] = -C * c * (kappa - 1.0 - 2.0 * s * s);
    fp[1] = -C * (-0.5 * s * (kappa - 1.0 - 2.0 * s * s) - 2.0 * s * c * c);
  }
  /* u_j = sqrt(r) f_j: d/dx1 = cos th d/dr - sin th / r d/dth, d/dx2 =
   * sin th d/dr + cos th / r d/dth */
  double sr = sqrt(r);
  for (int j = 0; j < 2; j++) {
    Hu[2 * j + 0] = (ct * 0.5 * f[j] - st * fp[j]) / sr;
    Hu[2 * j + 1] = (st * 0.5 * f[j] + ct * fp[j]) / sr;
  }
}

void ps_post_k_interaction(const ps_particles *P, const double *sigma, const double *H,
                           const double *tip, const double *dir, double l_in, double l_out,
                           double E, double nu, int plane, double *K) {
  tip_frame f = make_frame(tip, dir);
  double I[2] = {0.0, 0.0};
  for (ps_int a = 0; a < P->n; a++) {
    double x1, x2, gq[2], s[4], h[4];
    local_xy(&f, P, a, &x1, &x2);
    if (!q_gradient(x1, x2, l_in, l_out, gq)) continue;
    local_tensor(&f, &sigma[4 * a], s);
    local_tensor(&f, &H[4 * a], h);
    for (int mode = 1; mode <= 2; mode++) {
      double sa[4], ha[4];
      ps_post_williams(mode, x1, x2, E, nu, plane, sa, ha);
      double Wint = 0.0; /* the cross term of W = sigma_ij u_i,j / 2 */
      for (int k = 0; k < 4; k++) Wint += 0.5 * (s[k] * ha[k] + sa[k] * h[k]);
      for (int i = 0; i < 2; i++) {
        double t = s[2 * i] * ha[0] + s[2 * i + 1] * ha[2] + sa[2 * i] * h[0] +
                   sa[2 * i + 1] * h[2]; /* sigma_ij u^aux_j,1 + sigma^aux_ij u_j,1 */
        if (i == 0) t -= Wint;
        I[mode - 1] += t * gq[i] * P->volume[a];
      }
    }
  }
  double Ep = plane == PS_PLANE_STRESS ? E : E / (1.0 - nu * nu);
  K[0] = 0.5 * Ep * I[0];
  K[1] = 0.5 * Ep * I[1];
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
