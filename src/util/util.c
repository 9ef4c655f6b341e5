/* util.c: context, error messages, logging, timers, atomic output files. */
#define _XOPEN_SOURCE 700
#include "ps_util.h"

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

void ps_ctx_init(ps_ctx *ctx) {
  ctx->msg[0] = '\0';
  ctx->verbosity = 1;
  ctx->log = stderr;
  ctx->comm = NULL;
}

int ps_error(ps_ctx *ctx, int status, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(ctx->msg, sizeof ctx->msg, fmt, ap);
  va_end(ap);
  return status;
}

int ps_trace(ps_ctx *ctx, int status, const char *file, int line) {
  if (ctx->verbosity >= 3) {
    size_t n = strlen(ctx->msg);
    if (n + 64 < sizeof ctx->msg)
      snprintf(ctx->msg + n, sizeof ctx->msg - n, "\n  (at %s:%d)", file, line);
  }
  return status;
}

void ps_log(const ps_ctx *ctx, int level, const char *fmt, ...) {
  if (ctx->verbosity < level || !ctx->log) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(ctx->log, fmt, ap);
  va_end(ap);
  fflush(ctx->log);
}

/* the memory-failure test's countdown (ps_alloc_countdown): the one
 * piece of process-wide state, untouched unless a test sets it */
static long alloc_left = -1, alloc_count = 0;

long ps_alloc_countdown(long n) {
  long made = alloc_count;
  alloc_left = n;
  alloc_count = 0;
  return made;
}

int ps_alloc_countdown_fails(void) {
  alloc_count++;
  if (alloc_left < 0) return 0;
  if (alloc_left == 0) return 1;
  alloc_left--;
  return 0;
}

void *ps_calloc(size_t count, size_t size, ps_ctx *ctx) {
  void *p = ps_alloc_countdown_fails() ? NULL : calloc(count ? count : 1, size ? size : 1);
  if (!p)
    ps_error(ctx, PS_ERR_NOMEM, "out of memory allocating %zu x %zu bytes",
             count, size);
  return p;
}

int ps_realloc(void **p, size_t count, size_t size, ps_ctx *ctx) {
  if (size && count > SIZE_MAX / size)
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory: %zu x %zu bytes overflow", count,
                    size);
  void *q = ps_alloc_countdown_fails() ? NULL : realloc(*p, (count ? count : 1) * size);
  if (!q)
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory growing to %zu x %zu bytes",
                    count, size);
  *p = q;
  return PS_OK;
}

double ps_wtime(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double ps_peak_mib(void) {
  struct rusage ru;
  if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
  return (double)ru.ru_maxrss / 1024.0; /* ru_maxrss is KiB on Linux */
}

int ps_outfile_open(ps_outfile *o, const char *path, ps_ctx *ctx) {
  if (strlen(path) >= sizeof o->path)
    return ps_error(ctx, PS_ERR_IO, "%s: output path too long", path);
  strcpy(o->path, path);
  snprintf(o->tmp, sizeof o->tmp, "%s.tmp", path);
  o->f = fopen(o->tmp, "w");
  if (!o->f)
    return ps_error(ctx, PS_ERR_IO, "%s: cannot open for writing: %s", o->tmp,
                    strerror(errno));
  return PS_OK;
}

int ps_outfile_commit(ps_outfile *o, ps_ctx *ctx) {
  int bad = ferror(o->f);
  if (fclose(o->f) != 0) bad = 1;
  o->f = NULL;
  if (bad) {
    unlink(o->tmp);
    return ps_error(ctx, PS_ERR_IO, "%s: write failed", o->path);
  }
  if (rename(o->tmp, o->path) != 0) {
    unlink(o->tmp);
    return ps_error(ctx, PS_ERR_IO, "%s: cannot rename from %s: %s", o->path,
                    o->tmp, strerror(errno));
  }
  return PS_OK;
}

void ps_outfile_abort(ps_outfile *o) {
  if (o->f) fclose(o->f);
  o->f = NULL;
  unlink(o->tmp);
}

void ps_fnv1a(uint64_t *h, const void *data, size_t n) {
  const unsigned char *c = data;
  uint64_t v = *h;
  for (size_t k = 0; k < n; k++) {
    v ^= c[k];
    v *= 1099511628211ULL;
  }
  *h = v;
}

int ps_state_add(ps_state_list *l, const char *name, void *data, size_t bytes, ps_ctx *ctx) {
  if (strlen(name) >= PS_STATE_NAME)
    return ps_error(ctx, PS_ERR_INTERNAL, "state item name '%s' too long", name);
  for (int k = 0; k < l->n; k++)
    if (!strcmp(l->item[k].name, name))
      return ps_error(ctx, PS_ERR_INTERNAL, "state item '%s' listed twice", name);
  if (l->n == l->cap) {
    int cap = l->cap ? 2 * l->cap : 32;
    void *p = l->item;
    PS_CHECK(ps_realloc(&p, (size_t)cap, sizeof *l->item, ctx));
    l->item = p;
    l->cap = cap;
  }
  ps_state_item *it = &l->item[l->n++];
  snprintf(it->name, sizeof it->name, "%s", name);
  it->data = data;
  it->bytes = bytes;
  return PS_OK;
}

void ps_state_list_free(ps_state_list *l) {
  free(l->item);
  l->item = NULL;
  l->n = l->cap = 0;
}

int ps_dense_cholesky(int m, double *A, double tol) {
  double dmax = 0.0;
  for (int i = 0; i < m; i++) dmax = fmax(dmax, A[i * m + i]);
  if (tol > 0 && !(dmax > 0)) return 0;
  for (int j = 0; j < m; j++) {
    double d = A[j * m + j];
    for (int q = 0; q < j; q++) d -= A[j * m + q] * A[j * m + q];
    if (!(d > tol * dmax)) return 0;
    A[j * m + j] = sqrt(d);
    for (int i = j + 1; i < m; i++) {
      double t = A[i * m + j];
      for (int q = 0; q < j; q++) t -= A[i * m + q] * A[j * m + q];
      A[i * m + j] = t / A[j * m + j];
    }
  }
  return 1;
}

void ps_dense_cholesky_solve(int m, const double *L, double *x) {
  for (int i = 0; i < m; i++) {
    double t = x[i];
    for (int q = 0; q < i; q++) t -= L[i * m + q] * x[q];
    x[i] = t / L[i * m + i];
  }
  for (int i = m - 1; i >= 0; i--) {
    double t = x[i];
    for (int q = i + 1; q < m; q++) t -= L[q * m + i] * x[q];
    x[i] = t / L[i * m + i];
  }
}
