/* run.c: the load path of one case (increments, step cutting, breaking,
 * stopping rules, progress lines, outputs). */
#include "ps_app.h"

#include <gsl/gsl_math.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

/* per-particle and per-arm fields for the VTK and CSV files */
static int write_state(const ps_problem *pb, const ps_solver *s, const char *dir,
                       int step, int final, ps_ctx *ctx) {
  const ps_network *net = &pb->net;
  const ps_particles *P = &pb->P;
  int d = P->dim, status = PS_OK;
  ps_int n = P->n, na = net->n_arm;
  double *phi = ps_calloc((size_t)n, sizeof *phi, ctx);
  double *pstrain = ps_calloc((size_t)n, sizeof *phi, ctx);
  double *pplast = ps_calloc((size_t)n, sizeof *phi, ctx);
  double *astrain = ps_calloc((size_t)na, sizeof *phi, ctx);
  double *aplast = ps_calloc((size_t)na, sizeof *phi, ctx);
  double *abroken = ps_calloc((size_t)na, sizeof *phi, ctx);
  double *sigma = ps_calloc((size_t)(n * d * d), sizeof *phi, ctx);
  int ncomp = d == 2 ? 3 : 6; /* xx yy xy [zz yz xz] */
  static const char *const cname[6] = {"stress_xx", "stress_yy", "stress_xy",
                                       "stress_zz", "stress_yz", "stress_xz"};
  static const int cij[6][2] = {{0, 0}, {1, 1}, {0, 1}, {2, 2}, {1, 2}, {0, 2}};
  double *scomp = ps_calloc((size_t)(n * 6), sizeof *phi, ctx);
  if (!phi || !pstrain || !pplast || !astrain || !aplast || !abroken || !sigma || !scomp) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  ps_post_damage(net, &s->st, phi);
  double ey = pb->mat.yield_strain, delta = pb->mat.delta;
  for (ps_int i = 0; i < na; i++) {
    astrain[i] = s->sys.dl[i] / net->r0[i] / ey;
    aplast[i] = isfinite(delta) ? ps_arm_plastic_strain(&s->st, i, pb->mat.yield_rule) *
                                      net->r0[i] / delta
                                : 0.0;
    abroken[i] = s->st.broken[i];
    if (s->st.broken[i]) continue;
    ps_int e[2] = {net->a[i], net->b[i]};
    for (int k = 0; k < 2; k++) {
      if (fabs(astrain[i]) > fabs(pstrain[e[k]])) pstrain[e[k]] = astrain[i];
      if (aplast[i] > pplast[e[k]]) pplast[e[k]] = aplast[i];
    }
  }
  /* PD stress tensor, Eq. 24 of Fallah et al. (2020) */
  ps_post_stress_tensor(P, net, s->sys.T, s->sys.q, sigma);
  for (int c = 0; c < ncomp; c++)
    for (ps_int a = 0; a < n; a++)
      scomp[c * n + a] = sigma[a * d * d + cij[c][0] * d + cij[c][1]];
  char path[1200];
  ps_field pf[11] = {{"displacement", 3, s->u, d},
                     {"damage", 1, phi, 1},
                     {"arm_strain_over_eps_y", 1, pstrain, 1},
                     {"plastic_elongation_over_delta", 1, pplast, 1},
                     {"h", 1, P->h, 1}};
  int npf = 5;
  for (int c = 0; c < ncomp; c++) {
    ps_field fc = {cname[c], 1, &scomp[c * n], 1};
    pf[npf++] = fc;
  }
  ps_field af[3] = {{"arm_strain_over_eps_y", 1, astrain, 1},
                    {"plastic_elongation_over_delta", 1, aplast, 1},
                    {"broken", 1, abroken, 1}};
  snprintf(path, sizeof path, "%s/particles_%04d.vtk", dir, step);
  PS_CHECK_GOTO(ps_vtk_write(path, d, n, P->x, 0, NULL, NULL, pf, npf, NULL, 0, ctx));
  snprintf(path, sizeof path, "%s/arms_%04d.vtk", dir, step);
  PS_CHECK_GOTO(ps_vtk_write(path, d, n, P->x, na, net->a, net->b, pf, npf, af, 3, ctx));
  if (final) {
    ps_outfile o;
    snprintf(path, sizeof path, "%s/particles.csv", dir);
    PS_CHECK_GOTO(ps_outfile_open(&o, path, ctx));
    fprintf(o.f, d == 2 ? "id,x,y,ux,uy,damage,volume,mass,h,block"
                        : "id,x,y,z,ux,uy,uz,damage,volume,mass,h,block");
    for (int c = 0; c < ncomp; c++) fprintf(o.f, ",%s_Pa", cname[c]);
    fprintf(o.f, "\n");
    for (ps_int a = 0; a < n; a++) {
      fprintf(o.f, "%lld", (long long)a);
      for (int k = 0; k < d; k++) fprintf(o.f, ",%.10g", P->x[a * d + k]);
      for (int k = 0; k < d; k++) fprintf(o.f, ",%.10g", s->u[a * d + k]);
      fprintf(o.f, ",%.6g,%.6g,%.6g,%.6g,%d", phi[a], P->volume[a],
              pb->mat.rho * P->volume[a], P->h[a], P->block[a]);
      for (int c = 0; c < ncomp; c++) fprintf(o.f, ",%.6g", scomp[c * n + a]);
      fprintf(o.f, "\n");
    }
    PS_CHECK_GOTO(ps_outfile_commit(&o, ctx));
  }
cleanup:
  free(phi);
  free(pstrain);
  free(pplast);
  free(astrain);
  free(aplast);
  free(abroken);
  free(sigma);
  free(scomp);
  return status;
}

static void solver_opts_from_case(const ps_case *cs, ps_solver_opts *o) {
  ps_solver_opts_default(o);
  o->tolerance = cs->tolerance;
  o->max_iterations = cs->max_iterations;
  o->max_small_steps = cs->max_small_steps;
  o->line_search = cs->line_search;
  o->reuse_factor = cs->reuse_factor;
  o->pcg_rtol = cs->cg_tolerance;
  o->cg_forcing_adaptive = cs->cg_forcing_adaptive;
  o->cg_forcing = cs->cg_forcing;
  o->cg_forcing_max = cs->cg_forcing_max;
  o->pcg_max_iterations = cs->cg_max_iterations;
  o->pcg_skip_arms = cs->cg_skip_arms;
  o->majorant = cs->majorant;
  o->matrix_free = cs->matrix_free;
  o->cg_single_precision = cs->cg_single_precision;
  o->cg_truncate = cs->cg_truncate;
  o->reanalyze = cs->reanalyze;
  const ps_linsolve_type *t = ps_linsolve_type_find(cs->linear);
  if (t) o->linear = t;
}

int ps_failed_attempt_is_fracture(ps_int broken_total, double sig, double peak) {
  return broken_total > 0 && isfinite(peak) && sig < peak;
}

const char *ps_fmt_or_na(double v, int digits, char *buf, size_t len) {
  if (isfinite(v))
    snprintf(buf, len, "%.*g", digits, v);
  else
    snprintf(buf, len, "n/a");
  return buf;
}

/* converged increments whose boundary stresses tell a falling load */
#define PS_RECENT 3

/* One run along the load path: what its parts share. */
typedef struct run_state {
  ps_problem *pb;
  ps_material mat;          /* pb->mat with this run's delta */
  ps_solver s;
  ps_run_result *res;
  const char *out_dir;      /* NULL: no outputs */
  char staging[1200];       /* out_dir.partial, "" without outputs */
  FILE *hist;               /* staging/history.csv */
  char stall_msg[2048];     /* the error of a stalled run */
  double t0;                /* wall seconds at the start */
  double peak;              /* peak boundary stress of the settled states */
  ps_int broken_total;      /* arms broken so far */
  double recent[PS_RECENT]; /* boundary stresses of the last converged
                               increments, the newest last */
  int n_recent;
} run_state;

/* Stage the outputs: an empty out_dir.partial (ps_outdir_prepare has
 * checked it is ours) with history.csv's header. */
static int open_outputs(run_state *r, ps_ctx *ctx) {
  char path[1300];
  snprintf(r->staging, sizeof r->staging, "%s.partial", r->out_dir);
  PS_CHECK(ps_outdir_fresh(r->staging, ctx));
  snprintf(path, sizeof path, "%s/history.csv", r->staging);
  r->hist = fopen(path, "w");
  if (!r->hist) return ps_error(ctx, PS_ERR_IO, "%s: cannot open for writing", path);
  fprintf(r->hist, "step,load_factor,boundary_stress_Pa,stress_over_sigma_y,"
                   "newton_iterations,relative_residual,converged,arms_yielding,arms_broken,"
                   "crack_tip_over_c,wall_s\n");
  return PS_OK;
}

static void history_row(run_state *r, int step, int its, int converged, ps_int ny,
                        double sig, double tip) {
  char b[6][32];
  if (!r->hist) return;
  fprintf(r->hist, "%d,%s,%s,%s,%d,%s,%d,%lld,%lld,%s,%.4f\n", step,
          ps_fmt_or_na(r->s.lambda, 10, b[0], 32), ps_fmt_or_na(sig, 10, b[1], 32),
          ps_fmt_or_na(sig / r->mat.sigma_y, 10, b[2], 32), its,
          ps_fmt_or_na(r->s.last_residual, 4, b[3], 32), converged, (long long)ny,
          (long long)r->broken_total, ps_fmt_or_na(tip, 6, b[4], 32),
          ps_wtime() - r->t0);
  fflush(r->hist); /* tail -f history.csv follows the run */
}

/* SIGINT or SIGTERM received: the run ends here (res->interrupted) */
static int interrupted(run_state *r) {
  int sig = ps_signal_received();
  if (!sig) return 0;
  r->res->interrupted = sig;
  snprintf(r->res->stop_reason, sizeof r->res->stop_reason,
           "interrupted by %s at load factor %.6g", ps_signal_name(sig), r->s.lambda);
  return 1;
}

/* Fracture rounds at the load just reached, until no arm breaks; stop
 * early once the load has dropped past path.stop_load_drop of its peak or
 * the tip has passed path.stop_crack_tip (the crack has run), or on a
 * signal. *nb = arms broken, *settle = the last round's status, *settled
 * = 1 when no arm is left past delta. */
static int break_rounds(run_state *r, ps_int its0, double tip_start, ps_int *nb, int *settle,
                        int *settled, ps_ctx *ctx) {
  ps_problem *pb = r->pb;
  const ps_case *cs = &pb->cs;
  ps_solver *s = &r->s;
  int rounds = 0;
  double t_note = ps_wtime(); /* long increments print a line every 10 s */
  *nb = 0;
  for (;;) {
    ps_int nr, limit = 0;
    *settle = ps_solver_break_round(s, 0, &nr, ctx);
    /* re-equilibration failed: go back and break fewer arms, the worst
     * first, halving down to one; only if one arm cannot be broken and
     * re-equilibrated does the run end as unstable */
    while (*settle == PS_DIVERGED && nr > 1) {
      limit = nr / 2;
      ps_solver_restore(s);
      ps_log(ctx, 2, "    re-equilibration failed: breaking the worst %lld arms only\n",
             (long long)limit);
      *settle = ps_solver_break_round(s, limit, &nr, ctx);
      r->res->gentle_rounds++;
    }
    if (*settle < 0) return *settle;
    *nb += nr;
    *settled = *settle == PS_OK && nr == 0; /* no arm left past delta */
    if (*settle != PS_OK || nr == 0 || ps_signal_received()) return PS_OK;
    if (ps_wtime() - t_note > 10.0) {
      t_note = ps_wtime();
      ps_log(ctx, 1, "         ... load factor %.5f: breaking round %d, %lld arms broken "
                     "so far, %lld Newton iterations\n",
             s->lambda, rounds + 1, (long long)(r->broken_total + *nb),
             (long long)(s->newton_iterations - its0));
    }
    double sr = ps_post_boundary_stress(&pb->net, s->sys.T, s->sys.q, pb->measure,
                                        pb->measure_length);
    double tr = pb->c > 0 ? ps_post_crack_tip(&pb->P, &pb->net, &s->st, pb->c) : 0.0;
    if (sr < cs->stop_load_drop * fmax(r->peak, sr) ||
        (pb->c > 0 && tr >= cs->stop_crack_tip) ||
        (pb->c > 0 && cs->stop_tip_advance > 0 && tr - tip_start >= cs->stop_tip_advance))
      return PS_OK; /* the crack has run: the stop rules end the run */
    if (++rounds >= cs->max_break_rounds)
      return ps_error(ctx, PS_ERR_SOLVER,
                      "%s: arms still breaking after %d re-equilibrations at load "
                      "factor %.6g (path.max_break_rounds)",
                      cs->path, rounds, s->lambda);
  }
}

/* 1 when this model and delta can break arms */
static int model_breaks(const run_state *r) {
  const ps_model_type *type = ps_model_type_find(r->pb->cs.model);
  return type && type->break_arms != ps_model_never_breaks && r->mat.delta > 0 &&
         isfinite(r->mat.delta);
}

/* 1 when the last converged increments' boundary stresses fell */
static int load_falling(const run_state *r) {
  int n = r->n_recent < PS_RECENT ? r->n_recent : PS_RECENT;
  if (n < 2) return 0;
  for (int k = PS_RECENT - n + 1; k < PS_RECENT; k++)
    if (!(r->recent[k] < r->recent[k - 1])) return 0;
  return 1;
}

/* What a Newton stall showed and what can help, from what the run knows:
 * arms broken or not, the load falling, an indefinite tangent (negative
 * curvature in CG, shifted steps, non-positive pivots). *softens = 1 when
 * the model itself softens (the load fell with an indefinite tangent and
 * no arm broken): then smaller steps or another factorisation cannot help. */
static void stall_advice(const run_state *r, char *buf, size_t len, int *softens) {
  const ps_solver *s = &r->s;
  const ps_material *m = &r->mat;
  const ps_model_type *type = ps_model_type_find(r->pb->cs.model);
  ps_int indefinite = s->pcg_truncated + s->n_shifted + s->n_fallback;
  int falling = load_falling(r), breaks = model_breaks(r);
  char arms[64];
  if (r->broken_total > 0)
    snprintf(arms, sizeof arms, "%lld arms had broken", (long long)r->broken_total);
  else if (breaks)
    snprintf(arms, sizeof arms, "no arm had broken");
  else if (type && type->break_arms != ps_model_never_breaks)
    snprintf(arms, sizeof arms, "no arm can break (delta is infinite)");
  else
    snprintf(arms, sizeof arms, "this model does not break arms");
  *softens = falling && indefinite > 0 && r->broken_total == 0;
  size_t l = (size_t)snprintf(buf, len, "Seen: %s%s%s.", arms,
                              falling ? "; the boundary stress was falling over the last "
                                        "converged increments" : "",
                              indefinite > 0 ? "; the tangent turned indefinite" : "");
  if (l >= len) return;
  if (!isfinite(s->last_residual)) {
    snprintf(buf + l, len - l, " The residual is not finite: the forces overflow; check "
                               "material.E and the units of the case");
    return;
  }
  if (!*softens) {
    snprintf(buf + l, len - l, " Try a smaller path.load_step or solver.linear: umfpack");
    return;
  }
  if (type == ps_model_fibre &&
      m->plane == PS_PLANE_STRESS && m->nu < 1.0 / 3.0 && m->yield_rule == PS_YIELD_TOTAL)
    l += (size_t)snprintf(buf + l, len - l,
                          " The model itself softens: the fibre model in plane stress with "
                          "nu = %g < 1/3 under yield_rule total turns its family coefficient "
                          "negative as arms yield; use material.plane: strain, "
                          "material.yield_rule: deviatoric, or nu >= 1/3.", m->nu);
  else
    l += (size_t)snprintf(buf + l, len - l,
                          " The model itself softens (the load fell with no arm broken): "
                          "end the path before this load (path.max_load) or change the "
                          "material.");
  if (l < len)
    snprintf(buf + l, len - l, " A smaller path.load_step or solver.linear: umfpack will "
                               "not help");
}

/* Newton failed below path.min_step at load factor target: the run stalls */
static void newton_stalled(run_state *r, double target) {
  const ps_case *cs = &r->pb->cs;
  const ps_solver *s = &r->s;
  char advice[700], res_e[32] = "n/a", res_g[32] = "n/a";
  int softens;
  stall_advice(r, advice, sizeof advice, &softens);
  if (isfinite(s->last_residual)) {
    snprintf(res_e, sizeof res_e, "%.3e", s->last_residual);
    snprintf(res_g, sizeof res_g, "%.2e", s->last_residual);
  }
  r->res->stalled = 1;
  r->res->fractured = 0;
  snprintf(r->stall_msg, sizeof r->stall_msg,
           "%s: Newton diverged at load factor %.6g (%s; the increment is below "
           "path.min_step = %g; last relative residual %s). %s",
           cs->path, target, ps_newton_reason_text(s->last_reason), cs->min_step, res_e,
           advice);
  snprintf(r->res->stop_reason, sizeof r->res->stop_reason,
           "Newton stalled at load factor %.6g (increments below path.min_step did not "
           "converge, last residual %s) %s",
           target, res_g,
           r->broken_total > 0 ? "before the crack ran"
           : softens           ? "as the model softened, no arm broken"
           : model_breaks(r)   ? "before any arm broke"
                               : "(no arm can break)");
}

/* the final re-equilibration at load lambda did not converge */
static void reequilibration_failed(run_state *r, double sig) {
  const ps_case *cs = &r->pb->cs;
  ps_run_result *res = r->res;
  double lambda = r->s.lambda;
  /* a crack that runs at fixed displacement sheds load; a failed attempt
   * carrying at least the peak stress shows no fracture, only a solve
   * that failed (counted like a Newton stall: sigma_failure is then a
   * lower bound). The same rule reclassifies older runs (reuse_run). */
  if (ps_failed_attempt_is_fracture(r->broken_total, sig, r->peak)) {
    res->fractured = 1;
    snprintf(res->stop_reason, sizeof res->stop_reason,
             "re-equilibration after breaking arms did not converge at load factor "
             "%.5g: the crack ran unstably (outputs show the last attempt)", lambda);
    return;
  }
  res->stalled = 1;
  snprintf(r->stall_msg, sizeof r->stall_msg,
           "%s: re-equilibration after breaking arms did not converge at load "
           "factor %.6g with the boundary stress not below its peak (the crack had "
           "not run; last relative residual %.3e). Try a smaller "
           "path.load_step_after_break",
           cs->path, lambda, r->s.last_residual);
  snprintf(res->stop_reason, sizeof res->stop_reason,
           "re-equilibration after breaking arms did not converge at load factor "
           "%.5g with the load not below its peak: stalled before the crack ran", lambda);
}

/* The stop rules after a settled increment; 1 when the run ends here. */
static int stop_rule(run_state *r, int converged, double sig, double tip, double tip_start) {
  const ps_problem *pb = r->pb;
  const ps_case *cs = &pb->cs;
  ps_run_result *res = r->res;
  if (converged && pb->c > 0 && cs->stop_tip_advance > 0 &&
      tip - tip_start >= cs->stop_tip_advance) {
    res->fractured = 1;
    snprintf(res->stop_reason, sizeof res->stop_reason,
             "the crack tip advanced %.3g c at one load (from %.4g c to %.4g c): it "
             "runs unstably", tip - tip_start, tip_start, tip);
    return 1;
  }
  if (pb->c > 0 && tip >= cs->stop_crack_tip) {
    res->fractured = 1;
    snprintf(res->stop_reason, sizeof res->stop_reason,
             "crack tip passed %.3g c from the centre", cs->stop_crack_tip);
    return 1;
  }
  if (r->broken_total > 0 && sig < cs->stop_load_drop * r->peak) {
    res->fractured = 1;
    snprintf(res->stop_reason, sizeof res->stop_reason,
             "boundary stress fell below %.3g of its peak", cs->stop_load_drop);
    return 1;
  }
  if (r->s.lambda >= cs->max_load) { /* exact: target snaps to max_load */
    snprintf(res->stop_reason, sizeof res->stop_reason, "path.max_load = %g reached: %s",
             cs->max_load,
             r->broken_total ? "arms broke but the crack did not run" : "no fracture");
    return 1;
  }
  return 0;
}

/* The increments: step, cut on a Newton failure, break arms, record,
 * stop. Returns PS_OK (the reason is in res) or a fatal status. */
static int load_path(run_state *r, ps_ctx *ctx) {
  ps_problem *pb = r->pb;
  const ps_case *cs = &pb->cs;
  ps_solver *s = &r->s;
  ps_run_result *res = r->res;
  double dl_nominal = cs->load_step, dl = dl_nominal;
  int good_in_a_row = 0;
  snprintf(res->stop_reason, sizeof res->stop_reason, "max_increments reached (%d)",
           cs->max_increments);
  for (int step = 1; step <= cs->max_increments && !interrupted(r); step++) {
    double target = s->lambda + dl;
    if (target > cs->max_load - 1e-9 * dl) target = cs->max_load; /* no sliver */
    ps_int its0 = s->newton_iterations, nb;
    int status = ps_solver_step(s, target, ctx);
    if (status < 0) return status;
    if (status == PS_DIVERGED) {
      res->step_cuts++;
      dl *= 0.5;
      good_in_a_row = 0;
      ps_log(ctx, 1, "  step %d: Newton did not converge at load factor %.6g (%s, "
                     "residual %.2e); cutting the increment to %.4g\n",
             step, target, ps_newton_reason_text(s->last_reason), s->last_residual, dl);
      if (dl < cs->min_step) {
        /* the run ends here: an error for `run` (after the summary is
         * written to the partial output), a result for the sweep */
        newton_stalled(r, target);
        return PS_OK;
      }
      step--;
      continue;
    }
    ps_solver_commit(s);
    int settle, settled = 0;
    double tip_start = pb->c > 0 ? ps_post_crack_tip(&pb->P, &pb->net, &s->st, pb->c) : 0.0;
    PS_CHECK(break_rounds(r, its0, tip_start, &nb, &settle, &settled, ctx));
    r->broken_total += nb;
    if (r->broken_total > 0) dl_nominal = fmin(dl_nominal, cs->load_step_after_break);
    if (++good_in_a_row >= 2 && dl < dl_nominal) dl = fmin(2 * dl, dl_nominal);
    if (dl > dl_nominal) dl = dl_nominal;
    int converged = settle == PS_OK;
    if (!converged) /* make T, q, dl those of u (a rejected trial may linger) */
      PS_CHECK(ps_solver_evaluate(s, ctx));
    double sig = ps_post_boundary_stress(&pb->net, s->sys.T, s->sys.q, pb->measure,
                                        pb->measure_length);
    double tip = pb->c > 0 ? ps_post_crack_tip(&pb->P, &pb->net, &s->st, pb->c) : 0.0;
    ps_int ny = ps_solver_count_yielding(s);
    int its = (int)(s->newton_iterations - its0);
    res->increments = step;
    /* only a state that is converged and settled (no arm left past delta;
     * a stop rule may end the rounds early) sets the peak */
    if (converged && settled && sig > r->peak) {
      r->peak = sig;
      res->lambda_peak = s->lambda;
    }
    if (converged) {
      memmove(r->recent, r->recent + 1, (PS_RECENT - 1) * sizeof *r->recent);
      r->recent[PS_RECENT - 1] = sig;
      r->n_recent++;
    }
    ps_log(ctx, 1, "  %4d %9.5f %10.5f %6d %9.2e %8lld %7lld %6.2f\n", step, s->lambda,
           sig / r->mat.sigma_y, its, s->last_residual, (long long)ny,
           (long long)r->broken_total, tip);
    history_row(r, step, its, converged, ny, sig, tip);
    if (r->out_dir && cs->fields && cs->vtk_every > 0 && step % cs->vtk_every == 0)
      PS_CHECK(write_state(pb, s, r->staging, step, 0, ctx));
    if (converged) res->crack_tip = tip;
    if (!converged) {
      reequilibration_failed(r, sig);
      return PS_OK;
    }
    if (interrupted(r) || stop_rule(r, converged, sig, tip, tip_start)) return PS_OK;
  }
  return PS_OK;
}

/* the solver's counters and timings into res */
static void collect_stats(run_state *r) {
  const ps_solver *s = &r->s;
  ps_run_result *res = r->res;
  res->sigma_peak = r->peak;
  res->newton_iterations = s->newton_iterations;
  res->factorisations = s->ls.stats.n_factor + s->ls_fallback.stats.n_factor;
  res->arms_broken = r->broken_total;
  res->n_fallback = s->n_fallback;
  res->pcg_iterations = s->pcg_iterations;
  res->pcg_failures = s->pcg_failures;
  res->pcg_skipped = s->pcg_skipped;
  res->majorant_factorisations = s->ls_pre.stats.n_factor;
  res->majorant_failures = s->pre_failures;
  res->shifted_steps = s->n_shifted;
  res->cg_truncated = s->pcg_truncated;
  res->stagnated = s->n_stagnated;
  res->handovers = s->n_handovers;
  res->threads = ps_team_size(s->team);
  res->serial_share = s->sys_pre.net ? s->ls_pre.stats.serial_share : s->ls.stats.serial_share;
  res->line_search_cuts = s->n_line_search_cuts;
  res->t_majorant_factor = s->ls_pre.stats.t_factor;
  res->nnz_majorant_factor = s->ls_pre.stats.nnz_factor;
  res->t_cg = s->t_pcg;
  res->solves = s->ls.stats.n_solve + s->ls_fallback.stats.n_solve;
  res->nnz_tangent = (double)s->sys.A.p[s->sys.n_free];
  res->nnz_factor = s->ls.stats.nnz_factor;
  res->flops_factor = s->ls.stats.flops_factor;
  res->t_assembly = s->t_assembly;
  res->t_analyze = s->ls.stats.t_analyze + s->ls_fallback.stats.t_analyze;
  res->t_factor = s->ls.stats.t_factor + s->ls_fallback.stats.t_factor;
  res->t_solve = s->ls.stats.t_solve + s->ls_fallback.stats.t_solve;
  res->wall = ps_wtime() - r->t0;
}

static void log_end(const run_state *r, const ps_ctx *ctx) {
  const ps_run_result *res = r->res;
  char b[32];
  if (r->pb->measure_length > 0)
    ps_log(ctx, 1, "# end: %s\n# sigma_failure = %s Pa = %.5f sigma_y (peak at load "
                   "factor %.5g)%s; %lld increments, %lld Newton iterations, %.2f s\n",
           res->stop_reason, ps_fmt_or_na(r->peak, 6, b, sizeof b),
           r->peak / r->mat.sigma_y, res->lambda_peak,
           res->fractured ? "" : " [no fracture]", (long long)res->increments,
           (long long)res->newton_iterations, res->wall);
  else /* no measure: loaded by tractions or unmeasured displacements */
    ps_log(ctx, 1, "# end: %s\n# no boundary-stress measure (loading.boundary has no "
                   "measure: true): the stress column is 0; %lld increments, %lld Newton "
                   "iterations, %.2f s\n",
           res->stop_reason, (long long)res->increments, (long long)res->newton_iterations,
           res->wall);
}

/* "key: value" with `digits` significant digits, n/a when not finite */
static void put_g(FILE *f, const char *key, double v, int digits) {
  char b[40];
  fprintf(f, "%s: %s\n", key, ps_fmt_or_na(v, digits, b, sizeof b));
}

/* "key: value" with `decimals` decimals, n/a when not finite */
static void put_f(FILE *f, const char *key, double v, int decimals) {
  if (isfinite(v))
    fprintf(f, "%s: %.*f\n", key, decimals, v);
  else
    fprintf(f, "%s: n/a\n", key);
}

/* J of the final state (Eq. 39) around cs->j_tip, appended to summary.txt */
static int write_j_integral(const run_state *r, FILE *f, ps_ctx *ctx) {
  const ps_problem *pb = r->pb;
  const ps_case *cs = &pb->cs;
  const ps_solver *s = &r->s;
  double *sig = ps_calloc(4 * (size_t)pb->P.n, sizeof *sig, ctx);
  double *H = ps_calloc(4 * (size_t)pb->P.n, sizeof *H, ctx);
  if (!sig || !H) {
    free(sig);
    free(H);
    return ps_error(ctx, PS_ERR_NOMEM, "J-integral: out of memory");
  }
  ps_post_stress_tensor(&pb->P, &pb->net, s->sys.T, s->sys.q, sig);
  ps_post_displacement_gradient(&pb->P, &pb->net, &s->st, s->u, H);
  for (int i = 0; i < cs->n_j_rings; i++) {
    double l = cs->j_rings[i];
    double J = ps_post_j_domain(&pb->P, sig, H, cs->j_tip, 0.5 * l, l);
    double Jc = ps_post_j_contour(&pb->P, &pb->net, s->sys.T, s->sys.q, sig, H, cs->j_tip, l,
                                  cs->spacing);
    char key[96];
    snprintf(key, sizeof key, "j_domain_ring_%.6gm_N_per_m", l);
    put_g(f, key, J, 8);
    snprintf(key, sizeof key, "j_contour_%.6gm_N_per_m", l);
    put_g(f, key, Jc, 8);
    ps_log(ctx, 1, "# J-integral around (%.6g, %.6g), square of half-width %.4g m: "
                   "%.6g N/m (domain form, Eq. 39, q from l/2 to l), %.6g N/m (contour "
                   "form, Eq. 36)\n",
           cs->j_tip[0], cs->j_tip[1], l, J, Jc);
  }
  free(sig);
  free(H);
  return PS_OK;
}

/* staging/summary.txt: "key: value" lines, n/a for non-finite numbers */
static int write_summary(const run_state *r, double delta, ps_ctx *ctx) {
  const ps_problem *pb = r->pb;
  const ps_run_result *res = r->res;
  char path[1300];
  ps_outfile o;
  snprintf(path, sizeof path, "%s/summary.txt", r->staging);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  FILE *f = o.f;
  fprintf(f, "case: %s\nparticles: %lld\narms: %lld\nfree_dofs: %lld\n", pb->cs.name,
          (long long)pb->P.n, (long long)pb->net.n_arm, (long long)r->s.sys.n_free);
  put_g(f, "delta_m", delta, 10);
  put_g(f, "sigma_y_Pa", r->mat.sigma_y, 10);
  put_g(f, "sigma_failure_Pa", r->peak, 10);
  put_g(f, "sigma_failure_over_sigma_y", r->peak / r->mat.sigma_y, 8);
  put_g(f, "load_factor_at_peak", res->lambda_peak, 8);
  fprintf(f, "fractured: %s\nstalled: %s\nstop_reason: %s\nincrements: %lld\n"
             "newton_iterations: %lld\nfactorisations: %lld\numfpack_fallbacks: %lld\n"
             "step_cuts: %lld\ngentle_rounds: %lld\narms_broken: %lld\n",
          res->fractured ? "yes" : "no", res->stalled ? "yes" : "no", res->stop_reason,
          (long long)res->increments, (long long)res->newton_iterations,
          (long long)res->factorisations, (long long)res->n_fallback,
          (long long)res->step_cuts, (long long)res->gentle_rounds,
          (long long)res->arms_broken);
  put_g(f, "crack_tip_over_c", res->crack_tip, 6);
  put_f(f, "wall_s", res->wall, 3);
  put_f(f, "assembly_s", res->t_assembly, 3);
  put_f(f, "analyze_s", res->t_analyze, 3);
  put_f(f, "factor_s", res->t_factor, 3);
  put_f(f, "solve_s", res->t_solve, 3);
  put_f(f, "network_s", pb->t_network, 3);
  put_f(f, "peak_memory_MiB", ps_peak_mib(), 1);
  fprintf(f, "cg_iterations: %lld\ncg_failures: %lld\ncg_skipped: %lld\nsolves: %lld\n",
          (long long)res->pcg_iterations, (long long)res->pcg_failures,
          (long long)res->pcg_skipped, (long long)res->solves);
  put_f(f, "nnz_tangent_upper", res->nnz_tangent, 0);
  put_f(f, "nnz_factor", res->nnz_factor, 0);
  put_g(f, "flops_factor", res->flops_factor, 4);
  fprintf(f, "majorant_factorisations: %lld\nmajorant_cg_failures: %lld\n",
          (long long)res->majorant_factorisations, (long long)res->majorant_failures);
  put_f(f, "majorant_factor_s", res->t_majorant_factor, 3);
  put_f(f, "majorant_nnz_factor", res->nnz_majorant_factor, 0);
  put_f(f, "cg_s", res->t_cg, 3);
  fprintf(f, "shifted_steps: %lld\ncg_truncated: %lld\nnewton_stagnated: %lld\n"
             "line_search_cuts: %lld\nnewton_handovers: %lld\nthreads: %d\n",
          (long long)res->shifted_steps, (long long)res->cg_truncated,
          (long long)res->stagnated, (long long)res->line_search_cuts,
          (long long)res->handovers, res->threads);
  put_f(f, "preconditioner_serial_share", res->serial_share, 3);
  fprintf(f, "case_fingerprint: %016llx\n", (unsigned long long)ps_case_fingerprint(&pb->cs));
  if (pb->cs.n_j_rings > 0 && pb->P.dim == 2) {
    int status = write_j_integral(r, f, ctx);
    if (status < 0) {
      ps_outfile_abort(&o);
      return status;
    }
  }
  return ps_outfile_commit(&o, ctx);
}

/* The final state, history.csv and summary.txt into staging; then staging
 * replaces out_dir when commit is set. */
static int finish_outputs(run_state *r, double delta, int commit, ps_ctx *ctx) {
  if (r->pb->cs.fields)
    PS_CHECK(write_state(r->pb, &r->s, r->staging, r->res->increments, 1, ctx));
  int bad = ferror(r->hist);
  bad |= fclose(r->hist) != 0;
  r->hist = NULL;
  if (bad) return ps_error(ctx, PS_ERR_IO, "%s/history.csv: write failed", r->staging);
  PS_CHECK(write_summary(r, delta, ctx));
  if (commit) PS_CHECK(ps_dir_commit(r->staging, r->out_dir, ctx));
  return PS_OK;
}

/* The solver, created with SIGINT and SIGTERM blocked: its threads
 * inherit the mask, so the signals go to the thread that runs the load
 * path and ps_dir_commit's blocking holds them off. */
static int create_solver(run_state *r, ps_ctx *ctx) {
  ps_problem *pb = r->pb;
  const ps_case *cs = &pb->cs;
  ps_solver_opts opts;
  sigset_t block, saved;
  solver_opts_from_case(cs, &opts);
  opts.threads = pb->threads;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &block, &saved);
  int status = ps_solver_create(&r->s, &pb->P, &pb->net, ps_model_type_find(cs->model),
                                &r->mat, pb->fixed, pb->ubar, &opts, ctx);
  pthread_sigmask(SIG_SETMASK, &saved, NULL);
  if (status == PS_ERR_INPUT && strncmp(ctx->msg, cs->path, strlen(cs->path)) != 0) {
    char m[sizeof ctx->msg];
    snprintf(m, sizeof m, "%s", ctx->msg);
    ps_error(ctx, PS_ERR_INPUT, "%s: %s", cs->path, m); /* name the case file */
  }
  return status;
}

static int run_case(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                    ps_solver *keep, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  int status = PS_OK;
  run_state r;
  memset(&r, 0, sizeof r);
  memset(res, 0, sizeof *res);
  r.pb = pb;
  r.res = res;
  r.out_dir = out_dir;
  r.t0 = ps_wtime();
  r.peak = -INFINITY;
  r.mat = pb->mat;
  r.mat.delta = delta;
  res->sigma_y = r.mat.sigma_y;
  /* the folders are checked before anything is computed: only a folder
   * of ours is replaced, a result lost in a commit's rename is restored */
  if (out_dir) PS_CHECK_GOTO(ps_outdir_prepare(out_dir, ctx));
  PS_CHECK_GOTO(create_solver(&r, ctx));
  if (out_dir) PS_CHECK_GOTO(open_outputs(&r, ctx));
  ps_solver_set_forces(&r.s, pb->fext);
  ps_log(ctx, 1, "# %s: %lld particles, %lld arms, %lld free dofs, delta %s%.4g m, %d thread%s\n",
         cs->name, (long long)pb->P.n, (long long)pb->net.n_arm,
         (long long)r.s.sys.n_free, isfinite(delta) ? "" : "(no breaking) ", delta,
         ps_team_size(r.s.team), ps_team_size(r.s.team) > 1 ? "s" : "");
  ps_log(ctx, 1, "# %4s %9s %10s %6s %9s %8s %7s %6s\n", "step", "lambda", "sig/sig_y",
         "newton", "residual", "yielding", "broken", "tip/c");
  PS_CHECK_GOTO(load_path(&r, ctx));
  collect_stats(&r);
  log_end(&r, ctx);
  /* a stall is a result only in the sweep, and only after a settled peak */
  int stall_ok = pb->stall_is_result && isfinite(r.peak);
  int failed = (res->stalled && !stall_ok) || res->interrupted;
  if (out_dir) PS_CHECK_GOTO(finish_outputs(&r, delta, !failed, ctx));
  if (res->interrupted) {
    char where[2600] = "";
    if (out_dir)
      snprintf(where, sizeof where, "; the partial output is in %s, earlier results in %s "
               "are untouched", r.staging, out_dir);
    status = ps_error(ctx, PS_ERR_INTERRUPTED, "%s: %s%s", cs->path, res->stop_reason,
                      where);
    r.staging[0] = '\0'; /* the message says it all */
  } else if (failed) {
    status = ps_error(ctx, PS_ERR_SOLVER, "%s", r.stall_msg);
  }
cleanup:
  if (r.hist) fclose(r.hist);
  if (status < 0 && r.staging[0]) {
    size_t n = strlen(ctx->msg);
    snprintf(ctx->msg + n, sizeof ctx->msg - n,
             "\n(earlier results in %s are untouched; this run's partial output is in "
             "%s)",
             out_dir, r.staging);
  }
  if (keep && status >= 0)
    *keep = r.s;
  else
    ps_solver_free(&r.s);
  return status < 0 ? status : PS_OK;
}

int ps_run_keep(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                ps_solver *keep, ps_ctx *ctx) {
  ps_outdir_lock lk = {.fd = -1};
  if (out_dir) PS_CHECK(ps_outdir_lock_take(&lk, out_dir, ctx));
  int status = run_case(pb, delta, out_dir, res, keep, ctx);
  ps_outdir_lock_release(&lk);
  return status;
}

int ps_run(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
           ps_ctx *ctx) {
  return ps_run_keep(pb, delta, out_dir, res, NULL, ctx);
}

int ps_run_unlocked(ps_problem *pb, double delta, const char *out_dir, ps_run_result *res,
                    ps_ctx *ctx) {
  return run_case(pb, delta, out_dir, res, NULL, ctx);
}
