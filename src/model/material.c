/* material.c: parameter checks, derived moduli (Eq. 78-81), arm state and
 * tangent storage, model lookup. */
#include "ps_model.h"
#include "ps_moduli.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The derived moduli of ps_material_finish must be finite and positive
 * (they are for every E and nu in range; this guards callers that bypass
 * the case file's checks). */
static int check_derived(const ps_material *m, ps_ctx *ctx) {
  if (!(isfinite(m->G) && m->G > 0 && isfinite(m->K) && m->K > 0 && isfinite(m->kappa)))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.E = %g with material.nu = %g gives the moduli G = %g, K = "
                    "%g: not finite positive numbers", m->E, m->nu, m->G, m->K);
  if (!(isfinite(m->sigma_y) && m->sigma_y >= DBL_MIN))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.E x material.yield_strain = %g x %g gives the yield stress "
                    "sigma_y = %g: not a finite positive number", m->E, m->yield_strain,
                    m->sigma_y);
  return PS_OK;
}

int ps_material_finish(ps_material *m, int dim, ps_ctx *ctx) {
  if (!(m->E > 0) || !isfinite(m->E))
    return ps_error(ctx, PS_ERR_INPUT, "material.E must be > 0 (got %g)", m->E);
  if (m->E < PS_E_MIN || m->E > PS_E_MAX)
    return ps_error(ctx, PS_ERR_INPUT, "material.E must be in [%g, %g] Pa (got %g)",
                    PS_E_MIN, PS_E_MAX, m->E);
  if (!(m->nu > -1.0 && m->nu < 0.5))
    return ps_error(ctx, PS_ERR_INPUT, "material.nu must be in (-1, 0.5) (got %g)",
                    m->nu);
  if (m->plastic && !(m->yield_strain > 0))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.yield_strain must be > 0 (got %g)", m->yield_strain);
  if (m->plastic &&
      (m->yield_strain < PS_YIELD_STRAIN_MIN || m->yield_strain > PS_YIELD_STRAIN_MAX))
    return ps_error(ctx, PS_ERR_INPUT, "material.yield_strain must be in [%g, %g] (got %g)",
                    PS_YIELD_STRAIN_MIN, PS_YIELD_STRAIN_MAX, m->yield_strain);
  if (!(m->rho > 0) || !isfinite(m->rho))
    return ps_error(ctx, PS_ERR_INPUT, "material.rho must be > 0 (got %g)", m->rho);
  if (dim == 3 && m->plane != PS_SOLID_3D) m->plane = PS_SOLID_3D;
  if (dim == 2 && m->plane == PS_SOLID_3D)
    return ps_error(ctx, PS_ERR_INPUT, "a 2D case needs plane strain or plane stress");
  double E = m->E, nu = m->nu;
  m->G = E / (2.0 * (1.0 + nu)); /* Eq. 78 */
  switch (m->plane) {
  case PS_SOLID_3D:
    m->K = E / (3.0 * (1.0 - 2.0 * nu)); /* Eq. 79 */
    m->kappa = 3.0 - 4.0 * nu;
    break;
  case PS_PLANE_STRESS:
    m->K = E / (2.0 * (1.0 - nu)); /* Eq. 80 */
    m->kappa = (3.0 - nu) / (1.0 + nu);
    break;
  default:
    m->K = E / (2.0 * (1.0 - 2.0 * nu) * (1.0 + nu)); /* Eq. 81 */
    m->kappa = 3.0 - 4.0 * nu;
    break;
  }
  m->sigma_y = E * m->yield_strain;
  return check_derived(m, ctx);
}

int ps_arm_state_alloc(ps_arm_state *st, ps_int n_arm, ps_ctx *ctx) {
  memset(st, 0, sizeof *st);
  st->n_arm = n_arm;
  st->eps_p = ps_calloc((size_t)(2 * n_arm), sizeof *st->eps_p, ctx);
  st->eps_p_trial = ps_calloc((size_t)(2 * n_arm), sizeof *st->eps_p_trial, ctx);
  st->broken = ps_calloc((size_t)n_arm, 1, ctx);
  st->yielding = ps_calloc((size_t)n_arm, 1, ctx);
  st->stretch = ps_calloc((size_t)n_arm, sizeof *st->stretch, ctx);
  if (!st->eps_p || !st->eps_p_trial || !st->broken || !st->yielding || !st->stretch) {
    ps_arm_state_free(st);
    return PS_ERR_NOMEM;
  }
  return PS_OK;
}

void ps_arm_state_free(ps_arm_state *st) {
  free(st->eps_p);
  free(st->eps_p_trial);
  free(st->broken);
  free(st->yielding);
  free(st->stretch);
  memset(st, 0, sizeof *st);
}

void ps_arm_state_copy(ps_arm_state *dst, const ps_arm_state *st) {
  size_t n = (size_t)st->n_arm;
  memcpy(dst->eps_p, st->eps_p, 2 * n * sizeof *st->eps_p);
  memcpy(dst->eps_p_trial, st->eps_p_trial, 2 * n * sizeof *st->eps_p);
  memcpy(dst->broken, st->broken, n);
  memcpy(dst->yielding, st->yielding, n);
  memcpy(dst->stretch, st->stretch, n * sizeof *st->stretch);
  dst->broken_energy = st->broken_energy;
}

int ps_arm_state_list(ps_arm_state *st, const char *prefix, ps_state_list *l, ps_ctx *ctx) {
  size_t n = (size_t)st->n_arm;
  char name[PS_STATE_NAME];
#define PS_ITEM(field, bytes)                                        \
  do {                                                               \
    snprintf(name, sizeof name, "%s%s", prefix, #field);             \
    PS_CHECK(ps_state_add(l, name, st->field, bytes, ctx));          \
  } while (0)
  PS_ITEM(eps_p, 2 * n * sizeof *st->eps_p);
  PS_ITEM(eps_p_trial, 2 * n * sizeof *st->eps_p_trial);
  PS_ITEM(broken, n);
  PS_ITEM(yielding, n);
  PS_ITEM(stretch, n * sizeof *st->stretch);
#undef PS_ITEM
  snprintf(name, sizeof name, "%sbroken_energy", prefix);
  return ps_state_add(l, name, &st->broken_energy, sizeof st->broken_energy, ctx);
}

int ps_arm_tangent_alloc(ps_arm_tangent *t, const ps_network *net, ps_ctx *ctx) {
  memset(t, 0, sizeof *t); /* the rotation arrays (Dr) are the model's to add */
  t->D = ps_calloc((size_t)net->n_arm, sizeof *t->D, ctx);
  t->c = ps_calloc((size_t)net->n_particle, sizeof *t->c, ctx);
  t->w = ps_calloc((size_t)(2 * net->n_arm), sizeof *t->w, ctx);
  t->c2 = ps_calloc((size_t)net->n_particle, sizeof *t->c2, ctx);
  t->w2 = ps_calloc((size_t)(2 * net->n_arm), sizeof *t->w2, ctx);
  if (!t->D || !t->c || !t->w || !t->c2 || !t->w2) {
    ps_arm_tangent_free(t);
    return PS_ERR_NOMEM;
  }
  return PS_OK;
}

void ps_arm_tangent_free(ps_arm_tangent *t) {
  free(t->D);
  free(t->c);
  free(t->w);
  free(t->c2);
  free(t->w2);
  free(t->Dr);
  memset(t, 0, sizeof *t);
}

double ps_arm_plastic_strain(const ps_arm_state *st, ps_int i, int yield_rule) {
  return yield_rule == PS_YIELD_DEVIATORIC ? 0.5 * (st->eps_p[i] + st->eps_p[st->n_arm + i])
                                           : st->eps_p[i];
}

double ps_partial_volume(double xi, double delta, double dx) {
  if (xi <= delta - 0.5 * dx) return 1.0;
  if (xi >= delta + 0.5 * dx) return 0.0;
  return 0.5 + (delta - xi) / dx;
}

double ps_cell_size(const ps_material *mat, const ps_particles *P, ps_int a) {
  if (mat->spacing > 0) return mat->spacing;
  return P->dim == 2 ? sqrt(P->volume[a]) : cbrt(P->volume[a]);
}

void ps_arm_partial_volumes(const ps_material *mat, const ps_particles *P,
                            const ps_network *net, ps_int i, double *va, double *vb) {
  double xi = net->r0[i], delta = mat->horizon;
  if (mat->spacing > 0) { /* a lattice: one cell size */
    *va = *vb = ps_partial_volume(xi, delta, mat->spacing);
    return;
  }
  *va = ps_partial_volume(xi, delta, ps_cell_size(mat, P, net->b[i]));
  *vb = ps_partial_volume(xi, delta, ps_cell_size(mat, P, net->a[i]));
}

double ps_mean_spacing(const ps_particles *P) {
  double V = 0.0;
  for (ps_int a = 0; a < P->n; a++) V += P->volume[a];
  V /= (double)P->n;
  return P->dim == 2 ? sqrt(V) : cbrt(V);
}

int ps_lattice_model_check(const ps_material *mat, int dim, const ps_particles *P,
                           const char *model, ps_ctx *ctx) {
  if (!P)
    return ps_error(ctx, PS_ERR_INPUT, "the %s model needs the particle positions", model);
  if (!(mat->horizon > 0) || !isfinite(mat->horizon))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.model %s needs a horizon > 0 (material.horizon in m or "
                    "material.horizon_factor spacings; got %g m)", model, mat->horizon);
  if (!(mat->spacing >= 0) || !isfinite(mat->spacing))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.model %s: the lattice spacing must be >= 0 (0: cell sizes "
                    "from the particle volumes; got %g)", model, mat->spacing);
  if (mat->plastic)
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.model %s is elastic: set material.plastic: false", model);
  (void)dim;
  return PS_OK;
}

int ps_model_poisson_check(const ps_model_type *type, double nu, int dim, int plane,
                           ps_ctx *ctx) {
  if (!type->fixed_poisson) return PS_OK;
  double nu_fixed = type->fixed_poisson(dim, plane);
  if (fabs(nu - nu_fixed) <= 1e-3) return PS_OK;
  char value[32];
  if (nu_fixed == 1.0 / 3.0)
    snprintf(value, sizeof value, "1/3");
  else if (nu_fixed == 0.25)
    snprintf(value, sizeof value, "1/4");
  else
    snprintf(value, sizeof value, "%g", nu_fixed);
  return ps_error(ctx, PS_ERR_INPUT,
                  "material.nu = %g: %s-based peridynamics has nu = %s in %s (Fallah et al. "
                  "2020, section 5)",
                  nu, type->name, value,
                  dim == 3 ? "3D" : plane == PS_PLANE_STRESS ? "plane stress" : "plane strain");
}

const ps_model_type *ps_model_type_find(const char *name) {
  const ps_model_type *const all[] = {ps_model_fibre, ps_model_bond, ps_model_state,
                                      ps_model_threebody};
  for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
    if (strcmp(all[i]->name, name) == 0) return all[i];
  return NULL;
}

double ps_model_lattice_reach(const ps_model_type *type, double horizon_factor) {
  double e = type->reach_extra_spacings;
  return e > 0 ? horizon_factor + e * (1 - 1e-9) : horizon_factor * (1 + 1e-9);
}

double ps_model_cloud_reach(const ps_model_type *type, const ps_material *mat,
                            double dx_max) {
  double e = type->reach_extra_spacings, delta = mat->horizon;
  return e > 0 && !mat->full_volumes ? delta + e * dx_max * (1 - 1e-9) : delta * (1 + 1e-9);
}

int ps_model_whole_constants(const ps_model_type *type, const ps_material *mat) {
  return ps_moduli_correction_on(mat) && (type == ps_model_fibre || type == ps_model_state);
}

int ps_model_share_horizons(const ps_model_type *type, const ps_material *mat) {
  int h = 1;
  if (type->family_coupling || type->rotations) h++;
  if ((type == ps_model_bond || type == ps_model_threebody) && mat->surface_correction) h++;
  return h;
}

int ps_model_share_constants(const ps_model *whole, const ps_network *net,
                             const ps_int *global, double **arm_k, double **arm_side,
                             ps_ctx *ctx) {
  const ps_network *wn = whole->net;
  const ps_int na = net->n_arm, wa = wn->n_arm;
  *arm_k = *arm_side = NULL;
  if (whole->arm_k && !(*arm_k = ps_calloc((size_t)na + 1, sizeof **arm_k, ctx)))
    return PS_ERR_NOMEM;
  if (whole->arm_side && !(*arm_side = ps_calloc((size_t)(2 * na) + 1, sizeof **arm_side, ctx)))
    return PS_ERR_NOMEM;
  for (ps_int i = 0; i < na; i++) {
    ps_int ga = global[net->a[i]], gb = global[net->b[i]], j = -1;
    for (ps_int k = wn->fam_ptr[ga]; k < wn->fam_ptr[ga + 1] && j < 0; k++) {
      ps_int w = wn->fam_arm[k];
      if ((wn->a[w] == ga && wn->b[w] == gb) || (wn->a[w] == gb && wn->b[w] == ga)) j = w;
    }
    if (j < 0)
      return ps_error(ctx, PS_ERR_INTERNAL, "ps_model_share_constants: the arm of particles "
                      "%lld and %lld is not in the whole network", (long long)ga,
                      (long long)gb);
    if (*arm_k) (*arm_k)[i] = whole->arm_k[j];
    if (*arm_side) { /* sides in the share's orientation */
      int same = wn->a[j] == ga;
      (*arm_side)[i] = whole->arm_side[same ? j : wa + j];
      (*arm_side)[na + i] = whole->arm_side[same ? wa + j : j];
    }
  }
  return PS_OK;
}

int ps_model_take_given(ps_model *m, ps_ctx *ctx) {
  const ps_int na = m->net->n_arm;
  if (m->given->arm_k && m->arm_k)
    memcpy(m->arm_k, m->given->arm_k, (size_t)na * sizeof *m->arm_k);
  if (!m->given->arm_side) return PS_OK;
  if (!m->arm_side && !(m->arm_side = ps_calloc((size_t)(2 * na) + 1, sizeof *m->arm_side, ctx)))
    return PS_ERR_NOMEM;
  memcpy(m->arm_side, m->given->arm_side, (size_t)(2 * na) * sizeof *m->arm_side);
  return PS_OK;
}

int ps_model_create(ps_model *m, const ps_model_type *type,
                    const ps_particles *P, const ps_network *net,
                    const ps_material *mat, ps_ctx *ctx) {
  return ps_model_create_given(m, type, P, net, mat, NULL, ctx);
}

int ps_model_create_given(ps_model *m, const ps_model_type *type, const ps_particles *P,
                          const ps_network *net, const ps_material *mat,
                          const ps_model_given *given, ps_ctx *ctx) {
  memset(m, 0, sizeof *m);
  m->given = given;
  m->type = type;
  m->net = net;
  m->mat = *mat;
  m->R = ps_calloc((size_t)net->n_particle, sizeof *m->R, ctx);
  m->epsbar = ps_calloc((size_t)net->n_particle, sizeof *m->epsbar, ctx);
  if (!m->R || !m->epsbar) {
    ps_model_free(m);
    return PS_ERR_NOMEM;
  }
  int status = type->prepare ? type->prepare(m, P, ctx) : PS_OK;
  m->given = NULL; /* (copied: not kept) */
  if (status < 0) ps_model_free(m);
  return status;
}

void ps_model_set_team(ps_model *m, ps_team *team, int parts) {
  m->team = team;
  m->parts = parts < 1 ? 1 : parts > PS_PARTS_MAX ? PS_PARTS_MAX : parts;
}

void ps_model_free(ps_model *m) {
  free(m->R);
  free(m->epsbar);
  free(m->arm_k);
  free(m->arm_s0);
  free(m->arm_side);
  free(m->work);
  memset(m, 0, sizeof *m);
}
