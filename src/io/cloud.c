/* cloud.c: point clouds from text files, one particle per line:
 * "x y [z] volume [block]" (dim coordinates, the volume in m^N, then an
 * optional integer block id >= 0). '#' starts a comment; blank lines are
 * skipped. Errors name the file, the line and the offending field. */
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
  ps_int n, cap;
} cloud_buf;

/* Make room for one more particle (capacity doubles). */
static int cloud_grow(cloud_buf *b, int dim, ps_ctx *ctx) {
  if (b->n < b->cap) return PS_OK;
  ps_int cap = b->cap ? 2 * b->cap : 1024;
  void *x = b->x, *v = b->volume, *k = b->block;
  if (ps_realloc(&x, (size_t)(cap * dim), sizeof *b->x, ctx)) return PS_ERR_NOMEM;
  b->x = x;
  if (ps_realloc(&v, (size_t)cap, sizeof *b->volume, ctx)) return PS_ERR_NOMEM;
  b->volume = v;
  if (ps_realloc(&k, (size_t)cap, sizeof *b->block, ctx)) return PS_ERR_NOMEM;
  b->block = k;
  b->cap = cap;
  return PS_OK;
}

/* A line for messages: without its line break, cut to 60 characters. */
static void show_line(char *dst, size_t size, const char *line) {
  size_t n = strcspn(line, "\r\n");
  if (n > 60)
    snprintf(dst, size, "%.57s...", line);
  else
    snprintf(dst, size, "%.*s", (int)n, line);
}

/* Parse a whole token as a finite number. */
static int parse_real(const char *s, double *out) {
  char *end;
  double v = strtod(s, &end);
  if (end == s || *end != '\0' || !isfinite(v)) return 0;
  *out = v;
  return 1;
}

int ps_cloud_read(ps_particles *p, const char *path, int dim, ps_ctx *ctx) {
  static const char *const field_name[2][4] = {{"x", "y", "volume", "block"},
                                               {"x", "y", "z", "volume"}};
  memset(p, 0, sizeof *p);
  if (dim != 2 && dim != 3)
    return ps_error(ctx, PS_ERR_INPUT, "%s: point clouds are 2D or 3D (got dim %d)", path,
                    dim);
  const char *form = dim == 2 ? "x y volume [block]" : "x y z volume [block]";
  FILE *f = fopen(path, "r");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));

  int status = PS_OK;
  cloud_buf b = {0};
  char *line = NULL, text[80];
  size_t line_cap = 0;
  long lineno = 0;
  while (getline(&line, &line_cap, f) != -1) {
    lineno++;
    show_line(text, sizeof text, line);
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    char *tok[5], *save = NULL;
    int nt = 0;
    for (char *s = strtok_r(line, " \t\r\n\v\f", &save); s;
         s = strtok_r(NULL, " \t\r\n\v\f", &save)) {
      if (nt < 5) tok[nt] = s;
      nt++;
    }
    if (nt == 0) continue; /* blank or comment */
    if (nt != dim + 1 && nt != dim + 2) {
      status = ps_error(ctx, PS_ERR_INPUT, "%s:%ld: expected '%s': found %d fields in '%s'",
                        path, lineno, form, nt, text);
      goto cleanup;
    }
    PS_CHECK_GOTO(cloud_grow(&b, dim, ctx));
    double v[4];
    for (int k = 0; k <= dim; k++)
      if (!parse_real(tok[k], &v[k])) {
        status = ps_error(ctx, PS_ERR_INPUT,
                          "%s:%ld: expected '%s': field %d (%s) is not a number: '%s'",
                          path, lineno, form, k + 1, field_name[dim - 2][k], tok[k]);
        goto cleanup;
      }
    if (!(v[dim] > 0)) {
      status = ps_error(ctx, PS_ERR_INPUT, "%s:%ld: volume must be > 0 (got %s)", path,
                        lineno, tok[dim]);
      goto cleanup;
    }
    int block = 0;
    if (nt == dim + 2) {
      char *end;
      errno = 0;
      long bl = strtol(tok[dim + 1], &end, 10);
      if (end == tok[dim + 1] || *end != '\0' || errno != 0 || bl < 0 || bl > INT_MAX) {
        status = ps_error(ctx, PS_ERR_INPUT,
                          "%s:%ld: expected '%s': field %d (block) must be an integer "
                          ">= 0: '%s'",
                          path, lineno, form, dim + 2, tok[dim + 1]);
        goto cleanup;
      }
      block = (int)bl;
    }
    memcpy(&b.x[b.n * dim], v, (size_t)dim * sizeof *v);
    b.volume[b.n] = v[dim];
    b.block[b.n] = block;
    b.n++;
  }
  if (ferror(f)) {
    status = ps_error(ctx, PS_ERR_IO, "%s: read error: %s", path, strerror(errno));
    goto cleanup;
  }
  if (b.n == 0) {
    status = ps_error(ctx, PS_ERR_INPUT, "%s: no particles (expected lines '%s')", path,
                      form);
    goto cleanup;
  }
  PS_CHECK_GOTO(ps_particles_alloc(p, dim, b.n, ctx));
  memcpy(p->x, b.x, (size_t)(b.n * dim) * sizeof *b.x);
  memcpy(p->volume, b.volume, (size_t)b.n * sizeof *b.volume);
  memcpy(p->block, b.block, (size_t)b.n * sizeof *b.block);

cleanup:
  free(line);
  free(b.x);
  free(b.volume);
  free(b.block);
  fclose(f);
  return status;
}
