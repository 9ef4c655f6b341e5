/* case_impl.h: private to the case-file reader (src/io/case*.c), not part
 * of ps_io.h. The loader state, the libyaml document of one case file,
 * the typed getters every section handler uses (case_yaml.c), the text
 * checks run before libyaml (case_text.c), the section handlers and
 * their key lists (case_sections.c, case_loading.c, case_options.c) and
 * the checks across sections (case_checks.c).
 *
 * Every getter reads one node into one value or fails with PS_ERR_INPUT
 * and a message "FILE:LINE: NAME must be ... (got ...)", where NAME is
 * the key's dotted path ("material.E"); on failure *out is unchanged. */
#ifndef PS_CASE_IMPL_H
#define PS_CASE_IMPL_H

#include "ps_io.h"

#include <string.h>
#include <yaml.h>

/* Loader state: the document being walked, the case being filled and the
 * lines where keys needed by the final cross checks were given (0: not
 * given). */
typedef struct ps_loader {
  const char *file;
  yaml_document_t *doc;
  ps_case *cs;
  ps_ctx *ctx;
  int line_type, line_dim, line_counts, n_counts, line_lattice, line_cracks, line_holes;
  int line_j, line_j_tip;
  int line_j_dir, line_j_crack, line_j_tips; /* output.j_integral */
  int line_load_type, line_boundary, line_delta, line_delta_over_c;
  int line_sweep_list, line_sweep_den;
  int line_E, line_nu, line_yield_strain, line_plane;
  int line_fracture, line_micromodulus, line_partial_volumes, line_model, line_plastic;
  int line_fracture_criterion, n_fracture_given; /* within material.fracture */
  int line_softening;                            /* material.fracture.softening_ratio */
  int line_control, line_yield_rule;             /* path.control, material.yield_rule */
  int line_load_until_unstable;                  /* path.load_until_unstable */
  int line_break_rule, line_break_length;        /* material.break_rule, break_length */
  int line_steps, line_load_step, line_load_step_after_break, line_max_load; /* path */
  int line_horizon, line_horizon_factor;
  int line_geometry[24]; /* per ps_case_geometry_keys entry: where it was given */
  /* geometry.cracks and holes, per entry: its line, and the form given
   * (cracks: 2 for a segment of [x, y] points, 3 for a polygon of
   * [x, y, z] points; holes: the values, 3 or 4), checked against
   * geometry.dim once the file is read */
  int line_crack[PS_MAX_CRACKS], crack_dim[PS_MAX_CRACKS];
  int line_hole[PS_MAX_HOLES], hole_len[PS_MAX_HOLES];
} ps_loader;

/* Handler for one key of a mapping: key is the bare key, name its dotted
 * path for messages ("material.E"), v the value node; arg is walk_map's. */
typedef int (*ps_key_fn)(ps_loader *L, void *arg, const char *key, const char *name,
                         yaml_node_t *v);

/* In a handler: is this key k? */
#define IS(k) (!strcmp(key, (k)))

/* 1-based line where a node starts. */
static inline int line_of(const yaml_node_t *n) { return (int)n->start_mark.line + 1; }

/* Text of a scalar node. */
static inline const char *sval(const yaml_node_t *n) {
  return (const char *)n->data.scalar.value;
}

/* Number of items of a sequence node. */
static inline int seq_len(const yaml_node_t *n) {
  return (int)(n->data.sequence.items.top - n->data.sequence.items.start);
}

/* Item i of a sequence node. */
static inline yaml_node_t *seq_item(ps_loader *L, const yaml_node_t *n, int i) {
  return yaml_document_get_node(L->doc, n->data.sequence.items.start[i]);
}

/* ---- case_text.c: the text before libyaml ---- */

/* Read the whole case file into *text (NUL-terminated, *len bytes, freed
 * by the caller) if it is at most PS_CASE_MAX_BYTES long. Returns PS_OK,
 * PS_ERR_IO (cannot open, a directory, read error), PS_ERR_INPUT (too
 * large), PS_ERR_NOMEM. */
int ps_case_read_text(const char *path, char **text, size_t *len, ps_ctx *ctx);

/* Refuse, on libyaml's events before its loader builds the document, a
 * text nested deeper than PS_CASE_MAX_DEPTH levels ("case.yaml:7: nesting
 * deeper than 32 levels") or holding a YAML anchor or alias ("case.yaml:7:
 * case files use no YAML anchors (&) or aliases (*)"). Syntax and encoding
 * errors are left to ps_yaml_open. Returns PS_OK, PS_ERR_INPUT or
 * PS_ERR_NOMEM. */
int ps_case_check_nesting(const char *path, const char *text, size_t len, ps_ctx *ctx);

/* ---- case_yaml.c: libyaml's document and the typed getters ---- */

/* One case file's text parsed by libyaml: its first document (doc) and
 * the parser, left where the next document would start. */
typedef struct ps_yaml_file {
  const char *file;     /* the path, for messages */
  const char *text;     /* the text parsed, len bytes */
  size_t len;
  yaml_parser_t parser;
  yaml_document_t doc;
  int have_parser, have_doc;
} ps_yaml_file;

/* Parse the first document of text into Y->doc. Errors: "FILE:LINE: YAML
 * syntax error: problem (context at line N)", "FILE:LINE: YAML read
 * error: problem (column C)" (invalid UTF-8, control characters).
 * Returns PS_OK, PS_ERR_INPUT, PS_ERR_NOMEM; call ps_yaml_close in any
 * case. */
int ps_yaml_open(ps_yaml_file *Y, const char *file, const char *text, size_t len,
                 ps_ctx *ctx);

/* Refuse a second document after the first (it would be silently
 * ignored), or a syntax error there. Returns PS_OK, PS_ERR_INPUT,
 * PS_ERR_NOMEM. */
int ps_yaml_only_document(ps_yaml_file *Y, ps_ctx *ctx);

/* Free the parser and the document (safe after a failed ps_yaml_open). */
void ps_yaml_close(ps_yaml_file *Y);

/* Record "FILE:LINE: message" (or "FILE: message" when line is 0) as a
 * PS_ERR_INPUT error; returns PS_ERR_INPUT. */
__attribute__((format(printf, 3, 4))) int ps_yaml_fail(const ps_loader *L, int line,
                                                       const char *fmt, ...);

/* A short description of a node for "(got ...)": the scalar text (cut
 * to 60 characters), "nothing", "a list" or "a mapping". */
const char *ps_yaml_got(const yaml_node_t *n, char buf[80]);

/* Walk a mapping: every key must be a scalar in `allowed` (NULL-terminated)
 * and appear once; each (key, value) goes to fn. section is the dotted
 * path of the mapping ("" at the top). */
int ps_yaml_walk_map(ps_loader *L, yaml_node_t *map, const char *section,
                     const char *const *allowed, ps_key_fn fn, void *arg);

/* A number: the scalar must be a plain decimal number (ps_is_decimal)
 * that a double holds (no overflow; an underflow reads as the nearest
 * double, 0 or subnormal, which the ranges then judge), then lie in the
 * range lo..hi, each end open or closed (infinite bounds are not
 * checked). */
int ps_yaml_real(ps_loader *L, yaml_node_t *n, const char *name, double lo, int lo_open,
                 double hi, int hi_open, double *out);

/* A number > 0. */
int ps_yaml_pos(ps_loader *L, yaml_node_t *n, const char *name, double *out);

/* A number > 0 (ps_yaml_pos, and its message) that must also lie in [lo,
 * hi]: "material.E must be in [1e-20, 1e+20] (got 1e300): why". */
int ps_yaml_pos_in(ps_loader *L, yaml_node_t *n, const char *name, double lo, double hi,
                   const char *why, double *out);

/* A decimal integer (ps_is_decimal) in [lo, hi] (hi == LONG_MAX: no
 * upper bound but the type's); values past the range, including those
 * too large for a long, are refused with the range. */
int ps_yaml_long(ps_loader *L, yaml_node_t *n, const char *name, long lo, long hi,
                 long *out);

/* ps_yaml_long into an int, hi capped at INT_MAX. */
int ps_yaml_int(ps_loader *L, yaml_node_t *n, const char *name, long lo, long hi,
                int *out);

/* A boolean: true/false/yes/no (any case). */
int ps_yaml_bool(ps_loader *L, yaml_node_t *n, const char *name, int *out);

/* One of a NULL-terminated list of words; *out = its index. */
int ps_yaml_choice(ps_loader *L, yaml_node_t *n, const char *name,
                   const char *const *choices, int *out);

/* A non-empty string that fits in dst[size]. */
int ps_yaml_string(ps_loader *L, yaml_node_t *n, const char *name, char *dst,
                   size_t size);

/* A coordinate: a decimal number (ps_yaml_real) of magnitude at most
 * PS_MAX_COORD: "FILE:LINE: coordinates beyond 1e150 m (NAME: got X)". */
int ps_yaml_coord(ps_loader *L, yaml_node_t *n, const char *name, double *out);

/* A 2D point [x, y] of coordinates (a crack's end, output.j_integral.tip). */
int ps_yaml_point2(ps_loader *L, yaml_node_t *n, const char *name, double *x);

/* ---- the sections: allowed keys and the handler of each key ---- */

extern const char *const ps_case_geometry_keys[]; /* case_sections.c */
extern const char *const ps_case_kernel_keys[];
extern const char *const ps_case_material_keys[];
extern const char *const ps_case_loading_keys[];  /* case_loading.c */
extern const char *const ps_case_solver_keys[];   /* case_options.c */
extern const char *const ps_case_path_keys[];
extern const char *const ps_case_output_keys[];
extern const char *const ps_case_griffith_keys[];

int ps_case_on_geometry(ps_loader *L, void *arg, const char *key, const char *name,
                        yaml_node_t *v);
int ps_case_on_kernel(ps_loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v);
int ps_case_on_material(ps_loader *L, void *arg, const char *key, const char *name,
                        yaml_node_t *v);
int ps_case_on_loading(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v);
int ps_case_on_solver(ps_loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v);
int ps_case_on_path(ps_loader *L, void *arg, const char *key, const char *name,
                    yaml_node_t *v);
int ps_case_on_output(ps_loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v);
int ps_case_on_griffith(ps_loader *L, void *arg, const char *key, const char *name,
                        yaml_node_t *v);

/* ---- case_checks.c ---- */

/* Checks across sections, after the whole file is read (YAML keys come
 * in any order): dim against counts, loading type against geometry,
 * keys of another geometry type, the bond model's nu, particle counts,
 * delta given twice, ... Also settles dim (a disk is 2D) and counts[2]
 * in 2D. Returns PS_OK or PS_ERR_INPUT. */
int ps_case_cross_checks(ps_loader *L);

#endif
