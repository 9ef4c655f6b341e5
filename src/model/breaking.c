/* breaking.c: the one breaking mechanism of every model. A model says how
 * far each arm is past its criterion (ps_model_type.break_excess: Eq. 118
 * for the fibre model, a critical stretch or micropotential for the bond
 * and state models); this file marks the arms past it, all of them or the
 * worst max_count, and turns a fracture energy G_c into the criterion's
 * constant (the closed forms and their derivation: doc/fracture.md). */
#include "ps_model.h"

#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int ps_material_breaks(const ps_material *mat) {
  return mat->fracture != PS_FRACTURE_NONE || (mat->delta > 0 && isfinite(mat->delta));
}

/* An arm past the criterion: its excess, its number here, and its ends'
 * numbers in the whole model (ga < gb; the arm's number there orders its
 * arms as (ga, gb) does: ps_network_build numbers sorted pairs) */
typedef struct {
  double excess;
  ps_int arm, ga, gb;
} candidate;

/* by the arm's ends in the whole model, i.e. by its number there */
static int by_ends(const void *u, const void *v) {
  const candidate *cu = u, *cv = v;
  if (cu->ga != cv->ga) return (cu->ga > cv->ga) - (cu->ga < cv->ga);
  return (cu->gb > cv->gb) - (cu->gb < cv->gb);
}

/* the larger excess first; ties by_ends (the order qsort, which is not
 * stable, must not choose, and the same on every process) */
static int by_excess_desc(const void *u, const void *v) {
  const candidate *cu = u, *cv = v;
  if (cu->excess != cv->excess) return cu->excess > cv->excess ? -1 : 1;
  return by_ends(u, v);
}

/* arm i as a candidate with excess e */
static candidate candidate_of(const ps_model *m, ps_int i, double e) {
  ps_int a = m->net->a[i], b = m->net->b[i];
  if (m->global) {
    a = m->global[a];
    b = m->global[b];
  }
  return (candidate){e, i, a < b ? a : b, a < b ? b : a};
}

/* arm i breaks: its energy goes into st->broken_energy */
static void break_one(const ps_model *m, ps_arm_state *st, ps_int i) {
  if (ps_model_owns_arm(m, i))
    st->broken_energy += m->type->arm_energy ? m->type->arm_energy(m, st, i) : NAN;
  st->broken[i] = 1;
}

int ps_model_breaks_alike(const ps_model_type *type, const ps_material *mat) {
  return type->break_local && mat->yield_rule == PS_YIELD_TOTAL;
}

void ps_arm_halo_free(ps_arm_halo *ah) {
  if (!ah) return;
  ps_halo_free(&ah->h);
  free(ah->order);
  free(ah->x);
  memset(ah, 0, sizeof *ah);
}

int ps_arm_halo_create(ps_arm_halo *ah, const ps_model *m, const int *owner, ps_int n_global,
                       const ps_comm *comm, ps_ctx *ctx) {
  const ps_network *net = m->net;
  const ps_int n = net->n_arm;
  memset(ah, 0, sizeof *ah);
  if (ps_comm_any(comm, n_global > 3000000000LL)) /* (ga n_global + gb < 2^63) */
    return ps_error(ctx, PS_ERR_INPUT, "%lld particles: too many to name the arms of a "
                    "distributed model", (long long)n_global);
  ah->order = ps_calloc((size_t)n + 1, sizeof *ah->order, ctx);
  ah->x = ps_calloc((size_t)n + 1, sizeof *ah->x, ctx);
  ps_int *key = ps_calloc((size_t)n + 1, sizeof *key, ctx);
  int *arm_owner = ps_calloc((size_t)n + 1, sizeof *arm_owner, ctx);
  int status = PS_OK;
  if (ps_comm_any(comm, !ah->order || !ah->x || !key || !arm_owner)) {
    status = ps_error(ctx, PS_ERR_NOMEM, "out of memory for the arms' halo (here or on "
                      "another process)");
    goto cleanup;
  }
  ps_int k = 0;
  for (int own = 1; own >= 0; own--) { /* own arms first */
    for (ps_int i = 0; i < n; i++)
      if (ps_model_owns_arm(m, i) == own) ah->order[k++] = i;
    if (own) ah->n_own = k;
  }
  for (ps_int j = 0; j < n; j++) {
    ps_int i = ah->order[j];
    candidate c = candidate_of(m, i, 0.0);
    key[j] = c.ga * n_global + c.gb;
    if (j >= ah->n_own) /* (asked of the owner of the lower end) */
      arm_owner[j - ah->n_own] = owner[m->global[net->a[i]] == c.ga ? net->a[i] : net->b[i]];
  }
  status = ps_halo_create(&ah->h, comm, n, ah->n_own, key, arm_owner, ctx);
cleanup:
  free(key);
  free(arm_owner);
  if (status < 0) ps_arm_halo_free(ah);
  return status;
}

/* The other copies of the arms take their owners' broken flags (st's own
 * arms are judged; collective) */
static int broken_from_owners(const ps_model *m, ps_arm_state *st, ps_ctx *ctx) {
  ps_arm_halo *ah = m->arm_halo;
  const ps_int n = m->net->n_arm;
  for (ps_int j = 0; j < ah->n_own; j++) ah->x[j] = st->broken[ah->order[j]];
  PS_CHECK(ps_halo_exchange(&ah->h, ctx->comm, ah->x, 1, ctx));
  for (ps_int j = ah->n_own; j < n; j++) st->broken[ah->order[j]] = ah->x[j] != 0.0;
  return PS_OK;
}

ps_int ps_model_count_past(const ps_model *m, const ps_arm_state *st) {
  double (*excess)(const ps_model *, const ps_arm_state *, ps_int) = m->type->break_excess;
  ps_int nc = 0;
  if (!ps_material_breaks(&m->mat) || !excess) return 0;
  for (ps_int i = 0; i < m->net->n_arm; i++)
    nc += ps_model_owns_arm(m, i) && !st->broken[i] && excess(m, st, i) > 0;
  return nc;
}

double ps_model_max_excess(const ps_model *m, const ps_arm_state *st) {
  double (*excess)(const ps_model *, const ps_arm_state *, ps_int) = m->type->break_excess;
  double g = -1.0;
  if (!ps_material_breaks(&m->mat) || !excess) return g;
  for (ps_int i = 0; i < m->net->n_arm; i++)
    if (!st->broken[i] && ps_model_owns_arm(m, i)) g = fmax(g, excess(m, st, i));
  return g;
}

/* The max_count arms past the criterion by the most over the processes:
 * each process's own worst max_count (cand[nc], sorted), shared with
 * all, sorted again; every process then breaks its copies of the chosen
 * arms (own and ghost: the ends' numbers name them). Collective. */
static int break_worst_shared(const ps_model *m, ps_arm_state *st, const candidate *cand,
                              ps_int nc, ps_int max_count, int alike, ps_ctx *ctx) {
  ps_int k = nc < max_count ? nc : max_count, n_all = 0;
  double *mine = ps_calloc((size_t)(3 * k) + 1, sizeof *mine, ctx), *all = NULL;
  int status = PS_OK;
  if (ps_comm_any(ctx->comm, !mine)) {
    free(mine);
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory for the worst arms (here or on another "
                    "process)");
  }
  for (ps_int j = 0; j < k; j++) {
    mine[3 * j] = cand[j].excess;
    mine[3 * j + 1] = (double)cand[j].ga; /* (exact below 2^53) */
    mine[3 * j + 2] = (double)cand[j].gb;
  }
  PS_CHECK_GOTO(ps_comm_gather(ctx->comm, mine, k, 3, 1, &all, &n_all, ctx));
  candidate *chosen = ps_calloc((size_t)n_all + 1, sizeof *chosen, ctx);
  if (ps_comm_any(ctx->comm, !chosen)) {
    free(chosen);
    status = ps_error(ctx, PS_ERR_NOMEM, "out of memory for the worst arms (here or on "
                      "another process)");
    goto cleanup;
  }
  for (ps_int j = 0; j < n_all; j++)
    chosen[j] = (candidate){all[3 * j], -1, (ps_int)all[3 * j + 1], (ps_int)all[3 * j + 2]};
  qsort(chosen, (size_t)n_all, sizeof *chosen, by_excess_desc);
  ps_int n_chosen = n_all < max_count ? n_all : max_count;
  qsort(chosen, (size_t)n_chosen, sizeof *chosen, by_ends);
  for (ps_int i = 0; i < m->net->n_arm; i++) {
    if (st->broken[i]) continue;
    if (!alike && !ps_model_owns_arm(m, i)) continue; /* (its owner's flag comes) */
    candidate key = candidate_of(m, i, 0.0);
    if (bsearch(&key, chosen, (size_t)n_chosen, sizeof *chosen, by_ends)) break_one(m, st, i);
  }
  free(chosen);
cleanup:
  free(mine);
  free(all);
  return status;
}

int ps_model_break_arms(const ps_model *m, ps_arm_state *st, ps_int max_count,
                        ps_int *n_broken, ps_ctx *ctx) {
  const ps_network *net = m->net;
  double (*excess)(const ps_model *, const ps_arm_state *, ps_int) = m->type->break_excess;
  *n_broken = 0;
  if (!ps_material_breaks(&m->mat) || !excess) return PS_OK;
  /* the decision between all and the worst is the run's (every process
   * counts its own arms). On several processes each breaks its copies of
   * the arms past the criterion, own and ghost alike, when a ghost copy
   * is judged as its owner judges it: a criterion on the arm's own state
   * (ps_model_breaks_alike); otherwise (the deviatoric yield rule's
   * family strains, the three-body model's rotations, which a ghost's
   * truncated family gets wrong) each judges its own arms and the other
   * copies take the owners' flags (ps_model.arm_halo) */
  ps_int nc_here = ps_model_count_past(m, st), nc = ps_comm_count(ctx->comm, nc_here);
  if (nc == 0) return PS_OK;
  const int shared = ctx->comm && ctx->comm->size > 1;
  const int alike = !shared || ps_model_breaks_alike(m->type, &m->mat);
  if (!alike && !m->arm_halo)
    return ps_error(ctx, PS_ERR_INPUT, "%lld arms reached the breaking criterion: breaking in "
                    "a distributed model by a criterion that reads more than the arm's own "
                    "state needs the arms' halo (ps_model.arm_halo)", (long long)nc);
  if (max_count <= 0 || nc <= max_count) {
    for (ps_int i = 0; i < net->n_arm; i++)
      if (!st->broken[i] && (alike || ps_model_owns_arm(m, i)) && excess(m, st, i) > 0)
        break_one(m, st, i);
    if (!alike) PS_CHECK(broken_from_owners(m, st, ctx));
    *n_broken = nc;
    return PS_OK;
  }
  /* only the max_count arms past the criterion by the most: this
   * process's own candidates first */
  candidate *c = ps_calloc((size_t)nc_here + 1, sizeof *c, ctx);
  if (ps_comm_any(ctx->comm, !c)) {
    free(c);
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory for the worst arms (here or on another "
                    "process)");
  }
  ps_int k = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    double e = st->broken[i] || !ps_model_owns_arm(m, i) ? 0.0 : excess(m, st, i);
    if (e > 0) c[k++] = candidate_of(m, i, e);
  }
  qsort(c, (size_t)k, sizeof *c, by_excess_desc);
  int status = PS_OK;
  if (!shared)
    for (ps_int j = 0; j < max_count; j++) break_one(m, st, c[j].arm);
  else
    status = break_worst_shared(m, st, c, k, max_count, alike, ctx);
  if (status == PS_OK && !alike) status = broken_from_owners(m, st, ctx);
  free(c);
  if (status < 0) return status;
  *n_broken = max_count;
  return PS_OK;
}

double ps_model_stretch_excess(const ps_model *m, const ps_arm_state *st, ps_int i) {
  if (st->broken[i] || !m->arm_s0) return -1.0;
  return st->stretch[i] / m->arm_s0[i] - 1.0;
}

/* s0 or w_c from G_c (doc/fracture.md): the energy of every arm crossing a
 * unit crack, each at the criterion. With the micropotential w(xi) of an
 * arm at breaking, G_c = int_0^delta 2 xi^2 w dxi in 2D and pi int_0^delta
 * xi^3 w dxi in 3D. Bond, stretch criterion, w = 1/2 c(xi) s0^2 xi:
 *   constant c = 12K/(pi d^3) (2D), 18K/(pi d^4) (3D):
 *     s0 = sqrt(pi G_c / (3 K d)) (2D; Ha & Bobaru 2010's sqrt(4 pi G_c /
 *     (9 E d)) in plane stress with nu = 1/3), sqrt(5 G_c / (9 K d)) (3D;
 *     Silling & Askari 2005);
 *   conical c0 (1 - xi/d), c0 = 48K/(pi d^3) (2D), 90K/(pi d^4) (3D):
 *     s0 = sqrt(5 pi G_c / (12 K d)) (2D), sqrt(2 G_c / (3 K d)) (3D).
 * Bond, energy criterion (any c): w_c = 3 G_c / (2 d^3) (2D),
 * 4 G_c / (pi d^4) (3D); threebody (2D, energy criterion only): the same
 * w_c, the arm micropotential summed over stretch and shear
 * (doc/design-threebody.md, decision 5). State (Madenci & Oterkus 2014, influence d/xi):
 *   s0 = sqrt(G_c / ((6G/pi + 16/(9 pi^2) (K - 2G)) d)) (2D),
 *        sqrt(G_c / ((3G + (3/4)^4 (K - 5G/3)) d)) (3D). */
static int from_energy(ps_material *mat, const char *model, int dim, ps_ctx *ctx) {
  double Gc = mat->fracture_energy, K = mat->K, G = mat->G, d = mat->horizon;
  int bond = model[0] == 'b', threebody = model[0] == 't';
  if (mat->fracture == PS_FRACTURE_ENERGY) {
    if (!bond && !threebody)
      return ps_error(ctx, PS_ERR_INPUT,
                      "material.fracture.criterion energy is for the bond model (and "
                      "threebody): the %s "
                      "model breaks by critical stretch", model);
    mat->critical_micropotential = dim == 2 ? 1.5 * Gc / pow(d, 3) : 4.0 * Gc / (M_PI * pow(d, 4));
    return PS_OK;
  }
  double s2;
  if (bond && mat->micromodulus == PS_MICRO_CONSTANT)
    s2 = dim == 2 ? M_PI * Gc / (3.0 * K * d) : 5.0 * Gc / (9.0 * K * d);
  else if (bond)
    s2 = dim == 2 ? 5.0 * M_PI * Gc / (12.0 * K * d) : 2.0 * Gc / (3.0 * K * d);
  else if (dim == 2)
    s2 = Gc / ((6.0 * G / M_PI + 16.0 / (9.0 * M_PI * M_PI) * (K - 2.0 * G)) * d);
  else
    s2 = Gc / ((3.0 * G + pow(0.75, 4) * (K - 5.0 * G / 3.0)) * d);
  mat->critical_stretch = sqrt(s2);
  return PS_OK;
}

int ps_model_fracture_prepare(ps_model *m, const double *cxi, ps_ctx *ctx) {
  ps_material *mat = &m->mat;
  const ps_network *net = m->net;
  if (mat->fracture == PS_FRACTURE_NONE) return PS_OK;
  double r = mat->softening_ratio;
  if (r != 0.0 && (strcmp(m->type->name, "bond") || mat->fracture != PS_FRACTURE_STRETCH ||
                   !(r > 1.0 && isfinite(r))))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.fracture.softening_ratio (%g) must be a finite number > 1 and "
                    "is for the bond model's stretch criterion (the %s model%s)",
                    r, m->type->name,
                    mat->fracture == PS_FRACTURE_STRETCH ? "" : ", energy criterion");
  if (mat->fracture_energy > 0) {
    PS_CHECK(from_energy(mat, m->type->name, net->dim, ctx));
    /* a softening arm dissipates 1/2 c s0 s1 xi = 1/2 c s0^2 r xi: the
     * brittle s0 over sqrt(r) keeps G_c */
    if (r > 1.0) mat->critical_stretch /= sqrt(r);
  }
  double s0 = mat->critical_stretch, wc = mat->critical_micropotential;
  if (mat->fracture == PS_FRACTURE_STRETCH ? !(s0 > 0 && isfinite(s0))
                                           : !(wc > 0 && isfinite(wc)))
    return ps_error(ctx, PS_ERR_INPUT,
                    "material.fracture: the critical %s must be a finite number > 0 "
                    "(got %g)",
                    mat->fracture == PS_FRACTURE_STRETCH ? "stretch" : "micropotential",
                    mat->fracture == PS_FRACTURE_STRETCH ? s0 : wc);
  m->arm_s0 = ps_calloc((size_t)net->n_arm, sizeof *m->arm_s0, ctx);
  if (!m->arm_s0) return PS_ERR_NOMEM;
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (mat->fracture == PS_FRACTURE_STRETCH)
      m->arm_s0[i] = s0;
    else /* 1/2 cxi s^2 xi = w_c */
      m->arm_s0[i] = cxi[i] > 0 ? sqrt(2.0 * wc / (cxi[i] * net->r0[i])) : INFINITY;
    if (m->arm_k && !(m->arm_k[i] > 0)) m->arm_s0[i] = INFINITY; /* carries nothing */
  }
  return PS_OK;
}
