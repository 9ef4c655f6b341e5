/* case_checks.c: the checks across sections, after the whole file is
 * read (YAML keys come in any order): keys of another geometry type,
 * dim against counts, lattice, cracks, holes and J rings, the loading
 * type against the geometry, the bond model's nu, the number of
 * particles asked for, delta, the horizon and the Griffith list given
 * twice. (The bond and state models run on every geometry: a box
 * lattice, a point cloud, the disk; app/setup.c.) */
#include "case_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
/* A geometry key given for a geometry type it does not apply to (it
 * would be silently ignored): "case.yaml:7: geometry.file does not apply
 * to geometry.type disk (it is for types cloud and mesh)", for the first such key
 * in the file. Keys not listed (type, dim, sizes, size_neighbours,
 * cracks) apply to every type; geometry.holes has its own check. */
static int geometry_keys_apply(ps_loader *L) {
  enum { D = 1 << PS_GEOM_DISK, B = 1 << PS_GEOM_BOX, C = 1 << PS_GEOM_CLOUD,
         M = 1 << PS_GEOM_MESH };
  static const struct {
    const char *key;
    unsigned types;
    const char *for_text;
  } only[] = {{"c", D, "type disk"},          {"n_eta", D, "type disk"},
              {"n_xi", D, "type disk"},       {"per_zone", D, "type disk"},
              {"xi_min", D, "type disk"},     {"xi_max", D, "type disk"},
              {"refine_tips", D, "type disk"}, {"refine_radius", D, "type disk"},
              {"jitter", D | B, "types disk and box"},
              {"seed", D | B, "types disk and box"},
              {"counts", B, "type box"},      {"lattice", B, "type box"},
              {"origin", B, "type box"},      {"file", C | M, "types cloud and mesh"},
              {"format", M, "type mesh"},
              {"spacing", B, "type box, and for loading tractions"}};
  static const char *const gname[] = {"disk", "box", "cloud", "mesh"};
  const ps_case *cs = L->cs;
  int traction = 0;
  for (int i = 0; i < cs->n_bc; i++)
    for (int k = 0; k < 3; k++) traction |= cs->bc[i].traction_set[k];
  int first = 0, at = 0;
  for (size_t j = 0; j < sizeof only / sizeof only[0]; j++) {
    int i = 0;
    while (strcmp(ps_case_geometry_keys[i], only[j].key)) i++;
    int line = L->line_geometry[i];
    if (!line || (only[j].types >> cs->geometry & 1u)) continue;
    if (!strcmp(only[j].key, "spacing") && traction) continue;
    if (!first || line < first) {
      first = line;
      at = (int)j;
    }
  }
  if (!first) return PS_OK;
  return ps_yaml_fail(L, first,
                      "geometry.%s does not apply to geometry.type %s%s (it is for %s)",
                      only[at].key, gname[cs->geometry],
                      L->line_type ? "" : ", the default", only[at].for_text);
}

/* The line where geometry key `key` was given, else `otherwise`. */
static int geometry_line(const ps_loader *L, const char *key, int otherwise) {
  for (int i = 0; ps_case_geometry_keys[i]; i++)
    if (!strcmp(ps_case_geometry_keys[i], key) && L->line_geometry[i])
      return L->line_geometry[i];
  return otherwise;
}

/* The number of particles a box or disk asks for: at most
 * PS_MAX_PARTICLES (the generators' limit), named with the keys' line.
 * (Whether they fit in memory is judged later, by the size estimate.) */
static int particle_counts_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  double n = 1.0;
  if (cs->geometry == PS_GEOM_BOX) {
    for (int k = 0; k < cs->dim; k++) n *= (double)cs->counts[k];
    if (n > (double)PS_MAX_PARTICLES)
      return ps_yaml_fail(L, L->line_counts,
                          "geometry.counts asks for %.3g particles; at most "
                          "2^40 = %.4g can be indexed",
                          n, (double)PS_MAX_PARTICLES);
  } else if (cs->geometry == PS_GEOM_DISK) {
    const ps_disk_params *dp = &cs->disk;
    double m = dp->per_zone;
    int line = geometry_line(L, "per_zone", geometry_line(L, "n_xi", L->line_type));
    n = (double)dp->n_eta * dp->n_xi * m * m;
    if (n > (double)PS_MAX_PARTICLES)
      return ps_yaml_fail(
          L, line,
          "geometry.n_eta x geometry.n_xi x geometry.per_zone^2 = %d x %d x %d^2 "
          "asks for %.3g particles; at most 2^40 = %.4g can be indexed",
          dp->n_eta, dp->n_xi, dp->per_zone, n, (double)PS_MAX_PARTICLES);
    if (n * dp->refine_tips * dp->refine_tips > (double)PS_MAX_PARTICLES &&
        ps_geom_disk_count(dp) > (double)PS_MAX_PARTICLES)
      return ps_yaml_fail(L, geometry_line(L, "refine_tips", line),
                          "geometry.refine_tips %d asks for %.3g particles; at most 2^40 "
                          "= %.4g can be indexed",
                          dp->refine_tips, ps_geom_disk_count(dp), (double)PS_MAX_PARTICLES);
  }
  return PS_OK;
}

/* A model's own message (in L->ctx) at a line of the case file, with a
 * note after it. Returns PS_ERR_INPUT. */
static int fail_with_model_message(ps_loader *L, int line, const char *note) {
  char why[sizeof L->ctx->msg];
  snprintf(why, sizeof why, "%s", L->ctx->msg);
  return ps_yaml_fail(L, line, "%s%s", why, note);
}

/* A model that fixes Poisson's ratio (the type's fixed_poisson; bond-based
 * PD, Fallah et al. 2020: 1/3 in plane stress, 1/4 in plane strain and
 * 3D) refuses another one here, so that `info` refuses what `run` would
 * (the model checks it again when it is prepared). The message names the
 * file only, as the model's own does ("case.yaml: material.nu = 0.3:
 * bond-based ..."), and the line at its end. */
static int fixed_poisson_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  const ps_model_type *type = ps_model_type_find(cs->model);
  if (!type || ps_model_poisson_check(type, cs->mat.nu, cs->dim, cs->mat.plane, L->ctx) ==
                   PS_OK)
    return PS_OK;
  char where[64];
  if (L->line_nu)
    snprintf(where, sizeof where, " (material.nu is at line %d)", L->line_nu);
  else
    snprintf(where, sizeof where, " (material.nu is not given: the default is 0.3)");
  return fail_with_model_message(L, 0, where);
}

/* The threebody model (model/threebody.c): 2D only; nu at most 1/3 in
 * plane stress and 1/4 in plane strain (a non-negative bond-shear
 * stiffness kappa), within the 1e-3 of fixed_poisson; breaking by the arm
 * micropotential only: critical_micropotential, or fracture_energy with
 * criterion energy (its default here). The model's own checks
 * (ps_threebody_*_check) give the messages; here they get the line. */
static int threebody_check(ps_loader *L) {
  ps_case *cs = L->cs;
  if (cs->dim != 2)
    return ps_yaml_fail(L, L->line_dim ? L->line_dim : L->line_model,
                        "material.model threebody is 2D only (geometry.dim is %d): its "
                        "finite-rotation form has no 3D counterpart (doc/design-threebody.md); "
                        "use model state or bond in 3D", cs->dim);
  if (ps_threebody_poisson_check(cs->mat.nu, cs->mat.plane, L->ctx) != PS_OK)
    return fail_with_model_message(L, L->line_nu ? L->line_nu : L->line_model,
                                   L->line_nu ? "" : " (material.nu is not given: the "
                                                     "default is 0.3)");
  if (!L->line_fracture) return PS_OK;
  if (cs->mat.fracture_energy > 0 && !L->line_fracture_criterion)
    cs->mat.fracture = PS_FRACTURE_ENERGY; /* the threebody's default */
  if (ps_threebody_fracture_check(cs->mat.fracture, L->ctx) != PS_OK)
    return fail_with_model_message(
        L, L->line_fracture_criterion ? L->line_fracture_criterion : L->line_fracture, "");
  return PS_OK;
}

/* Keys that belong to some models only: material.fracture, micromodulus,
 * partial_volumes and horizon (bond, state) against material.delta
 * (fibre); material.horizon and horizon_factor not both. */
static int model_keys_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  int fibre = !strcmp(cs->model, "fibre"), bond = !strcmp(cs->model, "bond");
  int threebody = !strcmp(cs->model, "threebody");
  char model[64];
  if (!fibre && !L->line_plastic) L->cs->mat.plastic = 0; /* elastic models */
  if (L->line_model)
    snprintf(model, sizeof model, "material.model is %s (line %d)", cs->model, L->line_model);
  else
    snprintf(model, sizeof model, "material.model is not given: the default is fibre");
  if (fibre && L->line_fracture)
    return ps_yaml_fail(L, L->line_fracture,
                        "material.fracture is for the bond, state and threebody models: the fibre "
                        "model breaks arms by plastic elongation, material.delta (Eq. 118) "
                        "(%s)", model);
  if (!fibre && L->line_delta)
    return ps_yaml_fail(L, L->line_delta,
                        "material.delta is the fibre model's breaking limit (Eq. 118): the "
                        "%s model breaks arms by material.fracture: {critical_stretch: s0}",
                        cs->model);
  if (!bond && L->line_softening)
    return ps_yaml_fail(L, L->line_softening,
                        "material.fracture.softening_ratio is for the bond model (%s)", model);
  if (!bond && L->line_micromodulus)
    return ps_yaml_fail(L, L->line_micromodulus,
                        "material.micromodulus is for the bond model (%s)", model);
  if (fibre && L->line_partial_volumes)
    return ps_yaml_fail(L, L->line_partial_volumes,
                        "material.partial_volumes is for the bond, state and threebody models (%s)",
                        model);
  if (!fibre && (L->line_break_rule || L->line_break_length))
    return ps_yaml_fail(L, L->line_break_rule ? L->line_break_rule : L->line_break_length,
                        "material.break_rule and break_length are the fibre model's (how Eq. "
                        "118 measures an arm against delta): the %s model breaks arms by "
                        "material.fracture", cs->model);
  if (fibre && cs->mat.break_rule != PS_BREAK_ELONGATION && !L->line_break_length)
    return ps_yaml_fail(L, L->line_break_rule,
                        "material.break_rule %s needs material.break_length L (m): an arm "
                        "breaks at the plastic %s",
                        cs->mat.break_rule == PS_BREAK_STRAIN ? "strain" : "toughness",
                        cs->mat.break_rule == PS_BREAK_STRAIN ? "strain delta / L"
                                                              : "elongation delta sqrt(r0 / L)");
  if (fibre && L->line_break_length && cs->mat.break_rule == PS_BREAK_ELONGATION)
    return ps_yaml_fail(L, L->line_break_length,
                        "material.break_length goes with break_rule strain or toughness (the "
                        "elongation rule measures each arm by its own length)");
  if (fibre && L->line_horizon)
    return ps_yaml_fail(L, L->line_horizon,
                        "material.horizon is for the bond, state and threebody models: the fibre "
                        "model's horizon is kernel.alpha particle sizes (%s)", model);
  if (L->line_horizon && L->line_horizon_factor)
    return ps_yaml_fail(L, L->line_horizon,
                        "material.horizon and material.horizon_factor (line %d) are both "
                        "given: give one (the horizon in m, or in spacings)",
                        L->line_horizon_factor);
  if (threebody) {
    if (threebody_check(L) != PS_OK) return PS_ERR_INPUT;
  } else if (!bond && L->line_fracture && cs->mat.fracture == PS_FRACTURE_ENERGY)
    return ps_yaml_fail(L, L->line_fracture_criterion ? L->line_fracture_criterion
                                                      : L->line_fracture,
                        "material.fracture: the energy criterion is for the bond model "
                        "(and threebody); the %s model breaks by critical_stretch (or fracture_energy with "
                        "criterion stretch)",
                        cs->model);
  return PS_OK;
}

/* path.control dissipation needs a model that measures what it
 * dissipates with an exact rate (ps_model_type.arm_dissipation): softening
 * bond arms, or plastic fibre arms in the total reading */
static int dissipation_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  const ps_material *m = &cs->mat;
  if (cs->path.control != PS_CONTROL_DISSIPATION) return PS_OK;
  int bond = !strcmp(cs->model, "bond"), fibre = !strcmp(cs->model, "fibre");
  if (bond && m->softening_ratio > 1) return PS_OK;
  if (fibre && m->plastic && m->yield_rule == PS_YIELD_TOTAL) return PS_OK;
  return ps_yaml_fail(L, L->line_control,
                      "path.control dissipation needs arms that dissipate energy as they "
                      "deform: the bond model with material.fracture.softening_ratio, or the "
                      "fibre model with plasticity in the total yield reading (the %s model%s "
                      "here); use arc_length",
                      cs->model,
                      fibre ? (m->plastic ? ", yield_rule deviatoric" : ", elastic")
                            : bond ? " without softening_ratio" : "");
}

/* path.load_until_unstable is a phase of dissipation control */
static int load_phase_check(ps_loader *L) {
  const ps_path_opts *o = &L->cs->path;
  if (!o->load_until_unstable || o->control == PS_CONTROL_DISSIPATION) return PS_OK;
  return ps_yaml_fail(L, L->line_load_until_unstable,
                      "path.load_until_unstable starts dissipation control with load "
                      "control; it needs path.control dissipation");
}

/* path.control event follows arms to their breaking criterion: the
 * material needs one (material.fracture, or the fibre model's delta: given,
 * or on a disk delta_over_c c) */
static int event_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  const ps_material *m = &cs->mat;
  if (cs->path.control != PS_CONTROL_EVENT) return PS_OK;
  if (m->fracture != PS_FRACTURE_NONE || (m->delta > 0 && isfinite(m->delta)) ||
      (cs->geometry == PS_GEOM_DISK && cs->delta_over_c > 0))
    return PS_OK;
  return ps_yaml_fail(L, L->line_control,
                      "path.control event ends each increment where the next arm reaches "
                      "its breaking criterion, but no arm of this %s model can break: give "
                      "%s, or use load or arc_length",
                      cs->model,
                      !strcmp(cs->model, "fibre") ? "material.delta (or delta_over_c)"
                                                  : "material.fracture");
}

/* The displacement fields of loading.boundary against dim: a gradient of
 * dim numbers, a hessian of dim rows, about of dim coordinates. */
static int fields_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  for (int i = 0; i < cs->n_bc; i++) {
    const ps_bc *bc = &cs->bc[i];
    for (int k = 0; k < cs->dim; k++) {
      if (bc->gradient_n[k] && bc->gradient_n[k] != cs->dim)
        return ps_yaml_fail(L, bc->field_line,
                            "loading.boundary entry %d: displace.%c.gradient has %d numbers "
                            "but geometry.dim is %d (one per coordinate)",
                            i + 1, 'x' + k, bc->gradient_n[k], cs->dim);
      if (bc->hessian_n[k] && bc->hessian_n[k] != cs->dim)
        return ps_yaml_fail(L, bc->field_line,
                            "loading.boundary entry %d: displace.%c.hessian is %d x %d but "
                            "geometry.dim is %d",
                            i + 1, 'x' + k, bc->hessian_n[k], bc->hessian_n[k], cs->dim);
    }
    if (bc->about_n && bc->about_n != cs->dim)
      return ps_yaml_fail(L, bc->about_line,
                          "loading.boundary entry %d: about has %d coordinates but "
                          "geometry.dim is %d", i + 1, bc->about_n, cs->dim);
  }
  return PS_OK;
}

/* geometry.type mesh: a file, its format (geometry.format, else its
 * extension) and a reader for it in this build; select.set only with a
 * mesh (its names are checked when the mesh is read, app/setup.c). */
static int mesh_check(ps_loader *L) {
  ps_case *cs = L->cs;
  if (cs->geometry != PS_GEOM_MESH) {
    for (int i = 0; i < cs->n_bc; i++)
      if (cs->bc[i].sel.set[0])
        return ps_yaml_fail(L, cs->bc[i].line,
                            "loading.boundary entry %d: select.set names a set of a mesh: "
                            "it needs geometry.type mesh", i + 1);
    return PS_OK;
  }
  int line_file = geometry_line(L, "file", L->line_type);
  int line_format = geometry_line(L, "format", 0);
  if (!cs->cloud_file[0])
    return ps_yaml_fail(L, L->line_type, "geometry.type mesh needs geometry.file");
  if (cs->mesh_format < 0) {
    cs->mesh_format = ps_mesh_format_of_path(cs->cloud_file);
    if (cs->mesh_format < 0)
      return ps_yaml_fail(L, line_file,
                          "geometry.file %s: the extension names no mesh format (.msh: "
                          "Gmsh; .exo, .e, .g, .gen: Exodus II): give geometry.format gmsh "
                          "or exodus", cs->cloud_file);
  }
  if (!ps_mesh_format_built(cs->mesh_format)) {
    char msg[256];
    return ps_yaml_fail(L, line_format ? line_format : line_file, "%s",
                        ps_mesh_format_missing(cs->mesh_format, msg, sizeof msg));
  }
  return PS_OK;
}

/* path.steps is load control's list of load factors: not with another
 * control, nor with the keys it replaces; its last entry is max_load. */
static int steps_check(ps_loader *L) {
  ps_path_opts *o = &L->cs->path;
  static const char *const control[] = {"load", "arc_length", "dissipation", "event"};
  if (!L->line_steps) return PS_OK;
  if (o->control != PS_CONTROL_LOAD)
    return ps_yaml_fail(L, L->line_steps,
                        "path.steps is a list of load factors for load control, but "
                        "path.control is %s (line %d): remove one",
                        control[o->control], L->line_control);
  const char *key = L->line_load_step ? "load_step"
                    : L->line_load_step_after_break ? "load_step_after_break"
                    : L->line_max_load ? "max_load" : NULL;
  int line = L->line_load_step ? L->line_load_step
             : L->line_load_step_after_break ? L->line_load_step_after_break
                                              : L->line_max_load;
  if (key)
    return ps_yaml_fail(L, line,
                        "path.%s and path.steps (line %d) are both given: the list sets "
                        "every increment and its last entry is the last load factor",
                        key, L->line_steps);
  o->max_load = o->steps[o->n_steps - 1];
  return PS_OK;
}

/* Each geometry.cracks and geometry.holes entry in the form of
 * geometry.dim: 2D segments [[x0, y0], [x1, y1]] and circles [cx, cy, R],
 * 3D planar polygons [[x, y, z], ...] and spheres [cx, cy, cz, R]; the
 * first entry of the other form is named. */
static int cracks_holes_dim_check(ps_loader *L) {
  const ps_case *cs = L->cs;
  for (int i = 0; i < cs->n_cracks; i++) {
    if (L->crack_dim[i] == cs->dim) continue;
    if (cs->dim == 3)
      return ps_yaml_fail(L, L->line_crack[i],
                          "geometry.cracks entry %d is a 2D segment [[x0, y0], [x1, y1]] but "
                          "geometry.dim is 3: a 3D crack is a planar polygon [[x, y, z], "
                          "...] of 3 to %d points",
                          i + 1, PS_CRACK_MAX_VERTICES);
    return ps_yaml_fail(L, L->line_crack[i],
                        "geometry.cracks entry %d is a 3D polygon of [x, y, z] points but "
                        "geometry.dim is 2: a 2D crack is a segment [[x0, y0], [x1, y1]]",
                        i + 1);
  }
  for (int i = 0; i < cs->n_holes; i++) {
    if (L->hole_len[i] == cs->dim + 1) continue;
    if (cs->dim == 3)
      return ps_yaml_fail(L, L->line_hole[i],
                          "geometry.holes entry %d is a circle [cx, cy, R] but geometry.dim "
                          "is 3: a 3D hole is a sphere [cx, cy, cz, R]",
                          i + 1);
    return ps_yaml_fail(L, L->line_hole[i],
                        "geometry.holes entry %d is a sphere [cx, cy, cz, R] but "
                        "geometry.dim is 2: a 2D hole is a circle [cx, cy, R]",
                        i + 1);
  }
  return PS_OK;
}

/* case_impl.h */
int ps_case_cross_checks(ps_loader *L) {
  static const char *const gname[] = {"disk", "box", "cloud", "mesh"};
  ps_case *cs = L->cs;
  if (geometry_keys_apply(L) != PS_OK) return PS_ERR_INPUT;
  if (cs->geometry == PS_GEOM_DISK) {
    if (L->line_dim && cs->dim != 2)
      return ps_yaml_fail(L, L->line_dim,
                          "geometry.dim must be 2 for geometry.type disk (got %d)",
                          cs->dim);
    cs->dim = 2;
  }
  if (cs->geometry == PS_GEOM_BOX) {
    if (L->line_counts && L->n_counts != cs->dim)
      return ps_yaml_fail(L, L->line_counts,
                          "geometry.counts has %d values but geometry.dim is %d",
                          L->n_counts, cs->dim);
    if (!L->line_counts && cs->dim == 3)
      return ps_yaml_fail(L, L->line_dim, "a 3D box needs geometry.counts: [nx, ny, nz]");
    if (cs->dim == 3 && !strcmp(cs->lattice, "hex"))
      return ps_yaml_fail(L, L->line_lattice,
                          "geometry.lattice hex is 2D only (geometry.dim is 3)");
  }
  if (cs->dim == 2) cs->counts[2] = 1;
  if (cs->geometry == PS_GEOM_CLOUD && !cs->cloud_file[0] && !cs->given_particles)
    return ps_yaml_fail(L, L->line_type, "geometry.type cloud needs geometry.file");
  if (mesh_check(L) != PS_OK) return PS_ERR_INPUT;
  if (cracks_holes_dim_check(L) != PS_OK) return PS_ERR_INPUT;
  if (cs->output.n_j_rings > 0 && cs->dim == 3)
    return ps_yaml_fail(L, L->line_j, "output.j_integral is 2D only (geometry.dim is 3)");
  if (L->line_j_crack && cs->output.j_crack >= cs->n_cracks)
    return ps_yaml_fail(L, L->line_j_crack,
                        "output.j_integral.crack %d is not in geometry.cracks (%d given, "
                        "counted from 0)",
                        cs->output.j_crack, cs->n_cracks);
  if (cs->n_holes > 0 && cs->geometry != PS_GEOM_BOX && cs->geometry != PS_GEOM_CLOUD)
    return ps_yaml_fail(L, L->line_holes,
                        "geometry.holes need geometry.type box or cloud (got %s)",
                        gname[cs->geometry]);
  if (fixed_poisson_check(L) != PS_OK || particle_counts_check(L) != PS_OK ||
      model_keys_check(L) != PS_OK || dissipation_check(L) != PS_OK ||
      event_check(L) != PS_OK || load_phase_check(L) != PS_OK)
    return PS_ERR_INPUT;
  if (L->line_delta_over_c && cs->geometry != PS_GEOM_DISK)
    return ps_yaml_fail(
        L, L->line_delta_over_c,
        "material.delta_over_c needs geometry.type disk (c is the disk's half "
        "crack length): give material.delta in metres");
  if (L->line_delta && L->line_delta_over_c)
    return ps_yaml_fail(
        L, L->line_delta,
        "material.delta and material.delta_over_c (line %d) are both given: "
        "give one",
        L->line_delta_over_c);
  if (L->line_sweep_list && L->line_sweep_den)
    return ps_yaml_fail(
        L, L->line_sweep_den,
        "griffith.denominators and griffith.delta_over_c (line %d) are both "
        "given: give one",
        L->line_sweep_list);
  if (cs->load_type == PS_LOAD_EQ116) {
    if (cs->geometry != PS_GEOM_DISK)
      return ps_yaml_fail(L, L->line_load_type ? L->line_load_type : L->line_type,
                          "loading.type eq116%s needs geometry.type disk (got %s): set "
                          "loading.type: boundary",
                          L->line_load_type ? "" : " (the default)", gname[cs->geometry]);
    if (cs->n_bc > 0 || L->line_boundary)
      return ps_yaml_fail(L, L->line_boundary,
                          "loading.boundary is given but loading.type is eq116: set "
                          "loading.type: boundary");
  } else if (cs->n_bc == 0) {
    return ps_yaml_fail(L, L->line_boundary ? L->line_boundary : L->line_load_type,
                        "loading.boundary is empty: the model has no supports");
  }
  for (int i = 0; i < cs->n_bc && cs->dim == 2; i++) {
    const ps_bc *bc = &cs->bc[i];
    if (bc->fix[2] || bc->displace_set[2] || bc->traction_set[2] ||
        isfinite(bc->sel.lo[2]) || isfinite(bc->sel.hi[2]))
      return ps_yaml_fail(
          L, bc->line,
          "loading.boundary entry %d uses the z component but geometry.dim is 2", i + 1);
  }
  if (fields_check(L) != PS_OK || steps_check(L) != PS_OK) return PS_ERR_INPUT;
  return PS_OK;
}
