/* setup.c: from a case to a problem: particle cloud (disk, box or point
 * file), sizes (Eq. 115 or Eq. 44), arm network, material, and the
 * boundary conditions with the boundary-stress measure. */
#include "ps_app.h"

#include <gsl/gsl_math.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ps_problem_free(ps_problem *pb) {
  ps_network_free(&pb->net);
  ps_particles_free(&pb->P);
  free(pb->fixed);
  free(pb->ubar);
  free(pb->measure);
  free(pb->fext);
  memset(pb, 0, sizeof *pb);
}

static int selected(const ps_particles *P, ps_int a, const ps_select *s) {
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
                    pb->cs.path);
  return PS_OK;
}

static int setup_boundary(ps_problem *pb, ps_ctx *ctx) {
  const ps_particles *P = &pb->P;
  const ps_case *cs = &pb->cs;
  int d = P->dim, measure_dir = -1;
  for (int ib = 0; ib < cs->n_bc; ib++) {
    const ps_bc *bc = &cs->bc[ib];
    ps_int hits = 0;
    for (ps_int a = 0; a < P->n; a++) {
      if (!selected(P, a, &bc->sel)) continue;
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
          /* body force traction / layer over the selected layer */
          pb->fext[a * d + k] += bc->traction[k] * P->volume[a] / cs->spacing;
        }
        if (bc->displace_set[k]) {
          pb->fixed[a * d + k] = 1;
          pb->ubar[a * d + k] = bc->displace[k];
          if (bc->measure) {
            pb->measure[a * d + k] = bc->displace[k] >= 0 ? 1.0 : -1.0;
            if (measure_dir < 0) measure_dir = k;
          }
        }
      }
    }
    if (hits == 0)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%d: loading.boundary entry %d selects no particle", cs->path,
                      bc->line, ib + 1);
    if (bc->measure) {
      int any = 0;
      for (int k = 0; k < d; k++) any |= bc->displace_set[k];
      if (!any)
        return ps_error(ctx, PS_ERR_INPUT,
                        "%s:%d: measure: true needs a displaced component", cs->path,
                        bc->line);
    }
  }
  int loaded = 0;
  for (ps_int j = 0; j < (ps_int)d * P->n; j++) {
    if (pb->fext && pb->fixed[j]) pb->fext[j] = 0.0; /* a support takes it */
    loaded |= pb->ubar[j] != 0.0 || (pb->fext && pb->fext[j] != 0.0);
  }
  if (!loaded)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: nothing loads the model: no loading.boundary entry displaces "
                    "a particle (displace: {x: ...}) or applies a traction",
                    cs->path);
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

int ps_problem_setup(ps_problem *pb, const ps_case *cs, ps_ctx *ctx) {
  int status = PS_OK;
  double t0 = ps_wtime();
  memset(pb, 0, sizeof *pb);
  pb->cs = *cs;
  enum { HOLE_SIDES = 64 }; /* arms across a hole cross its inscribed polygon */
  ps_crack *cracks = ps_calloc((size_t)(cs->n_cracks + 1 + HOLE_SIDES * cs->n_holes),
                               sizeof *cracks, ctx);
  if (!cracks) return PS_ERR_NOMEM;
  int n_cracks = cs->n_cracks;
  memcpy(cracks, cs->cracks, sizeof(ps_crack) * (size_t)cs->n_cracks);
  /* the lattice models (bond, state): arms within the horizon delta = m
   * spacing (state: and the half spacing of partial volumes beyond it) */
  int lattice = strcmp(cs->model, "fibre") != 0;
  double reach = !strcmp(cs->model, "state") ? cs->horizon_factor + 0.5 * (1 - 1e-9)
                                              : cs->horizon_factor * (1 + 1e-9);
  int dim = cs->geometry == PS_GEOM_DISK ? 2 : cs->dim;
  switch (cs->geometry) {
  case PS_GEOM_DISK:
    PS_CHECK_GOTO(ps_geom_disk(&pb->P, &cs->disk, ctx));
    pb->c = cs->disk.c;
    memset(&cracks[n_cracks], 0, sizeof cracks[0]);
    cracks[n_cracks].p0[0] = -pb->c; /* the crack between the foci */
    cracks[n_cracks].p1[0] = pb->c;
    n_cracks++;
    break;
  case PS_GEOM_BOX:
    PS_CHECK_GOTO(ps_geom_box(&pb->P, dim, cs->counts, cs->spacing, cs->lattice,
                              cs->jitter, cs->seed, ctx));
    for (ps_int a = 0; a < pb->P.n; a++)
      for (int k = 0; k < dim; k++) pb->P.x[a * dim + k] += cs->origin[k];
    PS_CHECK_GOTO(ps_geom_cut_holes(&pb->P, (const double(*)[3])cs->holes, cs->n_holes,
                                    ctx));
    for (int i = 0; i < cs->n_holes; i++)
      for (int j = 0; j < HOLE_SIDES; j++, n_cracks++) {
        double t0 = 2 * M_PI * j / HOLE_SIDES, t1 = 2 * M_PI * (j + 1) / HOLE_SIDES;
        const double *h = cs->holes[i];
        cracks[n_cracks].p0[0] = h[0] + h[2] * cos(t0);
        cracks[n_cracks].p0[1] = h[1] + h[2] * sin(t0);
        cracks[n_cracks].p1[0] = h[0] + h[2] * cos(t1);
        cracks[n_cracks].p1[1] = h[1] + h[2] * sin(t1);
      }
    break;
  case PS_GEOM_CLOUD:
    PS_CHECK_GOTO(ps_cloud_read(&pb->P, cs->cloud_file, dim, ctx));
    break;
  default:
    status = ps_error(ctx, PS_ERR_INPUT, "%s: unknown geometry type", cs->path);
    goto cleanup;
  }
  double alpha = cs->alpha;
  if (lattice) { /* h = spacing, alpha = reach */
    for (ps_int a = 0; a < pb->P.n; a++) pb->P.h[a] = cs->spacing;
    alpha = reach;
  } else if (cs->size_rule == PS_SIZE_EQ44) {
    ps_geom_sizes_eq44(&pb->P);
  } else {
    PS_CHECK_GOTO(ps_geom_sizes_eq115(&pb->P, cs->size_neighbours, ctx));
  }
  PS_CHECK_GOTO(ps_kernel_init(&pb->kernel, dim, cs->kernel_k, alpha, ctx));
  PS_CHECK_GOTO(ps_network_build(&pb->net, &pb->P, &pb->kernel, cracks, n_cracks, ctx));
  pb->t_network = ps_wtime() - t0;

  pb->mat = cs->mat;
  if (lattice) {
    pb->mat.horizon = cs->horizon_factor * cs->spacing;
    pb->mat.spacing = cs->spacing;
  }
  if (cs->delta_over_c > 0 && pb->c > 0) pb->mat.delta = cs->delta_over_c * pb->c;
  if (!(pb->mat.delta > 0)) pb->mat.delta = INFINITY;
  if (ps_material_finish(&pb->mat, dim, ctx) < 0) {
    char m[sizeof ctx->msg];
    snprintf(m, sizeof m, "%s", ctx->msg);
    status = ps_error(ctx, PS_ERR_INPUT, "%s: %s", cs->path, m);
    goto cleanup;
  }
  ps_int nd = (ps_int)dim * pb->P.n;
  pb->fixed = ps_calloc((size_t)nd, 1, ctx);
  pb->ubar = ps_calloc((size_t)nd, sizeof *pb->ubar, ctx);
  pb->measure = ps_calloc((size_t)nd, sizeof *pb->measure, ctx);
  if (!pb->fixed || !pb->ubar || !pb->measure) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  if (cs->load_type == PS_LOAD_EQ116) {
    if (cs->geometry != PS_GEOM_DISK) {
      status = ps_error(ctx, PS_ERR_INPUT,
                        "%s: loading.type eq116 needs geometry.type disk", cs->path);
      goto cleanup;
    }
    PS_CHECK_GOTO(setup_eq116(pb, ctx));
  } else {
    PS_CHECK_GOTO(setup_boundary(pb, ctx));
  }
cleanup:
  free(cracks);
  if (status < 0) ps_problem_free(pb);
  return status;
}
