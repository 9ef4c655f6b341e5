/* fingerprint.c: the case fingerprint (ps_case_fingerprint, ps_io.h): a
 * 64-bit FNV-1a hash of the algorithm version and of every case setting
 * that determines a run's result, read from the case and its option
 * structs cs->solver and cs->path (cs->output and cs->sweep do not
 * enter). summary.txt carries it, and `griffith --resume` reuses a run
 * only when it matches. */
#include "ps_io.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* FNV-1a over the bytes of a formatted description */
static void fnv(uint64_t *h, const char *s) { ps_fnv1a(h, s, strlen(s)); }

/* Bumped when a change of the code changes what a run computes (beyond
 * the Newton tolerance), so that `griffith --resume` does not reuse runs
 * of an older algorithm. What each version changed:
 * doc/algorithm-versions.md. */
#define PS_ALGORITHM_VERSION 9
/* The same for what only arc-length, dissipation and event control
 * compute; it enters only off load control, so that a change there keeps
 * the fingerprints of load-controlled runs (the committed paper sweep):
 * 1 until algorithm version 9, 2 since the constrained steps on an
 * indefinite tangent solve by GMRES with the shifted tangent's factor. */
#define PS_PATH_CONTROL_VERSION 2

/* What enters the hash, as "%.17g" text (every double exactly): the
 * algorithm version; the geometry (a cloud's or mesh's file name, not its
 * contents; a mesh's format), the size rule, cracks and holes; the
 * kernel; the material but delta (and, for the horizon models,
 * horizon_factor and surface_correction, material.horizon when given;
 * micromodulus, partial volumes and fracture when set; the fibre model's
 * break_rule and break_length when the rule is not elongation); the loading (a
 * selection's set name when given);
 * Newton's
 * tolerance, iterations, line search and small steps; the CG settings
 * that change which solves near the plastic limit converge (cg_truncate
 * off, a fixed cg_forcing); solver.parts (the order of every parallel
 * sum: round-off, which a run to fracture can carry into the path); the load path (path.steps too) and its stop
 * rules; the displacement fields of loading.boundary (but not the
 * entries' names, which only label history.csv columns).
 * Not hashed (they do not change a run's result beyond the Newton
 * tolerance): the name and output keys, delta and the Griffith list,
 * path.max_break_rounds (a limit: a run that reaches it fails; its place
 * in the text keeps the old default, 500, so that fingerprints stay), the
 * linear solver and the other CG settings (cg_tolerance, cg_skip_arms,
 * cg_single_precision, majorant, ...), and solver.max_memory_gib (a limit
 * on what may be allocated). Keys added after the first version enter
 * only when set or not at their default, so that the fingerprints of
 * cases without them stay as they were. */
uint64_t ps_case_fingerprint(const ps_case *cs) {
  uint64_t h = PS_FNV_START;
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
  if (cs->given_particles) { /* particles from the caller: their data */
    const ps_particles *g = cs->given_particles;
    snprintf(b, sizeof b, "given %d %lld", g->dim, (long long)g->n);
    fnv(&h, b);
    for (ps_int a = 0; a < g->n; a++) {
      char *q = b;
      for (int k = 0; k < g->dim; k++) q += sprintf(q, "%.17g ", g->x[a * g->dim + k]);
      sprintf(q, "%.17g %d", g->volume[a], g->block ? g->block[a] : 0);
      fnv(&h, b);
    }
  }
  if (cs->disk.refine_tips > 1 && cs->disk.refine_radius > 0) {
    snprintf(b, sizeof b, "refine tips %d %.17g", cs->disk.refine_tips,
             cs->disk.refine_radius);
    fnv(&h, b);
  }
  if (cs->origin[0] != 0 || cs->origin[1] != 0 || cs->origin[2] != 0) {
    snprintf(b, sizeof b, "origin %.17g %.17g %.17g", cs->origin[0], cs->origin[1],
             cs->origin[2]);
    fnv(&h, b);
  }
  if (cs->geometry == PS_GEOM_MESH) { /* newer type: the file is hashed above */
    snprintf(b, sizeof b, "mesh format %d", cs->mesh_format);
    fnv(&h, b);
  }
  for (int i = 0; i < cs->n_holes; i++) {
    if (cs->dim == 3) /* newer form: 3D spheres */
      snprintf(b, sizeof b, "hole %.17g %.17g %.17g %.17g", cs->holes[i][0], cs->holes[i][1],
               cs->holes[i][2], cs->holes[i][3]);
    else
      snprintf(b, sizeof b, "hole %.17g %.17g %.17g", cs->holes[i][0], cs->holes[i][1],
               cs->holes[i][2]);
    fnv(&h, b);
  }
  const ps_model_type *type = ps_model_type_find(cs->model);
  if (type && type->lattice) {
    snprintf(b, sizeof b, "lattice %.17g %d", cs->horizon_factor, m->surface_correction != 0);
    fnv(&h, b);
  }
  /* surface_correction: unset (< 0) and true are alike for bond and
   * threebody; the moduli correction of fibre and state only when true */
  if (m->surface_correction == 1 && (!strcmp(cs->model, "fibre") || !strcmp(cs->model, "state")))
    fnv(&h, "moduli correction 1");
  if (type && type->lattice && m->horizon > 0) { /* newer key: only when set */
    snprintf(b, sizeof b, "horizon %.17g", m->horizon);
    fnv(&h, b);
  }
  if (m->break_rule != PS_BREAK_ELONGATION) { /* newer key: only when not the default */
    snprintf(b, sizeof b, "break rule %d length %.17g", m->break_rule, m->break_length);
    fnv(&h, b);
  }
  if (m->micromodulus != PS_MICRO_CONICAL || m->full_volumes) {
    snprintf(b, sizeof b, "micromodulus %d full volumes %d", m->micromodulus, m->full_volumes);
    fnv(&h, b);
  }
  if (m->fracture != PS_FRACTURE_NONE) {
    snprintf(b, sizeof b, "fracture %d %.17g %.17g %.17g", m->fracture, m->critical_stretch,
             m->critical_micropotential, m->fracture_energy);
    fnv(&h, b);
    if (m->softening_ratio > 0) {
      snprintf(b, sizeof b, "softening %.17g", m->softening_ratio);
      fnv(&h, b);
    }
  }
  for (int i = 0; i < cs->n_cracks; i++) {
    const ps_crack *c = &cs->cracks[i];
    if (c->kind == PS_CRACK_POLYGON) { /* newer form: a 3D polygon, its vertices */
      int w = snprintf(b, sizeof b, "crack polygon %d", c->n);
      for (int j = 0; j < c->n && w > 0 && (size_t)w < sizeof b; j++)
        w += snprintf(b + w, sizeof b - (size_t)w, " %.17g %.17g %.17g", c->v[j][0],
                      c->v[j][1], c->v[j][2]);
    } else {
      snprintf(b, sizeof b, "crack %.17g %.17g %.17g %.17g", c->p0[0], c->p0[1], c->p1[0],
               c->p1[1]);
    }
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
    for (int k = 0; k < 3; k++) { /* newer keys: displacement fields, when given */
      if (!bc->gradient_n[k] && !bc->hessian_n[k]) continue;
      const double *g = bc->gradient[k], *H = &bc->hessian[k][0][0];
      snprintf(b, sizeof b, "field %d about %.17g %.17g %.17g gradient %d %.17g %.17g %.17g "
               "hessian %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g", k,
               bc->about[0], bc->about[1], bc->about[2], bc->gradient_n[k], g[0], g[1], g[2],
               bc->hessian_n[k], H[0], H[1], H[2], H[3], H[4], H[5], H[6], H[7], H[8]);
      fnv(&h, b);
    }
    if (bc->sel.set[0]) { /* newer key: only when given */
      snprintf(b, sizeof b, "set %s", bc->sel.set);
      fnv(&h, b);
    }
    if (bc->traction_set[0] || bc->traction_set[1] || bc->traction_set[2]) {
      snprintf(b, sizeof b, "traction %d%d%d %.17g %.17g %.17g", bc->traction_set[0],
               bc->traction_set[1], bc->traction_set[2], bc->traction[0], bc->traction[1],
               bc->traction[2]);
      fnv(&h, b);
    }
  }
  const ps_solver_opts *so = &cs->solver;
  const ps_path_opts *po = &cs->path;
  snprintf(b, sizeof b, "solver %.17g %d %d path %.17g %.17g %.17g %d %.17g %.17g %.17g %d",
           so->tolerance, so->max_iterations, so->line_search, po->load_step,
           po->load_step_after_break, po->max_load, po->max_increments, po->min_step,
           po->stop_crack_tip, po->stop_load_drop, 500);
  fnv(&h, b);
  if (po->control != PS_CONTROL_LOAD) { /* newer keys: only off load control */
    snprintf(b, sizeof b, "control %d %.17g %.17g %d", po->control, po->arc_length_max,
             po->arc_length_psi, po->arc_length_iterations);
    fnv(&h, b);
    if (PS_PATH_CONTROL_VERSION > 1) { /* the fingerprints of version 1 stay */
      snprintf(b, sizeof b, "path control algorithm %d", PS_PATH_CONTROL_VERSION);
      fnv(&h, b);
    }
  }
  if (po->max_arms_per_step > 0 || po->control == PS_CONTROL_DISSIPATION) {
    snprintf(b, sizeof b, "path control %d %.17g %.17g", po->max_arms_per_step,
             po->dissipation_step, po->dissipation_max);
    fnv(&h, b);
  }
  if (po->load_until_unstable) { /* newer keys: only when set */
    snprintf(b, sizeof b, "load until unstable %d", po->unstable_arms);
    fnv(&h, b);
  }
  if (po->control == PS_CONTROL_EVENT) {
    snprintf(b, sizeof b, "event %.17g", po->event_tolerance);
    fnv(&h, b);
  }
  for (int i = 0; i < po->n_steps; i++) { /* newer key: only when set */
    snprintf(b, sizeof b, "step %.17g", po->steps[i]);
    fnv(&h, b);
  }
  if (po->max_arms_per_round > 0) { /* newer key: only when set */
    snprintf(b, sizeof b, "arms per round %d", po->max_arms_per_round);
    fnv(&h, b);
  }
  if (po->round_tolerance > 0) { /* newer key: only when set */
    snprintf(b, sizeof b, "round tolerance %.17g", po->round_tolerance);
    fnv(&h, b);
  }
  ps_solver_opts so_default;
  ps_solver_opts_default(&so_default);
  if (so->max_small_steps != so_default.max_small_steps) { /* newer keys: only
                                                               when not the default */
    snprintf(b, sizeof b, "small steps %d", so->max_small_steps);
    fnv(&h, b);
  }
  if (!so->cg_truncate) fnv(&h, "cg not truncated");
  if (!so->cg_forcing_adaptive) { /* the fixed rule (adaptive: the default) */
    snprintf(b, sizeof b, "cg forcing %.17g", so->cg_forcing);
    fnv(&h, b);
  }
  if (po->stop_tip_advance > 0) { /* newer key: only when set */
    snprintf(b, sizeof b, "tip advance %.17g", po->stop_tip_advance);
    fnv(&h, b);
  }
  if (so->parts != so_default.parts) { /* newer key: only when not the
                                          default; the order of the sums */
    snprintf(b, sizeof b, "parts %d", so->parts);
    fnv(&h, b);
  }
  return h;
}

int ps_algorithm_version(void) { return PS_ALGORITHM_VERSION; }

uint64_t ps_case_restart_fingerprint(const ps_case *cs) {
  ps_case *c = malloc(sizeof *c);
  if (!c) return 0; /* matches no checkpoint (the writer's is never 0 but by chance) */
  memcpy(c, cs, sizeof *c); /* its lists borrowed: read, never freed through c */
  c->path.max_increments = 1;
  uint64_t h = ps_case_fingerprint(c);
  free(c);
  const ps_solver_opts *so = &cs->solver;
  char b[512];
  snprintf(b, sizeof b, "restart: linear %s reuse %d cg %.17g %d %d skip %d forcing %d %.17g "
           "%.17g matrix-free %d truncate %d single %d reanalyze %d majorant %d",
           so->linear, so->reuse_factor, so->pcg_rtol, so->pcg_max_iterations, so->max_small_steps,
           so->pcg_skip_arms, so->cg_forcing_adaptive, so->cg_forcing_max, so->cg_forcing,
           so->matrix_free, so->cg_truncate, so->cg_single_precision, so->reanalyze,
           so->majorant);
  fnv(&h, b);
  snprintf(b, sizeof b, "path rounds %d", cs->path.max_break_rounds);
  fnv(&h, b);
  if (!strcmp(so->linear, "petsc")) { /* (the other backends have no options) */
    char o[sizeof so->petsc_options + 16];
    snprintf(o, sizeof o, "petsc %s", so->petsc_options);
    fnv(&h, o);
  }
  return h;
}

const char *const ps_case_restart_parts[PS_RESTART_PARTS + 1] = {
    "geometry", "material", "loading", "solver", "path", NULL};

void ps_case_restart_part_fingerprints(const ps_case *cs, uint64_t h[PS_RESTART_PARTS]) {
  ps_case *d = malloc(sizeof *d); /* the defaults (which own no list) with cs's
                                     part, its lists borrowed */
  for (int k = 0; k < PS_RESTART_PARTS; k++) h[k] = 0;
  if (!d) return;
  for (int k = 0; k < PS_RESTART_PARTS; k++) {
    ps_case_defaults(d);
    switch (k) {
    case 0:
      d->geometry = cs->geometry;
      d->dim = cs->dim;
      d->disk = cs->disk;
      memcpy(d->counts, cs->counts, sizeof d->counts);
      d->spacing = cs->spacing;
      memcpy(d->lattice, cs->lattice, sizeof d->lattice);
      d->jitter = cs->jitter;
      memcpy(d->origin, cs->origin, sizeof d->origin);
      d->n_holes = cs->n_holes;
      memcpy(d->holes, cs->holes, sizeof d->holes);
      d->seed = cs->seed;
      memcpy(d->cloud_file, cs->cloud_file, sizeof d->cloud_file);
      d->mesh_format = cs->mesh_format;
      d->given_particles = cs->given_particles;
      d->size_rule = cs->size_rule;
      d->size_neighbours = cs->size_neighbours;
      d->n_cracks = cs->n_cracks;
      memcpy(d->cracks, cs->cracks, sizeof d->cracks);
      break;
    case 1:
      d->alpha = cs->alpha;
      d->kernel_k = cs->kernel_k;
      memcpy(d->model, cs->model, sizeof d->model);
      d->horizon_factor = cs->horizon_factor;
      d->mat = cs->mat;
      break;
    case 2:
      d->load_type = cs->load_type;
      d->n_bc = cs->n_bc;
      d->bc = cs->bc; /* borrowed: read, never freed through d */
      d->stress_length = cs->stress_length;
      break;
    case 3: d->solver = cs->solver; break;
    default: d->path = cs->path; break;
    }
    h[k] = ps_case_restart_fingerprint(d);
  }
  free(d);
}
