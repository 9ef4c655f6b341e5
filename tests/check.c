/* check.c: see check.h. */
#include "check.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

static int n_pass, n_fail;

static int report(int ok, const char *fmt, va_list ap) {
  printf("%s: ", ok ? "PASS" : "FAIL");
  vprintf(fmt, ap);
  printf("\n");
  fflush(stdout);
  if (ok)
    n_pass++;
  else
    n_fail++;
  return ok;
}

static int reportf(int ok, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  report(ok, fmt, ap);
  va_end(ap);
  return ok;
}

int ps_check(int cond, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  report(cond != 0, fmt, ap);
  va_end(ap);
  return cond != 0;
}

int ps_check_rel(double got, double want, double rtol, const char *what) {
  double err = fabs(got - want);
  int ok = isfinite(got) && err <= rtol * fabs(want);
  return reportf(ok, "%s: got %.10g, want %.10g (rel err %.3g, tol %.3g)", what, got,
                 want, want != 0 ? err / fabs(want) : err, rtol);
}

int ps_check_le(double got, double limit, const char *what) {
  int ok = isfinite(got) && got <= limit;
  return reportf(ok, "%s: %.6g <= %.6g", what, got, limit);
}

int ps_check_summary(void) {
  printf("%d passed, %d failed\n", n_pass, n_fail);
  return n_fail ? 1 : 0;
}
