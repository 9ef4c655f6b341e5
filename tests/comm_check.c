/* comm_check.c: the MPI implementation of ps_comm (ps_parallel_comm,
 * src/linsolve/petsc.c), run by t990_petsc.sh as `mpiexec -n P
 * tests/comm_check` (P = 1, 2, 3). Rank r contributes values whose sum,
 * maximum and minimum over the P ranks have closed forms (exact in
 * floating point: small integers and halves); every rank checks every
 * result and prints one line, "comm_check: rank r of P: ok" or the first
 * difference; exit 0 when all agree. */
#include "linsolve/ps_linsolve.h"

#include <stdio.h>

static int failures = 0;
static void expect(int rank, const char *what, double got, double want) {
  if (got == want) return;
  if (!failures) printf("comm_check: rank %d: %s = %.17g, want %.17g\n", rank, what, got, want);
  failures++;
}

int main(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_comm c;
  if (ps_parallel_init(NULL, &ctx) || ps_parallel_comm(&c, &ctx)) {
    printf("comm_check: %s\n", ctx.msg);
    return 1;
  }
  const int r = c.rank;
  const double P = c.size;
  expect(r, "size", P, ps_parallel_size());
  double s[3] = {r + 1, -(r + 1), 0.5 * r};
  ps_comm_sum(&c, s, 3);
  expect(r, "sum of r + 1", s[0], P * (P + 1) / 2);
  expect(r, "sum of -(r + 1)", s[1], -P * (P + 1) / 2);
  expect(r, "sum of r / 2", s[2], P * (P - 1) / 4);
  double m[2] = {r, -r};
  ps_comm_max(&c, m, 2);
  expect(r, "max of r", m[0], P - 1);
  expect(r, "max of -r", m[1], 0);
  double n[2] = {r, -r};
  ps_comm_min(&c, n, 2);
  expect(r, "min of r", n[0], 0);
  expect(r, "min of -r", n[1], -(P - 1));
  expect(r, "sum1 of 1", ps_comm_sum1(&c, 1.0), P);
  expect(r, "count of r", (double)ps_comm_count(&c, r), P * (P - 1) / 2);
  expect(r, "any of (last rank)", ps_comm_any(&c, r == c.size - 1), 1);
  expect(r, "any of 0", ps_comm_any(&c, 0), 0);
  if (!failures) printf("comm_check: rank %d of %d: ok\n", r, c.size);
  ps_parallel_finalize();
  return failures != 0;
}
