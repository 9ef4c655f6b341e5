/* t950_nomem.c: the memory-failure sweep (in the style of CSparse's Tcov
 * malloc tests). A small case is run once to fracture (case file, setup,
 * network, solver, breaking rounds, outputs) while counting allocations;
 * then it is run again once per allocation with that allocation made to
 * fail (ps_alloc_countdown; SuiteSparse's allocator is wrapped onto the
 * same countdown). Each run must either end with PS_ERR_NOMEM and an
 * "out of memory" message, or recover (a fallback path) and give the
 * reference result: the same fracture flag, broken arms and sigma_failure
 * to 1e-6 (a fallback may change the linear solves, not the converged
 * states beyond the Newton tolerance 1e-8). Never a crash, never a silent
 * different answer. Leaks are found by LeakSanitizer in the sanitizer
 * build (make check-sanitize), which runs this program too.
 *
 * PS_NOMEM_STRIDE=k tests every k-th allocation (default: all of them;
 * make check uses the stride that keeps it under a minute). */
#include "check.h"
#include "app/ps_app.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <SuiteSparse_config.h>

#ifndef PS_TEST_DATA
#error "PS_TEST_DATA must name the tests/data directory"
#endif

static long n_ss; /* SuiteSparse's allocations in the reference run */
static void *ss_malloc(size_t n) {
  n_ss++;
  return ps_alloc_countdown_fails() ? NULL : malloc(n);
}
static void *ss_calloc(size_t n, size_t s) {
  n_ss++;
  return ps_alloc_countdown_fails() ? NULL : calloc(n, s);
}
static void *ss_realloc(void *p, size_t n) {
  n_ss++;
  return ps_alloc_countdown_fails() ? NULL : realloc(p, n);
}

/* The whole of `peristatic run CASE -o out`: load, set up, run. */
static int whole_run(const char *path, const char *out, ps_run_result *res, ps_ctx *ctx) {
  static ps_case cs; /* large: not on the stack */
  static ps_problem pb;
  ps_case_defaults(&cs);
  memset(res, 0, sizeof *res);
  PS_CHECK(ps_case_load(&cs, path, ctx));
  int status = ps_problem_setup(&pb, &cs, ctx);
  ps_case_free(&cs); /* pb has its own copy */
  if (status < 0) return status;
  pb.threads = 1;
  status = ps_run(&pb, pb.mat.delta, out, res, ctx);
  ps_problem_free(&pb);
  return status;
}

int main(void) {
  const char *path = PS_TEST_DATA "/nomem/tiny-fracture.yaml";
  const char *out = "t950_tmp/out";
  const char *s = getenv("PS_NOMEM_STRIDE");
  long stride = s ? atol(s) : 1;
  if (stride < 1) stride = 1;
  SuiteSparse_config.malloc_func = ss_malloc;
  SuiteSparse_config.calloc_func = ss_calloc;
  SuiteSparse_config.realloc_func = ss_realloc;

  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  ps_run_result ref, r;
  ps_alloc_countdown(-1);
  int st = whole_run(path, out, &ref, &ctx);
  long total = ps_alloc_countdown(-1);
  if (!ps_check(st == PS_OK && ref.fractured && ref.arms_broken > 0,
                "reference run fractures (status %d, %lld arms broken): %s", st,
                (long long)ref.arms_broken, ctx.msg))
    return ps_check_summary();
  ps_check(total >= 200 && n_ss > 0 && n_ss < total,
           "the run makes %ld allocations (%ld ours, %ld SuiteSparse's)", total, total - n_ss,
           n_ss);

  long tried = 0, nomem = 0, recovered = 0, bad = 0;
  for (long n = 0; n < total; n += stride) {
    ps_ctx_init(&ctx);
    ctx.verbosity = 0;
    ps_alloc_countdown(n);
    st = whole_run(path, out, &r, &ctx);
    ps_alloc_countdown(-1);
    tried++;
    int ok;
    if (st == PS_ERR_NOMEM) {
      ok = strstr(ctx.msg, "out of memory") != NULL;
      nomem += ok;
    } else if (st == PS_OK) {
      ok = r.fractured == ref.fractured && r.arms_broken == ref.arms_broken &&
           fabs(r.sigma_peak - ref.sigma_peak) <= 1e-6 * fabs(ref.sigma_peak);
      recovered += ok;
    } else {
      ok = 0;
    }
    if (!ok && ++bad <= 10)
      ps_check(0, "allocation %ld made to fail: status %d, %lld arms broken, sigma %.10g "
                  "(reference %lld, %.10g), message \"%s\"",
               n, st, (long long)r.arms_broken, r.sigma_peak, (long long)ref.arms_broken,
               ref.sigma_peak, ctx.msg);
  }
  ps_check(bad == 0,
           "each of %ld failing allocations (every %ld of %ld) ends with PS_ERR_NOMEM and "
           "'out of memory' (%ld) or recovers with the reference result (%ld); %ld did not",
           tried, stride, total, nomem, recovered, bad);
  /* the countdown is off again: the same run gives the same answer */
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  st = whole_run(path, out, &r, &ctx);
  ps_check(st == PS_OK && r.arms_broken == ref.arms_broken && r.sigma_peak == ref.sigma_peak,
           "after the sweep the run gives the reference result again (%lld arms, %.10g)",
           (long long)r.arms_broken, r.sigma_peak);
  return ps_check_summary();
}
