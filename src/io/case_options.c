/* case_options.c: the sections that say how a case is solved and
 * reported, each read straight into the option struct of the layer that
 * takes it: solver (Newton, the linear solver, CG: cs->solver, but
 * max_memory_gib), path (the load increments and the stop rules:
 * cs->path), output (folder, VTK, J-integral tips and rings: cs->output) and
 * griffith (the sweep's list of delta/c: cs->sweep). */
#include <config.h>

#include "case_impl.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- solver ---- */

const char *const ps_case_solver_keys[] = {
    "linear", "tolerance", "max_iterations", "max_small_steps", "line_search",
    "reuse_factor", "cg_tolerance", "cg_forcing", "cg_forcing_max", "cg_max_iterations",
    "cg_skip_arms", "reanalyze", "majorant", "matrix_free", "cg_single_precision",
    "cg_truncate", "max_memory_gib", "parts", "petsc_options", "layout", NULL};

int ps_case_on_solver(ps_loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v) {
  static const char *const linear[] = {"cholmod", "cholmod-simplicial", "umfpack",
                                       "petsc", NULL};
  ps_solver_opts *o = &L->cs->solver;
  (void)arg;
  if (IS("linear")) {
    int i;
    if (ps_yaml_choice(L, v, name, linear, &i)) return PS_ERR_INPUT;
#ifndef HAVE_PETSC
    if (!strcmp(linear[i], "petsc"))
      return ps_yaml_fail(L, line_of(v), "%s: petsc needs a peristatic configured --with-petsc "
                          "(scripts/install-deps.sh --with-petsc installs PETSc and MPI); this "
                          "one has cholmod, cholmod-simplicial and umfpack", name);
#endif
    snprintf(o->linear, sizeof o->linear, "%s", linear[i]);
    return PS_OK;
  }
  if (IS("petsc_options")) {
    if (v->type != YAML_SCALAR_NODE || strlen(sval(v)) >= sizeof o->petsc_options ||
        (sval(v)[0] && sval(v)[0] != '-'))
      return ps_yaml_fail(L, line_of(v), "%s must be PETSc options in one string, such as "
                          "\"-ksp_type cg -pc_type gamg\" (at most %zu characters)", name,
                          sizeof o->petsc_options - 1);
    snprintf(o->petsc_options, sizeof o->petsc_options, "%s", sval(v));
    return PS_OK;
  }
  if (IS("layout")) { /* in the order of enum ps_layout */
    static const char *const layout[] = {"auto", "distributed", "replicated", NULL};
    return ps_yaml_choice(L, v, name, layout, &o->layout);
  }
  if (IS("tolerance")) return ps_yaml_real(L, v, name, 0.0, 1, 1.0, 1, &o->tolerance);
  if (IS("max_iterations"))
    return ps_yaml_int(L, v, name, 1, INT_MAX, &o->max_iterations);
  if (IS("max_small_steps"))
    return ps_yaml_int(L, v, name, 0, INT_MAX, &o->max_small_steps);
  if (IS("reuse_factor")) return ps_yaml_bool(L, v, name, &o->reuse_factor);
  if (IS("reanalyze")) return ps_yaml_bool(L, v, name, &o->reanalyze);
  if (IS("majorant")) return ps_yaml_bool(L, v, name, &o->majorant);
  if (IS("matrix_free")) return ps_yaml_bool(L, v, name, &o->matrix_free);
  if (IS("cg_single_precision"))
    return ps_yaml_bool(L, v, name, &o->cg_single_precision);
  if (IS("cg_truncate")) return ps_yaml_bool(L, v, name, &o->cg_truncate);
  if (IS("cg_tolerance"))
    return ps_yaml_real(L, v, name, 0.0, 1, 1.0, 1, &o->pcg_rtol);
  if (IS("cg_forcing")) { /* adaptive, or a number >= 0: the fixed rule */
    if (v->type == YAML_SCALAR_NODE && !strcmp(sval(v), "adaptive")) {
      o->cg_forcing_adaptive = 1;
      return PS_OK;
    }
    char b[80];
    double x = -1.0;
    if (v->type == YAML_SCALAR_NODE && ps_is_decimal(sval(v), 0)) x = strtod(sval(v), NULL);
    if (!isfinite(x) || x < 0)
      return ps_yaml_fail(L, line_of(v), "%s must be adaptive or a number >= 0 (got %s)",
                          name, ps_yaml_got(v, b));
    o->cg_forcing_adaptive = 0;
    o->cg_forcing = x;
    return PS_OK;
  }
  if (IS("cg_forcing_max"))
    return ps_yaml_real(L, v, name, 0.0, 1, 1.0, 1, &o->cg_forcing_max);
  if (IS("cg_max_iterations"))
    return ps_yaml_int(L, v, name, 1, INT_MAX, &o->pcg_max_iterations);
  if (IS("cg_skip_arms")) return ps_yaml_int(L, v, name, 0, INT_MAX, &o->pcg_skip_arms);
  if (IS("parts")) return ps_yaml_int(L, v, name, 1, PS_PARTS_MAX, &o->parts);
  if (IS("max_memory_gib")) /* a limit, not a setting of the result */
    return ps_yaml_real(L, v, name, 0.0, 1, PS_MAX_MEMORY_GIB, 0, &L->cs->max_memory_gib);
  return ps_yaml_bool(L, v, name, &o->line_search);
}

/* ---- path ---- */

const char *const ps_case_path_keys[] = {
    "load_step", "load_step_after_break", "max_load", "max_increments", "min_step",
    "stop_crack_tip", "stop_tip_advance", "stop_load_drop", "max_break_rounds",
    "max_arms_per_round", "round_tolerance", "control", "arc_length_max", "arc_length_psi",
    "arc_length_iterations", "max_arms_per_step", "dissipation_step", "dissipation_max",
    "event_tolerance", "steps", "load_until_unstable", "unstable_arms", NULL};

/* path.steps: a list of load factors > 0, each above the one before */
static int get_steps(ps_loader *L, yaml_node_t *v, const char *name) {
  ps_path_opts *o = &L->cs->path;
  char b[80];
  L->line_steps = line_of(v);
  if (v->type != YAML_SEQUENCE_NODE || seq_len(v) == 0)
    return ps_yaml_fail(L, line_of(v), "%s must be a list of load factors, e.g. [0.25, 0.5, "
                        "1] (got %s)", name,
                        v->type == YAML_SEQUENCE_NODE ? "an empty list" : ps_yaml_got(v, b));
  int n = seq_len(v);
  o->n_steps = 0;
  o->steps = NULL; /* the list of the case loaded over, if any, is ps_case_load's */
  if (!(o->steps = ps_calloc((size_t)n, sizeof *o->steps, L->ctx))) return PS_ERR_NOMEM;
  for (int i = 0; i < n; i++) {
    yaml_node_t *e = seq_item(L, v, i);
    if (ps_yaml_pos(L, e, name, &o->steps[i])) return PS_ERR_INPUT;
    if (i > 0 && !(o->steps[i] > o->steps[i - 1]))
      return ps_yaml_fail(L, line_of(e), "%s must increase: entry %d (%g) is not above "
                          "entry %d (%g)", name, i + 1, o->steps[i], i, o->steps[i - 1]);
    o->n_steps++;
  }
  return PS_OK;
}

int ps_case_on_path(ps_loader *L, void *arg, const char *key, const char *name,
                    yaml_node_t *v) {
  ps_path_opts *o = &L->cs->path;
  (void)arg;
  if (IS("steps")) return get_steps(L, v, name);
  if (IS("load_step")) {
    L->line_load_step = line_of(v);
    return ps_yaml_pos(L, v, name, &o->load_step);
  }
  if (IS("load_step_after_break")) {
    L->line_load_step_after_break = line_of(v);
    return ps_yaml_pos(L, v, name, &o->load_step_after_break);
  }
  if (IS("max_load")) {
    L->line_max_load = line_of(v);
    return ps_yaml_pos(L, v, name, &o->max_load);
  }
  if (IS("max_increments"))
    return ps_yaml_int(L, v, name, 1, INT_MAX, &o->max_increments);
  if (IS("min_step")) return ps_yaml_pos(L, v, name, &o->min_step);
  if (IS("stop_crack_tip")) return ps_yaml_pos(L, v, name, &o->stop_crack_tip);
  if (IS("stop_tip_advance")) return ps_yaml_pos(L, v, name, &o->stop_tip_advance);
  if (IS("stop_load_drop"))
    return ps_yaml_real(L, v, name, 0.0, 0, 1.0, 1, &o->stop_load_drop);
  if (IS("max_arms_per_round"))
    return ps_yaml_int(L, v, name, 0, INT_MAX, &o->max_arms_per_round);
  if (IS("round_tolerance"))
    return ps_yaml_real(L, v, name, 0.0, 1, 1.0, 1, &o->round_tolerance);
  if (IS("control")) { /* the order of enum ps_path_control */
    static const char *const controls[] = {"load", "arc_length", "dissipation", "event", NULL};
    L->line_control = line_of(v);
    return ps_yaml_choice(L, v, name, controls, &o->control);
  }
  if (IS("arc_length_max")) return ps_yaml_pos(L, v, name, &o->arc_length_max);
  if (IS("max_arms_per_step"))
    return ps_yaml_int(L, v, name, 0, INT_MAX, &o->max_arms_per_step);
  if (IS("load_until_unstable")) {
    L->line_load_until_unstable = line_of(v);
    return ps_yaml_bool(L, v, name, &o->load_until_unstable);
  }
  if (IS("unstable_arms")) return ps_yaml_int(L, v, name, 0, INT_MAX, &o->unstable_arms);
  if (IS("dissipation_step")) return ps_yaml_pos(L, v, name, &o->dissipation_step);
  if (IS("dissipation_max")) return ps_yaml_pos(L, v, name, &o->dissipation_max);
  if (IS("event_tolerance"))
    return ps_yaml_real(L, v, name, 0.0, 1, 1.0, 1, &o->event_tolerance);
  if (IS("arc_length_psi"))
    return ps_yaml_real(L, v, name, 0.0, 0, INFINITY, 0, &o->arc_length_psi);
  if (IS("arc_length_iterations"))
    return ps_yaml_int(L, v, name, 1, 1000, &o->arc_length_iterations);
  return ps_yaml_int(L, v, name, 1, INT_MAX, &o->max_break_rounds);
}

/* ---- output ---- */

const char *const ps_case_output_keys[] = {"dir", "vtk_every", "fields", "verbosity",
                                           "j_integral", "checkpoint", "checkpoint_every", NULL};

static const char *const j_keys[] = {"tip", "direction", "crack", "tips", "rings", NULL};

static int on_j(ps_loader *L, void *arg, const char *key, const char *name,
                yaml_node_t *v) {
  ps_output_opts *o = &L->cs->output;
  char b[80];
  (void)arg;
  if (IS("tip")) {
    L->line_j_tip = line_of(v);
    return ps_yaml_point2(L, v, name, o->j_tip);
  }
  if (IS("direction")) {
    double d[2];
    L->line_j_dir = line_of(v);
    if (ps_yaml_point2(L, v, name, d)) return PS_ERR_INPUT;
    double n = hypot(d[0], d[1]);
    if (!(n > 0) || !isfinite(n))
      return ps_yaml_fail(L, line_of(v), "%s must be a nonzero vector [dx, dy] (got [%g, %g])",
                          name, d[0], d[1]);
    o->j_dir[0] = d[0] / n;
    o->j_dir[1] = d[1] / n;
    return PS_OK;
  }
  if (IS("crack")) {
    L->line_j_crack = line_of(v);
    return ps_yaml_int(L, v, name, 0, PS_MAX_CRACKS - 1, &o->j_crack);
  }
  if (IS("tips")) { /* the order of enum ps_j_tips */
    static const char *const tips[] = {"both", "start", "end", NULL};
    L->line_j_tips = line_of(v);
    return ps_yaml_choice(L, v, name, tips, &o->j_tips);
  }
  if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 1 || seq_len(v) > PS_MAX_J_RINGS)
    return ps_yaml_fail(L, line_of(v),
                        "%s must be a list of 1 to 8 ring sizes in m (got %s)", name,
                        ps_yaml_got(v, b));
  o->n_j_rings = seq_len(v);
  for (int i = 0; i < o->n_j_rings; i++)
    if (ps_yaml_real(L, seq_item(L, v, i), name, 0.0, 1, INFINITY, 0, &o->j_rings[i]))
      return PS_ERR_INPUT;
  return PS_OK;
}

int ps_case_on_output(ps_loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v) {
  ps_output_opts *o = &L->cs->output;
  (void)arg;
  if (IS("dir")) return ps_yaml_string(L, v, name, o->dir, sizeof o->dir);
  if (IS("vtk_every")) return ps_yaml_int(L, v, name, 0, INT_MAX, &o->vtk_every);
  if (IS("fields")) return ps_yaml_bool(L, v, name, &o->fields);
  if (IS("checkpoint")) return ps_yaml_bool(L, v, name, &o->checkpoint);
  if (IS("checkpoint_every")) return ps_yaml_int(L, v, name, 0, INT_MAX, &o->checkpoint_every);
  if (IS("j_integral")) {
    L->line_j = line_of(v);
    if (ps_yaml_walk_map(L, v, name, j_keys, on_j, NULL)) return PS_ERR_INPUT;
    if ((!L->line_j_tip && !L->line_j_crack) || !o->n_j_rings)
      return ps_yaml_fail(L, L->line_j,
                          "%s needs both tip: [x, y] (or crack: i) and rings: [l, ...]",
                          name);
    if (L->line_j_tip && L->line_j_crack)
      return ps_yaml_fail(L, L->line_j_crack,
                          "%s: give either tip (and direction) or crack (and tips), not "
                          "both", name);
    if (L->line_j_dir && !L->line_j_tip)
      return ps_yaml_fail(L, L->line_j_dir, "%s.direction goes with tip: [x, y]", name);
    if (L->line_j_tips && !L->line_j_crack)
      return ps_yaml_fail(L, L->line_j_tips, "%s.tips goes with crack: i", name);
    return PS_OK;
  }
  return ps_yaml_int(L, v, name, 0, 3, &o->verbosity);
}

/* ---- griffith ---- */

/* griffith.denominators: {first, last, step}, all three required. */
typedef struct sweep_range {
  long first, last, step;
  int line_first, line_last, line_step;
} sweep_range;

static const char *const den_keys[] = {"first", "last", "step", NULL};

static int on_den(ps_loader *L, void *arg, const char *key, const char *name,
                  yaml_node_t *v) {
  sweep_range *r = arg;
  if (IS("first")) {
    r->line_first = line_of(v);
    return ps_yaml_long(L, v, name, 1, LONG_MAX, &r->first);
  }
  if (IS("last")) {
    r->line_last = line_of(v);
    return ps_yaml_long(L, v, name, 1, LONG_MAX, &r->last);
  }
  r->line_step = line_of(v);
  return ps_yaml_long(L, v, name, 1, LONG_MAX, &r->step);
}

const char *const ps_case_griffith_keys[] = {"delta_over_c", "denominators", NULL};

int ps_case_on_griffith(ps_loader *L, void *arg, const char *key, const char *name,
                        yaml_node_t *v) {
  ps_sweep_opts *o = &L->cs->sweep;
  char b[80];
  (void)arg;
  if (IS("delta_over_c")) {
    L->line_sweep_list = line_of(v);
    if (v->type != YAML_SEQUENCE_NODE || seq_len(v) == 0)
      return ps_yaml_fail(L, line_of(v),
                          "%s must be a non-empty list of numbers (got %s)", name,
                          ps_yaml_got(v, b));
    int n = seq_len(v);
    if (n > PS_MAX_SWEEP)
      return ps_yaml_fail(L, line_of(v), "%s has %d values, at most %d are allowed", name,
                          n, PS_MAX_SWEEP);
    for (int i = 0; i < n; i++)
      if (ps_yaml_pos(L, seq_item(L, v, i), name, &o->delta_over_c[i]))
        return PS_ERR_INPUT;
    o->n = n;
    return PS_OK;
  }
  /* denominators */
  sweep_range r = {0};
  L->line_sweep_den = line_of(v);
  if (ps_yaml_walk_map(L, v, name, den_keys, on_den, &r)) return PS_ERR_INPUT;
  if (!r.line_first || !r.line_last || !r.line_step)
    return ps_yaml_fail(L, line_of(v), "%s needs first, last and step", name);
  if (r.last < r.first)
    return ps_yaml_fail(L, r.line_last, "%s.last must be >= first (got %ld < %ld)", name,
                        r.last, r.first);
  long n = (r.last - r.first) / r.step + 1;
  if (n > PS_MAX_SWEEP)
    return ps_yaml_fail(L, line_of(v), "%s gives %ld values, at most %d are allowed",
                        name, n, PS_MAX_SWEEP);
  for (long i = 0; i < n; i++)
    o->delta_over_c[i] = 1.0 / (double)(r.first + i * r.step);
  o->n = (int)n;
  return PS_OK;
}
