/* case_yaml.c: the YAML layer of case files. libyaml's document (the
 * one document a case file holds; syntax and encoding errors with their
 * line), walking a mapping's keys, and the typed getters: decimal
 * numbers in a range, integers, booleans, choices, strings and points,
 * each failing with "FILE:LINE: NAME must be ... (got ...)". Numbers are
 * plain decimal only (ps_is_decimal): forms that YAML 1.1 and strtod
 * read differently, or only one of them reads (010, 1_000, 0x10, .inf,
 * nan), are refused. */
#include "case_impl.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* case_impl.h */
int ps_yaml_fail(const ps_loader *L, int line, const char *fmt, ...) {
  char msg[1536];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (line > 0) return ps_error(L->ctx, PS_ERR_INPUT, "%s:%d: %s", L->file, line, msg);
  return ps_error(L->ctx, PS_ERR_INPUT, "%s: %s", L->file, msg);
}

/* case_impl.h */
const char *ps_yaml_got(const yaml_node_t *n, char buf[80]) {
  switch (n->type) {
  case YAML_SCALAR_NODE:
    if (n->data.scalar.length == 0) return "nothing";
    if (n->data.scalar.length > 60)
      snprintf(buf, 80, "%.57s...", sval(n));
    else
      snprintf(buf, 80, "%s", sval(n));
    return buf;
  case YAML_SEQUENCE_NODE: return "a list";
  case YAML_MAPPING_NODE: return "a mapping";
  default: return "nothing";
  }
}

/* ps_yaml_got(), with a non-empty scalar in quotes: "'0x10'" (blanks show). */
static const char *got_quoted(const yaml_node_t *n, char buf[84]) {
  char b[80];
  const char *g = ps_yaml_got(n, b);
  if (n->type != YAML_SCALAR_NODE || n->data.scalar.length == 0)
    snprintf(buf, 84, "%s", g);
  else
    snprintf(buf, 84, "'%s'", g);
  return buf;
}

/* "a, b, c" from a NULL-terminated list of names. */
static void join(char *buf, size_t size, const char *const *names) {
  size_t len = 0;
  buf[0] = '\0';
  for (int i = 0; names[i] && len + 1 < size; i++) {
    int w = snprintf(buf + len, size - len, "%s%s", i ? ", " : "", names[i]);
    if (w < 0) break;
    len += (size_t)w;
  }
}

/* Text of a range for messages: "> 0", "in (-1, 0.5)", "in [0, 1)". */
static void range_text(char *buf, size_t size, double lo, int lo_open, double hi,
                       int hi_open) {
  if (isinf(hi))
    snprintf(buf, size, "%s %g", lo_open ? ">" : ">=", lo);
  else if (isinf(lo))
    snprintf(buf, size, "%s %g", hi_open ? "<" : "<=", hi);
  else
    snprintf(buf, size, "in %c%g, %g%c", lo_open ? '(' : '[', lo, hi,
             hi_open ? ')' : ']');
}

/* ps_io.h */
int ps_is_decimal(const char *s, int integer) {
  const char *p = s + (*s == '+' || *s == '-');
  const char *d0 = p;
  while (*p >= '0' && *p <= '9') p++;
  size_t n_int = (size_t)(p - d0);
  if (integer) return *p == '\0' && n_int > 0 && !(n_int > 1 && *d0 == '0');
  if (*p == '\0' && n_int > 1 && *d0 == '0') return 0; /* "010": octal to YAML 1.1 */
  size_t n_frac = 0;
  if (*p == '.') {
    const char *f0 = ++p;
    while (*p >= '0' && *p <= '9') p++;
    n_frac = (size_t)(p - f0);
  }
  if (n_int + n_frac == 0) return 0;
  if (*p == 'e' || *p == 'E') {
    p++;
    p += *p == '+' || *p == '-';
    const char *e0 = p;
    while (*p >= '0' && *p <= '9') p++;
    if (p == e0) return 0;
  }
  return *p == '\0';
}

/* case_impl.h */
int ps_yaml_real(ps_loader *L, yaml_node_t *n, const char *name, double lo, int lo_open,
                 double hi, int hi_open, double *out) {
  char b[84], rng[64];
  if (n->type != YAML_SCALAR_NODE || !ps_is_decimal(sval(n), 0))
    return ps_yaml_fail(L, line_of(n), "%s must be a decimal number (got %s)", name,
                        got_quoted(n, b));
  errno = 0;
  double v = strtod(sval(n), NULL);
  if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0))
    return ps_yaml_fail(L, line_of(n),
                        "%s must be a finite decimal number (got %s: beyond the largest "
                        "double, about 1.8e308)",
                        name, got_quoted(n, b));
  if (!((isinf(lo) || (lo_open ? v > lo : v >= lo)) &&
        (isinf(hi) || (hi_open ? v < hi : v <= hi)))) {
    range_text(rng, sizeof rng, lo, lo_open, hi, hi_open);
    return ps_yaml_fail(L, line_of(n), "%s must be %s (got %s)", name, rng,
                        ps_yaml_got(n, b));
  }
  *out = v;
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_coord(ps_loader *L, yaml_node_t *n, const char *name, double *out) {
  double v;
  if (ps_yaml_real(L, n, name, -INFINITY, 0, INFINITY, 0, &v) != PS_OK) return PS_ERR_INPUT;
  if (fabs(v) > PS_MAX_COORD)
    return ps_yaml_fail(L, line_of(n), "coordinates beyond 1e150 m (%s: got %s)",
                        name, sval(n));
  *out = v;
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_pos(ps_loader *L, yaml_node_t *n, const char *name, double *out) {
  return ps_yaml_real(L, n, name, 0.0, 1, INFINITY, 0, out);
}

/* case_impl.h */
int ps_yaml_pos_in(ps_loader *L, yaml_node_t *n, const char *name, double lo, double hi,
                   const char *why, double *out) {
  double v;
  if (ps_yaml_pos(L, n, name, &v) != PS_OK) return PS_ERR_INPUT;
  if (v < lo || v > hi)
    return ps_yaml_fail(L, line_of(n), "%s must be in [%g, %g] (got %s): %s", name, lo,
                        hi, sval(n), why);
  *out = v;
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_long(ps_loader *L, yaml_node_t *n, const char *name, long lo, long hi,
                 long *out) {
  char b[84];
  if (n->type != YAML_SCALAR_NODE || !ps_is_decimal(sval(n), 1))
    return ps_yaml_fail(L, line_of(n), "%s must be a decimal integer (got %s)", name,
                        got_quoted(n, b));
  errno = 0;
  long v = strtol(sval(n), NULL, 10);
  int overflow = errno == ERANGE;
  if (overflow || v < lo || v > hi) {
    if (hi == LONG_MAX && !overflow)
      return ps_yaml_fail(L, line_of(n), "%s must be an integer >= %ld (got %s)", name,
                          lo, ps_yaml_got(n, b));
    return ps_yaml_fail(L, line_of(n), "%s must be an integer in %ld..%ld (got %s)", name,
                        lo, hi, ps_yaml_got(n, b));
  }
  *out = v;
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_int(ps_loader *L, yaml_node_t *n, const char *name, long lo, long hi,
                int *out) {
  long v;
  int s = ps_yaml_long(L, n, name, lo, hi < INT_MAX ? hi : INT_MAX, &v);
  if (s == PS_OK) *out = (int)v;
  return s;
}

/* case_impl.h */
int ps_yaml_bool(ps_loader *L, yaml_node_t *n, const char *name, int *out) {
  char b[80];
  if (n->type == YAML_SCALAR_NODE) {
    const char *s = sval(n);
    if (!strcasecmp(s, "true") || !strcasecmp(s, "yes")) {
      *out = 1;
      return PS_OK;
    }
    if (!strcasecmp(s, "false") || !strcasecmp(s, "no")) {
      *out = 0;
      return PS_OK;
    }
  }
  return ps_yaml_fail(L, line_of(n), "%s must be true or false (got %s)", name,
                      ps_yaml_got(n, b));
}

/* case_impl.h */
int ps_yaml_choice(ps_loader *L, yaml_node_t *n, const char *name,
                   const char *const *choices, int *out) {
  char b[80], list[256];
  if (n->type == YAML_SCALAR_NODE)
    for (int i = 0; choices[i]; i++)
      if (!strcmp(sval(n), choices[i])) {
        *out = i;
        return PS_OK;
      }
  join(list, sizeof list, choices);
  return ps_yaml_fail(L, line_of(n), "%s must be one of: %s (got %s)", name, list,
                      ps_yaml_got(n, b));
}

/* case_impl.h */
int ps_yaml_string(ps_loader *L, yaml_node_t *n, const char *name, char *dst,
                   size_t size) {
  char b[80];
  if (n->type != YAML_SCALAR_NODE || n->data.scalar.length == 0)
    return ps_yaml_fail(L, line_of(n), "%s must be a non-empty string (got %s)", name,
                        ps_yaml_got(n, b));
  if (n->data.scalar.length >= size)
    return ps_yaml_fail(L, line_of(n), "%s is too long (at most %zu characters)", name,
                        size - 1);
  memcpy(dst, sval(n), n->data.scalar.length + 1);
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_walk_map(ps_loader *L, yaml_node_t *map, const char *section,
                     const char *const *allowed, ps_key_fn fn, void *arg) {
  char b[80], list[512], name[160];
  if (map->type != YAML_MAPPING_NODE) {
    if (!section[0])
      return ps_yaml_fail(L, line_of(map),
                          "the case file must be a mapping of sections (got %s)",
                          ps_yaml_got(map, b));
    return ps_yaml_fail(L, line_of(map), "%s must be a mapping of keys (got %s)", section,
                        ps_yaml_got(map, b));
  }
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start;
       p < map->data.mapping.pairs.top; p++) {
    yaml_node_t *k = yaml_document_get_node(L->doc, p->key);
    yaml_node_t *v = yaml_document_get_node(L->doc, p->value);
    if (k->type != YAML_SCALAR_NODE)
      return ps_yaml_fail(L, line_of(k), "keys in %s must be plain names (got %s)",
                          section[0] ? section : "the case file", ps_yaml_got(k, b));
    const char *key = sval(k);
    snprintf(name, sizeof name, "%s%s%s", section, section[0] ? "." : "", key);
    int known = 0;
    for (int i = 0; allowed[i] && !known; i++) known = !strcmp(key, allowed[i]);
    if (!known) {
      join(list, sizeof list, allowed);
      if (!section[0])
        return ps_yaml_fail(L, line_of(k), "unknown key '%s' (allowed: %s)", name, list);
      return ps_yaml_fail(L, line_of(k), "unknown key '%s' (allowed in %s: %s)", name,
                          section, list);
    }
    for (yaml_node_pair_t *q = map->data.mapping.pairs.start; q < p; q++) {
      yaml_node_t *kq = yaml_document_get_node(L->doc, q->key);
      if (kq->type == YAML_SCALAR_NODE && !strcmp(sval(kq), key))
        return ps_yaml_fail(L, line_of(k), "%s is given twice (first at line %d)", name,
                            line_of(kq));
    }
    int s = fn(L, arg, key, name, v);
    if (s != PS_OK) return s;
  }
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_point2(ps_loader *L, yaml_node_t *n, const char *name, double *x) {
  char b[80];
  if (n->type != YAML_SEQUENCE_NODE || seq_len(n) != 2)
    return ps_yaml_fail(L, line_of(n), "%s: each end must be [x, y] (got %s)", name,
                        ps_yaml_got(n, b));
  for (int k = 0; k < 2; k++)
    if (ps_yaml_coord(L, seq_item(L, n, k), name, &x[k])) return PS_ERR_INPUT;
  return PS_OK;
}

/* 1-based line of byte offset `offset` of text (line breaks: \n, \r\n,
 * or \r alone, as libyaml counts them); its 1-based column in *col. */
static int line_at(const char *text, size_t len, size_t offset, size_t *col) {
  int line = 1;
  size_t start = 0;
  if (offset > len) offset = len;
  for (size_t i = 0; i < offset; i++)
    if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= len || text[i + 1] != '\n'))) {
      line++;
      start = i + 1;
    }
  *col = offset - start + 1;
  return line;
}

/* "FILE:LINE: YAML syntax error: problem (context at line N)"; encoding
 * errors (invalid UTF-8, control characters such as NUL) as "FILE:LINE:
 * YAML read error: problem (column C)", counted in text. */
static int syntax_error(const char *file, const yaml_parser_t *pa, const char *text,
                        size_t len, ps_ctx *ctx) {
  const char *problem = pa->problem ? pa->problem : "cannot parse";
  if (pa->error == YAML_MEMORY_ERROR)
    return ps_error(ctx, PS_ERR_NOMEM, "%s: out of memory while parsing YAML", file);
  if (pa->error == YAML_READER_ERROR) {
    size_t col;
    int line = line_at(text, len, pa->problem_offset, &col);
    return ps_error(ctx, PS_ERR_INPUT, "%s:%d: YAML read error: %s (column %zu)", file,
                    line, problem, col);
  }
  if (pa->context)
    return ps_error(ctx, PS_ERR_INPUT, "%s:%d: YAML syntax error: %s (%s at line %d)",
                    file, (int)pa->problem_mark.line + 1, problem, pa->context,
                    (int)pa->context_mark.line + 1);
  return ps_error(ctx, PS_ERR_INPUT, "%s:%d: YAML syntax error: %s", file,
                  (int)pa->problem_mark.line + 1, problem);
}

/* case_impl.h */
int ps_yaml_open(ps_yaml_file *Y, const char *file, const char *text, size_t len,
                 ps_ctx *ctx) {
  memset(Y, 0, sizeof *Y);
  Y->file = file;
  Y->text = text;
  Y->len = len;
  if (!yaml_parser_initialize(&Y->parser))
    return ps_error(ctx, PS_ERR_NOMEM, "%s: cannot initialise the YAML parser", file);
  Y->have_parser = 1;
  yaml_parser_set_input_string(&Y->parser, (const unsigned char *)text, len);
  if (!yaml_parser_load(&Y->parser, &Y->doc))
    return syntax_error(file, &Y->parser, text, len, ctx);
  Y->have_doc = 1;
  return PS_OK;
}

/* case_impl.h */
int ps_yaml_only_document(ps_yaml_file *Y, ps_ctx *ctx) {
  yaml_document_t extra;
  if (!yaml_parser_load(&Y->parser, &extra))
    return syntax_error(Y->file, &Y->parser, Y->text, Y->len, ctx);
  yaml_node_t *extra_root = yaml_document_get_root_node(&extra);
  int extra_line = extra_root ? line_of(extra_root) : 0;
  yaml_document_delete(&extra);
  if (extra_line)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s:%d: a case file holds one YAML document (a second starts here)",
                    Y->file, extra_line);
  return PS_OK;
}

/* case_impl.h */
void ps_yaml_close(ps_yaml_file *Y) {
  if (Y->have_doc) yaml_document_delete(&Y->doc);
  if (Y->have_parser) yaml_parser_delete(&Y->parser);
  Y->have_doc = Y->have_parser = 0;
}
