/* case_sections.c: the sections of a case file that describe the body:
 * geometry (disk of Eq. 114, box, point cloud or mesh; cracks, holes), kernel
 * (the horizon alpha and the exponent k of Eq. 112) and material (the
 * model, Table 1's constants, delta of Eq. 118). Each key's own range is
 * checked here; checks that involve several keys run in case_checks.c. */
#include "case_impl.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- geometry ---- */

/* geometry.cracks: a list of 2D segments [[x0, y0], [x1, y1]] or of 3D
 * planar polygons [[x, y, z], ...] of 3 to 16 points, each entry with
 * points of one form (which must be geometry.dim's: case_checks.c). A
 * polygon is checked here (ps_crack_polygon: planar, nonzero area). */
static int get_cracks(ps_loader *L, yaml_node_t *v, const char *name) {
  char b[80];
  ps_case *cs = L->cs;
  if (v->type != YAML_SEQUENCE_NODE)
    return ps_yaml_fail(L, line_of(v),
                        "%s must be a list of segments [[x0, y0], [x1, y1]] (2D) or planar "
                        "polygons [[x, y, z], ...] (3D) (got %s)",
                        name, ps_yaml_got(v, b));
  int n = seq_len(v);
  if (n > PS_MAX_CRACKS)
    return ps_yaml_fail(L, line_of(v), "%s has %d cracks, at most %d are allowed", name,
                        n, PS_MAX_CRACKS);
  cs->n_cracks = 0;
  for (int i = 0; i < n; i++) {
    yaml_node_t *e = seq_item(L, v, i);
    int np = e->type == YAML_SEQUENCE_NODE ? seq_len(e) : 0;
    if (np < 2)
      return ps_yaml_fail(L, line_of(e),
                          "%s entry %d must be a segment [[x0, y0], [x1, y1]] (2D) or a "
                          "planar polygon [[x, y, z], ...] of 3 to %d points (3D) (got %s)",
                          name, i + 1, PS_CRACK_MAX_VERTICES,
                          np == 1 ? "1 point" : ps_yaml_got(e, b));
    /* the points, all of the first one's form: [x, y] or [x, y, z] */
    double pt[PS_CRACK_MAX_VERTICES][3] = {{0}};
    int form = 0;
    for (int j = 0; j < np && j < PS_CRACK_MAX_VERTICES; j++) {
      yaml_node_t *q = seq_item(L, e, j);
      int nc = q->type == YAML_SEQUENCE_NODE ? seq_len(q) : 0;
      if (nc != 2 && nc != 3)
        return ps_yaml_fail(L, line_of(q),
                            "%s entry %d: point %d must be [x, y] (2D) or [x, y, z] (3D) "
                            "(got %s)",
                            name, i + 1, j + 1, ps_yaml_got(q, b));
      if (j == 0) form = nc;
      if (nc != form)
        return ps_yaml_fail(L, line_of(q),
                            "%s entry %d: point %d has %d coordinates but point 1 has %d: "
                            "give every point as [x, y] (2D) or [x, y, z] (3D)",
                            name, i + 1, j + 1, nc, form);
      for (int k = 0; k < nc; k++)
        if (ps_yaml_coord(L, seq_item(L, q, k), name, &pt[j][k])) return PS_ERR_INPUT;
    }
    L->line_crack[i] = line_of(e);
    L->crack_dim[i] = form;
    ps_crack *cr = &cs->cracks[i];
    memset(cr, 0, sizeof *cr);
    if (form == 2) {
      if (np != 2)
        return ps_yaml_fail(L, line_of(e),
                            "%s entry %d: a 2D crack is a segment of 2 points [[x0, y0], "
                            "[x1, y1]] (got %d points)",
                            name, i + 1, np);
      memcpy(cr->p0, pt[0], sizeof pt[0]);
      memcpy(cr->p1, pt[1], sizeof pt[1]);
      if (cr->p0[0] == cr->p1[0] && cr->p0[1] == cr->p1[1])
        return ps_yaml_fail(L, line_of(e), "%s entry %d: the segment has zero length", name,
                            i + 1);
    } else {
      if (np < 3 || np > PS_CRACK_MAX_VERTICES)
        return ps_yaml_fail(L, line_of(e),
                            "%s entry %d: a 3D crack is a planar polygon of 3 to %d points "
                            "[[x, y, z], ...] (got %d points)",
                            name, i + 1, PS_CRACK_MAX_VERTICES, np);
      int bad;
      if (ps_crack_polygon(cr, np, (const double(*)[3])pt, &bad, L->ctx) != PS_OK) {
        char m[sizeof L->ctx->msg];
        snprintf(m, sizeof m, "%s", L->ctx->msg);
        return ps_yaml_fail(L, line_of(bad >= 0 ? seq_item(L, e, bad) : e), "%s entry %d: %s",
                            name, i + 1, m);
      }
    }
    cs->n_cracks++;
  }
  L->line_cracks = line_of(v);
  return PS_OK;
}

/* geometry.holes: a list of circles [cx, cy, R] (2D) or spheres
 * [cx, cy, cz, R] (3D; which must be geometry.dim's: case_checks.c). */
static int get_holes(ps_loader *L, yaml_node_t *v, const char *name) {
  char b[80];
  ps_case *cs = L->cs;
  if (v->type != YAML_SEQUENCE_NODE)
    return ps_yaml_fail(L, line_of(v),
                        "%s must be a list of circles [cx, cy, R] (2D) or spheres "
                        "[cx, cy, cz, R] (3D) (got %s)",
                        name, ps_yaml_got(v, b));
  int n = seq_len(v);
  if (n > PS_MAX_HOLES)
    return ps_yaml_fail(L, line_of(v), "%s has %d holes, at most %d are allowed", name, n,
                        PS_MAX_HOLES);
  cs->n_holes = 0;
  for (int i = 0; i < n; i++) {
    yaml_node_t *h = seq_item(L, v, i);
    int nv = h->type == YAML_SEQUENCE_NODE ? seq_len(h) : 0;
    if (nv != 3 && nv != 4)
      return ps_yaml_fail(L, line_of(h),
                          "%s entry %d must be a circle [cx, cy, R] (2D) or a sphere "
                          "[cx, cy, cz, R] (3D) (got %s)",
                          name, i + 1, ps_yaml_got(h, b));
    double *c = cs->holes[i];
    memset(c, 0, sizeof cs->holes[i]);
    for (int k = 0; k + 1 < nv; k++)
      if (ps_yaml_coord(L, seq_item(L, h, k), name, &c[k])) return PS_ERR_INPUT;
    yaml_node_t *r = seq_item(L, h, nv - 1);
    char rname[96];
    snprintf(rname, sizeof rname, "%s entry %d: the radius R", name, i + 1);
    if (ps_yaml_real(L, r, rname, 0.0, 1, INFINITY, 0, &c[nv - 1])) return PS_ERR_INPUT;
    if (c[nv - 1] > PS_MAX_COORD) return ps_yaml_coord(L, r, name, &c[nv - 1]);
    L->line_hole[i] = line_of(h);
    L->hole_len[i] = nv;
    cs->n_holes++;
  }
  L->line_holes = line_of(v);
  return PS_OK;
}

const char *const ps_case_geometry_keys[] = {
    "type", "dim", "c", "n_eta", "n_xi", "per_zone", "xi_min", "xi_max",
    "jitter", "seed", "counts", "spacing", "lattice", "file", "sizes",
    "size_neighbours", "origin", "holes", "format", "cracks", "refine_tips",
    "refine_radius", NULL};

int ps_case_on_geometry(ps_loader *L, void *arg, const char *key, const char *name,
                        yaml_node_t *v) {
  static const char *const types[] = {"disk", "box", "cloud", "mesh", NULL};
  static const char *const formats[] = {"gmsh", "exodus", NULL};
  _Static_assert(PS_MESH_GMSH == 0 && PS_MESH_EXODUS == 1, "formats[] in enum order");
  static const char *const lattices[] = {"square", "hex", NULL};
  static const char *const sizes[] = {"eq115", "eq44", NULL};
  ps_case *cs = L->cs;
  char b[80];
  (void)arg;
  _Static_assert(sizeof ps_case_geometry_keys / sizeof ps_case_geometry_keys[0] <=
                     sizeof L->line_geometry / sizeof L->line_geometry[0],
                 "one line_geometry per geometry key");
  for (int i = 0; ps_case_geometry_keys[i]; i++)
    if (IS(ps_case_geometry_keys[i])) L->line_geometry[i] = line_of(v);
  if (IS("type")) {
    L->line_type = line_of(v);
    return ps_yaml_choice(L, v, name, types, &cs->geometry);
  }
  if (IS("dim")) {
    L->line_dim = line_of(v);
    return ps_yaml_int(L, v, name, 2, 3, &cs->dim);
  }
  if (IS("c")) return ps_yaml_pos(L, v, name, &cs->disk.c);
  if (IS("n_eta")) return ps_yaml_int(L, v, name, 1, INT_MAX, &cs->disk.n_eta);
  if (IS("n_xi")) return ps_yaml_int(L, v, name, 3, INT_MAX, &cs->disk.n_xi);
  if (IS("per_zone")) return ps_yaml_int(L, v, name, 1, INT_MAX, &cs->disk.per_zone);
  if (IS("refine_tips")) return ps_yaml_int(L, v, name, 1, 64, &cs->disk.refine_tips);
  if (IS("refine_radius"))
    return ps_yaml_real(L, v, name, 0.0, 1, INFINITY, 0, &cs->disk.refine_radius);
  if (IS("xi_min"))
    return ps_yaml_real(L, v, name, -INFINITY, 0, 0.0, 1, &cs->disk.xi_min);
  if (IS("xi_max"))
    return ps_yaml_real(L, v, name, 0.0, 1, INFINITY, 0, &cs->disk.xi_max);
  if (IS("jitter")) {
    /* one key for both generators: only the chosen geometry reads it */
    int s = ps_yaml_real(L, v, name, 0.0, 0, 0.5, 1, &cs->jitter);
    cs->disk.jitter = cs->jitter;
    return s;
  }
  if (IS("seed")) {
    long seed;
    int s = ps_yaml_long(L, v, name, 0, LONG_MAX, &seed);
    if (s == PS_OK) cs->seed = cs->disk.seed = (unsigned long)seed;
    return s;
  }
  if (IS("counts")) {
    if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 2 || seq_len(v) > 3)
      return ps_yaml_fail(L, line_of(v), "%s must be [nx, ny] or [nx, ny, nz] (got %s)",
                          name, ps_yaml_got(v, b));
    L->n_counts = seq_len(v);
    L->line_counts = line_of(v);
    cs->counts[2] = 1;
    for (int k = 0; k < L->n_counts; k++) {
      long c;
      if (ps_yaml_long(L, seq_item(L, v, k), name, 1, INT_MAX, &c)) return PS_ERR_INPUT;
      cs->counts[k] = (ps_int)c;
    }
    return PS_OK;
  }
  if (IS("spacing")) return ps_yaml_pos(L, v, name, &cs->spacing);
  if (IS("lattice")) {
    int i;
    L->line_lattice = line_of(v);
    if (ps_yaml_choice(L, v, name, lattices, &i)) return PS_ERR_INPUT;
    strcpy(cs->lattice, lattices[i]);
    return PS_OK;
  }
  if (IS("file")) {
    char f[1024];
    if (ps_yaml_string(L, v, name, f, sizeof f)) return PS_ERR_INPUT;
    int w = f[0] == '/' ? snprintf(cs->cloud_file, sizeof cs->cloud_file, "%s", f)
                        : snprintf(cs->cloud_file, sizeof cs->cloud_file, "%s/%s",
                                   cs->dir, f);
    if (w < 0 || (size_t)w >= sizeof cs->cloud_file)
      return ps_yaml_fail(L, line_of(v), "%s: path too long", name);
    return PS_OK;
  }
  if (IS("sizes")) return ps_yaml_choice(L, v, name, sizes, &cs->size_rule);
  if (IS("size_neighbours")) return ps_yaml_int(L, v, name, 1, 64, &cs->size_neighbours);
  if (IS("origin")) {
    if (v->type != YAML_SEQUENCE_NODE || seq_len(v) < 2 || seq_len(v) > 3)
      return ps_yaml_fail(L, line_of(v), "%s must be [x0, y0] or [x0, y0, z0] (got %s)",
                          name, ps_yaml_got(v, b));
    for (int k = 0; k < seq_len(v); k++)
      if (ps_yaml_coord(L, seq_item(L, v, k), name, &cs->origin[k])) return PS_ERR_INPUT;
    return PS_OK;
  }
  if (IS("holes")) return get_holes(L, v, name);
  if (IS("format")) return ps_yaml_choice(L, v, name, formats, &cs->mesh_format);
  return get_cracks(L, v, name); /* "cracks", the last allowed key */
}

/* ---- kernel ---- */

const char *const ps_case_kernel_keys[] = {"alpha", "k", NULL};

int ps_case_on_kernel(ps_loader *L, void *arg, const char *key, const char *name,
                      yaml_node_t *v) {
  (void)arg;
  if (IS("alpha"))
    return ps_yaml_pos_in(L, v, name, PS_ALPHA_MIN, PS_ALPHA_MAX,
                          "the horizon in particle sizes h (the paper: 5.1)",
                          &L->cs->alpha);
  return ps_yaml_int(L, v, name, 1, PS_KERNEL_K_MAX, &L->cs->kernel_k);
}

/* ---- material ---- */

/* The material models a case can name (ps_model_type_find knows them). */
static const char *const known_models[] = {"fibre", "bond", "state", "threebody",
                                            NULL};

const char *const ps_case_material_keys[] = {
    "model", "E", "nu", "plane", "yield_strain", "plastic", "delta",
    "delta_over_c", "rho", "yield_rule", "horizon_factor", "surface_correction",
    "micromodulus", "partial_volumes", "fracture", "horizon", "break_rule",
    "break_length", NULL};

/* material.fracture (bond, state and threebody models): one of
 * critical_stretch (s0), fracture_energy (G_c, J/m^2, with criterion
 * stretch or energy; threebody: energy, the default there, set by the
 * cross checks) and critical_micropotential (w_c). */
static const char *const fracture_keys[] = {"critical_stretch", "fracture_energy",
                                            "critical_micropotential", "criterion",
                                            "softening_ratio", NULL};

static int on_fracture(ps_loader *L, void *arg, const char *key, const char *name,
                       yaml_node_t *v) {
  static const char *const criteria[] = {"stretch", "energy", NULL};
  ps_material *m = &L->cs->mat;
  int i;
  (void)arg;
  if (IS("criterion")) {
    L->line_fracture_criterion = line_of(v);
    if (ps_yaml_choice(L, v, name, criteria, &i)) return PS_ERR_INPUT;
    m->fracture = i == 0 ? PS_FRACTURE_STRETCH : PS_FRACTURE_ENERGY;
    return PS_OK;
  }
  if (IS("softening_ratio")) {
    L->line_softening = line_of(v);
    return ps_yaml_pos_in(L, v, name, 1.0 + 1e-9, 1e6,
                          "s1/s0 > 1: the arm softens from s0 to zero force at s1",
                          &m->softening_ratio);
  }
  L->n_fracture_given++;
  if (IS("critical_stretch")) {
    if (!L->line_fracture_criterion) m->fracture = PS_FRACTURE_STRETCH;
    return ps_yaml_pos_in(L, v, name, PS_STRETCH_MIN, PS_STRETCH_MAX,
                          "a stretch dl/xi (Peridigm's examples: 0.001)",
                          &m->critical_stretch);
  }
  if (IS("fracture_energy")) {
    if (!L->line_fracture_criterion) m->fracture = PS_FRACTURE_STRETCH;
    return ps_yaml_pos_in(L, v, name, 1e-20, 1e20, "G_c in J/m^2 (glass: 8, steel: 1e4)",
                          &m->fracture_energy);
  }
  if (!L->line_fracture_criterion) m->fracture = PS_FRACTURE_ENERGY;
  return ps_yaml_pos_in(L, v, name, 1e-30, 1e300,
                        "w_c in J/m^6 (3D) or J/m^5 (2D, per unit thickness)",
                        &m->critical_micropotential);
}

/* the checks inside material.fracture once it is read */
static int fracture_check(ps_loader *L, const char *name) {
  ps_material *m = &L->cs->mat;
  if (L->n_fracture_given != 1)
    return ps_yaml_fail(L, L->line_fracture,
                        "%s needs exactly one of critical_stretch, fracture_energy and "
                        "critical_micropotential (got %d)",
                        name, L->n_fracture_given);
  if (L->line_softening && m->fracture != PS_FRACTURE_STRETCH)
    return ps_yaml_fail(L, L->line_softening,
                        "%s.softening_ratio goes with the stretch criterion "
                        "(critical_stretch, or fracture_energy with criterion stretch)",
                        name);
  if (L->line_fracture_criterion && !(m->fracture_energy > 0))
    return ps_yaml_fail(L, L->line_fracture_criterion,
                        "%s.criterion goes with fracture_energy (critical_stretch is the "
                        "stretch criterion, critical_micropotential the energy one)",
                        name);
  return PS_OK;
}

int ps_case_on_material(ps_loader *L, void *arg, const char *key, const char *name,
                        yaml_node_t *v) {
  static const char *const planes[] = {"strain", "stress", NULL};
  static const char *const rules[] = {"total", "deviatoric", NULL};
  ps_case *cs = L->cs;
  ps_material *m = &cs->mat;
  int i;
  (void)arg;
  if (IS("model")) {
    L->line_model = line_of(v);
    if (ps_yaml_choice(L, v, name, known_models, &i)) return PS_ERR_INPUT;
    strcpy(cs->model, known_models[i]);
    return PS_OK;
  }
  if (IS("E")) {
    L->line_E = line_of(v);
    return ps_yaml_pos_in(L, v, name, PS_E_MIN, PS_E_MAX,
                          "Young's modulus in Pa (steel: 2.1e11)", &m->E);
  }
  if (IS("nu")) {
    L->line_nu = line_of(v);
    return ps_yaml_real(L, v, name, -1.0, 1, 0.5, 1, &m->nu);
  }
  if (IS("plane")) {
    L->line_plane = line_of(v);
    if (ps_yaml_choice(L, v, name, planes, &i)) return PS_ERR_INPUT;
    m->plane = i == 0 ? PS_PLANE_STRAIN : PS_PLANE_STRESS;
    return PS_OK;
  }
  if (IS("yield_strain")) {
    L->line_yield_strain = line_of(v);
    return ps_yaml_pos_in(L, v, name, PS_YIELD_STRAIN_MIN, PS_YIELD_STRAIN_MAX,
                          "a strain (steel: 0.002)", &m->yield_strain);
  }
  if (IS("plastic")) {
    L->line_plastic = line_of(v);
    return ps_yaml_bool(L, v, name, &m->plastic);
  }
  if (IS("delta")) {
    L->line_delta = line_of(v);
    cs->delta_over_c = 0.0;
    return ps_yaml_pos(L, v, name, &m->delta);
  }
  if (IS("delta_over_c")) {
    L->line_delta_over_c = line_of(v);
    m->delta = NAN;
    return ps_yaml_pos(L, v, name, &cs->delta_over_c);
  }
  if (IS("rho")) return ps_yaml_pos(L, v, name, &m->rho);
  if (IS("horizon_factor")) {
    /* bond, state: the horizon in spacings, the box's geometry.spacing or
     * a point cloud's (or the disk's) mean spacing (sum V / n)^(1/N) */
    L->line_horizon_factor = line_of(v);
    return ps_yaml_pos_in(L, v, name, PS_ALPHA_MIN, PS_ALPHA_MAX,
                          "the horizon in lattice or mean spacings (Fallah et al.: 3)",
                          &cs->horizon_factor);
  }
  if (IS("horizon")) { /* bond, state: the horizon as a length, m */
    L->line_horizon = line_of(v);
    return ps_yaml_pos_in(L, v, name, 1e-150, PS_MAX_COORD,
                          "a length in m (Fallah et al.: 3 spacings)", &m->horizon);
  }
  if (IS("surface_correction")) return ps_yaml_bool(L, v, name, &m->surface_correction);
  if (IS("micromodulus")) {
    static const char *const micro[] = {"conical", "constant", NULL};
    L->line_micromodulus = line_of(v);
    if (ps_yaml_choice(L, v, name, micro, &i)) return PS_ERR_INPUT;
    m->micromodulus = i == 0 ? PS_MICRO_CONICAL : PS_MICRO_CONSTANT;
    return PS_OK;
  }
  if (IS("partial_volumes")) {
    int pv;
    L->line_partial_volumes = line_of(v);
    if (ps_yaml_bool(L, v, name, &pv)) return PS_ERR_INPUT;
    m->full_volumes = !pv;
    return PS_OK;
  }
  if (IS("fracture")) {
    L->line_fracture = line_of(v);
    if (ps_yaml_walk_map(L, v, name, fracture_keys, on_fracture, NULL)) return PS_ERR_INPUT;
    return fracture_check(L, name);
  }
  if (IS("break_rule")) { /* fibre: how Eq. 118 measures an arm (ps_break_rule) */
    static const char *const breaks[] = {"elongation", "strain", "toughness", NULL};
    L->line_break_rule = line_of(v);
    if (ps_yaml_choice(L, v, name, breaks, &i)) return PS_ERR_INPUT;
    m->break_rule = i == 0 ? PS_BREAK_ELONGATION : i == 1 ? PS_BREAK_STRAIN : PS_BREAK_TOUGHNESS;
    return PS_OK;
  }
  if (IS("break_length")) { /* L of break_rule strain and toughness */
    L->line_break_length = line_of(v);
    return ps_yaml_pos_in(L, v, name, 1e-150, PS_MAX_COORD,
                          "a length in m, the same for every arm (break_rule strain: an arm "
                          "breaks at the plastic strain delta / L; toughness: at the plastic "
                          "elongation delta sqrt(r0 / L))",
                          &m->break_length);
  }
  L->line_yield_rule = line_of(v);
  if (ps_yaml_choice(L, v, name, rules, &i)) return PS_ERR_INPUT; /* yield_rule */
  m->yield_rule = i == 0 ? PS_YIELD_TOTAL : PS_YIELD_DEVIATORIC;
  return PS_OK;
}
