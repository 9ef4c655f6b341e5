/* case_loading.c: the loading section. loading.type eq116 (the disk's
 * boundary zone follows Eq. 116's analytical field) or boundary, with
 * loading.boundary: a list of entries, each a particle selection with
 * fixed, displaced and traction components and the measure flag. Each
 * entry is checked on its own here; the checks that need dim or the
 * geometry run in case_checks.c. */
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

static int on_displace(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_bc *bc = arg;
  int k = key[0] - 'x';
  bc->displace_set[k] = 1;
  return ps_yaml_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->displace[k]);
}

static int on_traction(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  ps_bc *bc = arg;
  int k = key[0] - 'x';
  bc->traction_set[k] = 1;
  return ps_yaml_real(L, v, name, -INFINITY, 0, INFINITY, 0, &bc->traction[k]);
}

static const char *const bc_keys[] = {"select", "fix", "displace", "traction", "measure",
                                      NULL};

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
  if (n > PS_MAX_BC)
    return ps_yaml_fail(L, line_of(v), "%s has %d entries, at most %d are allowed", name,
                        n, PS_MAX_BC);
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
