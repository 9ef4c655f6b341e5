/* case.c: case files. ps_case_defaults fills the documented defaults;
 * ps_case_load reads a YAML file (libyaml document API) over them. Every
 * error names the file and the line of the offending node, e.g.
 * "case.yaml:14: material.E must be > 0 (got -3e9)". Checks that involve
 * several keys (dim against counts, loading type against geometry, keys
 * of another geometry type, the bond model's nu, ...) run after the whole
 * file is read, since YAML keys come in any order. The text is read whole
 * first and its size and nesting bounded before libyaml sees it (Debian's
 * libyaml 0.2.5 is quadratic in the nesting). */
#include "ps_io.h"

#include "../solver/ps_solver.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <yaml.h>

void ps_case_defaults(ps_case *cs) {
  /* the solver's defaults live in ps_solver_opts_default only */
  ps_solver_opts so;
  ps_solver_opts_default(&so);
  memset(cs, 0, sizeof *cs);
  strcpy(cs->name, "case");
  cs->geometry = PS_GEOM_DISK;
  cs->dim = 2;
  ps_disk_params_default(&cs->disk);
  cs->counts[0] = 20;
  cs->counts[1] = 20;
  cs->counts[2] = 1;
  cs->spacing = 1e-3;
  strcpy(cs->lattice, "square");
  cs->jitter = 0.0;
  cs->seed = 1;
  cs->size_rule = PS_SIZE_EQ115;
  cs->size_neighbours = 5;
  cs->n_cracks = 0;
  cs->alpha = 5.1;
  cs->kernel_k = 2;
  strcpy(cs->model, "fibre");
  cs->horizon_factor = 3.0;
  cs->mat.surface_correction = 1;
  cs->mat.E = 210e9;
  cs->mat.nu = 0.3;
  cs->mat.plane = PS_PLANE_STRAIN;
  cs->mat.yield_strain = 1.0 / 500.0;
  cs->mat.plastic = 1;
  cs->mat.delta = NAN; /* unset: delta_over_c applies */
  cs->mat.rho = 7800.0;
  cs->mat.yield_rule = PS_YIELD_TOTAL;
  cs->delta_over_c = 1e-3;
  cs->load_type = PS_LOAD_EQ116;
  cs->n_bc = 0;
  cs->stress_length = 0.0;
  snprintf(cs->linear, sizeof cs->linear, "%s", so.linear->name);
  cs->tolerance = so.tolerance;
  cs->max_iterations = so.max_iterations;
  cs->max_small_steps = so.max_small_steps;
  cs->line_search = so.line_search;
  cs->reuse_factor = so.reuse_factor;
  cs->cg_tolerance = so.pcg_rtol;
  cs->cg_forcing_adaptive = so.cg_forcing_adaptive;
  cs->cg_forcing = so.cg_forcing;
  cs->cg_forcing_max = so.cg_forcing_max;
  cs->cg_max_iterations = so.pcg_max_iterations;
  cs->cg_skip_arms = so.pcg_skip_arms;
  cs->reanalyze = so.reanalyze;
  cs->majorant = so.majorant;
  cs->matrix_free = so.matrix_free;
  cs->cg_single_precision = so.cg_single_precision;
  cs->cg_truncate = so.cg_truncate;
  cs->load_step = 0.02;
  cs->load_step_after_break = 0.005;
  cs->max_load = 5.0;
  cs->max_increments = 2000;
  cs->min_step = 1e-6;
  cs->stop_crack_tip = 9.0;
  cs->stop_load_drop = 0.5;
  cs->max_break_rounds = 500;
  cs->out_dir[0] = '\0';
  cs->vtk_every = 10;
  cs->fields = 1;
  cs->verbosity = 1;
  cs->n_sweep = 12; /* delta/c = 1/500, 1/750, ..., 1/3250 */
  for (int i = 0; i < cs->n_sweep; i++)
    cs->sweep_delta_over_c[i] = 1.0 / (500.0 + 250.0 * i);
}

/* ------------------------------------------------------------------ */
/* Loader state: the document being walked, the case being filled and the
 * lines where keys needed by the final cross checks were given (0: not
 * given). */
typedef struct loader {
  const char *file;
  yaml_document_t *doc;
  ps_case *cs;
  ps_ctx *ctx;
  int line_type, line_dim, line_counts, n_counts, line_lattice, line_cracks, line_holes;
  int line_j, line_j_tip;
  int line_load_type, line_boundary, line_delta, line_delta_over_c;
  int line_sweep_list, line_sweep_den;
  int line_E, line_nu, line_yield_strain, line_plane;
  int line_geometry[24]; /* per geometry_keys entry: where it was given */
} loader;

/* Handler for one key of a mapping: key is the bare key, name its dotted
 * path for messages ("material.E"), v the value node. */
typedef int (*key_fn)(loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v);

/* Record "FILE:LINE: message" (or "FILE: message" when line is 0) as a
 * PS_ERR_INPUT error; returns PS_ERR_INPUT. */
__attribute__((format(printf, 3, 4))) static int fail(const loader *L, int line,
                                                      const char *fmt, ...) {
  char msg[1536];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (line > 0) return ps_error(L->ctx, PS_ERR_INPUT, "%s:%d: %s", L->file, line, msg);
  return ps_error(L->ctx, PS_ERR_INPUT, "%s: %s", L->file, msg);
}

/* 1-based line where a node starts. */
static int line_of(const yaml_node_t *n) { return (int)n->start_mark.line + 1; }

/* Text of a scalar node. */
static const char *sval(const yaml_node_t *n) {
  return (const char *)n->data.scalar.value;
}

/* A short description of a node for "(got ...)": the scalar text (cut
 * to 60 characters), "nothing", "a list" or "a mapping". */
static const char *got(const yaml_node_t *n, char buf[80]) {
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

/* got(), with a non-empty scalar in quotes: "'0x10'" (blanks show). */
static const char *got_quoted(const yaml_node_t *n, char buf[84]) {
  char b[80];
  const char *g = got(n, b);
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

/* A number: the scalar must be a plain decimal number (is_decimal) that
 * a double holds (no overflow; an underflow reads as the nearest double,
 * 0 or subnormal, which the ranges then judge), then lie in the range
 * (infinite bounds are not checked). */
static int get_real(loader *L, yaml_node_t *n, const char *name, double lo,
                    int lo_open, double hi, int hi_open, double *out) {
  char b[84], rng[64];
  if (n->type != YAML_SCALAR_NODE || !ps_is_decimal(sval(n), 0))
    return fail(L, line_of(n), "%s must be a decimal number (got %s)", name,
                got_quoted(n, b));
  errno = 0;
  double v = strtod(sval(n), NULL);
  if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0))
    return fail(L, line_of(n),
                "%s must be a finite decimal number (got %s: beyond the largest "
                "double, about 1.8e308)", name, got_quoted(n, b));
  if (!((isinf(lo) || (lo_open ? v > lo : v >= lo)) &&
        (isinf(hi) || (hi_open ? v < hi : v <= hi)))) {
    range_text(rng, sizeof rng, lo, lo_open, hi, hi_open);
    return fail(L, line_of(n), "%s must be %s (got %s)", name, rng, got(n, b));
  }
  *out = v;
  return PS_OK;
}

/* A number > 0. */
static int get_pos(loader *L, yaml_node_t *n, const char *name, double *out) {
  return get_real(L, n, name, 0.0, 1, INFINITY, 0, out);
}

/* A number > 0 (get_pos, and its message) that must also lie in [lo,
 * hi]: "material.E must be in [1e-20, 1e+20] (got 1e300): why". */
static int get_pos_in(loader *L, yaml_node_t *n, const char *name, double lo, double hi,
                      const char *why, double *out) {
  double v;
  if (get_pos(L, n, name, &v) != PS_OK) return PS_ERR_INPUT;
  if (v < lo || v > hi)
    return fail(L, line_of(n), "%s must be in [%g, %g] (got %s): %s", name, lo, hi,
                sval(n), why);
  *out = v;
  return PS_OK;
}

/* A decimal integer (is_decimal) in [lo, hi] (hi == LONG_MAX: no upper
 * bound but the type's); values past the range, including those too
 * large for a long, are refused with the range. */
static int get_long(loader *L, yaml_node_t *n, const char *name, long lo, long hi,
                    long *out) {
  char b[84];
  if (n->type != YAML_SCALAR_NODE || !ps_is_decimal(sval(n), 1))
    return fail(L, line_of(n), "%s must be a decimal integer (got %s)", name,
                got_quoted(n, b));
  errno = 0;
  long v = strtol(sval(n), NULL, 10);
  int overflow = errno == ERANGE;
  if (overflow || v < lo || v > hi) {
    if (hi == LONG_MAX && !overflow)
      return fail(L, line_of(n), "%s must be an integer >= %ld (got %s)", name, lo,
                  got(n, b));
    return fail(L, line_of(n), "%s must be an integer in %ld..%ld (got %s)", name, lo,
                hi, got(n, b));
  }
  *out = v;
  return PS_OK;
}

/* get_long into an int, hi capped at INT_MAX. */
static int get_int(loader *L, yaml_node_t *n, const char *name, long lo, long hi,
                   int *out) {
  long v;
  int s = get_long(L, n, name, lo, hi < INT_MAX ? hi : INT_MAX, &v);
  if (s == PS_OK) *out = (int)v;
  return s;
}

/* A boolean: true/false/yes/no (any case). */
static int get_bool(loader *L, yaml_node_t *n, const char *name, int *out) {
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
  return fail(L, line_of(n), "%s must be true or false (got %s)", name, got(n, b));
}

/* One of a NULL-terminated list of words; *out = its index. */
static int get_choice(loader *L, yaml_node_t *n, const char *name,
                      const char *const *choices, int *out) {
  char b[80], list[256];
  if (n->type == YAML_SCALAR_NODE)
    for (int i = 0; choices[i]; i++)
      if (!strcmp(sval(n), choices[i])) {
        *out = i;
        return PS_OK;
      }
  join(list, sizeof list, choices);
  return fail(L, line_of(n), "%s must be one of: %s (got %s)", name, list, got(n, b));
}

/* A non-empty string that fits in dst[size]. */
static int get_string(loader *L, yaml_node_t *n, const char *name, char *dst,
                      size_t size) {
  char b[80];
  if (n->type != YAML_SCALAR_NODE || n->data.scalar.length == 0)
    return fail(L, line_of(n), "%s must be a non-empty string (got %s)", name, got(n, b));
  if (n->data.scalar.length >= size)
    return fail(L, line_of(n), "%s is too long (at most %zu characters)", name, size - 1);
  memcpy(dst, sval(n), n->data.scalar.length + 1);
  return PS_OK;
}

/* Walk a mapping: every key must be a scalar in `allowed` (NULL-terminated)
 * and appear once; each (key, value) goes to fn. section is the dotted
 * path of the mapping ("" at the top). */
static int walk_map(loader *L, yaml_node_t *map, const char *section,
                    const char *const *allowed, key_fn fn, void *arg) {
  char b[80], list[512], name[160];
  if (map->type != YAML_MAPPING_NODE) {
    if (!section[0])
      return fail(L, line_of(map), "the case file must be a mapping of sections (got %s)",
                  got(map, b));
    return fail(L, line_of(map), "%s must be a mapping of keys (got %s)", section,
                got(map, b));
  }
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start;
       p < map->data.mapping.pairs.top; p++) {
    yaml_node_t *k = yaml_document_get_node(L->doc, p->key);
    yaml_node_t *v = yaml_document_get_node(L->doc, p->value);
    if (k->type != YAML_SCALAR_NODE)
      return fail(L, line_of(k), "keys in %s must be plain names (got %s)",
                  section[0] ? section : "the case file", got(k, b));
    const char *key = sval(k);
    snprintf(name, sizeof name, "%s%s%s", section, section[0] ? "." : "", key);
    int known = 0;
    for (int i = 0; allowed[i] && !known; i++) known = !strcmp(key, allowed[i]);
    if (!known) {
      join(list, sizeof list, allowed);
      if (!section[0])
        return fail(L, line_of(k), "unknown key '%s' (allowed: %s)", name, list);
      return fail(L, line_of(k), "unknown key '%s' (allowed in %s: %s)", name, section,
                  list);
    }
    for (yaml_node_pair_t *q = map->data.mapping.pairs.start; q < p; q++) {
      yaml_node_t *kq = yaml_document_get_node(L->doc, q->key);
      if (kq->type == YAML_SCALAR_NODE && !strcmp(sval(kq), key))
        return fail(L, line_of(k), "%s is given twice (first at line %d)", name,
                    line_of(kq));
    }
    int s = fn(L, arg, key, name, v);
    if (s != PS_OK) return s;
  }
  return PS_OK;
}

/* Number of items of a sequence node. */
static int seq_len(const yaml_node_t *n) {
  return (int)(n->data.sequence.items.top - n->data.sequence.items.start);
}

/* Item i of a sequence node. */
static yaml_node_t *seq_item(loader *L, const yaml_node_t *n, int i) {
  return yaml_document_get_node(L->doc, n->data.sequence.items.start[i]);
}

#define IS(k) (!strcmp(key, (k)))

/* ---- geometry ---- */

/* A 2D point [x, y] of a crack segment. */
static int get_point2(loader *L, yaml_node_t *n, const char *name, double *x) {
  char b[80];
  if (n->type != YAML_SEQUENCE_NODE || seq_len(n) != 2)
    return fail(L, line_of(n), "%s: each end must be [x, y] (got %s)", name, got(n, b));
  for (int k = 0; k < 2; k++)
    if (get_real(L, seq_item(L, n, k), name, -INFINITY, 0, INFINITY, 0, &x[k]))
      return PS_ERR_INPUT;
  return PS_OK;
}

/* geometry.cracks: a list of segments [[x0, y0], [x1, y1]]. */
static int get_cracks(loader *L, yaml_node_t *v, const char *name) {
  char b[80];
  ps_case *cs = L->cs;
  if (v->type != YAML_SEQUENCE_NODE)
    return fail(L, line_of(v), "%s must be a list of segments [[x0, y0], [x1, y1]] (got %s)",
                name, got(v, b));
  int n = seq_len(v);
  if (n > PS_MAX_CRACKS)
    return fail(L, line_of(v), "%s has %d segments, at most %d are allowed", name, n,
                PS_MAX_CRACKS);
  cs->n_cracks = 0;
  for (int i = 0; i < n; i++) {
    yaml_node_t *seg = seq_item(L, v, i);
    if (seg->type != YAML_SEQUENCE_NODE || seq_len(seg) != 2)
      return fail(L, line_of(seg), "%s: a segment must be [[x0, y0], [x1, y1]] (got %s)",
                  name, got(seg, b));
    ps_crack *cr = &cs->cracks[i];
    memset(cr, 0, sizeof *cr);
    if (get_point2(L, seq_item(L, seg, 0), name, cr->p0) ||
        get_point2(L, seq_item(L, seg, 1), name, cr->p1))
      return PS_ERR_INPUT;
    if (cr->p0[0] == cr->p1[0] && cr->p0[1] == cr->p1[1])
      return fail(L, line_of(seg), "%s: segment %d has zero length", name, i + 1);
    cs->n_cracks++;
  }
  L->line_cracks = line_of(v);
  return PS_OK;
}

/* geometry.holes: a list of circles [cx, cy, R]. */
static int get_holes(loader *L, yaml_node_t *v, const char *name) {
  char b[80];
  ps_case *cs = L->cs;
  if (v->type != YAML_SEQUENCE_NODE)
    return fail(L, line_of(v), "%s must be a list of circles [cx, cy, R] (got %s)", name,
                got(v, b));
  int n = seq_len(v);
  if (n > PS_MAX_HOLES)
    return fail(L, line_of(v), "%s has %d circles, at most %d are allowed", name, n,
                PS_MAX_HOLES);
  cs->n_holes = 0;
  for (int i = 0; i < n; i++) {
    yaml_node_t *h = seq_item(L, v, i);
    if (h->type != YAML_SEQUENCE_NODE || seq_len(h) != 3)
      return fail(L, line_of(h), "%s: a hole must be [cx, cy, R] (got %s)", name, got(h, b));
    double *c = cs->holes[i];
    if (get_real(L, seq_item(L, h, 0), name, -INFINITY, 0, INFINITY, 0, &c[0]) ||
        get_real(L, seq_item(L, h, 1), name, -INFINITY, 0, INFINITY, 0, &c[1]) ||
        get_real(L, seq_item(L, h, 2), name, 0.0, 1, INFINITY, 0, &c[2]))
      return PS_ERR_INPUT;
    cs->n_holes++;
  }
  L->line_holes = line_of(v);
  return PS_OK;
}

static const char *const geometry_keys[] = {
    "type", "dim", "c", "n_eta", "n_xi", "per_zone", "xi_min", "xi_max",
    "jitter", "seed", "counts", "spacing", "lattice", "file", "sizes",
    "size_neighbours", "origin", "holes", "cracks", NULL};

static int on_geometry(loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  static const char *const types[] = {"disk", "box", "cloud", NULL};
  static const char *const lattices[] = {"square", "hex", NULL};
  static const char *const sizes[] = {"eq115", "eq44", NULL};
  ps_case *cs = L->cs;
  char b[80];
  (void)arg;
  _Static_assert(sizeof geometry_keys / sizeof geometry_keys[0] <=
                     sizeof L->line_geometry / sizeof L->line_geometry[0],
                 "one line_geometry per geometry key");
  for (int i = 0; geometry_keys[i]; i++)
    if (IS(geometry_keys[i])) L->line_geometry[i] = line_of(v);
  if (IS("type")) {
    L->line_type = line_of(v);
    return get_choice(L, v, name, types, &cs->geometry);
  }
  if (IS("dim")) {
    L->line_dim = line_of(v);
    return get_int(L, v, name, 2, 3, &cs->dim);
  }
  if (IS("c")) return get_pos(L, v, name, &cs->disk.c);
  if (IS("n_eta")) return get_int(L, v, name, 1, INT_MAX, &cs->disk.n_eta);
  if (IS("n_xi")) return get_int(L, v, name, 3, INT_MAX, &cs->disk.n_xi);
  if (IS("per_zone")) return get_int(L, v, name, 1, INT_MAX, &cs->disk.per_zone);
  if (IS("xi_min")) return get_real(L, v, name, -INFINITY, 0, 0.0, 1, &cs->disk.xi_min);
  if (IS("xi_max")) return get_real(L, v, name, 0.0, 1, INFINITY, 0, &cs->disk.xi_max);
  if (IS("jitter")) {
    /* one key for both generators: only the chosen geometry reads it */
    int s = get_real(L, v, name, 0.0, 0, 0.5, 1, &cs->jitter);
    cs->disk.jitter = cs->jitter;
    return s;
  }
  if (IS("seed")) {
    long seed;
    int s = get_long(L, v, name, 0, LONG_MAX, &seed);
    if (s == PS_OK) cs->seed = cs->disk.seed = (unsigned long)seed;
    return s;
  }
  if (IS("counts")) {
    if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 2 || seq_len(v) > 3)
      return fail(L, line_of(v), "%s must be [nx, ny] or [nx, ny, nz] (got %s)", name,
                  got(v, b));
    L->n_counts = seq_len(v);
    L->line_counts = line_of(v);
    cs->counts[2] = 1;
    for (int k = 0; k < L->n_counts; k++) {
      long c;
      if (get_long(L, seq_item(L, v, k), name, 1, INT_MAX, &c)) return PS_ERR_INPUT;
      cs->counts[k] = (ps_int)c;
    }
    return PS_OK;
  }
  if (IS("spacing")) return get_pos(L, v, name, &cs->spacing);
  if (IS("lattice")) {
    int i;
    L->line_lattice = line_of(v);
    if (get_choice(L, v, name, lattices, &i)) return PS_ERR_INPUT;
    strcpy(cs->lattice, lattices[i]);
    return PS_OK;
  }
  if (IS("file")) {
    char f[1024];
    if (get_string(L, v, name, f, sizeof f)) return PS_ERR_INPUT;
    int w = f[0] == '/' ? snprintf(cs->cloud_file, sizeof cs->cloud_file, "%s", f)
                        : snprintf(cs->cloud_file, sizeof cs->cloud_file, "%s/%s",
                                   cs->dir, f);
    if (w < 0 || (size_t)w >= sizeof cs->cloud_file)
      return fail(L, line_of(v), "%s: path too long", name);
    return PS_OK;
  }
  if (IS("sizes")) return get_choice(L, v, name, sizes, &cs->size_rule);
  if (IS("size_neighbours")) return get_int(L, v, name, 1, 64, &cs->size_neighbours);
  if (IS("origin")) {
    if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 2 || seq_len(v) > 3)
      return fail(L, line_of(v), "%s must be [x0, y0] or [x0, y0, z0] (got %s)", name,
                  got(v, b));
    for (int k = 0; k < seq_len(v); k++)
      if (get_real(L, seq_item(L, v, k), name, -INFINITY, 0, INFINITY, 0, &cs->origin[k]))
        return PS_ERR_INPUT;
    return PS_OK;
  }
  if (IS("holes")) return get_holes(L, v, name);
  return get_cracks(L, v, name); /* "cracks", the last allowed key */
}

/* ---- kernel ---- */

static const char *const kernel_keys[] = {"alpha", "k", NULL};

static int on_kernel(loader *L, void *arg, const char *key, const char *name,
                     yaml_node_t *v) {
  (void)arg;
  if (IS("alpha"))
    return get_pos_in(L, v, name, PS_ALPHA_MIN, PS_ALPHA_MAX,
                      "the horizon in particle sizes h (the paper: 5.1)", &L->cs->alpha);
  return get_int(L, v, name, 1, PS_KERNEL_K_MAX, &L->cs->kernel_k);
}

/* ---- material ---- */

/* The material models a case can name (ps_model_type_find knows them). */
static const char *const known_models[] = {"fibre", "bond", "state", NULL};

static const char *const material_keys[] = {
    "model", "E", "nu", "plane", "yield_strain", "plastic", "delta",
    "delta_over_c", "rho", "yield_rule", "horizon_factor", "surface_correction", NULL};

static int on_material(loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  static const char *const planes[] = {"strain", "stress", NULL};
  static const char *const rules[] = {"total", "deviatoric", NULL};
  ps_case *cs = L->cs;
  ps_material *m = &cs->mat;
  int i;
  (void)arg;
  if (IS("model")) {
    if (get_choice(L, v, name, known_models, &i)) return PS_ERR_INPUT;
    strcpy(cs->model, known_models[i]);
    return PS_OK;
  }
  if (IS("E")) {
    L->line_E = line_of(v);
    return get_pos_in(L, v, name, PS_E_MIN, PS_E_MAX,
                      "Young's modulus in Pa (steel: 2.1e11)", &m->E);
  }
  if (IS("nu")) {
    L->line_nu = line_of(v);
    return get_real(L, v, name, -1.0, 1, 0.5, 1, &m->nu);
  }
  if (IS("plane")) {
    L->line_plane = line_of(v);
    if (get_choice(L, v, name, planes, &i)) return PS_ERR_INPUT;
    m->plane = i == 0 ? PS_PLANE_STRAIN : PS_PLANE_STRESS;
    return PS_OK;
  }
  if (IS("yield_strain")) {
    L->line_yield_strain = line_of(v);
    return get_pos_in(L, v, name, PS_YIELD_STRAIN_MIN, PS_YIELD_STRAIN_MAX,
                      "a strain (steel: 0.002)", &m->yield_strain);
  }
  if (IS("plastic")) return get_bool(L, v, name, &m->plastic);
  if (IS("delta")) {
    L->line_delta = line_of(v);
    cs->delta_over_c = 0.0;
    return get_pos(L, v, name, &m->delta);
  }
  if (IS("delta_over_c")) {
    L->line_delta_over_c = line_of(v);
    m->delta = NAN;
    return get_pos(L, v, name, &cs->delta_over_c);
  }
  if (IS("rho")) return get_pos(L, v, name, &m->rho);
  if (IS("horizon_factor"))
    return get_pos_in(L, v, name, PS_ALPHA_MIN, PS_ALPHA_MAX,
                      "the horizon in lattice spacings (Fallah et al.: 3)",
                      &cs->horizon_factor);
  if (IS("surface_correction")) return get_bool(L, v, name, &m->surface_correction);
  if (get_choice(L, v, name, rules, &i)) return PS_ERR_INPUT; /* yield_rule */
  m->yield_rule = i == 0 ? PS_YIELD_TOTAL : PS_YIELD_DEVIATORIC;
  return PS_OK;
}

/* ---- loading ---- */

static const char *const select_keys[] = {"x_min", "x_max", "y_min", "y_max",
                                          "z_min", "z_max", "block", NULL};

static int on_select(loader *L, void *arg, const char *key, const char *name,
                     yaml_node_t *v) {
  ps_select *s = arg;
  if (IS("block")) return get_int(L, v, name, 0, INT_MAX, &s->block);
  int k = key[0] - 'x'; /* x, y, z -> 0, 1, 2 */
  double *dst = !strcmp(key + 1, "_min") ? &s->lo[k] : &s->hi[k];
  return get_real(L, v, name, -INFINITY, 0, INFINITY, 0, dst);
}

static const char *const component_keys[] = {"x", "y", "z", NULL};

static int on_displace(loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_bc *bc = arg;
  int k = key[0] - 'x';
  bc->displace_set[k] = 1;
  return get_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->displace[k]);
}

static int on_traction(loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_bc *bc = arg;
  int k = key[0] - 'x';
  bc->traction_set[k] = 1;
  return get_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->traction[k]);
}

static const char *const bc_keys[] = {"select", "fix", "displace", "traction", "measure",
                                      NULL};

static int on_bc(loader *L, void *arg, const char *key, const char *name,
                 yaml_node_t *v) {
  ps_bc *bc = arg;
  char b[80];
  if (IS("select")) {
    if (v->type == YAML_MAPPING_NODE &&
        v->data.mapping.pairs.top == v->data.mapping.pairs.start)
      return fail(L, line_of(v), "%s is empty: select matches everything", name);
    if (walk_map(L, v, name, select_keys, on_select, &bc->sel)) return PS_ERR_INPUT;
    for (int k = 0; k < 3; k++)
      if (bc->sel.lo[k] > bc->sel.hi[k])
        return fail(L, line_of(v), "%s: %c_min > %c_max selects nothing", name, 'x' + k,
                    'x' + k);
    return PS_OK;
  }
  if (IS("fix")) {
    if (v->type != YAML_SEQUENCE_NODE)
      return fail(L, line_of(v), "%s must be a list of components, e.g. [x, y] (got %s)",
                  name, got(v, b));
    for (int i = 0; i < seq_len(v); i++) {
      int k;
      if (get_choice(L, seq_item(L, v, i), name, component_keys, &k)) return PS_ERR_INPUT;
      bc->fix[k] = 1;
    }
    return PS_OK;
  }
  if (IS("displace")) return walk_map(L, v, name, component_keys, on_displace, bc);
  if (IS("traction")) return walk_map(L, v, name, component_keys, on_traction, bc);
  return get_bool(L, v, name, &bc->measure);
}

/* loading.boundary: a list of entries, each checked on its own here (the
 * checks that need dim run at the end). */
static int get_boundary(loader *L, yaml_node_t *v, const char *name) {
  char b[80];
  ps_case *cs = L->cs;
  L->line_boundary = line_of(v);
  if (v->type != YAML_SEQUENCE_NODE)
    return fail(L, line_of(v), "%s must be a list of entries (got %s)", name, got(v, b));
  int n = seq_len(v);
  if (n > PS_MAX_BC)
    return fail(L, line_of(v), "%s has %d entries, at most %d are allowed", name, n,
                PS_MAX_BC);
  cs->n_bc = 0;
  for (int i = 0; i < n; i++) {
    yaml_node_t *e = seq_item(L, v, i);
    ps_bc *bc = &cs->bc[i];
    memset(bc, 0, sizeof *bc);
    for (int k = 0; k < 3; k++) {
      bc->sel.lo[k] = -INFINITY;
      bc->sel.hi[k] = INFINITY;
    }
    bc->sel.block = -1;
    bc->line = line_of(e);
    if (walk_map(L, e, name, bc_keys, on_bc, bc)) return PS_ERR_INPUT;
    int has_select = 0, fixes = 0, displaces = 0, tractions = 0;
    for (yaml_node_pair_t *p = e->data.mapping.pairs.start; p < e->data.mapping.pairs.top;
         p++)
      has_select |= !strcmp(sval(yaml_document_get_node(L->doc, p->key)), "select");
    if (!has_select)
      return fail(L, bc->line,
                  "%s entry %d has no select: it would apply to every particle", name,
                  i + 1);
    for (int k = 0; k < 3; k++) {
      fixes += bc->fix[k];
      displaces += bc->displace_set[k];
      tractions += bc->traction_set[k];
      if (bc->fix[k] && bc->displace_set[k])
        return fail(L, bc->line, "%s entry %d: component %c is both fixed and displaced",
                    name, i + 1, 'x' + k);
      if (bc->traction_set[k] && (bc->fix[k] || bc->displace_set[k]))
        return fail(L, bc->line,
                    "%s entry %d: component %c has a traction and a prescribed "
                    "displacement", name, i + 1, 'x' + k);
    }
    if (!fixes && !displaces && !tractions)
      return fail(L, bc->line,
                  "%s entry %d has no fix, displace or traction: it does nothing", name,
                  i + 1);
    if (bc->measure && !displaces)
      return fail(L, bc->line, "%s entry %d: measure: true needs a displaced component",
                  name, i + 1);
    cs->n_bc++;
  }
  return PS_OK;
}

static const char *const loading_keys[] = {"type", "stress_length", "boundary", NULL};

static int on_loading(loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v) {
  static const char *const types[] = {"eq116", "boundary", NULL};
  (void)arg;
  if (IS("type")) {
    L->line_load_type = line_of(v);
    return get_choice(L, v, name, types, &L->cs->load_type);
  }
  if (IS("stress_length")) return get_pos(L, v, name, &L->cs->stress_length);
  return get_boundary(L, v, name);
}

/* ---- solver, path, output ---- */

static const char *const solver_keys[] = {"linear", "tolerance", "max_iterations",
                                          "max_small_steps",
                                          "line_search", "reuse_factor",
                                          "cg_tolerance", "cg_forcing", "cg_forcing_max",
                                          "cg_max_iterations",
                                          "cg_skip_arms", "reanalyze", "majorant", "matrix_free",
                                          "cg_single_precision", "cg_truncate",
                                          "max_memory_gib", NULL};

static int on_solver(loader *L, void *arg, const char *key, const char *name,
                     yaml_node_t *v) {
  static const char *const linear[] = {"cholmod", "cholmod-simplicial", "umfpack",
                                       NULL};
  ps_case *cs = L->cs;
  (void)arg;
  if (IS("linear")) {
    int i;
    if (get_choice(L, v, name, linear, &i)) return PS_ERR_INPUT;
    strcpy(cs->linear, linear[i]);
    return PS_OK;
  }
  if (IS("tolerance")) return get_real(L, v, name, 0.0, 1, 1.0, 1, &cs->tolerance);
  if (IS("max_iterations")) return get_int(L, v, name, 1, INT_MAX, &cs->max_iterations);
  if (IS("max_small_steps")) return get_int(L, v, name, 0, INT_MAX, &cs->max_small_steps);
  if (IS("reuse_factor")) return get_bool(L, v, name, &cs->reuse_factor);
  if (IS("reanalyze")) return get_bool(L, v, name, &cs->reanalyze);
  if (IS("majorant")) return get_bool(L, v, name, &cs->majorant);
  if (IS("matrix_free")) return get_bool(L, v, name, &cs->matrix_free);
  if (IS("cg_single_precision")) return get_bool(L, v, name, &cs->cg_single_precision);
  if (IS("cg_truncate")) return get_bool(L, v, name, &cs->cg_truncate);
  if (IS("cg_tolerance")) return get_real(L, v, name, 0.0, 1, 1.0, 1, &cs->cg_tolerance);
  if (IS("cg_forcing")) { /* adaptive, or a number >= 0: the fixed rule */
    if (v->type == YAML_SCALAR_NODE && !strcmp(sval(v), "adaptive")) {
      cs->cg_forcing_adaptive = 1;
      return PS_OK;
    }
    char b[80];
    double x = -1.0;
    if (v->type == YAML_SCALAR_NODE && ps_is_decimal(sval(v), 0)) x = strtod(sval(v), NULL);
    if (!isfinite(x) || x < 0)
      return fail(L, line_of(v), "%s must be adaptive or a number >= 0 (got %s)", name,
                  got(v, b));
    cs->cg_forcing_adaptive = 0;
    cs->cg_forcing = x;
    return PS_OK;
  }
  if (IS("cg_forcing_max"))
    return get_real(L, v, name, 0.0, 1, 1.0, 1, &cs->cg_forcing_max);
  if (IS("cg_max_iterations"))
    return get_int(L, v, name, 1, INT_MAX, &cs->cg_max_iterations);
  if (IS("cg_skip_arms")) return get_int(L, v, name, 0, INT_MAX, &cs->cg_skip_arms);
  if (IS("max_memory_gib")) /* a limit, not a setting of the result */
    return get_real(L, v, name, 0.0, 1, PS_MAX_MEMORY_GIB, 0, &cs->max_memory_gib);
  return get_bool(L, v, name, &cs->line_search);
}

static const char *const path_keys[] = {
    "load_step", "load_step_after_break", "max_load", "max_increments", "min_step",
    "stop_crack_tip", "stop_tip_advance", "stop_load_drop", "max_break_rounds", NULL};

static int on_path(loader *L, void *arg, const char *key, const char *name,
                   yaml_node_t *v) {
  ps_case *cs = L->cs;
  (void)arg;
  if (IS("load_step")) return get_pos(L, v, name, &cs->load_step);
  if (IS("load_step_after_break")) return get_pos(L, v, name, &cs->load_step_after_break);
  if (IS("max_load")) return get_pos(L, v, name, &cs->max_load);
  if (IS("max_increments")) return get_int(L, v, name, 1, INT_MAX, &cs->max_increments);
  if (IS("min_step")) return get_pos(L, v, name, &cs->min_step);
  if (IS("stop_crack_tip")) return get_pos(L, v, name, &cs->stop_crack_tip);
  if (IS("stop_tip_advance")) return get_pos(L, v, name, &cs->stop_tip_advance);
  if (IS("stop_load_drop"))
    return get_real(L, v, name, 0.0, 0, 1.0, 1, &cs->stop_load_drop);
  return get_int(L, v, name, 1, INT_MAX, &cs->max_break_rounds);
}

static const char *const output_keys[] = {"dir", "vtk_every", "fields", "verbosity",
                                          "j_integral", NULL};

static const char *const j_keys[] = {"tip", "rings", NULL};

static int on_j(loader *L, void *arg, const char *key, const char *name, yaml_node_t *v) {
  ps_case *cs = L->cs;
  char b[80];
  (void)arg;
  if (IS("tip")) {
    L->line_j_tip = line_of(v);
    return get_point2(L, v, name, cs->j_tip);
  }
  if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 1 || seq_len(v) > 8)
    return fail(L, line_of(v), "%s must be a list of 1 to 8 ring sizes in m (got %s)", name,
                got(v, b));
  cs->n_j_rings = seq_len(v);
  for (int i = 0; i < cs->n_j_rings; i++)
    if (get_real(L, seq_item(L, v, i), name, 0.0, 1, INFINITY, 0, &cs->j_rings[i]))
      return PS_ERR_INPUT;
  return PS_OK;
}

static int on_output(loader *L, void *arg, const char *key, const char *name,
                     yaml_node_t *v) {
  ps_case *cs = L->cs;
  (void)arg;
  if (IS("dir")) return get_string(L, v, name, cs->out_dir, sizeof cs->out_dir);
  if (IS("vtk_every")) return get_int(L, v, name, 0, INT_MAX, &cs->vtk_every);
  if (IS("fields")) return get_bool(L, v, name, &cs->fields);
  if (IS("j_integral")) {
    L->line_j = line_of(v);
    if (walk_map(L, v, name, j_keys, on_j, NULL)) return PS_ERR_INPUT;
    if (!L->line_j_tip || !cs->n_j_rings)
      return fail(L, L->line_j, "%s needs both tip: [x, y] and rings: [l, ...]", name);
    return PS_OK;
  }
  return get_int(L, v, name, 0, 3, &cs->verbosity);
}

/* ---- griffith ---- */

/* griffith.denominators: {first, last, step}, all three required. */
typedef struct sweep_range {
  long first, last, step;
  int line_first, line_last, line_step;
} sweep_range;

static const char *const den_keys[] = {"first", "last", "step", NULL};

static int on_den(loader *L, void *arg, const char *key, const char *name,
                  yaml_node_t *v) {
  sweep_range *r = arg;
  if (IS("first")) {
    r->line_first = line_of(v);
    return get_long(L, v, name, 1, LONG_MAX, &r->first);
  }
  if (IS("last")) {
    r->line_last = line_of(v);
    return get_long(L, v, name, 1, LONG_MAX, &r->last);
  }
  r->line_step = line_of(v);
  return get_long(L, v, name, 1, LONG_MAX, &r->step);
}

static const char *const griffith_keys[] = {"delta_over_c", "denominators", NULL};

static int on_griffith(loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_case *cs = L->cs;
  char b[80];
  (void)arg;
  if (IS("delta_over_c")) {
    L->line_sweep_list = line_of(v);
    if (v->type != YAML_SEQUENCE_NODE || seq_len(v) == 0)
      return fail(L, line_of(v), "%s must be a non-empty list of numbers (got %s)", name,
                  got(v, b));
    int n = seq_len(v);
    if (n > PS_MAX_SWEEP)
      return fail(L, line_of(v), "%s has %d values, at most %d are allowed", name, n,
                  PS_MAX_SWEEP);
    for (int i = 0; i < n; i++)
      if (get_pos(L, seq_item(L, v, i), name, &cs->sweep_delta_over_c[i]))
        return PS_ERR_INPUT;
    cs->n_sweep = n;
    return PS_OK;
  }
  /* denominators */
  sweep_range r = {0};
  L->line_sweep_den = line_of(v);
  if (walk_map(L, v, name, den_keys, on_den, &r)) return PS_ERR_INPUT;
  if (!r.line_first || !r.line_last || !r.line_step)
    return fail(L, line_of(v), "%s needs first, last and step", name);
  if (r.last < r.first)
    return fail(L, r.line_last, "%s.last must be >= first (got %ld < %ld)", name, r.last,
                r.first);
  long n = (r.last - r.first) / r.step + 1;
  if (n > PS_MAX_SWEEP)
    return fail(L, line_of(v), "%s gives %ld values, at most %d are allowed", name, n,
                PS_MAX_SWEEP);
  for (long i = 0; i < n; i++)
    cs->sweep_delta_over_c[i] = 1.0 / (double)(r.first + i * r.step);
  cs->n_sweep = (int)n;
  return PS_OK;
}

/* ---- top level ---- */

static const char *const top_keys[] = {"name",   "geometry", "kernel",
                                       "material", "loading", "solver",
                                       "path",   "output",   "griffith", NULL};

static int on_top(loader *L, void *arg, const char *key, const char *name,
                  yaml_node_t *v) {
  (void)arg;
  if (IS("name")) {
    if (get_string(L, v, name, L->cs->name, sizeof L->cs->name)) return PS_ERR_INPUT;
    if (strchr(L->cs->name, '/'))
      return fail(L, line_of(v), "name must not contain '/' (got %s)", L->cs->name);
    return PS_OK;
  }
  if (IS("geometry")) return walk_map(L, v, name, geometry_keys, on_geometry, NULL);
  if (IS("kernel")) return walk_map(L, v, name, kernel_keys, on_kernel, NULL);
  if (IS("material")) return walk_map(L, v, name, material_keys, on_material, NULL);
  if (IS("loading")) return walk_map(L, v, name, loading_keys, on_loading, NULL);
  if (IS("solver")) return walk_map(L, v, name, solver_keys, on_solver, NULL);
  if (IS("path")) return walk_map(L, v, name, path_keys, on_path, NULL);
  if (IS("output")) return walk_map(L, v, name, output_keys, on_output, NULL);
  return walk_map(L, v, name, griffith_keys, on_griffith, NULL);
}

/* A geometry key given for a geometry type it does not apply to (it
 * would be silently ignored): "case.yaml:7: geometry.file does not apply
 * to geometry.type disk (it is for type cloud)", for the first such key
 * in the file. Keys not listed (type, dim, sizes, size_neighbours,
 * cracks) apply to every type; geometry.holes has its own check. */
static int geometry_keys_apply(loader *L) {
  enum { D = 1 << PS_GEOM_DISK, B = 1 << PS_GEOM_BOX, C = 1 << PS_GEOM_CLOUD };
  static const struct {
    const char *key;
    unsigned types;
    const char *for_text;
  } only[] = {{"c", D, "type disk"},          {"n_eta", D, "type disk"},
              {"n_xi", D, "type disk"},       {"per_zone", D, "type disk"},
              {"xi_min", D, "type disk"},     {"xi_max", D, "type disk"},
              {"jitter", D | B, "types disk and box"},
              {"seed", D | B, "types disk and box"},
              {"counts", B, "type box"},      {"lattice", B, "type box"},
              {"origin", B, "type box"},      {"file", C, "type cloud"},
              {"spacing", B, "type box, and for loading tractions"}};
  static const char *const gname[] = {"disk", "box", "cloud"};
  const ps_case *cs = L->cs;
  int traction = 0;
  for (int i = 0; i < cs->n_bc; i++)
    for (int k = 0; k < 3; k++) traction |= cs->bc[i].traction_set[k];
  int first = 0, at = 0;
  for (size_t j = 0; j < sizeof only / sizeof only[0]; j++) {
    int i = 0;
    while (strcmp(geometry_keys[i], only[j].key)) i++;
    int line = L->line_geometry[i];
    if (!line || (only[j].types >> cs->geometry & 1u)) continue;
    if (!strcmp(only[j].key, "spacing") && traction) continue;
    if (!first || line < first) {
      first = line;
      at = (int)j;
    }
  }
  if (!first) return PS_OK;
  return fail(L, first, "geometry.%s does not apply to geometry.type %s%s (it is for %s)",
              only[at].key, gname[cs->geometry], L->line_type ? "" : ", the default",
              only[at].for_text);
}

/* The line where geometry key `key` was given, else `otherwise`. */
static int geometry_line(const loader *L, const char *key, int otherwise) {
  for (int i = 0; geometry_keys[i]; i++)
    if (!strcmp(geometry_keys[i], key) && L->line_geometry[i]) return L->line_geometry[i];
  return otherwise;
}

/* The number of particles a box or disk asks for: at most
 * PS_MAX_PARTICLES (the generators' limit), named with the keys' line.
 * (Whether they fit in memory is judged later, by the size estimate.) */
static int particle_counts_check(loader *L) {
  const ps_case *cs = L->cs;
  double n = 1.0;
  if (cs->geometry == PS_GEOM_BOX) {
    for (int k = 0; k < cs->dim; k++) n *= (double)cs->counts[k];
    if (n > (double)PS_MAX_PARTICLES)
      return fail(L, L->line_counts, "geometry.counts asks for %.3g particles; at most "
                  "2^40 = %.4g can be indexed", n, (double)PS_MAX_PARTICLES);
  } else if (cs->geometry == PS_GEOM_DISK) {
    const ps_disk_params *dp = &cs->disk;
    double m = dp->per_zone;
    int line = geometry_line(L, "per_zone", geometry_line(L, "n_xi", L->line_type));
    n = (double)dp->n_eta * dp->n_xi * m * m;
    if (n > (double)PS_MAX_PARTICLES)
      return fail(L, line,
                  "geometry.n_eta x geometry.n_xi x geometry.per_zone^2 = %d x %d x %d^2 "
                  "asks for %.3g particles; at most 2^40 = %.4g can be indexed",
                  dp->n_eta, dp->n_xi, dp->per_zone, n, (double)PS_MAX_PARTICLES);
  }
  return PS_OK;
}

/* The bond-based model fixes Poisson's ratio (Fallah et al. 2020): 1/3
 * in plane stress, 1/4 in plane strain and 3D. Checked here, so that
 * `info` refuses what `run` would (bond.c checks it again). The message
 * names the file only, as the model's own did ("case.yaml: material.nu
 * = 0.3: bond-based ..."), and the line at its end. */
static int bond_nu_check(loader *L) {
  const ps_case *cs = L->cs;
  if (strcmp(cs->model, "bond") != 0) return PS_OK;
  int stress = cs->dim == 2 && cs->mat.plane == PS_PLANE_STRESS;
  double nu_fixed = stress ? 1.0 / 3.0 : 0.25;
  if (fabs(cs->mat.nu - nu_fixed) <= 1e-3) return PS_OK;
  char where[64];
  if (L->line_nu)
    snprintf(where, sizeof where, "material.nu is at line %d", L->line_nu);
  else
    snprintf(where, sizeof where, "material.nu is not given: the default is 0.3");
  return fail(L, 0,
              "material.nu = %g: bond-based peridynamics has nu = %s in %s (Fallah et "
              "al. 2020, section 5) (%s)",
              cs->mat.nu, stress ? "1/3" : "1/4",
              cs->dim == 3 ? "3D" : stress ? "plane stress" : "plane strain", where);
}

/* Checks across sections, after the whole file is read. */
static int cross_checks(loader *L) {
  static const char *const gname[] = {"disk", "box", "cloud"};
  ps_case *cs = L->cs;
  if (geometry_keys_apply(L) != PS_OK) return PS_ERR_INPUT;
  if (cs->geometry == PS_GEOM_DISK) {
    if (L->line_dim && cs->dim != 2)
      return fail(L, L->line_dim, "geometry.dim must be 2 for geometry.type disk (got %d)",
                  cs->dim);
    cs->dim = 2;
  }
  if (cs->geometry == PS_GEOM_BOX) {
    if (L->line_counts && L->n_counts != cs->dim)
      return fail(L, L->line_counts,
                  "geometry.counts has %d values but geometry.dim is %d", L->n_counts,
                  cs->dim);
    if (!L->line_counts && cs->dim == 3)
      return fail(L, L->line_dim, "a 3D box needs geometry.counts: [nx, ny, nz]");
    if (cs->dim == 3 && !strcmp(cs->lattice, "hex"))
      return fail(L, L->line_lattice, "geometry.lattice hex is 2D only (geometry.dim is 3)");
  }
  if (cs->dim == 2) cs->counts[2] = 1;
  if (cs->geometry == PS_GEOM_CLOUD && !cs->cloud_file[0])
    return fail(L, L->line_type, "geometry.type cloud needs geometry.file");
  if (cs->n_cracks > 0 && cs->dim == 3)
    return fail(L, L->line_cracks, "geometry.cracks are 2D only (geometry.dim is 3)");
  if (cs->n_j_rings > 0 && cs->dim == 3)
    return fail(L, L->line_j, "output.j_integral is 2D only (geometry.dim is 3)");
  if (cs->n_holes > 0 && (cs->dim == 3 || cs->geometry != PS_GEOM_BOX))
    return fail(L, L->line_holes, "geometry.holes need a 2D box");
  if (strcmp(cs->model, "fibre") != 0 && cs->geometry != PS_GEOM_BOX)
    return fail(L, L->line_type ? L->line_type : 1,
                "material.model %s needs geometry.type box (a regular lattice: the "
                "horizon is material.horizon_factor * geometry.spacing)", cs->model);
  if (bond_nu_check(L) != PS_OK || particle_counts_check(L) != PS_OK) return PS_ERR_INPUT;
  if (L->line_delta_over_c && cs->geometry != PS_GEOM_DISK)
    return fail(L, L->line_delta_over_c,
                "material.delta_over_c needs geometry.type disk (c is the disk's half "
                "crack length): give material.delta in metres");
  if (L->line_delta && L->line_delta_over_c)
    return fail(L, L->line_delta,
                "material.delta and material.delta_over_c (line %d) are both given: "
                "give one",
                L->line_delta_over_c);
  if (L->line_sweep_list && L->line_sweep_den)
    return fail(L, L->line_sweep_den,
                "griffith.denominators and griffith.delta_over_c (line %d) are both "
                "given: give one",
                L->line_sweep_list);
  if (cs->load_type == PS_LOAD_EQ116) {
    if (cs->geometry != PS_GEOM_DISK)
      return fail(L, L->line_load_type ? L->line_load_type : L->line_type,
                  "loading.type eq116%s needs geometry.type disk (got %s): set "
                  "loading.type: boundary",
                  L->line_load_type ? "" : " (the default)", gname[cs->geometry]);
    if (cs->n_bc > 0 || L->line_boundary)
      return fail(L, L->line_boundary,
                  "loading.boundary is given but loading.type is eq116: set "
                  "loading.type: boundary");
  } else if (cs->n_bc == 0) {
    return fail(L, L->line_boundary ? L->line_boundary : L->line_load_type,
                "loading.boundary is empty: the model has no supports");
  }
  for (int i = 0; i < cs->n_bc && cs->dim == 2; i++) {
    const ps_bc *bc = &cs->bc[i];
    if (bc->fix[2] || bc->displace_set[2] || bc->traction_set[2] ||
        isfinite(bc->sel.lo[2]) || isfinite(bc->sel.hi[2]))
      return fail(L, bc->line,
                  "loading.boundary entry %d uses the z component but geometry.dim is 2",
                  i + 1);
  }
  return PS_OK;
}

/* ---- the text before libyaml ---- */

/* Read the whole case file into *text (NUL-terminated, *len bytes, freed
 * by the caller) if it is at most PS_CASE_MAX_BYTES long. Returns PS_OK,
 * PS_ERR_IO (cannot open, a directory, read error), PS_ERR_INPUT (too
 * large), PS_ERR_NOMEM. */
static int read_case_text(const char *path, char **text, size_t *len, ps_ctx *ctx) {
  const size_t max = PS_CASE_MAX_BYTES;
  *text = NULL;
  *len = 0;
  FILE *f = fopen(path, "rb");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat st;
  int regular = fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode);
  if (!regular && fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
    fclose(f);
    return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(EISDIR));
  }
  if (regular && (uintmax_t)st.st_size > max) {
    fclose(f);
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: larger than 1 MiB (%jd bytes); case files are small YAML texts",
                    path, (intmax_t)st.st_size);
  }
  /* a regular file's size is known; pipes and devices grow the buffer
   * (to one byte past the limit, to tell "too large") */
  size_t cap = regular ? (size_t)st.st_size + 1 : 4096, n = 0;
  void *buf = ps_calloc(cap + 1, 1, ctx);
  int status = buf ? PS_OK : PS_ERR_NOMEM;
  while (status == PS_OK) {
    n += fread((char *)buf + n, 1, cap - n, f);
    if (n < cap || cap > max) break; /* end of file, an error, or too large */
    size_t grown = 2 * cap > max + 1 ? max + 1 : 2 * cap;
    status = ps_realloc(&buf, grown + 1, 1, ctx);
    cap = grown;
  }
  if (status == PS_OK && ferror(f))
    status = ps_error(ctx, PS_ERR_IO, "%s: read error: %s", path, strerror(errno));
  else if (status == PS_OK && n > max)
    status = ps_error(ctx, PS_ERR_INPUT,
                      "%s: larger than 1 MiB (more than %zu bytes); case files are small "
                      "YAML texts", path, max);
  fclose(f);
  if (status != PS_OK) {
    free(buf);
    return status;
  }
  ((char *)buf)[n] = '\0';
  *text = buf;
  *len = n;
  return PS_OK;
}

/* The nesting of a case file's text, measured before libyaml parses it:
 * block levels (a stack of indentation columns, with a sequence at its
 * parent key's column and each compact "- " on a line one more) plus
 * flow levels ('[' and '{' where a node may start, outside quoted
 * scalars, comments and block scalars). An approximation of YAML's
 * grammar, close enough to bound libyaml's work: it can count a level
 * more than libyaml builds (a plain scalar continued on a line that
 * starts with '['), never many fewer. */
typedef struct nest_scan {
  int flow;         /* open flow collections */
  char quote;       /* '\'' or '"' inside a quoted scalar, else 0 */
  int node_start;   /* a node may start at the next character */
  int block_scalar; /* >= 0: inside a block scalar ('|', '>') whose
                       header line is indented this much; -1: not */
  int n_level;      /* block levels: columns and kinds (1: sequence) */
  int col[PS_CASE_MAX_DEPTH + 2];
  char seq[PS_CASE_MAX_DEPTH + 2];
} nest_scan;

/* Push a block level; 0 when that makes the nesting too deep. */
static int nest_push(nest_scan *S, int col, int seq) {
  if (S->n_level + S->flow >= PS_CASE_MAX_DEPTH) return 0;
  S->col[S->n_level] = col;
  S->seq[S->n_level++] = (char)seq;
  return 1;
}

/* Is s[i] an indicator followed by a blank or the end of the line? */
static int indicator(const char *s, size_t i, size_t len, char c) {
  return s[i] == c && (i + 1 == len || s[i + 1] == ' ' || s[i + 1] == '\t');
}

/* Scan the characters s[i..len) of one line for quotes, comments and flow
 * brackets. Returns 0 when the nesting gets too deep. */
static int nest_chars(nest_scan *S, const char *s, size_t i, size_t len, int indent) {
  for (; i < len; i++) {
    char c = s[i];
    if (S->quote) {
      if (S->quote == '"' && c == '\\')
        i++;
      else if (c == '\'' && S->quote == '\'' && i + 1 < len && s[i + 1] == '\'')
        i++;
      else if (c == S->quote)
        S->quote = 0;
      continue;
    }
    if (c == ' ' || c == '\t') continue;
    if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) break;
    if (S->node_start && (c == '\'' || c == '"')) {
      S->quote = c;
      S->node_start = 0;
    } else if ((c == '[' || c == '{') && (S->node_start || S->flow > 0)) {
      if (S->n_level + ++S->flow > PS_CASE_MAX_DEPTH) return 0;
      S->node_start = 1;
    } else if ((c == ']' || c == '}') && S->flow > 0) {
      S->flow--;
      S->node_start = 0;
    } else if (c == ',' && S->flow > 0) {
      S->node_start = 1;
    } else if (c == ':' && (indicator(s, i, len, ':') ||
                            (S->flow > 0 && i + 1 < len && strchr(",[]{}", s[i + 1])))) {
      S->node_start = 1;
    } else if (S->node_start && (indicator(s, i, len, '-') || indicator(s, i, len, '?'))) {
      /* a node may still start after "- " or "? " */
    } else if (S->node_start && (c == '&' || c == '!')) {
      while (i + 1 < len && s[i + 1] != ' ' && s[i + 1] != '\t') i++; /* anchor, tag */
    } else if (S->node_start && S->flow == 0 && (c == '|' || c == '>')) {
      S->block_scalar = indent; /* the rest of the line: indicators, comment */
      break;
    } else {
      S->node_start = 0;
    }
  }
  return 1;
}

/* One line (without its line break) of block context: the levels its
 * indentation closes and opens, then its characters. Returns 0 when the
 * nesting gets too deep. */
static int nest_block_line(nest_scan *S, const char *s, size_t len) {
  size_t i = 0;
  while (i < len && s[i] == ' ') i++;
  int indent = (int)i;
  if (i == len || s[i] == '#' || (i == 0 && s[0] == '%')) return 1; /* blank, comment,
                                                                   directive */
  if (i == 0 && len >= 3 && (!strncmp(s, "---", 3) || !strncmp(s, "...", 3)) &&
      (len == 3 || s[3] == ' ' || s[3] == '\t')) { /* a document starts or ends */
    S->n_level = 0;
    S->node_start = 1;
    return nest_chars(S, s, 3, len, 0);
  }
  int seq_line = indicator(s, i, len, '-');
  while (S->n_level > 0 && S->col[S->n_level - 1] > indent) S->n_level--;
  if (S->n_level > 0 && S->col[S->n_level - 1] == indent && S->seq[S->n_level - 1] &&
      !seq_line)
    S->n_level--; /* a sequence at its key's column ended */
  int top = S->n_level > 0 ? S->col[S->n_level - 1] : -1;
  if (top < indent || (top == indent && seq_line && !S->seq[S->n_level - 1]))
    if (!nest_push(S, indent, seq_line)) return 0;
  /* compact nesting on the line: "- - key: [..." */
  while (indicator(s, i, len, '-') || indicator(s, i, len, '?')) {
    i++;
    while (i < len && (s[i] == ' ' || s[i] == '\t')) i++;
    if (i == len || s[i] == '#') break;
    if (!nest_push(S, (int)i, indicator(s, i, len, '-'))) return 0;
  }
  S->node_start = 1;
  return nest_chars(S, s, i, len, indent);
}

/* Refuse a text nested deeper than PS_CASE_MAX_DEPTH levels (nest_scan)
 * before libyaml parses it: "case.yaml:7: nesting deeper than 32 levels".
 * Returns PS_OK or PS_ERR_INPUT. */
static int check_nesting(const char *path, const char *text, size_t len, ps_ctx *ctx) {
  nest_scan S = {.block_scalar = -1};
  int line = 1;
  for (size_t at = 0; at < len; line++) {
    const char *nl = memchr(text + at, '\n', len - at);
    size_t end = nl ? (size_t)(nl - text) : len, n = end - at;
    const char *s = text + at;
    at = end + 1;
    if (n > 0 && s[n - 1] == '\r') n--;
    if (S.block_scalar >= 0) {
      size_t i = 0;
      while (i < n && s[i] == ' ') i++;
      if (i == n || (int)i > S.block_scalar) continue; /* the scalar's text */
      S.block_scalar = -1;
    }
    int ok = S.quote || S.flow > 0 ? nest_chars(&S, s, 0, n, 0) : nest_block_line(&S, s, n);
    if (!ok)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%d: nesting deeper than %d levels (lists and mappings); case "
                      "files nest a few", path, line, PS_CASE_MAX_DEPTH);
  }
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

/* Set path, dir (the directory part, "." when none) and the default name
 * (the file name without .yaml / .yml) of cs from path. */
static void set_names(ps_case *cs, const char *path) {
  snprintf(cs->path, sizeof cs->path, "%s", path);
  const char *slash = strrchr(path, '/');
  if (!slash)
    strcpy(cs->dir, ".");
  else if (slash == path)
    strcpy(cs->dir, "/");
  else
    snprintf(cs->dir, sizeof cs->dir, "%.*s", (int)(slash - path), path);
  const char *base = slash ? slash + 1 : path;
  size_t n = strlen(base);
  if (n > 5 && !strcmp(base + n - 5, ".yaml"))
    n -= 5;
  else if (n > 4 && !strcmp(base + n - 4, ".yml"))
    n -= 4;
  if (n == 0) return; /* keep the default name */
  if (n >= sizeof cs->name) n = sizeof cs->name - 1;
  memcpy(cs->name, base, n);
  cs->name[n] = '\0';
}

int ps_case_load(ps_case *cs, const char *path, ps_ctx *ctx) {
  if (strlen(path) >= sizeof cs->path)
    return ps_error(ctx, PS_ERR_IO, "%s: path too long", path);
  /* size and nesting are checked before libyaml sees the text */
  char *text;
  size_t len;
  PS_CHECK(read_case_text(path, &text, &len, ctx));
  int status = check_nesting(path, text, len, ctx);
  if (status != PS_OK) {
    free(text);
    return status;
  }
  /* fill a copy so that a failed load leaves *cs as it was */
  ps_case *work = ps_calloc(1, sizeof *work, ctx);
  if (!work) {
    free(text);
    return PS_ERR_NOMEM;
  }
  *work = *cs;
  set_names(work, path);

  int have_doc = 0;
  yaml_parser_t parser;
  yaml_document_t doc;
  if (!yaml_parser_initialize(&parser)) {
    free(work);
    free(text);
    return ps_error(ctx, PS_ERR_NOMEM, "%s: cannot initialise the YAML parser", path);
  }
  yaml_parser_set_input_string(&parser, (const unsigned char *)text, len);
  if (!yaml_parser_load(&parser, &doc)) {
    status = syntax_error(path, &parser, text, len, ctx);
    goto cleanup;
  }
  have_doc = 1;
  loader L = {.file = path, .doc = &doc, .cs = work, .ctx = ctx};
  yaml_node_t *root = yaml_document_get_root_node(&doc);
  if (root) { /* an empty file keeps every default */
    status = walk_map(&L, root, "", top_keys, on_top, NULL);
    if (status != PS_OK) goto cleanup;
  }
  /* a second document would be silently ignored: refuse it */
  yaml_document_t extra;
  if (!yaml_parser_load(&parser, &extra)) {
    status = syntax_error(path, &parser, text, len, ctx);
    goto cleanup;
  }
  yaml_node_t *extra_root = yaml_document_get_root_node(&extra);
  int extra_line = extra_root ? line_of(extra_root) : 0;
  yaml_document_delete(&extra);
  if (extra_line) {
    status = fail(&L, extra_line, "a case file holds one YAML document (a second starts here)");
    goto cleanup;
  }
  status = cross_checks(&L);
  if (status == PS_OK) *cs = *work;

cleanup:
  if (have_doc) yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  free(work);
  free(text);
  return status;
}

/* FNV-1a over the bytes of a formatted description */
static void fnv(uint64_t *h, const char *s) {
  for (; *s; s++) {
    *h ^= (unsigned char)*s;
    *h *= 1099511628211ULL;
  }
}

/* Bump when the algorithm changes what a run computes, so that `griffith
 * --resume` does not reuse runs of an older algorithm. 2: breaking rounds
 * that fail to re-equilibrate are retried with fewer arms. 3: Newton
 * steps that point uphill (indefinite tangent) are replaced by a shifted
 * Cholesky step. 4: only settled states (no arm left past delta) set the
 * peak; path.stop_tip_advance. 5: CG truncated at negative curvature
 * (solver.cg_truncate) and Newton solves that stagnate
 * (solver.max_small_steps) can change which solves near the plastic
 * limit load converge (the paper's sweep, rerun: 11 of 12 sigma_f as in
 * version 4, and c/1250 fractures where version 4 stalled). 6: after a
 * failed increment the fresh factor is the majorant's, not the tangent's,
 * which changes where runs near the plastic limit stall (c/500: at 1.535
 * in a breaking round instead of 1.53438 in Newton). Other CG
 * settings, e.g. solver.cg_skip_arms or cg_single_precision, do not change
 * results beyond the Newton tolerance and are not counted; turning
 * cg_truncate off is (it brings back version 4's route through UMFPACK).
 * 7: arm lengths rounded at zero (PS_ARM_LENGTH_ROUNDING): an arm crushed
 * at the crack tip no longer stalls Newton, and c/1000 fractures at 20k
 * where it stalled at 1.47.
 * 8: the adaptive CG tolerance (cg_forcing: adaptive, with the fixed rule
 * once a solve reaches max_iterations) is the default, and a CG
 * iteration's sums are split in two parts for two threads (the same
 * numbers on one thread or two, but other round-off than version 7's);
 * the fixed rule now enters the fingerprint (near the plastic limit the
 * two rules' paths differ by ~1e-4). */
#define PS_ALGORITHM_VERSION 8

/* Not hashed (they do not change a run's result): the output keys, delta
 * and the Griffith list, the CG settings named above, and
 * solver.max_memory_gib (a limit on what may be allocated). */
uint64_t ps_case_fingerprint(const ps_case *cs) {
  uint64_t h = 1469598103934665603ULL;
  char b[1600];
  snprintf(b, sizeof b, "peristatic algorithm %d", PS_ALGORITHM_VERSION);
  fnv(&h, b);
  const ps_disk_params *dp = &cs->disk;
  const ps_material *m = &cs->mat;
  snprintf(b, sizeof b, "g%d d%d disk %.17g %d %d %d %.17g %.17g %.17g %lu", cs->geometry,
           cs->dim, dp->c, dp->n_eta, dp->n_xi, dp->per_zone, dp->xi_min, dp->xi_max,
           dp->jitter, dp->seed);
  fnv(&h, b);
  snprintf(b, sizeof b, "box %lld %lld %lld %.17g %s %.17g %lu cloud %s size %d %d",
           (long long)cs->counts[0], (long long)cs->counts[1], (long long)cs->counts[2],
           cs->spacing, cs->lattice, cs->jitter, cs->seed, cs->cloud_file, cs->size_rule,
           cs->size_neighbours);
  fnv(&h, b);
  /* newer keys enter only when set, so fingerprints of older cases stay */
  if (cs->origin[0] != 0 || cs->origin[1] != 0 || cs->origin[2] != 0) {
    snprintf(b, sizeof b, "origin %.17g %.17g %.17g", cs->origin[0], cs->origin[1],
             cs->origin[2]);
    fnv(&h, b);
  }
  for (int i = 0; i < cs->n_holes; i++) {
    snprintf(b, sizeof b, "hole %.17g %.17g %.17g", cs->holes[i][0], cs->holes[i][1],
             cs->holes[i][2]);
    fnv(&h, b);
  }
  if (strcmp(cs->model, "fibre") != 0) {
    snprintf(b, sizeof b, "lattice %.17g %d", cs->horizon_factor, m->surface_correction);
    fnv(&h, b);
  }
  for (int i = 0; i < cs->n_cracks; i++) {
    snprintf(b, sizeof b, "crack %.17g %.17g %.17g %.17g", cs->cracks[i].p0[0],
             cs->cracks[i].p0[1], cs->cracks[i].p1[0], cs->cracks[i].p1[1]);
    fnv(&h, b);
  }
  snprintf(b, sizeof b, "kernel %.17g %d model %s E %.17g nu %.17g plane %d ey %.17g "
           "plastic %d rho %.17g rule %d load %d len %.17g",
           cs->alpha, cs->kernel_k, cs->model, m->E, m->nu, m->plane, m->yield_strain,
           m->plastic, m->rho, m->yield_rule, cs->load_type, cs->stress_length);
  fnv(&h, b);
  for (int i = 0; i < cs->n_bc; i++) {
    const ps_bc *bc = &cs->bc[i];
    snprintf(b, sizeof b, "bc %.17g %.17g %.17g %.17g %.17g %.17g %d %d%d%d %d%d%d "
             "%.17g %.17g %.17g %d",
             bc->sel.lo[0], bc->sel.lo[1], bc->sel.lo[2], bc->sel.hi[0], bc->sel.hi[1],
             bc->sel.hi[2], bc->sel.block, bc->fix[0], bc->fix[1], bc->fix[2],
             bc->displace_set[0], bc->displace_set[1], bc->displace_set[2],
             bc->displace[0], bc->displace[1], bc->displace[2], bc->measure);
    fnv(&h, b);
    if (bc->traction_set[0] || bc->traction_set[1] || bc->traction_set[2]) {
      snprintf(b, sizeof b, "traction %d%d%d %.17g %.17g %.17g", bc->traction_set[0],
               bc->traction_set[1], bc->traction_set[2], bc->traction[0], bc->traction[1],
               bc->traction[2]);
      fnv(&h, b);
    }
  }
  snprintf(b, sizeof b, "solver %.17g %d %d path %.17g %.17g %.17g %d %.17g %.17g %.17g %d",
           cs->tolerance, cs->max_iterations, cs->line_search, cs->load_step,
           cs->load_step_after_break, cs->max_load, cs->max_increments, cs->min_step,
           cs->stop_crack_tip, cs->stop_load_drop, cs->max_break_rounds);
  fnv(&h, b);
  ps_solver_opts so;
  ps_solver_opts_default(&so);
  if (cs->max_small_steps != so.max_small_steps) { /* newer keys: only when not
                                                      the default */
    snprintf(b, sizeof b, "small steps %d", cs->max_small_steps);
    fnv(&h, b);
  }
  if (!cs->cg_truncate) fnv(&h, "cg not truncated");
  if (!cs->cg_forcing_adaptive) { /* the default since version 8 */
    snprintf(b, sizeof b, "cg forcing %.17g", cs->cg_forcing);
    fnv(&h, b);
  }
  if (cs->stop_tip_advance > 0) { /* newer key: only when set */
    snprintf(b, sizeof b, "tip advance %.17g", cs->stop_tip_advance);
    fnv(&h, b);
  }
  return h;
}
