/* case.c: case files. ps_case_defaults fills the documented defaults;
 * ps_case_load reads a YAML file over them: the text is read and its
 * size and nesting bounded (case_text.c), libyaml parses it (case_yaml.c),
 * each section's keys go to their handlers (case_sections.c,
 * case_loading.c, case_options.c) and the checks that involve several
 * keys run after the whole file is read (case_checks.c), since YAML keys
 * come in any order. Every error names the file and the line of the
 * offending node, e.g. "case.yaml:14: material.E must be > 0 (got -3e9)". */
#include "case_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void ps_case_defaults(ps_case *cs) {
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
  cs->mesh_format = -1;
  cs->size_rule = PS_SIZE_EQ115;
  cs->size_neighbours = 5;
  cs->n_cracks = 0;
  cs->alpha = 5.1;
  cs->kernel_k = 2;
  strcpy(cs->model, "fibre");
  cs->horizon_factor = 3.0; /* bond, state: spacings (a box's, or a cloud's mean) */
  cs->mat.horizon = 0.0;    /* material.horizon, m: unset (horizon_factor applies) */
  cs->mat.surface_correction = -1; /* unset: the model's default (bond, threebody: on;
                                      fibre, state: off; model/ps_moduli.h) */
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
  /* the options of the layers: their defaults live beside them */
  ps_solver_opts_default(&cs->solver);
  cs->max_memory_gib = 0.0; /* 80% of the RAM */
  ps_path_opts_default(&cs->path);
  ps_output_opts_default(&cs->output);
  ps_sweep_opts_default(&cs->sweep);
}

void ps_case_free(ps_case *cs) {
  free(cs->bc);
  cs->bc = NULL;
  cs->n_bc = 0;
  free(cs->path.steps);
  cs->path.steps = NULL;
  cs->path.n_steps = 0;
}

int ps_case_copy(ps_case *dst, const ps_case *src, ps_ctx *ctx) {
  *dst = *src;
  dst->bc = NULL;
  dst->path.steps = NULL;
  if (src->n_bc > 0) {
    dst->bc = ps_calloc((size_t)src->n_bc, sizeof *dst->bc, ctx);
    if (!dst->bc) goto nomem;
    memcpy(dst->bc, src->bc, (size_t)src->n_bc * sizeof *dst->bc);
  }
  if (src->path.n_steps > 0) {
    dst->path.steps = ps_calloc((size_t)src->path.n_steps, sizeof *dst->path.steps, ctx);
    if (!dst->path.steps) goto nomem;
    memcpy(dst->path.steps, src->path.steps,
           (size_t)src->path.n_steps * sizeof *dst->path.steps);
  }
  return PS_OK;
nomem: /* ps_calloc has recorded the error */
  ps_case_free(dst);
  return PS_ERR_NOMEM;
}

int ps_case_add_bc(ps_case *cs, const ps_bc *bc, ps_ctx *ctx) {
  void *p = cs->bc;
  PS_CHECK(ps_realloc(&p, (size_t)cs->n_bc + 1, sizeof *cs->bc, ctx));
  cs->bc = p;
  cs->bc[cs->n_bc++] = *bc;
  return PS_OK;
}

/* ---- the top level: the sections ---- */

static const char *const top_keys[] = {"name",     "geometry", "kernel",
                                       "material", "loading",  "solver",
                                       "path",     "output",   "griffith", NULL};

static int on_top(ps_loader *L, void *arg, const char *key, const char *name,
                  yaml_node_t *v) {
  (void)arg;
  if (IS("name")) {
    /* the name goes into out/NAME, summary.txt's `case:` line and the
     * title of griffith.gp: only characters that mean nothing to a shell,
     * a file system, gnuplot or a key: value reader */
    if (ps_yaml_string(L, v, name, L->cs->name, sizeof L->cs->name)) return PS_ERR_INPUT;
    const char *s = L->cs->name;
    char shown[80]; /* control characters as '?', at most 60 characters */
    size_t k = 0;
    int bad = 0;
    for (const char *c = s; *c; c++)
      bad |= !((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') ||
               (*c >= '0' && *c <= '9') || strchr("._+- ", *c));
    for (const char *c = s; *c && k < 60; c++)
      shown[k++] = (unsigned char)*c < 0x20 || *c == 0x7f ? '?' : *c;
    snprintf(shown + k, sizeof shown - k, "%s", s[k] ? "..." : "");
    if (bad)
      return ps_yaml_fail(L, line_of(v),
                          "name may hold only letters, digits, spaces and . _ + - (got '%s')",
                          shown);
    if (s[0] == '.' || s[0] == '-')
      return ps_yaml_fail(L, line_of(v), "name must not start with '.' or '-' (got '%s')",
                          shown);
    return PS_OK;
  }
  if (IS("geometry"))
    return ps_yaml_walk_map(L, v, name, ps_case_geometry_keys, ps_case_on_geometry, NULL);
  if (IS("kernel"))
    return ps_yaml_walk_map(L, v, name, ps_case_kernel_keys, ps_case_on_kernel, NULL);
  if (IS("material"))
    return ps_yaml_walk_map(L, v, name, ps_case_material_keys, ps_case_on_material, NULL);
  if (IS("loading"))
    return ps_yaml_walk_map(L, v, name, ps_case_loading_keys, ps_case_on_loading, NULL);
  if (IS("solver"))
    return ps_yaml_walk_map(L, v, name, ps_case_solver_keys, ps_case_on_solver, NULL);
  if (IS("path"))
    return ps_yaml_walk_map(L, v, name, ps_case_path_keys, ps_case_on_path, NULL);
  if (IS("output"))
    return ps_yaml_walk_map(L, v, name, ps_case_output_keys, ps_case_on_output, NULL);
  return ps_yaml_walk_map(L, v, name, ps_case_griffith_keys, ps_case_on_griffith, NULL);
}

/* Set file, dir (the directory part, "." when none) and the default name
 * (the file name without .yaml / .yml) of cs from path. */
static void set_names(ps_case *cs, const char *path) {
  snprintf(cs->file, sizeof cs->file, "%s", path);
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

/* Parse text[len] over *cs (unchanged on failure); `path` names the file
 * in messages; dir = NULL takes the file's folder and name from path,
 * else dir is the folder relative paths resolve against. The text's size
 * and nesting are checked before libyaml sees it. */
static int load_text(ps_case *cs, const char *text, size_t len, const char *path,
                     const char *dir, ps_ctx *ctx) {
  if (strlen(path) >= sizeof cs->file)
    return ps_error(ctx, PS_ERR_IO, "%s: path too long", path);
  if (len > PS_CASE_MAX_BYTES)
    return ps_error(ctx, PS_ERR_INPUT, "%s: case text of %zu bytes is over the limit of %zu",
                    path, len, PS_CASE_MAX_BYTES);
  PS_CHECK(ps_case_check_nesting(path, text, len, ctx));
  /* fill a copy so that a failed load leaves *cs as it was */
  ps_case *work = ps_calloc(1, sizeof *work, ctx);
  if (!work) return PS_ERR_NOMEM;
  *work = *cs;
  set_names(work, path);
  if (dir) snprintf(work->dir, sizeof work->dir, "%s", dir);

  ps_yaml_file Y;
  int status = ps_yaml_open(&Y, path, text, len, ctx);
  if (status == PS_OK) {
    ps_loader L = {.file = path, .doc = &Y.doc, .cs = work, .ctx = ctx};
    yaml_node_t *root = yaml_document_get_root_node(&Y.doc);
    if (root) /* an empty file keeps every default */
      status = ps_yaml_walk_map(&L, root, "", top_keys, on_top, NULL);
    if (status == PS_OK) status = ps_yaml_only_document(&Y, ctx);
    if (status == PS_OK) status = ps_case_cross_checks(&L);
  }
  /* the lists the file gave are new: they replace (and free) those of
   * *cs on success, and are freed on failure */
  int bc_new = work->bc != cs->bc, steps_new = work->path.steps != cs->path.steps;
  if (status == PS_OK) {
    if (bc_new) free(cs->bc);
    if (steps_new) free(cs->path.steps);
    *cs = *work;
  } else {
    if (bc_new) free(work->bc);
    if (steps_new) free(work->path.steps);
  }
  ps_yaml_close(&Y);
  free(work);
  return status;
}

int ps_case_load(ps_case *cs, const char *path, ps_ctx *ctx) {
  if (strlen(path) >= sizeof cs->file)
    return ps_error(ctx, PS_ERR_IO, "%s: path too long", path);
  char *text;
  size_t len;
  PS_CHECK(ps_case_read_text(path, &text, &len, ctx));
  int status = load_text(cs, text, len, path, NULL, ctx);
  free(text);
  return status;
}

int ps_case_load_text(ps_case *cs, const char *text, size_t len, const char *name,
                      ps_ctx *ctx) {
  return load_text(cs, text, len, name, ".", ctx);
}
