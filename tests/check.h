/* check.h: a tiny test harness in the spirit of gsl_test: NaN-safe
 * comparisons, one PASS/FAIL line per check, and a closing
 * "N passed, N failed" line from ps_check_summary(). */
#ifndef PS_CHECK_H
#define PS_CHECK_H

/* Pass when cond is true. Returns cond. */
int ps_check(int cond, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Pass when |got - want| <= rtol |want| (NaN fails). */
int ps_check_rel(double got, double want, double rtol, const char *what);
/* Pass when got <= limit (NaN fails). */
int ps_check_le(double got, double limit, const char *what);
/* Print "N passed, N failed"; returns the exit status (0 if none failed). */
int ps_check_summary(void);

#endif
