/* problem_pd.c: the peridynamic problem (problem_pd.h) and its
 * ps_nl_problem operations: evaluation by ps_system_eval (minus lambda
 * fext), the product and the matrices of the assembly, and the arms'
 * yielding/broken flags as the state that changes the tangent. */
#include "problem_pd.h"

#include <stdlib.h>
#include <string.h>

/* the arm's tangent-changing state: yielding | 2 broken */
static inline unsigned char arm_state(const ps_arm_state *st, ps_int i) {
  return (unsigned char)(st->yielding[i] | (st->broken[i] << 1));
}

static int pd_evaluate(void *prob, const double *u, double *f, double *energy,
                       int want_tangent, ps_ctx *ctx) {
  ps_pd *pd = prob;
  double t = ps_wtime();
  int want = !want_tangent ? PS_EVAL_FORCES
             : pd->matrix_free ? PS_EVAL_OPERATOR
                               : PS_EVAL_TANGENT;
  int status = ps_system_eval(&pd->sys, &pd->model, &pd->st, pd->P->x, u, f, energy,
                              want, ctx);
  if (pd->fext && status == PS_OK)
    for (ps_int j = 0; j < pd->sys.n_dof; j++) {
      f[j] -= pd->lambda * pd->fext[j];
      if (!pd->owned_dof || pd->owned_dof[j]) *energy -= pd->lambda * pd->fext[j] * u[j];
    }
  /* the processes agree on the outcome before the energy's sum (a
   * collective); one that failed keeps its own message */
  if (ps_comm_any(pd->comm, status != PS_OK) && status == PS_OK)
    status = ps_error(ctx, PS_ERR_SOLVER, "the evaluation failed on another process");
  if (status == PS_OK) ps_comm_sum(pd->comm, energy, 1);
  if (status == PS_OK) pd->dissipation_valid = 0; /* ps_pd_step_dissipation */
  pd->t_assembly += ps_wtime() - t;
  return status;
}

static void pd_apply(void *prob, const double *x, double *y) {
  ps_pd *pd = prob;
  ps_operator K = pd->matrix_free ? ps_system_operator(&pd->sys) : ps_csc_operator(&pd->sys.A);
  K.apply(K.data, x, y);
}

static int pd_assemble(void *prob, int majorant, ps_csc **A, ps_ctx *ctx) {
  ps_pd *pd = prob;
  if (majorant) {
    if (!pd->have_majorant) return ps_error(ctx, PS_ERR_INPUT, "no majorant");
    PS_CHECK(ps_system_assemble_majorant(&pd->sys_pre, &pd->sys, ctx));
    *A = &pd->sys_pre.A;
    return PS_OK;
  }
  *A = &pd->sys.A;
  if (pd->sys.assembled) return PS_OK;
  double t = ps_wtime();
  int status = ps_system_assemble(&pd->sys, ctx);
  pd->t_assembly += ps_wtime() - t;
  return status;
}

static void pd_mark(void *prob) {
  ps_pd *pd = prob;
  for (ps_int i = 0; i < pd->net->n_arm; i++) pd->arm_state_at_factor[i] = arm_state(&pd->st, i);
}

static ps_int pd_changed(void *prob, ps_int limit) {
  const ps_pd *pd = prob;
  if (limit <= 0) limit = pd->net->n_arm;
  ps_int n = 0;
  for (ps_int i = 0; i < pd->net->n_arm && n <= limit; i++)
    n += ps_model_owns_arm(&pd->model, i) && pd->arm_state_at_factor[i] != arm_state(&pd->st, i);
  return ps_comm_count(pd->comm, n);
}

static void pd_dof_name(void *prob, ps_int k, char *buf, size_t len) {
  const ps_pd *pd = prob;
  ps_system_dof_name(&pd->sys, pd->P->x, pd->sys.dof_of_free[k], buf, len);
}

static const ps_nl_problem_ops pd_ops = {pd_evaluate, pd_apply,   pd_assemble,
                                         pd_mark,     pd_changed, pd_dof_name};

ps_nl_problem ps_pd_problem(ps_pd *pd) {
  ps_nl_problem p = {&pd_ops,       pd,           pd->sys.n_dof,     pd->sys.n_free,
                     pd->sys.dof_of_free, pd->sys.fixed, pd->have_majorant, pd->comm,
                     pd->owned_dof, pd->owned_free};
  return p;
}

void ps_pd_free(ps_pd *pd) {
  if (!pd) return;
  ps_system_free(&pd->sys_pre);
  ps_system_free(&pd->sys);
  ps_arm_state_free(&pd->st);
  ps_arm_state_free(&pd->st_saved);
  ps_model_free(&pd->model);
  free(pd->arm_state_at_factor);
  free(pd->owned_dof);
  free(pd->owned_free);
  ps_arm_halo_free(&pd->arm_halo);
  free(pd);
}

/* the whole free tangent's upper-triangle nonzeros from the shares'
 * patterns: each share counts the entries of its owned rows in both
 * triangles (an owned row of a share is the whole one's), the diagonal
 * once; summed over the processes that is 2 off-diagonal + diagonal, and
 * the upper triangle is (that + diagonal) / 2. Collective. */
static double whole_nnz(const ps_pd *pd) {
  const ps_csc *A = &pd->sys.A;
  const unsigned char *own = pd->owned_free;
  double c[2] = {0, 0}; /* owned rows' entries, owned diagonal entries */
  for (ps_int j = 0; A->p && j < pd->sys.n_free; j++)
    for (ps_int k = A->p[j]; k < A->p[j + 1]; k++) {
      ps_int i = A->i[k];
      c[0] += i == j ? own[j] : own[i] + own[j];
      c[1] += i == j && own[j];
    }
  ps_comm_sum(pd->comm, c, 2);
  return 0.5 * (c[0] + c[1]);
}

int ps_pd_set_share(ps_pd *pd, const unsigned char *own_arm, const unsigned char *own_particle,
                    const ps_int *global, const int *owner, ps_int n_global, ps_ctx *ctx) {
  int d = pd->net->dim;
  pd->model.own_arm = own_arm;
  pd->model.own_particle = own_particle;
  pd->model.global = global;
  free(pd->owned_dof);
  free(pd->owned_free);
  pd->owned_dof = ps_calloc((size_t)pd->sys.n_dof + 1, 1, ctx);
  pd->owned_free = ps_calloc((size_t)pd->sys.n_free + 1, 1, ctx);
  if (!pd->owned_dof || !pd->owned_free) return PS_ERR_NOMEM;
  for (ps_int j = 0; j < pd->sys.n_dof; j++) pd->owned_dof[j] = own_particle[j / d];
  for (ps_int k = 0; k < pd->sys.n_free; k++)
    pd->owned_free[k] = pd->owned_dof[pd->sys.dof_of_free[k]];
  pd->nnz_whole = whole_nnz(pd);
  /* (the same on every process: one material) */
  if (pd->comm && pd->comm->size > 1 && global && owner && ps_material_breaks(&pd->model.mat) &&
      !ps_model_breaks_alike(pd->model.type, &pd->model.mat)) {
    ps_arm_halo_free(&pd->arm_halo);
    pd->model.arm_halo = NULL;
    PS_CHECK(ps_arm_halo_create(&pd->arm_halo, &pd->model, owner, n_global, pd->comm, ctx));
    pd->model.arm_halo = &pd->arm_halo;
  }
  return PS_OK;
}

int ps_pd_create(ps_pd **out, const ps_particles *P, const ps_network *net,
                 const ps_model_type *type, const ps_material *mat,
                 const unsigned char *fixed, int majorant, int matrix_free, ps_ctx *ctx) {
  return ps_pd_create_given(out, P, net, type, mat, NULL, fixed, majorant, matrix_free, ctx);
}

int ps_pd_create_given(ps_pd **out, const ps_particles *P, const ps_network *net,
                       const ps_model_type *type, const ps_material *mat,
                       const ps_model_given *given, const unsigned char *fixed, int majorant,
                       int matrix_free, ps_ctx *ctx) {
  int status = PS_OK;
  *out = NULL;
  ps_pd *pd = ps_calloc(1, sizeof *pd, ctx);
  if (!pd) return PS_ERR_NOMEM;
  pd->P = P;
  pd->net = net;
  pd->matrix_free = matrix_free;
  pd->comm = ctx->comm;
  pd->dissipation_valid = 1; /* dissipation_step 0 before any evaluation */
  PS_CHECK_GOTO(ps_model_create_given(&pd->model, type, P, net, mat, given, ctx));
  PS_CHECK_GOTO(ps_system_create_pattern(&pd->sys, net, fixed, type->family_coupling, ctx));
  PS_CHECK_GOTO(ps_arm_state_alloc(&pd->st, net->n_arm, ctx));
  PS_CHECK_GOTO(ps_arm_state_alloc(&pd->st_saved, net->n_arm, ctx));
  if (majorant && type->family_coupling) {
    PS_CHECK_GOTO(ps_system_create_pattern(&pd->sys_pre, net, fixed, 0, ctx));
    pd->have_majorant = 1;
  }
  pd->arm_state_at_factor = ps_calloc((size_t)net->n_arm + 1, 1, ctx);
  if (!pd->arm_state_at_factor) status = PS_ERR_NOMEM;
cleanup:
  if (status < 0)
    ps_pd_free(pd);
  else
    *out = pd;
  return status;
}

int ps_pd_set_team(ps_pd *pd, ps_team *team, int parts, ps_ctx *ctx) {
  pd->sys.team = team;
  PS_CHECK(ps_system_set_parts(&pd->sys, parts, ctx));
  ps_model_set_team(&pd->model, team, parts);
  return PS_OK;
}

void ps_pd_commit(ps_pd *pd) {
  ps_int na = pd->net->n_arm;
  memcpy(pd->st.eps_p, pd->st.eps_p_trial, (size_t)(2 * na) * sizeof *pd->st.eps_p);
  ps_arm_state_copy(&pd->st_saved, &pd->st);
}

void ps_pd_restore(ps_pd *pd) { ps_arm_state_copy(&pd->st, &pd->st_saved); }

double ps_pd_dissipation(const ps_pd *pd, double *g) {
  const ps_model *m = &pd->model;
  const ps_network *net = pd->net;
  const int N = net->dim;
  double D = 0.0;
  if (g) memset(g, 0, (size_t)pd->sys.n_dof * sizeof *g);
  if (!m->type->arm_dissipation || (m->type->dissipates && !m->type->dissipates(m)))
    return 0.0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    double dD, Di = m->type->arm_dissipation(m, &pd->st_saved, &pd->st, i, pd->sys.dl[i], &dD);
    if (ps_model_owns_arm(m, i)) D += Di; /* g: every arm of an owned dof */
    if (g && dD != 0.0) /* dl_i/dy_b = q_i = -dl_i/dy_a */
      for (int k = 0; k < N; k++) {
        g[net->b[i] * N + k] += dD * pd->sys.q[i * N + k];
        g[net->a[i] * N + k] -= dD * pd->sys.q[i * N + k];
      }
  }
  return ps_comm_sum1(pd->comm, D);
}

double ps_pd_step_dissipation(ps_pd *pd) {
  if (!pd->dissipation_valid) {
    pd->dissipation_step = ps_pd_dissipation(pd, NULL);
    pd->dissipation_valid = 1;
  }
  return pd->dissipation_step;
}

void ps_pd_step_committed(ps_pd *pd) {
  pd->dissipation_step = 0.0;
  pd->dissipation_valid = 1;
}

int ps_pd_break_arms(ps_pd *pd, ps_int max_count, ps_int *n_broken, ps_ctx *ctx) {
  return ps_model_break_arms(&pd->model, &pd->st, max_count, n_broken, ctx);
}

void ps_pd_coupling(ps_pd *pd, const double *du, double *out) {
  ps_system_coupling(&pd->sys, du, out);
}

ps_int ps_pd_count_yielding(const ps_pd *pd) {
  ps_int n = 0;
  for (ps_int i = 0; i < pd->net->n_arm; i++)
    n += ps_model_owns_arm(&pd->model, i) && pd->st.yielding[i] && !pd->st.broken[i];
  return ps_comm_count(pd->comm, n);
}

double ps_pd_nnz_tangent(const ps_pd *pd) {
  if (pd->owned_free) return pd->nnz_whole;
  return pd->sys.A.p ? (double)pd->sys.A.p[pd->sys.n_free] : 0.0;
}
