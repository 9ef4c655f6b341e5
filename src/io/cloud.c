/* cloud.c: point clouds from text files, one particle per line:
 * "x y [z] volume [block]" (dim coordinates, the volume in m^N, then an
 * optional integer block id >= 0). '#' starts a comment; blank lines are
 * skipped. Numbers are plain decimal (ps_is_decimal). Errors name the
 * file, the line and the offending field; the particles keep their file
 * and lines (ps_particles.source, .line) for later messages. Memory comes
 * from ps_calloc/ps_realloc only, and a read or memory error is never
 * taken for the end of the file. */
#include "ps_io.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Per-particle arrays grown while reading. */
typedef struct cloud_buf {
  double *x, *volume;
  int *block;
  ps_int *line;
  ps_int n, cap;
} cloud_buf;

/* Make room for one more particle (capacity doubles). */
static int cloud_grow(cloud_buf *b, int dim, ps_ctx *ctx) {
  if (b->n < b->cap) return PS_OK;
  ps_int cap = b->cap ? 2 * b->cap : 1024;
  void *x = b->x, *v = b->volume, *k = b->block, *l = b->line;
  if (ps_realloc(&x, (size_t)cap * (size_t)dim, sizeof *b->x, ctx)) return PS_ERR_NOMEM;
  b->x = x;
  if (ps_realloc(&v, (size_t)cap, sizeof *b->volume, ctx)) return PS_ERR_NOMEM;
  b->volume = v;
  if (ps_realloc(&k, (size_t)cap, sizeof *b->block, ctx)) return PS_ERR_NOMEM;
  b->block = k;
  if (ps_realloc(&l, (size_t)cap, sizeof *b->line, ctx)) return PS_ERR_NOMEM;
  b->line = l;
  b->cap = cap;
  return PS_OK;
}

static void cloud_buf_free(cloud_buf *b) {
  free(b->x);
  free(b->volume);
  free(b->block);
  free(b->line);
}

/* A line for messages, cut to 60 characters. */
static void show_line(char *dst, size_t size, const char *line) {
  if (strlen(line) > 60)
    snprintf(dst, size, "%.57s...", line);
  else
    snprintf(dst, size, "%s", line);
}

enum { LINE_OK = 1, LINE_EOF = 0, LINE_LONG = -1, LINE_ERROR = -2, LINE_NUL = -3 };

/* Read one line of f into buf[PS_CLOUD_MAX_LINE + 1] without its line
 * break (and a '\r' before it). Returns LINE_OK, LINE_EOF (end of file,
 * nothing read), LINE_LONG (more than PS_CLOUD_MAX_LINE characters),
 * LINE_ERROR (ferror: a read error, not the end of the file) or LINE_NUL
 * (a NUL byte: not a text file). */
static int read_line(FILE *f, char *buf) {
  size_t n = 0;
  int c;
  while ((c = getc(f)) != EOF && c != '\n') {
    if (c == '\0') return LINE_NUL;
    if (n == PS_CLOUD_MAX_LINE) return LINE_LONG;
    buf[n++] = (char)c;
  }
  if (c == EOF && ferror(f)) return LINE_ERROR;
  if (c == EOF && n == 0) return LINE_EOF;
  if (n > 0 && buf[n - 1] == '\r') n--;
  buf[n] = '\0';
  return LINE_OK;
}

/* Split a line (comment cut) into at most 5 tokens; returns the count
 * (which may exceed 5: only the first 5 are stored). */
static int split(char *line, char *tok[5]) {
  char *hash = strchr(line, '#'), *save = NULL;
  if (hash) *hash = '\0';
  int nt = 0;
  for (char *s = strtok_r(line, " \t\v\f\r", &save); s; s = strtok_r(NULL, " \t\v\f\r", &save)) {
    if (nt < 5) tok[nt] = s;
    nt++;
  }
  return nt;
}

/* Parse the fields of one particle line (nt tokens) into v[0..dim] and
 * *block; errors name file:line and the field. */
static int parse_particle(const char *path, long lineno, int dim, char *const tok[5],
                          int nt, const char *text, double v[4], int *block,
                          ps_ctx *ctx) {
  static const char *const field_name[2][4] = {{"x", "y", "volume", "block"},
                                               {"x", "y", "z", "volume"}};
  const char *form = dim == 2 ? "x y volume [block]" : "x y z volume [block]";
  if (nt != dim + 1 && nt != dim + 2)
    return ps_error(ctx, PS_ERR_INPUT, "%s:%ld: expected '%s': found %d fields in '%s'",
                    path, lineno, form, nt, text);
  for (int k = 0; k <= dim; k++) {
    errno = 0;
    v[k] = ps_is_decimal(tok[k], 0) ? strtod(tok[k], NULL) : NAN;
    if (!isfinite(v[k]) || (errno == ERANGE && fabs(v[k]) > 1.0))
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%ld: %s (field %d of '%s') is not a finite decimal number "
                      "(got '%s')",
                      path, lineno, field_name[dim - 2][k], k + 1, form, tok[k]);
    if (k < dim && fabs(v[k]) > PS_MAX_COORD)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%ld: coordinates beyond 1e150 m (%s, field %d of '%s': got "
                      "'%s')",
                      path, lineno, field_name[dim - 2][k], k + 1, form, tok[k]);
  }
  if (!(v[dim] > 0))
    return ps_error(ctx, PS_ERR_INPUT, "%s:%ld: volume must be > 0 (got %s)", path, lineno,
                    tok[dim]);
  *block = 0;
  if (nt == dim + 2) {
    errno = 0;
    long bl = ps_is_decimal(tok[dim + 1], 1) ? strtol(tok[dim + 1], NULL, 10) : -1;
    if (errno != 0 || bl < 0 || bl > INT_MAX)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%ld: expected '%s': field %d (block) must be an integer in "
                      "0..%d: '%s'",
                      path, lineno, form, dim + 2, INT_MAX, tok[dim + 1]);
    *block = (int)bl;
  }
  return PS_OK;
}

/* Read every particle line of f into b. */
static int read_particles(FILE *f, const char *path, int dim, cloud_buf *b,
                          ps_ctx *ctx) {
  char line[PS_CLOUD_MAX_LINE + 1], text[80];
  long lineno = 0;
  for (;;) {
    int r = read_line(f, line);
    if (r == LINE_EOF) return PS_OK;
    lineno++;
    if (r == LINE_LONG)
      return ps_error(ctx, PS_ERR_INPUT, "%s:%ld: line longer than %d characters", path,
                      lineno, PS_CLOUD_MAX_LINE);
    if (r == LINE_NUL)
      return ps_error(ctx, PS_ERR_INPUT, "%s:%ld: a NUL byte: not a text file", path,
                      lineno);
    if (r == LINE_ERROR)
      return ps_error(ctx, PS_ERR_IO, "%s:%ld: read error: %s", path, lineno,
                      strerror(errno));
    show_line(text, sizeof text, line);
    char *tok[5];
    int nt = split(line, tok);
    if (nt == 0) continue; /* blank or comment */
    double v[4];
    int block;
    PS_CHECK(parse_particle(path, lineno, dim, tok, nt, text, v, &block, ctx));
    if (cloud_grow(b, dim, ctx) != PS_OK) {
      char m[sizeof ctx->msg];
      snprintf(m, sizeof m, "%s", ctx->msg);
      return ps_error(ctx, PS_ERR_NOMEM, "%s:%ld: %s (particle %lld)", path, lineno, m,
                      (long long)b->n + 1);
    }
    memcpy(&b->x[b->n * dim], v, (size_t)dim * sizeof *v);
    b->volume[b->n] = v[dim];
    b->block[b->n] = block;
    b->line[b->n] = lineno;
    b->n++;
  }
}

int ps_cloud_read(ps_particles *p, const char *path, int dim, ps_ctx *ctx) {
  memset(p, 0, sizeof *p);
  if (dim != 2 && dim != 3)
    return ps_error(ctx, PS_ERR_INPUT, "%s: point clouds are 2D or 3D (got dim %d)", path,
                    dim);
  FILE *f = fopen(path, "r");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  cloud_buf b = {0};
  int status = read_particles(f, path, dim, &b, ctx);
  fclose(f);
  if (status == PS_OK && b.n == 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: no particles (expected lines '%s')", path,
                      dim == 2 ? "x y volume [block]" : "x y z volume [block]");
  if (status == PS_OK) status = ps_particles_alloc(p, dim, b.n, ctx);
  if (status == PS_OK) {
    size_t len = strlen(path) + 1;
    p->source = ps_calloc(len, 1, ctx);
    p->line = ps_calloc((size_t)b.n, sizeof *p->line, ctx);
    if (!p->source || !p->line) {
      ps_particles_free(p);
      status = PS_ERR_NOMEM;
    } else {
      memcpy(p->source, path, len);
      memcpy(p->x, b.x, (size_t)b.n * (size_t)dim * sizeof *b.x);
      memcpy(p->volume, b.volume, (size_t)b.n * sizeof *b.volume);
      memcpy(p->block, b.block, (size_t)b.n * sizeof *b.block);
      memcpy(p->line, b.line, (size_t)b.n * sizeof *b.line);
    }
  }
  cloud_buf_free(&b);
  return status;
}
