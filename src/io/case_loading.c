/* case_loading.c: the loading section. loading.type eq116 (the disk's
 * boundary zone follows Eq. 116's analytical field) or boundary, with
 * loading.boundary: a list of entries (as many as the file gives), each a
 * particle selection with fixed, displaced and traction components, the
 * measure flag and a name; a displaced component is a number or a field
 * {value, gradient, hessian} about the entry's point `about`
 * (ps_bc_displacement). Each entry is checked on its own here; the
 * checks that need dim or the geometry run in case_checks.c. */
#include "case_impl.h"

#include <limits.h>
#include <math.h>
#include <string.h>

static const char *const select_keys[] = {"x_min", "x_max", "y_min", "y_max",
                                          "z_min", "z_max", "block", "set", NULL};

static int on_select(ps_loader *L, void *arg, const char *key, const char *name,
                     yaml_node_t *v) {
  ps_select *s = arg;
  if (IS("block")) return ps_yaml_int(L, v, name, 0, INT_MAX, &s->block);
  if (IS("set")) return ps_yaml_string(L, v, name, s->set, sizeof s->set);
  int k = key[0] - 'x'; /* x, y, z -> 0, 1, 2 */
  double *dst = !strcmp(key + 1, "_min") ? &s->lo[k] : &s->hi[k];
  return ps_yaml_real(L, v, name, -INFINITY, 0, INFINITY, 0, dst);
}

static const char *const component_keys[] = {"x", "y", "z", NULL};

double ps_bc_displacement(const ps_bc *bc, int k, const double *x, int dim) {
  double u = bc->displace[k], dx[3];
  if (!bc->gradient_n[k] && !bc->hessian_n[k]) return u;
  for (int j = 0; j < dim; j++) dx[j] = x[j] - bc->about[j];
  for (int j = 0; j < dim && bc->gradient_n[k]; j++) u += bc->gradient[k][j] * dx[j];
  for (int j = 0; j < dim && bc->hessian_n[k]; j++)
    for (int l = 0; l < dim; l++) u += 0.5 * bc->hessian[k][j][l] * dx[j] * dx[l];
  return u;
}

/* A list of 1 to 3 numbers (coordinates when coords != 0: at most
 * PS_MAX_COORD) into out[]; *n = how many. */
static int get_vector(ps_loader *L, yaml_node_t *v, const char *name, int coords,
                      double *out, int *n) {
  char b[80];
  if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 1 || seq_len(v) > 3)
    return ps_yaml_fail(L, line_of(v), "%s must be a list of numbers, one per "
                        "coordinate (got %s)", name,
                        v->type == YAML_SEQUENCE_NODE ? "a list of another length"
                                                      : ps_yaml_got(v, b));
  for (int j = 0; j < seq_len(v); j++) {
    yaml_node_t *e = seq_item(L, v, j);
    int st = coords ? ps_yaml_coord(L, e, name, &out[j])
                    : ps_yaml_real(L, e, name, -INFINITY, 0, INFINITY, 0, &out[j]);
    if (st) return PS_ERR_INPUT;
  }
  *n = seq_len(v);
  return PS_OK;
}

/* One displaced component given as a field: {value, gradient, hessian}. */
typedef struct field_arg {
  ps_bc *bc;
  int k;
} field_arg;

static const char *const field_keys[] = {"value", "gradient", "hessian", NULL};

static int on_field(ps_loader *L, void *arg, const char *key, const char *name,
                    yaml_node_t *v) {
  field_arg *f = arg;
  ps_bc *bc = f->bc;
  int k = f->k;
  char b[80];
  if (!bc->field_line) bc->field_line = line_of(v);
  if (IS("value"))
    return ps_yaml_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->displace[k]);
  if (IS("gradient")) return get_vector(L, v, name, 0, bc->gradient[k], &bc->gradient_n[k]);
  /* hessian: n rows of n numbers, symmetric */
  int n = v->type == YAML_SEQUENCE_NODE ? seq_len(v) : 0;
  if (n < 1 || n > 3)
    return ps_yaml_fail(L, line_of(v), "%s must be a list of 2 or 3 rows, e.g. [[0, 1e-3], "
                        "[1e-3, 0]] (got %s)", name,
                        v->type == YAML_SEQUENCE_NODE ? "a list of another length"
                                                      : ps_yaml_got(v, b));
  for (int j = 0; j < n; j++) {
    int m = 0;
    yaml_node_t *row = seq_item(L, v, j);
    if (get_vector(L, row, name, 0, bc->hessian[k][j], &m)) return PS_ERR_INPUT;
    if (m != n)
      return ps_yaml_fail(L, line_of(row), "%s must be square: row %d has %d numbers, "
                          "there are %d rows", name, j + 1, m, n);
  }
  for (int j = 0; j < n; j++)
    for (int l = 0; l < j; l++)
      if (bc->hessian[k][j][l] != bc->hessian[k][l][j])
        return ps_yaml_fail(L, line_of(v), "%s must be symmetric (row %d, column %d is %g; "
                            "row %d, column %d is %g): it holds second derivatives",
                            name, j + 1, l + 1, bc->hessian[k][j][l], l + 1, j + 1,
                            bc->hessian[k][l][j]);
  bc->hessian_n[k] = n;
  return PS_OK;
}

static int on_displace(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_bc *bc = arg;
  int k = key[0] - 'x';
  bc->displace_set[k] = 1;
  if (v->type == YAML_MAPPING_NODE) {
    field_arg f = {bc, k};
    if (v->data.mapping.pairs.top == v->data.mapping.pairs.start)
      return ps_yaml_fail(L, line_of(v), "%s is empty: give a number, or value, gradient "
                          "and/or hessian", name);
    return ps_yaml_walk_map(L, v, name, field_keys, on_field, &f);
  }
  return ps_yaml_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->displace[k]);
}

static int on_traction(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_bc *bc = arg;
  int k = key[0] - 'x';
  bc->traction_set[k] = 1;
  return ps_yaml_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->traction[k]);
}

static const char *const bc_keys[] = {"select",  "fix",   "displace", "about",
                                      "traction", "measure", "name",   NULL};

static int on_bc(ps_loader *L, void *arg, const char *key, const char *name,
                 yaml_node_t *v) {
  ps_bc *bc = arg;
  char b[80];
  if (IS("select")) {
    if (v->type == YAML_MAPPING_NODE &&
        v->data.mapping.pairs.top == v->data.mapping.pairs.start)
      return ps_yaml_fail(L, line_of(v), "%s is empty: select matches everything", name);
    if (ps_yaml_walk_map(L, v, name, select_keys, on_select, &bc->sel))
      return PS_ERR_INPUT;
    for (int k = 0; k < 3; k++)
      if (bc->sel.lo[k] > bc->sel.hi[k])
        return ps_yaml_fail(L, line_of(v), "%s: %c_min > %c_max selects nothing", name,
                            'x' + k, 'x' + k);
    return PS_OK;
  }
  if (IS("fix")) {
    if (v->type != YAML_SEQUENCE_NODE)
      return ps_yaml_fail(L, line_of(v),
                          "%s must be a list of components, e.g. [x, y] (got %s)", name,
                          ps_yaml_got(v, b));
    for (int i = 0; i < seq_len(v); i++) {
      int k;
      if (ps_yaml_choice(L, seq_item(L, v, i), name, component_keys, &k))
        return PS_ERR_INPUT;
      bc->fix[k] = 1;
    }
    return PS_OK;
  }
  if (IS("displace"))
    return ps_yaml_walk_map(L, v, name, component_keys, on_displace, bc);
  if (IS("traction"))
    return ps_yaml_walk_map(L, v, name, component_keys, on_traction, bc);
  if (IS("about")) {
    bc->about_line = line_of(v);
    return get_vector(L, v, name, 1, bc->about, &bc->about_n);
  }
  if (IS("name")) {
    if (ps_yaml_string(L, v, name, bc->name, sizeof bc->name)) return PS_ERR_INPUT;
    for (const char *c = bc->name; *c; c++)
      if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') ||
            (*c >= '0' && *c <= '9') || *c == '_'))
        return ps_yaml_fail(L, line_of(v), "%s may hold only letters, digits and _ (it "
                            "names the history.csv columns reaction_NAME_x, ...; character "
                            "%d is not one)", name, (int)(c - bc->name) + 1);
    return PS_OK;
  }
  return ps_yaml_bool(L, v, name, &bc->measure);
}

/* loading.boundary: a list of entries, each checked on its own here (the
 * checks that need dim run at the end). */
static int get_boundary(ps_loader *L, yaml_node_t *v, const char *name) {
  char b[80];
  ps_case *cs = L->cs;
  L->line_boundary = line_of(v);
  if (v->type != YAML_SEQUENCE_NODE)
    return ps_yaml_fail(L, line_of(v), "%s must be a list of entries (got %s)", name,
                        ps_yaml_got(v, b));
  int n = seq_len(v);
  cs->n_bc = 0;
  cs->bc = NULL; /* the list of the case loaded over, if any, is ps_case_load's */
  if (n > 0 && !(cs->bc = ps_calloc((size_t)n, sizeof *cs->bc, L->ctx))) return PS_ERR_NOMEM;
  for (int i = 0; i < n; i++) {
    yaml_node_t *e = seq_item(L, v, i);
    ps_bc *bc = &cs->bc[i];
    for (int k = 0; k < 3; k++) {
      bc->sel.lo[k] = -INFINITY;
      bc->sel.hi[k] = INFINITY;
    }
    bc->sel.block = -1;
    bc->line = line_of(e);
    if (ps_yaml_walk_map(L, e, name, bc_keys, on_bc, bc)) return PS_ERR_INPUT;
    int has_select = 0, fixes = 0, displaces = 0, tractions = 0;
    for (yaml_node_pair_t *p = e->data.mapping.pairs.start; p < e->data.mapping.pairs.top;
         p++)
      has_select |= !strcmp(sval(yaml_document_get_node(L->doc, p->key)), "select");
    if (!has_select)
      return ps_yaml_fail(L, bc->line,
                          "%s entry %d has no select: it would apply to every particle",
                          name, i + 1);
    for (int k = 0; k < 3; k++) {
      fixes += bc->fix[k];
      displaces += bc->displace_set[k];
      tractions += bc->traction_set[k];
      if (bc->fix[k] && bc->displace_set[k])
        return ps_yaml_fail(L, bc->line,
                            "%s entry %d: component %c is both fixed and displaced", name,
                            i + 1, 'x' + k);
      if (bc->traction_set[k] && (bc->fix[k] || bc->displace_set[k]))
        return ps_yaml_fail(L, bc->line,
                            "%s entry %d: component %c has a traction and a prescribed "
                            "displacement",
                            name, i + 1, 'x' + k);
    }
    if (!fixes && !displaces && !tractions)
      return ps_yaml_fail(L, bc->line,
                          "%s entry %d has no fix, displace or traction: it does nothing",
                          name, i + 1);
    if (bc->measure && !displaces)
      return ps_yaml_fail(L, bc->line,
                          "%s entry %d: measure: true needs a displaced component", name,
                          i + 1);
    int fields = 0;
    for (int k = 0; k < 3; k++) fields |= bc->gradient_n[k] || bc->hessian_n[k];
    if (bc->about_n && !fields)
      return ps_yaml_fail(L, bc->about_line,
                          "%s entry %d: about is the point of a displacement field, but no "
                          "displaced component has a gradient or hessian", name, i + 1);
    if (bc->name[0] && !fixes && !displaces)
      return ps_yaml_fail(L, bc->line,
                          "%s entry %d: name '%s' reports the reactions of supports, but the "
                          "entry fixes or displaces no component", name, i + 1, bc->name);
    for (int j = 0; j < i && bc->name[0]; j++)
      if (!strcmp(cs->bc[j].name, bc->name))
        return ps_yaml_fail(L, bc->line, "%s entry %d: name '%s' is taken by entry %d (line "
                            "%d)", name, i + 1, bc->name, j + 1, cs->bc[j].line);
    cs->n_bc++;
  }
  return PS_OK;
}

const char *const ps_case_loading_keys[] = {"type", "stress_length", "boundary", NULL};

int ps_case_on_loading(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  static const char *const types[] = {"eq116", "boundary", NULL};
  (void)arg;
  if (IS("type")) {
    L->line_load_type = line_of(v);
    return ps_yaml_choice(L, v, name, types, &L->cs->load_type);
  }
  if (IS("stress_length")) return ps_yaml_pos(L, v, name, &L->cs->stress_length);
  return get_boundary(L, v, name);
}
