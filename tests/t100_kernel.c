/* t100_kernel.c: the kernel of Eq. 112 (src/network), checked against
 * independent computations: GSL's normalisation Z = the closed form
 * (k = 2); Eq. 54 by our own Simpson rule (k = 3); f' = central
 * difference of f; support [0, alpha); invalid parameters refused. */
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "geomnet.h"

static void test_kernel(ps_ctx *ctx) {
  const double alpha = 5.1;
  for (int dim = 2; dim <= 3; dim++) {
    ps_kernel K;
    if (ps_kernel_init(&K, dim, 2, alpha, ctx)) tg_die("ps_kernel_init", ctx);
    /* tol 1e-12: qag with GAUSS61 integrates a polynomial of degree <= 6
     * exactly; what is left is round-off (~1e-15) */
    char what[128];
    snprintf(what, sizeof what, "kernel %dD k=2: GSL Z = closed form Z", dim);
    ps_check_rel(K.Z, ps_kernel_Z_k2(dim, alpha), 1e-12, what);
  }
  for (int dim = 2; dim <= 3; dim++) {
    ps_kernel K;
    if (ps_kernel_init(&K, dim, 3, alpha, ctx)) tg_die("ps_kernel_init", ctx);
    /* Eq. 54 by our own composite Simpson rule, 200000 intervals: the
     * integrand is a polynomial of degree 6 (2D) or 8 (3D) on [0, alpha],
     * truncation error ~ h^4 f''''/180 ~ 1e-20 relative; tol 1e-8 is
     * the brief's, leaves room for accumulated round-off (~1e-13). */
    int m = 200000;
    double hs = alpha / m;
    long double s = 0.0L;
    for (int i = 0; i <= m; i++) {
      double u = i * hs;
      double g = ps_kernel_f(&K, u) * 2.0 * (dim - 1) * M_PI * pow(u, dim - 1);
      double w = (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      s += (long double)w * g;
    }
    double integral = (double)(s * hs / 3.0L);
    char what[128];
    snprintf(what, sizeof what, "kernel %dD k=3: Simpson int f 2(N-1)pi u^(N-1) du = 1",
             dim);
    ps_check_rel(integral, 1.0, 1e-8, what);

    /* f' against a central difference with step 1e-5: truncation
     * h^2 f'''/6 ~ 1e-11 relative, round-off eps f/h ~ 1e-11; tol 1e-6 */
    const double us[] = {0.3, 1.0, 2.2, 3.7, 4.9};
    double worst = 0.0;
    for (size_t i = 0; i < sizeof us / sizeof *us; i++) {
      double u = us[i], dh = 1e-5;
      double fd = (ps_kernel_f(&K, u + dh) - ps_kernel_f(&K, u - dh)) / (2 * dh);
      double an = ps_kernel_df(&K, u);
      double e = fabs(an - fd) / fabs(fd);
      if (!(e <= worst)) worst = e; /* NaN-safe */
    }
    snprintf(what, sizeof what, "kernel %dD k=3: max rel |f' - central diff| at 5 u",
             dim);
    ps_check_le(worst, 1e-6, what);
    /* support: exact zeros at and beyond alpha (exact: a branch returns 0) */
    int zero = ps_kernel_f(&K, alpha) == 0.0 && ps_kernel_df(&K, alpha) == 0.0 &&
               ps_kernel_f(&K, 1.01 * alpha) == 0.0 &&
               ps_kernel_df(&K, 1.01 * alpha) == 0.0 &&
               ps_kernel_f(&K, 1e3 * alpha) == 0.0 &&
               ps_kernel_df(&K, 1e3 * alpha) == 0.0;
    ps_check(zero, "kernel %dD k=3: f and f' vanish for u >= alpha (exact)", dim);
    ps_check(ps_kernel_f(&K, 0.999 * alpha) > 0 && ps_kernel_df(&K, 0.5) < 0,
             "kernel %dD k=3: f > 0 and f' < 0 inside the support", dim);
  }
  ps_kernel K;
  ps_ctx quiet;
  ps_ctx_init(&quiet);
  ps_check(ps_kernel_init(&K, 2, 2, 0.0, &quiet) == PS_ERR_INPUT &&
               ps_kernel_init(&K, 2, 0, 5.1, &quiet) == PS_ERR_INPUT &&
               ps_kernel_init(&K, 4, 2, 5.1, &quiet) == PS_ERR_INPUT,
           "kernel: alpha <= 0, k < 1, dim 4 rejected with PS_ERR_INPUT");
}

int main(int argc, char **argv) {
  (void)argc;
  (void)argv;
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  double t0 = ps_wtime();
  test_kernel(&ctx);
  printf("t100_kernel: %.2f s in all (information only)\n", ps_wtime() - t0);
  return ps_check_summary();
}
