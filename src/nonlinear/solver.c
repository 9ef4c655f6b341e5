/* solver.c: the solver's lifecycle (options, create with the support
 * check, free; the peridynamic problem through problem_pd.h), the path steps
 * (predictor and Newton for an increment, an arc-length increment with its
 * own Newton loop on the bordered system, commit/restore of the plastic
 * state, one round of arm breaking, Eq. 118) and the read-only views:
 * statistics and accessors. */
#include "solver_impl.h"
#include "problem_pd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void ps_solver_opts_default(ps_solver_opts *o) {
  o->tolerance = 1e-8;
  o->max_iterations = 30;
  o->max_small_steps = 5;
  o->line_search = 1;
  snprintf(o->linear, sizeof o->linear, "%s", "cholmod");
  o->reuse_factor = 1;
  o->pcg_rtol = 1e-6;
  o->pcg_max_iterations = 25;
  o->pcg_skip_arms = 0;
  o->reanalyze = 0;
  o->majorant = 1;
  o->cg_forcing_adaptive = 1;
  o->cg_forcing_max = 0.5;
  o->cg_forcing = PS_CG_FORCING_FIXED;
  o->matrix_free = 1;
  o->cg_single_precision = 1;
  o->cg_truncate = 1;
  o->parts = PS_PARTS_DEFAULT;
  o->threads = 0;
  o->layout = PS_LAYOUT_AUTO;
}

void ps_solver_free(ps_solver *s) {
  if (!s) return;
  ps_linsolve_destroy(&s->ls);
  ps_linsolve_destroy(&s->ls_fallback);
  ps_linsolve_destroy(&s->ls_ldl);
  ps_linsolve_destroy(&s->ls_pre);
  ps_pd_free(s->pd);
  ps_team_free(s->team);
  free(s->u);
  free(s->u_saved);
  free(s->u_prev);
  free(s->ubar);
  free(s->f);
  free(s->rhs);
  free(s->du);
  free(s->work);
  free(s->pcg_work);
  free(s->u_trial);
  free(s->work_dof);
  free(s->diag_saved);
  free(s->f_trial);
  free(s->al_q);
  free(s->al_v);
  free(s->al_dr);
  free(s->al_g);
  free(s);
}

void ps_solver_set_forces(ps_solver *s, const double *fext) { s->pd->fext = fext; }

/* a quick necessary condition of support: each direction has a
 * prescribed dof. Returns PS_OK or PS_ERR_INPUT. */
static int check_directions(const ps_network *net, const unsigned char *fixed, ps_ctx *ctx) {
  int d = net->dim;
  for (int k = 0; k < d; k++) {
    int any = 0;
    for (ps_int a = 0; a < net->n_particle && !any; a++) any = fixed[a * d + k];
    if (!ps_comm_any(ctx->comm, any)) /* (on any process of the run) */
      return ps_error(ctx, PS_ERR_INPUT,
                      "the model has no supports in direction %c: no particle has "
                      "a prescribed %c displacement (see loading.boundary)",
                      "xyz"[k], "xyz"[k]);
  }
  return PS_OK;
}

/* what a backend may use beyond the matrix: the unknowns' rigid-body
 * modes and the PETSc options */
static void set_backend_data(ps_linsolve *ls, const ps_solver *s, const ps_particles *P) {
  ls->dim = P->dim;
  ls->x = P->x;
  ls->dof_of_free = s->prob.dof_of_free;
  ls->n_dof = s->prob.n_dof;
  ls->options = s->opts.petsc_options;
}

/* the linear solvers and their threads, min(threads or the CPUs, parts)
 * (more would idle); the majorant's factor when the direction strategy
 * uses one */
static int create_linear(ps_solver *s, const ps_particles *P, ps_ctx *ctx) {
  const ps_solver_opts *opts = &s->opts;
  int threads = opts->threads > 0 ? opts->threads : ps_cpu_count();
  PS_CHECK(ps_team_create(&s->team, threads < opts->parts ? threads : opts->parts, ctx));
  PS_CHECK(ps_pd_set_team(s->pd, s->team, opts->parts, ctx));
  PS_CHECK(ps_linsolve_create(&s->ls, s->linear, ctx));
  set_backend_data(&s->ls, s, P);
  s->ls.team = s->team;
  s->ls.parts = opts->parts;
  s->ls.reanalyze = opts->reanalyze;
  /* simplicial LDL^T pays on the one-horizon pattern (arms only); on the
   * two-horizon one of family terms it was 6x slower than UMFPACK */
  s->ldl_ok = !s->pd->model.type->family_coupling;
  s->ls.single_precision = opts->cg_single_precision;
  if (s->prob.has_majorant) {
    /* CHOLMOD's single-precision factor, or PETSc's PC where the run
     * asked for PETSc */
    PS_CHECK(ps_linsolve_create(&s->ls_pre,
                                s->linear == ps_linsolve_petsc ? ps_linsolve_petsc
                                                               : ps_linsolve_cholmod,
                                ctx));
    set_backend_data(&s->ls_pre, s, P);
    s->ls_pre.single_precision = opts->cg_single_precision;
    s->ls_pre.team = s->team;
    s->ls_pre.parts = opts->parts;
    /* a majorant's factor serves the CG solves of many Newton systems:
     * its single-precision copy is made from the first one */
    s->ls_pre.single_after = 0;
    s->have_majorant = 1;
  }
  return PS_OK;
}

int ps_nl_alloc_work(ps_solver *s, ps_ctx *ctx) {
  ps_int nd = s->prob.n_dof, nf = s->prob.n_free;
  s->u = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->u_saved = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->u_prev = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->work_dof = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->ubar = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->f = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->u_trial = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->f_trial = ps_calloc((size_t)nd, sizeof *s->u, ctx);
  s->rhs = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->du = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->work = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->diag_saved = ps_calloc((size_t)nf, sizeof *s->u, ctx);
  s->pcg_work = ps_calloc((size_t)(4 * nf), sizeof *s->u, ctx);
  if (!s->pcg_work || !s->u_prev || !s->work_dof || !s->u || !s->u_saved || !s->ubar ||
      !s->f || !s->u_trial || !s->f_trial || !s->rhs || !s->du || !s->work ||
      !s->diag_saved)
    return PS_ERR_NOMEM;
  return PS_OK;
}

int ps_solver_create(ps_solver **out, const ps_particles *P,
                     const ps_network *net, const ps_model_type *type,
                     const ps_material *mat, const unsigned char *fixed,
                     const double *ubar, const ps_solver_opts *opts,
                     ps_ctx *ctx) {
  return ps_solver_create_share(out, P, net, type, mat, fixed, ubar, opts, NULL, ctx);
}

int ps_solver_create_share(ps_solver **out, const ps_particles *P, const ps_network *net,
                           const ps_model_type *type, const ps_material *mat,
                           const unsigned char *fixed, const double *ubar,
                           const ps_solver_opts *opts, const ps_solver_share *share,
                           ps_ctx *ctx) {
  int status = PS_OK;
  *out = NULL;
  const ps_linsolve_type *linear = ps_linsolve_type_find(opts->linear);
  if (!linear)
    return ps_error(ctx, PS_ERR_INPUT,
                    "unknown linear solver '%s' (solver.linear: cholmod, "
                    "cholmod-simplicial, umfpack or petsc)",
                    opts->linear);
  if (share && (linear != ps_linsolve_petsc || (opts->reuse_factor && opts->majorant)))
    return ps_error(ctx, PS_ERR_INPUT, "a distributed model is solved by PETSc, with no "
                    "majorant (solver.linear: petsc, majorant: false)");
  if ((status = check_directions(net, fixed, ctx)) != PS_OK) return status;
  ps_solver *s = ps_calloc(1, sizeof *s, ctx);
  if (!s) return PS_ERR_NOMEM;
  s->opts = *opts;
  s->linear = linear;
  /* the tangent is kept as data and applied matrix-free where CG uses it
   * (opts.reuse_factor) and opts.matrix_free; a majorant where CG uses it
   * and the model has family terms */
  PS_CHECK_GOTO(ps_pd_create_given(&s->pd, P, net, type, mat, share ? share->given : NULL,
                                   fixed, opts->majorant && opts->reuse_factor,
                                   opts->reuse_factor && opts->matrix_free, ctx));
  if (share) {
    PS_CHECK_GOTO(ps_pd_set_share(s->pd, share->own_arm, share->own_particle, share->global,
                                  share->owner, share->n_global / P->dim, ctx));
  }
  s->prob = ps_pd_problem(s->pd);
  if ((status = create_linear(s, P, ctx)) < 0) goto cleanup; /* traced */
  if (share) {
    s->ls.global_row = share->global_row;
    s->ls.n_global = share->n_global;
    s->ls.row0 = share->row0;
    s->ls.n_rows = share->n_rows;
  }
  if ((status = ps_nl_alloc_work(s, ctx)) != PS_OK) goto cleanup;
  for (ps_int j = 0; j < s->prob.n_dof; j++) s->ubar[j] = fixed[j] ? ubar[j] : 0.0;
  /* support check: every particle held at rest (the spring that holds
   * loose particles and pieces once arms break must not hide a missing
   * support), and the tangent at rest nonsingular */
  PS_CHECK_GOTO(ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx));
  ps_int loose = ps_system_first_loose(&s->pd->sys, share ? share->own_particle : NULL);
  if (ps_comm_any(ctx->comm, loose >= 0)) {
    if (loose < 0) {
      status = ps_error(ctx, PS_ERR_INPUT, "the model is not properly supported (a particle "
                        "of another process is not held at rest)");
      goto cleanup;
    }
    char name[160];
    ps_system_dof_name(&s->pd->sys, P->x, loose, name, sizeof name);
    status = ps_error(ctx, PS_ERR_INPUT,
                      "the model is not properly supported: %s is not held at rest (its "
                      "arms do not span the %s there, or it lies in a piece of the body "
                      "with no support); check the geometry (cracks that cut a piece off) "
                      "and loading.boundary",
                      name, P->dim == 3 ? "space" : "plane");
    goto cleanup;
  }
  status = ps_nl_factor_tangent(s, ctx);
  if (status > 0) {
    char msg[sizeof ctx->msg];
    snprintf(msg, sizeof msg, "%s", ctx->msg);
    status = ps_error(ctx, PS_ERR_INPUT,
                      "the model is not properly supported: %s at rest. A rigid-body "
                      "motion is free or a particle is held by no arm; check "
                      "loading.boundary",
                      msg);
    goto cleanup;
  }
  if (status < 0) goto cleanup;
  ps_solver_commit(s);
cleanup:
  if (status < 0)
    ps_solver_free(s);
  else
    *out = s;
  return status;
}

void ps_solver_commit(ps_solver *s) {
  /* the committed state dissipates nothing from itself: the incremental
   * energy there is the stored one */
  double D = ps_pd_step_dissipation(s->pd);
  s->dissipated += D;
  s->energy -= D;
  ps_pd_step_committed(s->pd);
  ps_pd_commit(s->pd);
  memcpy(s->u_saved, s->u, (size_t)s->prob.n_dof * sizeof *s->u);
  s->lambda_saved = s->pd->lambda;
}

int ps_solver_reject(ps_solver *s, ps_ctx *ctx) {
  ps_solver_restore(s);
  s->pd->lambda = s->lambda_saved;
  s->have_prev = 0;
  return ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx);
}

ps_int ps_solver_count_past_criterion(const ps_solver *s) {
  return ps_comm_count(s->prob.comm, ps_model_count_past(&s->pd->model, &s->pd->st));
}

double ps_solver_max_excess(const ps_solver *s) {
  double g = ps_model_max_excess(&s->pd->model, &s->pd->st);
  ps_comm_max(s->prob.comm, &g, 1);
  return g;
}

void ps_solver_restore(ps_solver *s) {
  ps_pd_restore(s->pd);
  memcpy(s->u, s->u_saved, (size_t)s->prob.n_dof * sizeof *s->u);
}

/* The predictor of the increment lambda0 -> lambda (dl = lambda -
 * lambda0) from the converged u at lambda0 (copied to u_prev):
 *   secant, when the last increment converged with no break since:
 *     u_f += dl / (lambda0 - lambda_prev) (u_f - u_prev,f);
 *   else tangent, with the last factor:
 *     K_ff du_f = -(r_f + K_fp du_p) + dl fext_f;
 * then u_p = lambda ubar_p. Returns PS_OK or fatal. */
/* the prescribed dofs and the problem at load factor lambda */
static void set_lambda(ps_solver *s, double lambda) {
  const ps_nl_problem *sys = &s->prob;
  for (ps_int j = 0; j < sys->n_dof; j++)
    if (sys->fixed[j]) s->u[j] = lambda * s->ubar[j];
  s->pd->lambda = lambda;
}

static int predict(ps_solver *s, double lambda, ps_ctx *ctx) {
  const ps_nl_problem *sys = &s->prob;
  const double *fext = s->pd->fext;
  double lambda0 = s->pd->lambda, dl = lambda - lambda0;
  ps_int nd = sys->n_dof, nf = sys->n_free;
  int secant = s->have_prev && lambda0 > s->lambda_prev;
  double *u_start = s->u_trial; /* the start, for the secant history */
  memcpy(u_start, s->u, (size_t)nd * sizeof *s->u);
  if (secant) {
    double r = dl / (lambda0 - s->lambda_prev);
    for (ps_int k = 0; k < nf; k++) {
      ps_int j = sys->dof_of_free[k];
      s->u[j] += r * (s->u[j] - s->u_prev[j]);
    }
  } else if (s->have_factor) {
    for (ps_int j = 0; j < nd; j++) s->work_dof[j] = sys->fixed[j] ? dl * s->ubar[j] : 0.0;
    ps_pd_coupling(s->pd, s->work_dof, s->work);
    for (ps_int k = 0; k < nf; k++) {
      ps_int j = sys->dof_of_free[k];
      s->rhs[k] = -(s->f[j] + s->work[k]) + (fext ? dl * fext[j] : 0.0);
    }
    PS_CHECK(ps_linsolve_solve((ps_linsolve *)s->ls_last, s->rhs, s->du, ctx));
    for (ps_int k = 0; k < nf; k++) s->u[sys->dof_of_free[k]] += s->du[k];
  }
  set_lambda(s, lambda);
  memcpy(s->u_prev, u_start, (size_t)nd * sizeof *s->u); /* u_trial is reused */
  return PS_OK;
}

int ps_solver_step(ps_solver *s, double lambda, ps_ctx *ctx) {
  double lambda0 = s->pd->lambda;
  int status = predict(s, lambda, ctx);
  if (status < 0) return status; /* traced */
  status = ps_newton_solve(s, ctx);
  if (status == PS_OK) {
    s->lambda_prev = lambda0;
    s->have_prev = 1;
  } else {
    s->have_prev = 0;
  }
  if (status == PS_DIVERGED) {
    /* back to the last commit, with a fresh factor there for the next
     * try (the majorant's when there is one: it preconditions CG as well
     * as the tangent's own factor, at a fraction of its cost) */
    ps_solver_restore(s);
    s->pd->lambda = lambda0;
    PS_CHECK(ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx));
    int st2 = ps_nl_fresh_factor(s, ctx);
    if (st2 < 0) return st2;
  }
  return status;
}

/* ---- arc-length (Riks/Crisfield) ---- */

/* q[n_free] = -dr_free/dlambda = fext_f - K_fp ubar_p, with the tangent of
 * the last evaluation with one (r_free = f_int,f(u_f, lambda ubar_p) -
 * lambda fext_f) */
static void load_vector(ps_solver *s, double *q) {
  const ps_nl_problem *sys = &s->prob;
  const double *fext = s->pd->fext;
  for (ps_int j = 0; j < sys->n_dof; j++) s->work_dof[j] = sys->fixed[j] ? s->ubar[j] : 0.0;
  ps_pd_coupling(s->pd, s->work_dof, q);
  for (ps_int k = 0; k < sys->n_free; k++)
    q[k] = (fext ? fext[sys->dof_of_free[k]] : 0.0) - q[k];
}

/* x = K_ff^-1 b by the direction strategy; or, once the tangent has
 * needed an indefinite factor (UMFPACK's or LDL^T's: softening or
 * perfectly plastic arms past a peak; s->indefinite), by a route of its
 * own: CG preconditioned by the factor of another indefinite matrix fails
 * at nearly every iteration there, and CHOLMOD's LL^T refuses K. For
 * models with family terms (whose LDL^T is slow: ldl_ok 0), first GMRES
 * preconditioned by the LL^T factor of the shifted current tangent
 * (ps_nl_shifted_gmres: a CHOLMOD factor instead of an LU of twice its
 * flops); where that fails, and for the others, a factor of the current
 * tangent made straight by LDL^T (UMFPACK where it meets a zero pivot).
 * fresh = 1: the tangent changed since the last call (a new iteration),
 * 0: the same tangent (the iteration's second right-hand side), whose
 * factor is reused. Returns PS_OK, PS_SINGULAR or fatal. */
static int solve_tangent(ps_solver *s, const double *b, double *x, int fresh, ps_ctx *ctx) {
  size_t bytes = (size_t)s->prob.n_free * sizeof *b;
  memcpy(s->rhs, b, bytes);
  int status;
  if (s->have_factor && s->indefinite) {
    if (fresh) s->lu_current = s->shifted_current = 0;
    status = PS_DIVERGED;
    if (!s->lu_current && !s->ldl_ok && s->opts.reuse_factor) {
      status = ps_nl_shifted_gmres(s, !s->shifted_current, ctx);
      if (status < 0) return status;
    }
    if (status != PS_OK) {
      if (!s->lu_current) {
        s->lu_first = 1;
        status = ps_nl_factor_tangent(s, ctx); /* sets lu_current */
        s->lu_first = 0;
        if (status != PS_OK) return status;
      }
      status = ps_linsolve_solve((ps_linsolve *)s->ls_last, s->rhs, s->du, ctx);
    }
  } else {
    status = ps_nl_direction(s, ctx);
  }
  if (status != PS_OK) return status;
  memcpy(x, s->du, bytes);
  return PS_OK;
}

/* The root x of A x^2 + B x + C = 0 whose increment turns least from the
 * current one (Crisfield): cos(x) = c0 + c1 x, the larger wins. Returns 0
 * when the roots are complex. */
static int crisfield_root(double A, double B, double C, double c0, double c1, double *x) {
  double disc = B * B - 4 * A * C;
  if (!(A > 0) || !(disc >= 0)) return 0;
  double q = -0.5 * (B + copysign(sqrt(disc), B));
  double x1 = q / A, x2 = q != 0 ? C / q : x1;
  *x = c0 + c1 * x1 >= c0 + c1 * x2 ? x1 : x2;
  return 1;
}

/* The constraint of a path-following step, c(u, lambda) = 0 with the
 * committed state (u_saved, lambda0) as its origin. predict: the load
 * factor increment of the tangent predictor u = u0 + dlam v (v = K^-1 q
 * at the committed state); correct: the correction x of lambda for the
 * Newton update du = dr + x v (dr = K^-1 (-r_free), v = K^-1 q at the
 * iterate); holds: 1 when the constraint is met at the iterate (checked
 * with the residual). predict and correct return 1, or 0 when they cannot
 * go on (the step fails with *reason), or a fatal status. */
typedef struct step_constraint {
  int (*predict)(ps_solver *s, void *c, const double *v, double *dlam, int *reason, ps_ctx *ctx);
  int (*correct)(ps_solver *s, void *c, const double *dr, const double *v, double *x,
                 int *reason, ps_ctx *ctx);
  int (*holds)(ps_solver *s, void *c);
  /* 1: an iterate whose residual grew more than tenfold is pulled back
   * halfway towards the last one, up to four times (dissipation: arms
   * that switch between yielding and elastic, or loading and unloading,
   * from one iterate to the next) */
  int damped;
} step_constraint;

/* 1 when free dof k is this process's (counted in the constraints'
 * sums; a share's ghost dofs are their owners') */
static inline int own_free(const ps_solver *s, ps_int k) {
  return !s->prob.owned_free || s->prob.owned_free[k];
}

/* arc-length: ||Du_f||^2 / U^2 + psi^2 Dlambda^2 = ds^2 */
typedef struct arc_constraint {
  double ds, psi, lambda0;
} arc_constraint;

static int arc_predict(ps_solver *s, void *data, const double *v, double *dlam, int *reason,
                       ps_ctx *ctx) {
  const arc_constraint *c = data;
  const ps_int nf = s->prob.n_free, *dof = s->prob.dof_of_free;
  double vv = 0, p2 = c->psi * c->psi;
  for (ps_int k = 0; k < nf; k++)
    if (own_free(s, k)) vv += v[k] * v[k];
  vv = ps_comm_sum1(s->prob.comm, vv);
  if (!(s->al_scale > 0)) {
    s->al_scale = sqrt(vv);
    if (!(s->al_scale > 0) || !isfinite(s->al_scale)) {
      (void)reason;
      return ps_error(ctx, PS_ERR_INPUT, "arc-length: the load moves no free dof (the "
                                         "tangent's response to the load is zero)");
    }
  }
  const double U2 = s->al_scale * s->al_scale;
  *dlam = c->ds / sqrt(vv / U2 + p2);
  if (s->al_have_dir) {
    double d = 0;
    for (ps_int k = 0; k < nf; k++)
      if (own_free(s, k)) d += (s->u_saved[dof[k]] - s->u_prev[dof[k]]) * v[k];
    d = ps_comm_sum1(s->prob.comm, d);
    if (d / U2 + p2 * (c->lambda0 - s->lambda_prev) < 0) *dlam = -*dlam;
  }
  return 1;
}

/* each iterate on the constraint: Crisfield's quadratic, its
 * linearisation where the roots are complex */
static int arc_correct(ps_solver *s, void *data, const double *dr, const double *v, double *x,
                       int *reason, ps_ctx *ctx) {
  const arc_constraint *c = data;
  const ps_int nf = s->prob.n_free, *dof = s->prob.dof_of_free;
  const double U2 = s->al_scale * s->al_scale, p2 = c->psi * c->psi, ds = c->ds;
  double dl = s->pd->lambda - c->lambda0;
  double m[6] = {0, 0, 0, 0, 0, 0};
  for (ps_int k = 0; k < nf; k++) {
    if (!own_free(s, k)) continue;
    double Du = s->u[dof[k]] - s->u_saved[dof[k]], w = Du + dr[k];
    m[0] += v[k] * v[k];
    m[1] += w * v[k];
    m[2] += w * w;
    m[3] += Du * v[k];
    m[4] += Du * w;
    m[5] += Du * Du;
  }
  ps_comm_sum(s->prob.comm, m, 6);
  const double a = m[0], b = m[1], cc = m[2], e = m[3], f = m[4], g = m[5];
  if (!crisfield_root(a / U2 + p2, 2 * (b / U2 + p2 * dl), cc / U2 + p2 * dl * dl - ds * ds,
                      f / U2 + p2 * dl * dl, e / U2 + p2 * dl, x)) {
    double den = 2 * (e / U2 + p2 * dl);
    *x = -(g / U2 + p2 * dl * dl - ds * ds + 2 * (f - g) / U2) / den;
    ps_log(ctx, 2, "    arc-length: complex roots, linearised constraint\n");
    if (!isfinite(*x)) {
      *reason = PS_NEWTON_NOT_FINITE;
      return 0;
    }
  }
  return 1;
}

static int arc_holds(ps_solver *s, void *data) {
  (void)s;
  (void)data;
  return 1; /* every iterate is on it */
}

/* dissipation: D(u, lambda) - tau = 0, D the energy the arms dissipate
 * from the committed state (ps_pd_dissipation), linearised with its
 * gradient g: dD = g_f . du_f + (g_p . ubar_p) dlambda */
typedef struct dissipation_constraint {
  double tau;
} dissipation_constraint;

/* dD/dlambda along du_f = x_f, du_p = ubar_p (g of the last evaluation;
 * on a share complete at its own dofs, which the sums count) */
static double dissipation_rate(const ps_solver *s, const double *g, const double *x) {
  const ps_nl_problem *sys = &s->prob;
  double r = 0;
  for (ps_int k = 0; k < sys->n_free; k++)
    if (own_free(s, k)) r += g[sys->dof_of_free[k]] * x[k];
  for (ps_int j = 0; j < sys->n_dof; j++)
    if (sys->fixed[j] && (!sys->owned || sys->owned[j])) r += g[j] * s->ubar[j];
  return ps_comm_sum1(sys->comm, r);
}

/* x = -(G + g_f . dr) / (dD/dlambda along v), G = D - tau; dr = NULL:
 * zero */
static int dissipation_update(ps_solver *s, const dissipation_constraint *c, const double *dr,
                              const double *v, double *x, int *reason) {
  const ps_int nf = s->prob.n_free, *dof = s->prob.dof_of_free;
  double G = ps_pd_dissipation(s->pd, s->al_g) - c->tau, gdr = 0;
  if (dr) {
    for (ps_int k = 0; k < nf; k++)
      if (own_free(s, k)) gdr += s->al_g[dof[k]] * dr[k];
    gdr = ps_comm_sum1(s->prob.comm, gdr);
  }
  double rate = dissipation_rate(s, s->al_g, v);
  *x = -(G + gdr) / rate;
  if (!isfinite(*x) || rate == 0.0) {
    *reason = PS_NEWTON_NO_DISSIPATION;
    return 0;
  }
  return 1;
}

/* at the committed state D = 0: dlam = tau / rate */
static int dissipation_predict(ps_solver *s, void *data, const double *v, double *dlam,
                               int *reason, ps_ctx *ctx) {
  (void)ctx;
  return dissipation_update(s, data, NULL, v, dlam, reason);
}

static int dissipation_correct(ps_solver *s, void *data, const double *dr, const double *v,
                               double *x, int *reason, ps_ctx *ctx) {
  (void)ctx;
  return dissipation_update(s, data, dr, v, x, reason);
}

/* met to 1e-2 of tau: the constraint only chooses the point of the path
 * (the dissipation committed is measured, whatever tau), and where an arm
 * sits at a kink (loading or unloading, yielding or elastic) the
 * equilibrium iterates can meet the residual's tolerance while D moves
 * in steps of that arm's share */
static int dissipation_holds(ps_solver *s, void *data) {
  const dissipation_constraint *c = data;
  return fabs(ps_pd_step_dissipation(s->pd) - c->tau) <= 1e-2 * fabs(c->tau);
}

static const step_constraint arc_length_constraint = {arc_predict, arc_correct, arc_holds, 0};
static const step_constraint dissipation_constraint_ops = {
    dissipation_predict, dissipation_correct, dissipation_holds, 1};

/* One path-following step from the last commit under constraint `con`:
 * the tangent predictor, then Newton on the bordered system (two
 * right-hand sides per iteration, exact directions, no line search). */
static int constrained_step(ps_solver *s, const step_constraint *con, void *c, const char *name,
                            ps_ctx *ctx) {
  const ps_nl_problem *sys = &s->prob;
  const ps_int nd = sys->n_dof, nf = sys->n_free, *dof = sys->dof_of_free;
  const double lambda0 = s->pd->lambda;
  int status = PS_OK, reason = PS_NEWTON_MAX_ITER;
  if (!s->al_q) {
    s->al_q = ps_calloc((size_t)nf, sizeof *s->al_q, ctx);
    s->al_v = ps_calloc((size_t)nf, sizeof *s->al_q, ctx);
    s->al_dr = ps_calloc((size_t)nf, sizeof *s->al_q, ctx);
    s->al_g = ps_calloc((size_t)nd, sizeof *s->al_g, ctx);
    if (!s->al_q || !s->al_v || !s->al_dr || !s->al_g) return PS_ERR_NOMEM;
  }
  /* no truncated directions: past a limit point K is indefinite, where
   * CG's truncated iterate would not solve the bordered system (the
   * predictor solves to cg_tolerance, the corrector to the forcing rule) */
  int truncate = s->opts.cg_truncate;
  s->opts.cg_truncate = 0;
  s->cg_rtol = s->opts.pcg_rtol;
  double *q = s->al_q, *v = s->al_v, *dr = s->al_dr;

  /* the tangent predictor at the committed state: du = dlam v, v =
   * K^-1 q */
  if ((status = ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx)) < 0) goto done;
  load_vector(s, q);
  if ((status = solve_tangent(s, q, v, 1, ctx)) < 0) goto done;
  if (status > 0) {
    reason = PS_NEWTON_SINGULAR;
    goto failed;
  }
  double dlam;
  int ok = con->predict(s, c, v, &dlam, &reason, ctx);
  if (ok < 0) {
    status = ok;
    goto done;
  }
  if (!ok) goto failed;
  for (ps_int k = 0; k < nf; k++) s->u[dof[k]] += dlam * v[k];
  set_lambda(s, lambda0 + dlam);

  /* the corrector: Newton on r_free = 0 and the constraint, its two
   * solves to the fixed forcing rule (cg_forcing; 0: exact). The adaptive
   * rule's loose first solves would move the load factor by the
   * constraint's response to CG's error. */
  ps_forcing forcing;
  ps_forcing_init(&forcing, 0, s->opts.cg_forcing_max, s->opts.cg_forcing, s->opts.pcg_rtol,
                  s->opts.tolerance);
  double rel0 = NAN, rel_last = INFINITY, lambda_last = lambda0, rel_best = INFINITY;
  int halvings = 0, it_best = 0;
  for (int it = 0;; it++) {
    double rn;
    if ((status = ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx)) < 0) goto done;
    double rel = ps_nl_relative_residual(&s->prob, s->f, &rn);
    s->last_iterations = it;
    s->last_residual = rel;
    ps_log(ctx, 2, "    %s %2d  |r|/|R| = %.3e  load factor = %.10g\n", name, it, rel,
           s->pd->lambda);
    if (!isfinite(rel) || !isfinite(s->energy)) {
      reason = PS_NEWTON_NOT_FINITE;
      goto failed;
    }
    if ((rel <= s->opts.tolerance || rn == 0.0) && con->holds(s, c)) break;
    if (it == 0) rel0 = rel;
    if (it >= s->opts.max_iterations || (it > 2 && rel > 1e6 * rel0)) {
      reason = PS_NEWTON_MAX_ITER;
      goto failed;
    }
    /* a corrector that has not lowered its best residual for a while,
     * far from the tolerance, is cycling among arm states (yielding or
     * elastic, loading or unloading) or wandering: a smaller step
     * converges sooner than the remaining iterations. (Near the
     * tolerance the residual can wander at round-off for a few
     * iterations and then converge.) */
    if (rel < rel_best) {
      rel_best = rel;
      it_best = it;
    } else if (it - it_best >= PS_CORRECTOR_PATIENCE &&
               rel_best > PS_CORRECTOR_FAR * s->opts.tolerance) {
      reason = PS_NEWTON_NO_PROGRESS;
      goto failed;
    }
    if (con->damped) {
      if (rel > 10 * rel_last && halvings < 4) {
        for (ps_int j = 0; j < nd; j++) s->u[j] = 0.5 * (s->u[j] + s->u_trial[j]);
        set_lambda(s, 0.5 * (s->pd->lambda + lambda_last));
        halvings++;
        continue;
      }
      halvings = 0;
      rel_last = rel;
      lambda_last = s->pd->lambda;
      memcpy(s->u_trial, s->u, (size_t)nd * sizeof *s->u);
    }
    load_vector(s, q);
    s->cg_rtol = ps_forcing_next(&forcing, rel);
    for (ps_int k = 0; k < nf; k++) s->work[k] = -s->f[dof[k]];
    if ((status = solve_tangent(s, s->work, dr, 1, ctx)) == PS_OK)
      status = solve_tangent(s, q, v, 0, ctx);
    if (status < 0) goto done;
    if (status > 0) {
      reason = PS_NEWTON_SINGULAR;
      goto failed;
    }
    s->newton_iterations++;
    double x;
    if (!con->correct(s, c, dr, v, &x, &reason, ctx)) goto failed;
    for (ps_int k = 0; k < nf; k++) s->u[dof[k]] += dr[k] + x * v[k];
    set_lambda(s, s->pd->lambda + x);
  }
  /* converged: the increment's start is the next predictor's reference */
  memcpy(s->u_prev, s->u_saved, (size_t)nd * sizeof *s->u);
  s->lambda_prev = lambda0;
  s->al_have_dir = 1;
  s->have_prev = 0;
  s->last_reason = PS_NEWTON_CONVERGED;
  goto done;
failed:
  s->last_reason = reason;
  s->have_prev = 0;
  ps_solver_restore(s);
  s->pd->lambda = lambda0;
  if ((status = ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx)) < 0) goto done;
  if ((status = ps_nl_fresh_factor(s, ctx)) < 0) goto done;
  status = PS_DIVERGED;
done:
  s->opts.cg_truncate = truncate;
  return status;
}

int ps_solver_arclength_step(ps_solver *s, double ds, double psi, ps_ctx *ctx) {
  arc_constraint c = {ds, psi, s->pd->lambda};
  return constrained_step(s, &arc_length_constraint, &c, "arc-length", ctx);
}

int ps_solver_dissipation_step(ps_solver *s, double tau, ps_ctx *ctx) {
  dissipation_constraint c = {tau};
  return constrained_step(s, &dissipation_constraint_ops, &c, "dissipation", ctx);
}

double ps_solver_dissipated(const ps_solver *s) { return s->dissipated; }

double ps_solver_step_dissipation(const ps_solver *s) { return ps_pd_step_dissipation(s->pd); }

int ps_solver_break_round(ps_solver *s, ps_int max_count, ps_int *n_broken,
                          ps_ctx *ctx) {
  return ps_solver_break_round_to(s, max_count, 0.0, n_broken, ctx);
}

int ps_solver_break_round_to(ps_solver *s, ps_int max_count, double tolerance,
                             ps_int *n_broken, ps_ctx *ctx) {
  PS_CHECK(ps_pd_break_arms(s->pd, max_count, n_broken, ctx));
  if (*n_broken == 0) return PS_OK;
  s->have_prev = 0; /* no secant predictor across a break */
  ps_log(ctx, 2, "    %lld arms broke, re-equilibrating\n", (long long)*n_broken);
  double tol = s->opts.tolerance;
  if (tolerance > tol) s->opts.tolerance = tolerance;
  int status = ps_newton_solve(s, ctx);
  s->opts.tolerance = tol;
  if (status != PS_OK) return status;
  ps_solver_commit(s);
  return PS_OK;
}

int ps_solver_resettle(ps_solver *s, ps_ctx *ctx) {
  ps_log(ctx, 2, "    re-equilibrating to solver.tolerance\n");
  int status = ps_newton_solve(s, ctx);
  if (status != PS_OK) return status;
  ps_solver_commit(s);
  return PS_OK;
}

int ps_solver_break_in_place(ps_solver *s, ps_int max_count, ps_int *n_broken, ps_ctx *ctx) {
  PS_CHECK(ps_pd_break_arms(s->pd, max_count, n_broken, ctx));
  if (*n_broken == 0) return PS_OK;
  s->have_prev = 0;
  /* forces, energy and tangent of the broken state; it becomes the
   * commit (its arm states are those of the converged one) */
  PS_CHECK(ps_nl_eval(s, s->u, s->f, &s->energy, 1, ctx));
  ps_solver_commit(s);
  return PS_OK;
}

int ps_solver_evaluate(ps_solver *s, ps_ctx *ctx) {
  return ps_nl_eval(s, s->u, s->f, &s->energy, 0, ctx);
}

double ps_solver_stored_energy(const ps_solver *s) {
  /* the work of the external forces is summed over the processes, the
   * first of which starts from the (global) energy less the dissipation,
   * so that one process adds in the order it always did */
  double psi = s->energy - ps_pd_step_dissipation(s->pd);
  if (!s->pd->fext) return psi;
  if (ps_comm_rank(s->prob.comm) > 0) psi = 0.0;
  for (ps_int j = 0; j < s->pd->sys.n_dof; j++)
    if (!s->prob.owned || s->prob.owned[j]) psi += s->pd->lambda * s->pd->fext[j] * s->u[j];
  return ps_comm_sum1(s->prob.comm, psi);
}

ps_int ps_solver_count_yielding(const ps_solver *s) { return ps_pd_count_yielding(s->pd); }

const ps_comm *ps_solver_comm(const ps_solver *s) { return s->prob.comm; }

const unsigned char *ps_solver_own_arm(const ps_solver *s) { return s->pd->model.own_arm; }

void ps_solver_get_stats(const ps_solver *s, ps_solver_stats *st) {
  memset(st, 0, sizeof *st);
  st->newton_iterations = s->newton_iterations;
  st->factorisations =
      s->ls.stats.n_factor + s->ls_fallback.stats.n_factor + s->ls_ldl.stats.n_factor;
  st->n_fallback = s->n_fallback;
  st->ldl_factorisations = s->ls_ldl.stats.n_factor;
  st->solves = s->ls.stats.n_solve + s->ls_fallback.stats.n_solve + s->ls_ldl.stats.n_solve;
  st->pcg_iterations = s->pcg_iterations;
  st->ksp_iterations = s->ls.stats.n_iterations + s->ls_pre.stats.n_iterations;
  st->pcg_failures = s->pcg_failures;
  st->pcg_skipped = s->pcg_skipped;
  st->majorant_factorisations = s->ls_pre.stats.n_factor;
  st->majorant_failures = s->pre_failures;
  st->shifted_steps = s->n_shifted;
  st->cg_truncated = s->pcg_truncated;
  st->gmres_iterations = s->gmres_iterations;
  st->stagnated = s->n_stagnated;
  st->handovers = s->n_handovers;
  st->line_search_cuts = s->n_line_search_cuts;
  st->loose_particles = s->pd->sys.loose_max;
  st->fragments = s->pd->sys.fragments_max;
  st->n_free = s->prob.n_free;
  st->threads = ps_team_size(s->team);
  st->parts = s->opts.parts;
  st->serial_share = s->have_majorant ? s->ls_pre.stats.serial_share : s->ls.stats.serial_share;
  st->nnz_tangent = ps_pd_nnz_tangent(s->pd);
  st->nnz_factor = s->ls.stats.nnz_factor;
  st->flops_factor = s->ls.stats.flops_factor;
  st->nnz_majorant_factor = s->ls_pre.stats.nnz_factor;
  st->t_assembly = s->pd->t_assembly;
  st->t_analyze =
      s->ls.stats.t_analyze + s->ls_fallback.stats.t_analyze + s->ls_ldl.stats.t_analyze;
  st->t_factor = s->ls.stats.t_factor + s->ls_fallback.stats.t_factor + s->ls_ldl.stats.t_factor;
  st->t_solve = s->ls.stats.t_solve + s->ls_fallback.stats.t_solve + s->ls_ldl.stats.t_solve;
  st->t_majorant_factor = s->ls_pre.stats.t_factor;
  st->t_cg = s->t_pcg;
}

double ps_solver_lambda(const ps_solver *s) { return s->pd->lambda; }
const double *ps_solver_u(const ps_solver *s) { return s->u; }
const double *ps_solver_force(const ps_solver *s) { return s->f; }
const double *ps_solver_arm_tension(const ps_solver *s) { return s->pd->sys.T; }
const double *ps_solver_arm_direction(const ps_solver *s) { return s->pd->sys.q; }
const double *ps_solver_arm_elongation(const ps_solver *s) { return s->pd->sys.dl; }
const ps_arm_state *ps_solver_arm_state(const ps_solver *s) { return &s->pd->st; }
int ps_solver_last_reason(const ps_solver *s) { return s->last_reason; }
double ps_solver_last_residual(const ps_solver *s) { return s->last_residual; }

/* ---- checkpoints ---- */

int ps_solver_keep_factors(ps_solver *s, ps_ctx *ctx) {
  s->keep_factors = 1;
  s->ls.keep_matrix = s->ls_pre.keep_matrix = 1;
  s->ls_fallback.keep_matrix = s->ls_ldl.keep_matrix = 1;
  if (!s->have_factor || !s->ls_last || s->ls_last->kept.n) return PS_OK;
  /* the factor at rest: the tangent of the last evaluation, unchanged
   * since ps_solver_create */
  if (s->ls_last != &s->ls)
    return ps_error(ctx, PS_ERR_INTERNAL, "ps_solver_keep_factors: call it right after "
                                          "ps_solver_create");
  ps_csc *A = NULL;
  PS_CHECK(s->prob.ops->assemble(s->prob.data, 0, &A, ctx));
  return ps_linsolve_keep(&s->ls, A, ctx);
}

/* the linear solvers by the numbers of ps_solver_factor_matrix (1..4) */
static ps_linsolve *linsolve_of(ps_solver *s, int which) {
  ps_linsolve *const all[] = {&s->ls, &s->ls_pre, &s->ls_fallback, &s->ls_ldl};
  return which >= 1 && which <= 4 ? all[which - 1] : NULL;
}

/* the items that make the solver's state: where it is, what it
 * committed, what its next step starts from */
static int state_items(ps_solver *s, ps_state_list *l, ps_ctx *ctx) {
  const size_t nd = (size_t)s->prob.n_dof * sizeof(double);
#define PS_ITEM(name, field) PS_CHECK(ps_state_add(l, name, &(field), sizeof(field), ctx))
  PS_CHECK(ps_state_add(l, "u", s->u, nd, ctx));
  PS_CHECK(ps_state_add(l, "u_saved", s->u_saved, nd, ctx));
  PS_CHECK(ps_state_add(l, "u_prev", s->u_prev, nd, ctx));
  PS_CHECK(ps_state_add(l, "f", s->f, nd, ctx));
  PS_ITEM("energy", s->energy);
  PS_ITEM("lambda", s->pd->lambda);
  PS_ITEM("lambda_prev", s->lambda_prev);
  PS_ITEM("lambda_saved", s->lambda_saved);
  PS_ITEM("have_prev", s->have_prev);
  PS_ITEM("have_factor", s->have_factor);
  PS_ITEM("al_scale", s->al_scale);
  PS_ITEM("al_have_dir", s->al_have_dir);
  PS_ITEM("dissipated", s->dissipated);
  PS_ITEM("cg_rtol", s->cg_rtol);
  PS_ITEM("last_reason", s->last_reason);
  PS_ITEM("last_iterations", s->last_iterations);
  PS_ITEM("last_residual", s->last_residual);
  ps_pd_step_dissipation(s->pd); /* computed before it is written (or read over) */
  PS_ITEM("pd.dissipation_step", s->pd->dissipation_step);
#undef PS_ITEM
  PS_CHECK(ps_arm_state_list(&s->pd->st, "st.", l, ctx));
  PS_CHECK(ps_arm_state_list(&s->pd->st_saved, "st_saved.", l, ctx));
  return ps_system_state_list(&s->pd->sys, l, ctx);
}

/* the items that count the work done: iterations, failures, times, the
 * backends' statistics; and those of the factor in use: its lag, the arms'
 * state it was made at */
static int counter_items(ps_solver *s, ps_state_list *l, ps_ctx *ctx) {
  const size_t na = (size_t)s->pd->net->n_arm;
  PS_CHECK(ps_state_add(l, "pd.arm_state_at_factor", s->pd->arm_state_at_factor, na + 1, ctx));
#define PS_ITEM(name, field) PS_CHECK(ps_state_add(l, name, &(field), sizeof(field), ctx))
  PS_ITEM("newton_iterations", s->newton_iterations);
  PS_ITEM("n_fallback", s->n_fallback);
  PS_ITEM("n_line_search_cuts", s->n_line_search_cuts);
  PS_ITEM("n_shifted", s->n_shifted);
  PS_ITEM("pcg_iterations", s->pcg_iterations);
  PS_ITEM("pcg_solves", s->pcg_solves);
  PS_ITEM("pcg_failures", s->pcg_failures);
  PS_ITEM("pcg_skipped", s->pcg_skipped);
  PS_ITEM("its_since_factor", s->its_since_factor);
  PS_ITEM("solves_since_factor", s->solves_since_factor);
  PS_ITEM("its_fresh", s->its_fresh);
  PS_ITEM("pre_failures", s->pre_failures);
  PS_ITEM("pcg_truncated", s->pcg_truncated);
  PS_ITEM("gmres_iterations", s->gmres_iterations);
  PS_ITEM("indefinite", s->indefinite);
  PS_ITEM("lu_current", s->lu_current);
  PS_ITEM("shifted_current", s->shifted_current);
  PS_ITEM("n_handovers", s->n_handovers);
  PS_ITEM("n_stagnated", s->n_stagnated);
  PS_ITEM("t_pcg", s->t_pcg);
  PS_ITEM("pd.t_assembly", s->pd->t_assembly);
  static const char *const ls_names[4][2] = {{"ls.stats", "ls.n_since_factor"},
                                             {"ls_pre.stats", "ls_pre.n_since_factor"},
                                             {"ls_umfpack.stats", "ls_umfpack.n_since_factor"},
                                             {"ls_ldl.stats", "ls_ldl.n_since_factor"}};
  for (int k = 0; k < 4; k++) {
    ps_linsolve *ls = linsolve_of(s, k + 1);
    PS_ITEM(ls_names[k][0], ls->stats);
    PS_ITEM(ls_names[k][1], ls->n_since_factor);
  }
#undef PS_ITEM
  return PS_OK;
}

int ps_solver_state_list(ps_solver *s, ps_state_list *l, ps_ctx *ctx) {
  PS_CHECK(state_items(s, l, ctx));
  return counter_items(s, l, ctx);
}

/* the bytes of l's items */
static size_t list_bytes(const ps_state_list *l) {
  size_t size = 0;
  for (int k = 0; k < l->n; k++) size += l->item[k].bytes;
  return size;
}

int ps_solver_snapshot_take(ps_solver *s, ps_solver_snapshot *snap, ps_ctx *ctx) {
  ps_state_list l = {0};
  int status = PS_OK;
  PS_CHECK_GOTO(state_items(s, &l, ctx));
  size_t size = list_bytes(&l);
  if (size > snap->cap) {
    void *p = realloc(snap->data, size);
    if (!p) {
      status = ps_error(ctx, PS_ERR_NOMEM, "out of memory for a copy of the solver's state "
                                           "(%zu bytes)", size);
      goto cleanup;
    }
    snap->data = p;
    snap->cap = size;
  }
  snap->size = 0;
  for (int k = 0; k < l.n; k++) {
    memcpy(snap->data + snap->size, l.item[k].data, l.item[k].bytes);
    snap->size += l.item[k].bytes;
  }
cleanup:
  ps_state_list_free(&l);
  return status;
}

int ps_solver_snapshot_restore(ps_solver *s, const ps_solver_snapshot *snap, ps_ctx *ctx) {
  ps_state_list l = {0};
  int status = PS_OK;
  PS_CHECK_GOTO(state_items(s, &l, ctx));
  if (list_bytes(&l) != snap->size) {
    status = ps_error(ctx, PS_ERR_INTERNAL, "a copy of the solver's state of %zu bytes does "
                      "not fit its %zu", snap->size, list_bytes(&l));
    goto cleanup;
  }
  size_t at = 0;
  for (int k = 0; k < l.n; k++) {
    memcpy(l.item[k].data, snap->data + at, l.item[k].bytes);
    at += l.item[k].bytes;
  }
  /* the tangent of the restored evaluation (assembled again from its
   * data, as after a restart), a fresh factor of it as after a failed
   * step */
  s->have_factor = 0;
  s->pd->sys.assembled = 0;
  status = ps_nl_fresh_factor(s, ctx);
cleanup:
  ps_state_list_free(&l);
  return status;
}

void ps_solver_snapshot_free(ps_solver_snapshot *snap) {
  free(snap->data);
  *snap = (ps_solver_snapshot){0};
}

int ps_solver_factor_matrix(const ps_solver *s, int *which, const ps_csc **A, ps_ctx *ctx) {
  *which = 0;
  *A = NULL;
  if (!s->keep_factors)
    return ps_error(ctx, PS_ERR_INTERNAL, "the solver keeps no factor matrices "
                                          "(ps_solver_keep_factors)");
  if (!s->have_factor || !s->ls_last) return PS_OK;
  for (int k = 1; k <= 4; k++)
    if (s->ls_last == linsolve_of((ps_solver *)s, k)) *which = k;
  if (!*which || s->ls_last->kept.n != s->prob.n_free)
    return ps_error(ctx, PS_ERR_INTERNAL, "the solver's last factor has no kept matrix");
  *A = &s->ls_last->kept;
  return PS_OK;
}

int ps_solver_state_restored(ps_solver *s, int which, const ps_csc *A, ps_ctx *ctx) {
  /* the linear solvers made on first need: created again with the
   * statistics read back (a backend that factored once exists) */
  const ps_linsolve_type *lazy[2] = {ps_linsolve_umfpack, ps_linsolve_cholmod_ldl};
  for (int k = 0; k < 2; k++) {
    ps_linsolve *ls = linsolve_of(s, 3 + k);
    if (ls->type || ls->stats.n_factor == 0) continue;
    ps_linsolve_stats st = ls->stats;
    int since = ls->n_since_factor;
    PS_CHECK(ps_linsolve_create(ls, lazy[k], ctx));
    ls->keep_matrix = s->keep_factors;
    ls->stats = st;
    ls->n_since_factor = since;
  }
  s->pd->sys.assembled = 0; /* assembled again from the restored tangent */
  if (which == 0) {
    s->have_factor = 0;
    return PS_OK;
  }
  ps_linsolve *ls = linsolve_of(s, which);
  /* the pattern it was made on: the majorant's or the tangent's */
  const ps_csc *pat = which == 2 ? &s->pd->sys_pre.A : &s->pd->sys.A;
  int fits = ls && ls->type && A && (which != 2 || s->pd->have_majorant) && A->n == pat->n &&
             !memcmp(A->p, pat->p, ((size_t)pat->n + 1) * sizeof *A->p) &&
             !memcmp(A->i, pat->i, (size_t)pat->p[pat->n] * sizeof *A->i);
  if (!fits)
    return ps_error(ctx, PS_ERR_INPUT, "the checkpoint's factor (%d, order %lld) does not fit "
                    "this solver (%lld free dofs, or another pattern)", which,
                    A ? (long long)A->n : -1LL, (long long)s->prob.n_free);
  ps_csc M = {pat->n, pat->p, pat->i, A->x}; /* the values on the solver's own pattern */
  ps_linsolve_stats st = ls->stats;
  int since = ls->n_since_factor;
  ps_int bad = -1;
  int status = ps_linsolve_factor(ls, &M, &bad, ctx);
  if (status < 0) return status;
  if (status != PS_OK)
    return ps_error(ctx, PS_ERR_INPUT, "the checkpoint's factor matrix does not factor again "
                    "(status %d): not this solver's checkpoint", status);
  ls->stats = st;
  ls->n_since_factor = since;
  s->ls_last = ls;
  s->have_factor = 1;
  return PS_OK;
}
