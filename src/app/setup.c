/* setup.c: from a case to a problem: particle cloud (disk, box, point
 * file or mesh), sizes (Eq. 115 or Eq. 44), arm network, material, and the
 * boundary conditions with the boundary-stress measure. */
#include "ps_app.h"

#include <gsl/gsl_math.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

int ps_problem_share(const ps_problem *pb, const ps_partition *pt, int part, ps_share *sh,
                     ps_ctx *ctx) {
  int h = ps_model_share_horizons(ps_model_type_find(pb->cs.model), &pb->mat);
  /* J's displacement gradients at the ghost ends of the arms across its
   * contours need those ghosts' whole families: two horizons */
  if (h < 2 && pb->cs.output.n_j_rings > 0) h = 2;
  return ps_share_build(sh, &pb->P, pt, part, h, &pb->kernel, pb->cracks, pb->n_cracks, ctx);
}

void ps_problem_free(ps_problem *pb) {
  ps_network_free(&pb->net);
  ps_particles_free(&pb->P);
  free(pb->fixed);
  free(pb->ubar);
  free(pb->measure);
  free(pb->fext);
  free(pb->group_bc);
  free(pb->group_ptr);
  free(pb->group_particle);
  free(pb->cracks);
  ps_case_free(&pb->cs);
  memset(pb, 0, sizeof *pb);
}

/* Is particle a selected by s (in_set: a's membership of s's named set,
 * or NULL when s names none)? */
static int selected(const ps_particles *P, ps_int a, const ps_select *s,
                    const unsigned char *in_set) {
  if (in_set && !in_set[a]) return 0;
  for (int k = 0; k < P->dim; k++) {
    double x = P->x[a * P->dim + k];
    if (x < s->lo[k] || x > s->hi[k]) return 0;
  }
  return s->block < 0 || P->block[a] == s->block;
}

/* disk: boundary zone follows Eq. 116 scaled by the load factor */
static int setup_eq116(ps_problem *pb, ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  const ps_disk_params *dp = &pb->cs.disk;
  double S = pb->mat.sigma_y; /* load factor = remote stress / sigma_y */
  for (ps_int a = 0; a < P->n; a++) {
    if (!P->in_boundary_zone[a]) continue;
    double x = P->x[2 * a], y = P->x[2 * a + 1], u, v, xi, eta;
    ps_geom_eq116(x, y, pb->c, S, pb->mat.G, pb->mat.kappa, &u, &v);
    pb->fixed[2 * a] = pb->fixed[2 * a + 1] = 1;
    pb->ubar[2 * a] = u;
    pb->ubar[2 * a + 1] = v;
    /* outward normal of the confocal ellipse through the particle */
    ps_geom_elliptic_coords(x, y, pb->c, &xi, &eta);
    double A = pb->c * cosh(xi), B = pb->c * sinh(xi);
    double nx = x / (A * A), ny = y / (B * B), nn = hypot(nx, ny);
    pb->measure[2 * a] = nx / nn;
    pb->measure[2 * a + 1] = ny / nn;
  }
  /* interface between the boundary zone and the interior */
  double xi_out = fmin(dp->xi_max, -dp->xi_min);
  double dxi = (dp->xi_max - dp->xi_min) / dp->n_xi;
  pb->measure_length = ps_geom_ellipse_perimeter(pb->c, xi_out - dxi);
  if (!(pb->measure_length > 0))
    return ps_error(ctx, PS_ERR_INPUT, "%s: cannot compute the boundary-zone perimeter",
                    pb->cs.file);
  return PS_OK;
}

/* The membership of the named set of selection bc->sel (a mesh's set)
 * into in_set[n]; an unknown name is an error listing the mesh's sets. */
static int set_members(const ps_problem *pb, const ps_bc *bc, int ib,
                       const ps_mesh_sets *sets, unsigned char *in_set, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  const ps_mesh_set *s = sets ? ps_mesh_set_find(sets, bc->sel.set) : NULL;
  if (!s) {
    char names[1024];
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s:%d: loading.boundary entry %d: no set '%s' in %s (its sets: %s)",
                    cs->file, bc->line, ib + 1, bc->sel.set, cs->cloud_file,
                    sets ? ps_mesh_set_names(sets, names, sizeof names) : "none");
  }
  for (const ps_mesh_set *t = s + 1; t < sets->set + sets->n; t++)
    if (!strcmp(t->name, s->name))
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%d: loading.boundary entry %d: '%s' names two sets of %s (a %s "
                      "and a %s): rename one in the mesh",
                      cs->file, bc->line, ib + 1, s->name, cs->cloud_file, s->kind,
                      t->kind);
  memset(in_set, 0, (size_t)pb->P.n);
  for (ps_int i = 0; i < s->n; i++) in_set[s->particle[i]] = 1;
  return PS_OK;
}

/* The particles boundary entry ib selects: selected() with its named
 * set's membership in in_set (filled here; NULL when no entry names a
 * set). */
static int entry_selects(const ps_problem *pb, int ib, const ps_mesh_sets *sets,
                         unsigned char *in_set, ps_ctx *ctx) {
  const ps_bc *bc = &pb->cs.bc[ib];
  if (bc->sel.set[0]) PS_CHECK(set_members(pb, bc, ib, sets, in_set, ctx));
  return PS_OK;
}

/* The named loading.boundary entries and the particles each selects
 * (pb->group_*), for their reactions in history.csv. */
static int setup_groups(ps_problem *pb, const ps_mesh_sets *sets, unsigned char *in_set,
                        ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  const ps_case *cs = &pb->cs;
  int n = 0;
  for (int ib = 0; ib < cs->n_bc; ib++) n += cs->bc[ib].name[0] != '\0';
  if (n == 0) return PS_OK;
  pb->group_bc = ps_calloc((size_t)n, sizeof *pb->group_bc, ctx);
  pb->group_ptr = ps_calloc((size_t)n + 1, sizeof *pb->group_ptr, ctx);
  if (!pb->group_bc || !pb->group_ptr) return PS_ERR_NOMEM;
  for (int ib = 0, g = 0; ib < cs->n_bc; ib++) {
    if (!cs->bc[ib].name[0]) continue;
    const ps_select *sel = &cs->bc[ib].sel;
    PS_CHECK(entry_selects(pb, ib, sets, in_set, ctx));
    pb->group_bc[g] = ib;
    ps_int hits = 0;
    for (ps_int a = 0; a < P->n; a++) hits += selected(P, a, sel, sel->set[0] ? in_set : NULL);
    pb->group_ptr[g + 1] = pb->group_ptr[g] + hits;
    g++;
  }
  pb->group_particle =
      ps_calloc((size_t)pb->group_ptr[n] + 1, sizeof *pb->group_particle, ctx);
  if (!pb->group_particle) return PS_ERR_NOMEM;
  for (int g = 0; g < n; g++) {
    ps_int j = pb->group_ptr[g];
    const ps_select *sel = &cs->bc[pb->group_bc[g]].sel;
    PS_CHECK(entry_selects(pb, pb->group_bc[g], sets, in_set, ctx));
    for (ps_int a = 0; a < P->n; a++)
      if (selected(P, a, sel, sel->set[0] ? in_set : NULL)) pb->group_particle[j++] = a;
  }
  pb->n_groups = n;
  return PS_OK;
}

/* The thickness h of the layer of particles that boundary entry ib
 * selects (in_set as setup_bc's), across its edge: a traction t is
 * applied as the body force t / h, so that the layer carries t times the
 * edge's length. On a square or cubic lattice a layer one spacing thick
 * has h = spacing. On the hex lattice rows are dy = sqrt(3)/2 d apart
 * and each row's particles d apart: a layer along a horizontal edge
 * (wider in x than in y) of n_rows rows has h = n_rows dy, one along a
 * vertical edge holding n particles in n_rows rows has h = (n / n_rows)
 * d (d for one particle per row). Rows are counted by their lattice
 * index (jitter moves a particle by less than half a row). Returns
 * PS_OK (*h set) or PS_ERR_NOMEM. */
static int layer_thickness(const ps_problem *pb, int ib, const unsigned char *in_set, double *h,
                           ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  const ps_case *cs = &pb->cs;
  *h = cs->spacing;
  if (cs->geometry != PS_GEOM_BOX || P->dim != 2 || strcmp(cs->lattice, "hex") != 0)
    return PS_OK;
  const ps_select *sel = &cs->bc[ib].sel;
  const double d = cs->spacing, dy = ps_geom_row_spacing(cs->lattice, d);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  ps_int n = 0, n_rows = 0;
  unsigned char *row = ps_calloc((size_t)cs->counts[1], 1, ctx);
  if (!row) return PS_ERR_NOMEM;
  for (ps_int a = 0; a < P->n; a++) {
    if (!selected(P, a, sel, sel->set[0] ? in_set : NULL)) continue;
    n++;
    for (int k = 0; k < 2; k++) {
      lo[k] = fmin(lo[k], P->x[2 * a + k]);
      hi[k] = fmax(hi[k], P->x[2 * a + k]);
    }
    long j = lround((P->x[2 * a + 1] - cs->origin[1]) / dy - 0.5);
    j = j < 0 ? 0 : j >= (long)cs->counts[1] ? (long)cs->counts[1] - 1 : j;
    n_rows += !row[j];
    row[j] = 1;
  }
  free(row);
  if (n == 0) return PS_OK;
  if (hi[0] - lo[0] >= hi[1] - lo[1])
    *h = (double)n_rows * dy; /* along a horizontal edge */
  else
    *h = d * ((double)n / (double)n_rows); /* along a vertical edge */
  return PS_OK;
}

/* Boundary entry ib of the case on the particles it selects (in_set:
 * room for a named set's membership, NULL when no entry names one);
 * *measure_dir: the first measured component. */
static int setup_bc(ps_problem *pb, int ib, const ps_mesh_sets *sets, unsigned char *in_set,
                    int *measure_dir, ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  const ps_case *cs = &pb->cs;
  const ps_bc *bc = &cs->bc[ib];
  int d = P->dim;
  PS_CHECK(entry_selects(pb, ib, sets, in_set, ctx));
  int loads = 0; /* a traction: it needs the layer's thickness h */
  for (int k = 0; k < d; k++) loads |= bc->traction_set[k] && bc->traction[k] != 0.0;
  double h = cs->spacing;
  if (loads) PS_CHECK(layer_thickness(pb, ib, in_set, &h, ctx));
  ps_int hits = 0;
  for (ps_int a = 0; a < P->n; a++) {
    if (!selected(P, a, &bc->sel, bc->sel.set[0] ? in_set : NULL)) continue;
    hits++;
    for (int k = 0; k < d; k++) {
      if (bc->fix[k]) {
        pb->fixed[a * d + k] = 1;
        pb->ubar[a * d + k] = 0.0;
      }
      if (bc->traction_set[k] && bc->traction[k] != 0.0) {
        if (!pb->fext) {
          pb->fext = ps_calloc((size_t)d * P->n, sizeof *pb->fext, ctx);
          if (!pb->fext) return PS_ERR_NOMEM;
        }
        /* body force traction / thickness over the selected layer */
        pb->fext[a * d + k] += bc->traction[k] * P->volume[a] / h;
      }
      if (bc->displace_set[k]) {
        pb->fixed[a * d + k] = 1;
        pb->ubar[a * d + k] = ps_bc_displacement(bc, k, &P->x[a * d], d);
        if (!isfinite(pb->ubar[a * d + k]))
          return ps_error(ctx, PS_ERR_INPUT,
                          "%s:%d: loading.boundary entry %d: the displacement field of "
                          "component %c is not finite at particle %lld",
                          cs->file, bc->line, ib + 1, 'x' + k, (long long)a);
        if (bc->measure) { /* the direction: the sign of the constant part */
          pb->measure[a * d + k] = bc->displace[k] >= 0 ? 1.0 : -1.0;
          if (*measure_dir < 0) *measure_dir = k;
        }
      }
    }
  }
  if (hits == 0)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s:%d: loading.boundary entry %d selects no particle", cs->file,
                    bc->line, ib + 1);
  if (bc->measure) {
    int any = 0;
    for (int k = 0; k < d; k++) any |= bc->displace_set[k];
    if (!any)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%d: measure: true needs a displaced component", cs->file,
                      bc->line);
  }
  return PS_OK;
}

static int setup_boundary(ps_problem *pb, const ps_mesh_sets *sets, ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  const ps_case *cs = &pb->cs;
  int d = P->dim, measure_dir = -1, status = PS_OK;
  unsigned char *in_set = NULL;
  for (int ib = 0; ib < cs->n_bc; ib++)
    if (cs->bc[ib].sel.set[0] && !in_set) {
      in_set = ps_calloc((size_t)P->n, 1, ctx);
      if (!in_set) return PS_ERR_NOMEM;
    }
  for (int ib = 0; ib < cs->n_bc && status == PS_OK; ib++)
    status = setup_bc(pb, ib, sets, in_set, &measure_dir, ctx);
  if (status == PS_OK) status = setup_groups(pb, sets, in_set, ctx);
  free(in_set);
  PS_CHECK(status);
  int loaded = 0;
  for (ps_int j = 0; j < (ps_int)d * P->n; j++) {
    if (pb->fext && pb->fixed[j]) pb->fext[j] = 0.0; /* a support takes it */
    loaded |= pb->ubar[j] != 0.0 || (pb->fext && pb->fext[j] != 0.0);
  }
  if (!loaded)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: nothing loads the model: no loading.boundary entry displaces "
                    "a particle (displace: {x: ...}) or applies a traction",
                    cs->file);
  if (cs->stress_length > 0) {
    pb->measure_length = cs->stress_length;
  } else if (measure_dir >= 0) {
    /* the cross-section normal to the measured direction, from the
     * bounding box widened by one particle spacing */
    double len = 1.0;
    for (int k = 0; k < d; k++) {
      if (k == measure_dir) continue;
      double lo = INFINITY, hi = -INFINITY, hmean = 0;
      for (ps_int a = 0; a < P->n; a++) {
        lo = fmin(lo, P->x[a * d + k]);
        hi = fmax(hi, P->x[a * d + k]);
        hmean += pow(P->volume[a], 1.0 / d) / P->n;
      }
      len *= hi - lo + hmean;
    }
    pb->measure_length = len;
  }
  return PS_OK;
}

/* Prefix an input error of geometry, sizes or network (which name the
 * particle, not the case) with the case file. Returns status. */
static int in_case(ps_ctx *ctx, int status, const char *path) {
  if (status != PS_ERR_INPUT) return status;
  char m[sizeof ctx->msg];
  snprintf(m, sizeof m, "%s", ctx->msg);
  return ps_error(ctx, status, "%s: %s", path, m);
}

/* The particles a caller gave (positions, volumes, blocks) into *p. */
static int copy_given(ps_particles *p, const ps_particles *g, ps_ctx *ctx) {
  PS_CHECK(ps_particles_alloc(p, g->dim, g->n, ctx));
  memcpy(p->x, g->x, sizeof *p->x * (size_t)g->dim * (size_t)g->n);
  memcpy(p->volume, g->volume, sizeof *p->volume * (size_t)g->n);
  if (g->block) memcpy(p->block, g->block, sizeof *p->block * (size_t)g->n);
  return PS_OK;
}

/* 2D: arms across a hole cross its inscribed polygon of this many sides */
enum { HOLE_SIDES = 64 };

/* The holes of a box or a cloud: the particles inside removed, and the
 * cracks that keep arms from crossing them added to cracks[*n_cracks..]:
 * in 2D the HOLE_SIDES segments of each circle's inscribed polygon, in 3D
 * each sphere itself (ps_crack_cuts: closest distance below R). */
static int add_holes(ps_problem *pb, const ps_case *cs, int dim, ps_crack *cracks,
                     int *n_cracks, ps_ctx *ctx) {
  if (cs->n_holes == 0) return PS_OK;
  PS_CHECK(in_case(ctx, ps_geom_cut_holes(&pb->P, (const double(*)[4])cs->holes,
                                          cs->n_holes, ctx), cs->file));
  for (int i = 0; i < cs->n_holes; i++) {
    const double *h = cs->holes[i];
    if (dim == 3) {
      ps_crack_sphere(&cracks[(*n_cracks)++], h, h[3]);
      continue;
    }
    for (int j = 0; j < HOLE_SIDES; j++, ++*n_cracks) {
      double t0 = 2 * M_PI * j / HOLE_SIDES, t1 = 2 * M_PI * (j + 1) / HOLE_SIDES;
      cracks[*n_cracks].p0[0] = h[0] + h[2] * cos(t0);
      cracks[*n_cracks].p0[1] = h[1] + h[2] * sin(t0);
      cracks[*n_cracks].p1[0] = h[0] + h[2] * cos(t1);
      cracks[*n_cracks].p1[1] = h[1] + h[2] * sin(t1);
    }
  }
  return PS_OK;
}

/* The particles of the case (disk, box or cloud with holes, or mesh), the
 * cracks the geometry adds (the disk's, the holes') and a mesh's named
 * sets (*sets, zeroed for the other types). */
static int make_particles(ps_problem *pb, const ps_case *cs, int dim, ps_crack *cracks,
                          int *n_cracks, ps_mesh_sets *sets, ps_ctx *ctx) {
  switch (cs->geometry) {
  case PS_GEOM_DISK:
    PS_CHECK(in_case(ctx, ps_geom_disk(&pb->P, &cs->disk, ctx), cs->file));
    pb->c = cs->disk.c;
    memset(&cracks[*n_cracks], 0, sizeof cracks[0]);
    cracks[*n_cracks].p0[0] = -pb->c; /* the crack between the foci */
    cracks[*n_cracks].p1[0] = pb->c;
    ++*n_cracks;
    break;
  case PS_GEOM_BOX:
    PS_CHECK(in_case(ctx, ps_geom_box(&pb->P, dim, cs->counts, cs->spacing, cs->lattice,
                                      cs->jitter, cs->seed, ctx), cs->file));
    for (ps_int a = 0; a < pb->P.n; a++)
      for (int k = 0; k < dim; k++) pb->P.x[a * dim + k] += cs->origin[k];
    PS_CHECK(add_holes(pb, cs, dim, cracks, n_cracks, ctx));
    break;
  case PS_GEOM_CLOUD: /* its errors name the cloud file and line */
    if (cs->given_particles)
      PS_CHECK(copy_given(&pb->P, cs->given_particles, ctx));
    else
      PS_CHECK(ps_cloud_read(&pb->P, cs->cloud_file, dim, ctx));
    PS_CHECK(add_holes(pb, cs, dim, cracks, n_cracks, ctx));
    break;
  case PS_GEOM_MESH: /* its errors name the mesh file (and element) */
    PS_CHECK(ps_mesh_read(&pb->P, sets, cs->cloud_file, cs->mesh_format, dim, ctx));
    break;
  default:
    return ps_error(ctx, PS_ERR_INPUT, "%s: unknown geometry type", cs->file);
  }
  return in_case(ctx, ps_particles_check(&pb->P, ctx), cs->file);
}

/* What a run of the case builds, for the estimate. */
static ps_estimate_opts estimate_opts(const ps_case *cs, double free_fraction) {
  const ps_model_type *type = ps_model_type_find(cs->model);
  ps_estimate_opts o;
  o.family_coupling = type ? type->family_coupling : 1;
  o.majorant = cs->solver.majorant && o.family_coupling && cs->solver.reuse_factor &&
               cs->mat.plastic;
  o.single_precision = cs->solver.cg_single_precision;
  o.lu = !strcmp(cs->solver.linear, "umfpack");
  o.iterative = !strcmp(cs->solver.linear, "petsc") &&
                !ps_petsc_options_factor(cs->solver.petsc_options);
  o.ranks = ps_parallel_size();
  o.free_fraction = free_fraction;
  /* per arm: a critical stretch when arms break by a criterion (8); the
   * three-body model's rotations, moments and their gradients (64) */
  o.arm_bytes = (cs->mat.fracture != PS_FRACTURE_NONE ? 8.0 : 0.0) +
                (type && type->rotations ? 64.0 : 0.0);
  return o;
}

/* Stage 1 of the estimate, from the case alone: the particle count (box:
 * product of the counts, holes ignored; disk: n_eta n_xi per_zone^2) and
 * the particles a horizon holds: Eq. 44 sizes make the horizon alpha h
 * hold alpha^N particle volumes (Eq. 115 sizes ~0.92 of that in 2D, ~0.52
 * in 3D on lattices); the lattice models' horizon of m spacings pi m^2
 * cells (3D: 4/3 pi m^3). Refuses, before anything is allocated, a case
 * whose particles and network alone exceed the memory limit. */
static int estimate_counts(const ps_case *cs, int dim, int lattice, double reach,
                           int purpose, ps_ctx *ctx) {
  double n = 1, nb;
  if (purpose == PS_ESTIMATE_NONE || cs->geometry == PS_GEOM_CLOUD ||
      cs->geometry == PS_GEOM_MESH)
    return PS_OK;
  if (lattice && !(reach > 0)) return PS_OK; /* not known before the particles */
  if (cs->geometry == PS_GEOM_DISK)
    n = ps_geom_disk_count(&cs->disk);
  else
    for (int k = 0; k < dim; k++) n *= (double)cs->counts[k];
  if (lattice) {
    double cell = ps_geom_row_spacing(cs->lattice, 1.0);
    nb = (dim == 2 ? M_PI * reach * reach : 4.0 / 3.0 * M_PI * pow(reach, 3)) / cell;
  } else {
    double f = cs->size_rule == PS_SIZE_EQ44 ? 1.0 : dim == 2 ? 0.92 : 0.52;
    nb = f * pow(cs->alpha, dim);
  }
  ps_estimate e;
  ps_estimate_opts o = estimate_opts(cs, 1.0);
  ps_estimate_density(&e, dim, n, nb, &o);
  return ps_estimate_check(&e, e.mem_particles + e.mem_network, cs->max_memory_gib,
                           cs->max_memory_key, cs->file,
                           "building its particles and arms", ctx);
}

/* Stage 2, with the particles, sizes and supports, before the network:
 * print it to report (info) and refuse a case beyond the limit for its
 * purpose (`jobs` runs at once share the particles and the network). */
static int estimate_sampled(ps_problem *pb, const ps_case *cs, double alpha,
                            const ps_crack *cracks, int n_cracks, int purpose, int jobs,
                            FILE *report, ps_ctx *ctx) {
  if (purpose == PS_ESTIMATE_NONE) return PS_OK;
  ps_int nd = (ps_int)pb->P.dim * pb->P.n, nfree = 0;
  for (ps_int j = 0; j < nd; j++) nfree += !pb->fixed[j];
  ps_estimate_opts o = estimate_opts(cs, nd > 0 ? (double)nfree / (double)nd : 1.0);
  ps_estimate e;
  PS_CHECK(ps_estimate_sample(&e, &pb->P, alpha, cracks, n_cracks, &o, ctx));
  const char *lw;
  double limit = ps_memory_limit(cs->max_memory_gib, cs->max_memory_key, &lw);
  if (report) {
    ps_estimate_print(&e, report);
    fprintf(report, "memory_limit_MiB: %.0f (%s)\n", floor(limit / 1048576.0), lw);
    fflush(report);
  }
  if (purpose == PS_ESTIMATE_INFO)
    return ps_estimate_check(&e, e.mem_build, cs->max_memory_gib, cs->max_memory_key,
                             cs->file, "info (particles, arms and the tangent's pattern)", ctx);
  if (jobs < 1) jobs = 1;
  double need = e.mem_particles + jobs * (e.mem_run - e.mem_particles);
  char what[64];
  snprintf(what, sizeof what, jobs > 1 ? "%d runs at once" : "a run", jobs);
  return ps_estimate_check(&e, need, cs->max_memory_gib, cs->max_memory_key, cs->file,
                           what, ctx);
}

/* The horizon models (bond, state; type->lattice): their horizon delta,
 * the cell size of their partial volumes (ps_material.spacing), every
 * particle's size h and the kernel's alpha, so that the network's rule r
 * < alpha max(h_a, h_b) = alpha h is the model's reach:
 *  - a box lattice of spacing d: h = d, delta = m d with m =
 *    material.horizon_factor (or material.horizon / d when the horizon is
 *    given as a length: then delta is that length), alpha =
 *    ps_model_lattice_reach(m) spacings, cell size d: the arms and
 *    constants of the lattice models as they were before clouds;
 *  - a point cloud, a mesh or the disk: h = hm, the mean spacing (sum V / n)^(1/N)
 *    (ps_mean_spacing: the side of the mean particle's square or cube),
 *    delta = material.horizon, or material.horizon_factor hm, alpha =
 *    ps_model_cloud_reach / hm (the reach in metres: with partial volumes
 *    it covers the largest cell, V^(1/N)), cell size 0: each particle's
 *    own, V^(1/N) (ps_cell_size).
 * Sets pb->P.h, *alpha, *delta, *dx. */
static int horizon_setup(ps_problem *pb, const ps_case *cs, const ps_model_type *type,
                         double *alpha, double *delta, double *dx, ps_ctx *ctx) {
  ps_particles *P = &pb->P;
  double h;
  if (cs->geometry == PS_GEOM_BOX) {
    h = *dx = cs->spacing;
    if (cs->mat.horizon > 0) {
      *delta = cs->mat.horizon;
      *alpha = ps_model_lattice_reach(type, *delta / cs->spacing);
    } else {
      *delta = cs->horizon_factor * cs->spacing;
      *alpha = ps_model_lattice_reach(type, cs->horizon_factor);
    }
  } else {
    h = ps_mean_spacing(P);
    *delta = cs->mat.horizon > 0 ? cs->mat.horizon : cs->horizon_factor * h;
    *dx = 0.0;
    double dx_max = 0.0;
    ps_material m = cs->mat;
    m.horizon = *delta;
    m.spacing = 0.0;
    for (ps_int a = 0; a < P->n; a++) dx_max = fmax(dx_max, ps_cell_size(&m, P, a));
    *alpha = ps_model_cloud_reach(type, &m, dx_max) / h;
  }
  if (!(*delta > 0) || !isfinite(*delta) || !(h > 0) || !isfinite(*alpha))
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: material.model %s: the horizon %g m (mean spacing %g m) is not a "
                    "finite length > 0", cs->file, cs->model, *delta, h);
  for (ps_int a = 0; a < P->n; a++) P->h[a] = h;
  return PS_OK;
}

/* A horizon model needs every particle held: at least N - (its prescribed
 * components) neighbours within the horizon delta (1 + 1e-9) (arms that
 * carry force in every model), else its displacement is not determined
 * (a singular tangent). The first particle short of them is named, with
 * its cloud file and line, before the network is built (cracks aside:
 * they may cut arms further). */
static int horizon_neighbours_check(const ps_problem *pb, const ps_case *cs, ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  int N = P->dim;
  double delta = pb->mat.horizon;
  ps_kdtree *tree = NULL;
  PS_CHECK(ps_kdtree_build(&tree, P->x, P->n, N, ctx));
  ps_int bad = -1, found = 0;
  int need = 0;
  for (ps_int a = 0; a < P->n && bad < 0; a++) {
    need = N;
    for (int k = 0; k < N; k++) need -= pb->fixed[a * N + k] != 0;
    if (need == 0) continue;
    found = ps_kdtree_count(tree, &P->x[a * N], delta * (1 + 1e-9), need + 1) - 1;
    if (found < need) bad = a;
  }
  ps_kdtree_free(&tree);
  if (bad < 0) return PS_OK;
  char w[1200], at[200];
  return ps_error(ctx, PS_ERR_INPUT,
                  "%s: %s at %s has %lld neighbour%s within the horizon delta = %g m (%s), "
                  "fewer than %d%s: its displacement is not determined. The particles are "
                  "too sparse for the horizon: raise it",
                  cs->file, ps_particle_where(P, bad, w, sizeof w),
                  ps_particle_at(P, bad, at, sizeof at), (long long)found,
                  found == 1 ? "" : "s", delta,
                  cs->mat.horizon > 0 ? "material.horizon" : "material.horizon_factor", need,
                  need < N ? " (its other components are prescribed)" : "");
}

/* The material, the load factor's delta and the boundary conditions;
 * the horizon models' horizon delta and cell size dx (horizon_setup). */
static int setup_loading(ps_problem *pb, const ps_case *cs, int dim, int lattice,
                         double delta, double dx, const ps_mesh_sets *sets, ps_ctx *ctx) {
  pb->mat = cs->mat;
  if (lattice) {
    pb->mat.horizon = delta;
    pb->mat.spacing = dx;
  }
  if (cs->delta_over_c > 0 && pb->c > 0) pb->mat.delta = cs->delta_over_c * pb->c;
  /* the horizon models break by material.fracture, never by delta (Eq.
   * 118: the fibre model's; a disk sets it from delta_over_c) */
  if (lattice) pb->mat.delta = INFINITY;
  if (!(pb->mat.delta > 0)) pb->mat.delta = INFINITY;
  if (ps_material_finish(&pb->mat, dim, ctx) < 0) return in_case(ctx, PS_ERR_INPUT, cs->file);
  ps_int nd = (ps_int)dim * pb->P.n;
  pb->fixed = ps_calloc((size_t)nd, 1, ctx);
  pb->ubar = ps_calloc((size_t)nd, sizeof *pb->ubar, ctx);
  pb->measure = ps_calloc((size_t)nd, sizeof *pb->measure, ctx);
  if (!pb->fixed || !pb->ubar || !pb->measure) return PS_ERR_NOMEM;
  if (cs->load_type == PS_LOAD_EQ116) {
    if (cs->geometry != PS_GEOM_DISK)
      return ps_error(ctx, PS_ERR_INPUT, "%s: loading.type eq116 needs geometry.type disk",
                      cs->file);
    return setup_eq116(pb, ctx);
  }
  return setup_boundary(pb, sets, ctx);
}

int ps_problem_setup(ps_problem *pb, const ps_case *cs, ps_ctx *ctx) {
  return ps_problem_setup_sized(pb, cs, PS_ESTIMATE_RUN, 1, NULL, ctx);
}

int ps_problem_setup_sized(ps_problem *pb, const ps_case *cs, int purpose, int jobs,
                           FILE *report, ps_ctx *ctx) {
  PS_CHECK(ps_problem_setup_cloud(pb, cs, purpose, jobs, report, ctx));
  int status = ps_problem_setup_network(pb, ctx);
  if (status < 0) ps_problem_free(pb);
  return status;
}

int ps_problem_setup_network(ps_problem *pb, ps_ctx *ctx) {
  double t0 = ps_wtime();
  PS_CHECK(in_case(ctx, ps_network_build(&pb->net, &pb->P, &pb->kernel, pb->cracks,
                                         pb->n_cracks, ctx), pb->cs.file));
  pb->t_network += ps_wtime() - t0;
  return PS_OK;
}

int ps_problem_setup_cloud(ps_problem *pb, const ps_case *cs, int purpose, int jobs,
                           FILE *report, ps_ctx *ctx) {
  int status = PS_OK;
  double t0 = ps_wtime();
  ps_crack *cracks = NULL;
  ps_mesh_sets sets = {0, NULL}; /* a mesh's named sets, for the supports */
  memset(pb, 0, sizeof *pb);
  /* the horizon models (bond, state): arms within the horizon delta (and
   * the model's reach beyond it), horizon_setup */
  const ps_model_type *type = ps_model_type_find(cs->model);
  if (!type)
    return ps_error(ctx, PS_ERR_INPUT, "%s: unknown material.model %s", cs->file, cs->model);
  int lattice = type->lattice;
  /* stage 1's reach in spacings: a box's; the disk's in mean spacings
   * when the horizon is a factor of them (the largest cell aside), else
   * not known before the particles (0) */
  double reach = 0.0, delta = 0.0, dx = 0.0;
  if (cs->geometry == PS_GEOM_BOX && cs->mat.horizon > 0)
    reach = ps_model_lattice_reach(type, cs->mat.horizon / cs->spacing);
  else if (cs->geometry == PS_GEOM_BOX || !(cs->mat.horizon > 0))
    reach = ps_model_lattice_reach(type, cs->horizon_factor);
  int dim = cs->geometry == PS_GEOM_DISK ? 2 : cs->dim;
  PS_CHECK(estimate_counts(cs, dim, lattice, reach, purpose, ctx));
  PS_CHECK(ps_case_copy(&pb->cs, cs, ctx)); /* pb owns its copy: ps_problem_free */
  cracks = ps_calloc((size_t)(cs->n_cracks + 1 + HOLE_SIDES * cs->n_holes), sizeof *cracks,
                     ctx);
  if (!cracks) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  int n_cracks = cs->n_cracks;
  memcpy(cracks, cs->cracks, sizeof(ps_crack) * (size_t)cs->n_cracks);
  PS_CHECK_GOTO(make_particles(pb, cs, dim, cracks, &n_cracks, &sets, ctx));
  double alpha = cs->alpha;
  if (lattice) { /* uniform h, alpha = the reach in h */
    PS_CHECK_GOTO(horizon_setup(pb, cs, type, &alpha, &delta, &dx, ctx));
  } else if (cs->size_rule == PS_SIZE_EQ44) {
    ps_geom_sizes_eq44(&pb->P);
  } else {
    PS_CHECK_GOTO(in_case(ctx, ps_geom_sizes_eq115(&pb->P, cs->size_neighbours, ctx),
                          cs->file));
  }
  PS_CHECK_GOTO(in_case(ctx, ps_kernel_init(&pb->kernel, dim, cs->kernel_k, alpha, ctx),
                        cs->file));
  /* the supports before the network: the estimate counts the free dofs */
  PS_CHECK_GOTO(setup_loading(pb, cs, dim, lattice, delta, dx, &sets, ctx));
  if (lattice) PS_CHECK_GOTO(horizon_neighbours_check(pb, cs, ctx));
  PS_CHECK_GOTO(estimate_sampled(pb, cs, alpha, cracks, n_cracks, purpose, jobs, report,
                                 ctx));
  pb->t_network = ps_wtime() - t0;
  pb->cracks = cracks;
  pb->n_cracks = n_cracks;
  cracks = NULL;
cleanup:
  free(cracks);
  ps_mesh_sets_free(&sets);
  if (status < 0) ps_problem_free(pb);
  return status;
}
