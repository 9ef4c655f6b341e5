/* run.c: the load path of one case (increments, step cutting, breaking,
 * stopping rules, progress lines, outputs) and the Griffith sweep. */
#include "ps_app.h"

#include <errno.h>
#include <fcntl.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "config.h"

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

/* A re-equilibration that failed after arms broke counts as the crack
 * running only when arms broke and the failed attempt's boundary stress
 * fell below the peak of the settled states. */
static int failed_attempt_is_fracture(ps_int broken_total, double sig, double peak) {
  return broken_total > 0 && isfinite(peak) && sig < peak;
}

int ps_run_keep(ps_problem *pb, double delta, const char *out_dir,
                ps_run_result *res, ps_solver *keep, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  int status = PS_OK;
  ps_solver s;
  ps_solver_opts opts;
  FILE *hist = NULL;
  char staging[1100] = "", path[1200], stall_msg[1024] = "";
  double t0 = ps_wtime();
  memset(res, 0, sizeof *res);
  memset(&s, 0, sizeof s);
  ps_material mat = pb->mat;
  mat.delta = delta;
  res->sigma_y = mat.sigma_y;
  solver_opts_from_case(cs, &opts);
  opts.threads = pb->threads;
  status = ps_solver_create(&s, &pb->P, &pb->net, ps_model_type_find(cs->model), &mat,
                            pb->fixed, pb->ubar, &opts, ctx);
  if (status == PS_ERR_INPUT && strncmp(ctx->msg, cs->path, strlen(cs->path)) != 0) {
    char m[sizeof ctx->msg];
    snprintf(m, sizeof m, "%s", ctx->msg);
    ps_error(ctx, PS_ERR_INPUT, "%s: %s", cs->path, m); /* name the case file */
  }
  if (status < 0) goto cleanup;
  ps_solver_set_forces(&s, pb->fext);
  if (out_dir) {
    snprintf(staging, sizeof staging, "%s.partial", out_dir);
    PS_CHECK_GOTO(ps_rm_rf(staging, ctx));
    PS_CHECK_GOTO(ps_mkdir_p(staging, ctx));
    snprintf(path, sizeof path, "%s/history.csv", staging);
    hist = fopen(path, "w");
    if (!hist) {
      status = ps_error(ctx, PS_ERR_IO, "%s: cannot open for writing", path);
      goto cleanup;
    }
    fprintf(hist, "step,load_factor,boundary_stress_Pa,stress_over_sigma_y,"
                  "newton_iterations,relative_residual,converged,arms_yielding,arms_broken,"
                  "crack_tip_over_c,wall_s\n");
  }
  ps_log(ctx, 1, "# %s: %lld particles, %lld arms, %lld free dofs, delta %s%.4g m, %d thread%s\n",
         cs->name, (long long)pb->P.n, (long long)pb->net.n_arm,
         (long long)s.sys.n_free, isfinite(delta) ? "" : "(no breaking) ", delta,
         ps_team_size(s.team), ps_team_size(s.team) > 1 ? "s" : "");
  ps_log(ctx, 1, "# %4s %9s %10s %6s %9s %8s %7s %6s\n", "step", "lambda", "sig/sig_y",
         "newton", "residual", "yielding", "broken", "tip/c");
  double dl_nominal = cs->load_step, dl = dl_nominal, peak = -INFINITY;
  ps_int broken_total = 0;
  int good_in_a_row = 0;
  snprintf(res->stop_reason, sizeof res->stop_reason, "max_increments reached (%d)",
           cs->max_increments);
  for (int step = 1; step <= cs->max_increments; step++) {
    double target = s.lambda + dl;
    if (target > cs->max_load - 1e-9 * dl) target = cs->max_load; /* no sliver */
    ps_int its0 = s.newton_iterations;
    status = ps_solver_step(&s, target, ctx);
    if (status < 0) goto cleanup;
    if (status == PS_DIVERGED) {
      res->step_cuts++;
      dl *= 0.5;
      good_in_a_row = 0;
      ps_log(ctx, 1, "  step %d: Newton did not converge at load factor %.6g (%s, "
                     "residual %.2e); cutting the increment to %.4g\n",
             step, target, ps_newton_reason_text(s.last_reason), s.last_residual, dl);
      if (dl < cs->min_step) {
        /* the run ends here: an error for `run` (after the summary is
         * written to the partial output), a result for the sweep */
        res->stalled = 1;
        res->fractured = 0;
        snprintf(stall_msg, sizeof stall_msg,
                 "%s: Newton diverged at load factor %.6g (%s; the increment is below "
                 "path.min_step = %g; last relative residual %.3e). Try a smaller "
                 "path.load_step or solver.linear: umfpack",
                 cs->path, target, ps_newton_reason_text(s.last_reason), cs->min_step, s.last_residual);
        snprintf(res->stop_reason, sizeof res->stop_reason,
                 "Newton stalled at load factor %.6g (increments below path.min_step "
                 "did not converge, last residual %.2e) before the crack ran",
                 target, s.last_residual);
        break;
      }
      step--;
      continue;
    }
    ps_solver_commit(&s);
    /* fracture rounds at this load until no arm breaks; stop early once
     * the load has dropped past path.stop_load_drop of its peak or the tip
     * has passed path.stop_crack_tip: the crack has run */
    ps_int nb = 0;
    int settle = PS_OK, rounds = 0, settled = 0;
    double tip_start = pb->c > 0 ? ps_post_crack_tip(&pb->P, &pb->net, &s.st, pb->c) : 0.0;
    double t_note = ps_wtime(); /* long increments print a line every 10 s */
    for (;;) {
      ps_int nr, limit = 0;
      settle = ps_solver_break_round(&s, 0, &nr, ctx);
      /* re-equilibration failed: go back and break fewer arms, the worst
       * first, halving down to one; only if one arm cannot be broken and
       * re-equilibrated does the run end as unstable */
      while (settle == PS_DIVERGED && nr > 1) {
        limit = nr / 2;
        ps_solver_restore(&s);
        ps_log(ctx, 2, "    re-equilibration failed: breaking the worst %lld arms only\n",
               (long long)limit);
        settle = ps_solver_break_round(&s, limit, &nr, ctx);
        res->gentle_rounds++;
      }
      if (settle < 0) {
        status = settle;
        goto cleanup;
      }
      nb += nr;
      settled = settle == PS_OK && nr == 0; /* no arm left past delta */
      if (settle != PS_OK || nr == 0) break;
      if (ps_wtime() - t_note > 10.0) {
        t_note = ps_wtime();
        ps_log(ctx, 1, "         ... load factor %.5f: breaking round %d, %lld arms broken "
                       "so far, %lld Newton iterations\n",
               s.lambda, rounds + 1, (long long)(broken_total + nb),
               (long long)(s.newton_iterations - its0));
      }
      double sr = ps_post_boundary_stress(&pb->net, s.sys.T, s.sys.q, pb->measure,
                                          pb->measure_length);
      double tr = pb->c > 0 ? ps_post_crack_tip(&pb->P, &pb->net, &s.st, pb->c) : 0.0;
      if (sr < cs->stop_load_drop * fmax(peak, sr) ||
          (pb->c > 0 && tr >= cs->stop_crack_tip) ||
          (pb->c > 0 && cs->stop_tip_advance > 0 && tr - tip_start >= cs->stop_tip_advance))
        break; /* the crack has run: the stop rules below end the run */
      if (++rounds >= cs->max_break_rounds) {
        status = ps_error(ctx, PS_ERR_SOLVER,
                          "%s: arms still breaking after %d re-equilibrations at load "
                          "factor %.6g (path.max_break_rounds)",
                          cs->path, rounds, s.lambda);
        goto cleanup;
      }
    }
    broken_total += nb;
    if (broken_total > 0) dl_nominal = fmin(dl_nominal, cs->load_step_after_break);
    if (++good_in_a_row >= 2 && dl < dl_nominal) dl = fmin(2 * dl, dl_nominal);
    if (dl > dl_nominal) dl = dl_nominal;
    int converged = settle == PS_OK;
    if (!converged) /* make T, q, dl those of u (a rejected trial may linger) */
      PS_CHECK_GOTO(ps_solver_evaluate(&s, ctx));
    double sig = ps_post_boundary_stress(&pb->net, s.sys.T, s.sys.q, pb->measure,
                                        pb->measure_length);
    double tip = pb->c > 0 ? ps_post_crack_tip(&pb->P, &pb->net, &s.st, pb->c) : 0.0;
    ps_int ny = ps_solver_count_yielding(&s);
    int its = (int)(s.newton_iterations - its0);
    res->increments = step;
    /* only a state that is converged and settled (no arm left past delta;
     * a stop rule may end the rounds early) sets the peak */
    if (converged && settled && sig > peak) {
      peak = sig;
      res->lambda_peak = s.lambda;
    }
    ps_log(ctx, 1, "  %4d %9.5f %10.5f %6d %9.2e %8lld %7lld %6.2f\n", step, s.lambda,
           sig / mat.sigma_y, its, s.last_residual, (long long)ny, (long long)broken_total,
           tip);
    if (hist)
      fprintf(hist, "%d,%.10g,%.10g,%.10g,%d,%.4g,%d,%lld,%lld,%.6g,%.4f\n", step,
              s.lambda, sig, sig / mat.sigma_y, its, s.last_residual, converged,
              (long long)ny, (long long)broken_total, tip, ps_wtime() - t0);
    if (hist) fflush(hist); /* tail -f history.csv follows the run */
    if (out_dir && cs->fields && cs->vtk_every > 0 && step % cs->vtk_every == 0)
      PS_CHECK_GOTO(write_state(pb, &s, staging, step, 0, ctx));
    if (converged) res->crack_tip = tip;
    if (!converged) {
      /* a crack that runs at fixed displacement sheds load; a failed attempt
       * carrying at least the peak stress shows no fracture, only a solve
       * that failed (counted like a Newton stall: sigma_failure is then a
       * lower bound). The same rule reclassifies older runs (reuse_run). */
      if (failed_attempt_is_fracture(broken_total, sig, peak)) {
        res->fractured = 1;
        snprintf(res->stop_reason, sizeof res->stop_reason,
                 "re-equilibration after breaking arms did not converge at load factor "
                 "%.5g: the crack ran unstably (outputs show the last attempt)",
                 s.lambda);
      } else {
        res->stalled = 1;
        snprintf(stall_msg, sizeof stall_msg,
                 "%s: re-equilibration after breaking arms did not converge at load "
                 "factor %.6g with the boundary stress not below its peak (the crack had "
                 "not run; last relative residual %.3e). Try a smaller "
                 "path.load_step_after_break",
                 cs->path, s.lambda, s.last_residual);
        snprintf(res->stop_reason, sizeof res->stop_reason,
                 "re-equilibration after breaking arms did not converge at load factor "
                 "%.5g with the load not below its peak: stalled before the crack ran",
                 s.lambda);
      }
      break;
    }
    if (converged && pb->c > 0 && cs->stop_tip_advance > 0 &&
        tip - tip_start >= cs->stop_tip_advance) {
      res->fractured = 1;
      snprintf(res->stop_reason, sizeof res->stop_reason,
               "the crack tip advanced %.3g c at one load (from %.4g c to %.4g c): it "
               "runs unstably", tip - tip_start, tip_start, tip);
      break;
    }
    if (pb->c > 0 && tip >= cs->stop_crack_tip) {
      res->fractured = 1;
      snprintf(res->stop_reason, sizeof res->stop_reason,
               "crack tip passed %.3g c from the centre", cs->stop_crack_tip);
      break;
    }
    if (broken_total > 0 && sig < cs->stop_load_drop * peak) {
      res->fractured = 1;
      snprintf(res->stop_reason, sizeof res->stop_reason,
               "boundary stress fell below %.3g of its peak", cs->stop_load_drop);
      break;
    }
    if (s.lambda >= cs->max_load) { /* exact: target snaps to max_load */
      snprintf(res->stop_reason, sizeof res->stop_reason,
               "path.max_load = %g reached: %s", cs->max_load,
               broken_total ? "arms broke but the crack did not run" : "no fracture");
      break;
    }
  }
  res->sigma_peak = peak;
  /* a stall is a result only in the sweep, and only after a settled peak */
  int stall_ok = pb->stall_is_result && isfinite(peak);
  res->newton_iterations = s.newton_iterations;
  res->factorisations = s.ls.stats.n_factor + s.ls_fallback.stats.n_factor;
  res->arms_broken = broken_total;
  res->n_fallback = s.n_fallback;
  res->pcg_iterations = s.pcg_iterations;
  res->pcg_failures = s.pcg_failures;
  res->pcg_skipped = s.pcg_skipped;
  res->majorant_factorisations = s.ls_pre.stats.n_factor;
  res->majorant_failures = s.pre_failures;
  res->shifted_steps = s.n_shifted;
  res->cg_truncated = s.pcg_truncated;
  res->stagnated = s.n_stagnated;
  res->handovers = s.n_handovers;
  res->threads = ps_team_size(s.team);
  res->serial_share = s.sys_pre.net ? s.ls_pre.stats.serial_share : s.ls.stats.serial_share;
  res->line_search_cuts = s.n_line_search_cuts;
  res->t_majorant_factor = s.ls_pre.stats.t_factor;
  res->nnz_majorant_factor = s.ls_pre.stats.nnz_factor;
  res->t_cg = s.t_pcg;
  res->solves = s.ls.stats.n_solve + s.ls_fallback.stats.n_solve;
  res->nnz_tangent = (double)s.sys.A.p[s.sys.n_free];
  res->nnz_factor = s.ls.stats.nnz_factor;
  res->flops_factor = s.ls.stats.flops_factor;
  res->t_assembly = s.t_assembly;
  res->t_analyze = s.ls.stats.t_analyze + s.ls_fallback.stats.t_analyze;
  res->t_factor = s.ls.stats.t_factor + s.ls_fallback.stats.t_factor;
  res->t_solve = s.ls.stats.t_solve + s.ls_fallback.stats.t_solve;
  res->wall = ps_wtime() - t0;
  if (pb->measure_length > 0)
    ps_log(ctx, 1, "# end: %s\n# sigma_failure = %.6g Pa = %.5f sigma_y (peak at load "
                   "factor %.5g)%s; %lld increments, %lld Newton iterations, %.2f s\n",
           res->stop_reason, peak, peak / mat.sigma_y, res->lambda_peak,
           res->fractured ? "" : " [no fracture]", (long long)res->increments,
           (long long)res->newton_iterations, res->wall);
  else /* no measure: loaded by tractions or unmeasured displacements */
    ps_log(ctx, 1, "# end: %s\n# no boundary-stress measure (loading.boundary has no "
                   "measure: true): the stress column is 0; %lld increments, %lld Newton "
                   "iterations, %.2f s\n",
           res->stop_reason, (long long)res->increments, (long long)res->newton_iterations,
           res->wall);
  if (out_dir) {
    if (cs->fields) PS_CHECK_GOTO(write_state(pb, &s, staging, res->increments, 1, ctx));
    int bad = ferror(hist);
    if (fclose(hist) != 0 || bad) {
      hist = NULL;
      status = ps_error(ctx, PS_ERR_IO, "%s/history.csv: write failed", staging);
      goto cleanup;
    }
    hist = NULL;
    ps_outfile o;
    snprintf(path, sizeof path, "%s/summary.txt", staging);
    PS_CHECK_GOTO(ps_outfile_open(&o, path, ctx));
    fprintf(o.f,
            "case: %s\nparticles: %lld\narms: %lld\nfree_dofs: %lld\ndelta_m: %.10g\n"
            "sigma_y_Pa: %.10g\nsigma_failure_Pa: %.10g\nsigma_failure_over_sigma_y: "
            "%.8g\nload_factor_at_peak: %.8g\nfractured: %s\nstalled: %s\nstop_reason: %s\n"
            "increments: %lld\nnewton_iterations: %lld\nfactorisations: %lld\n"
            "umfpack_fallbacks: %lld\nstep_cuts: %lld\ngentle_rounds: %lld\narms_broken: %lld\n"
            "crack_tip_over_c: %.6g\nwall_s: %.3f\nassembly_s: %.3f\nanalyze_s: %.3f\n"
            "factor_s: %.3f\nsolve_s: %.3f\nnetwork_s: %.3f\npeak_memory_MiB: %.1f\n"
            "cg_iterations: %lld\ncg_failures: %lld\ncg_skipped: %lld\nsolves: %lld\nnnz_tangent_upper: %.0f\n"
            "nnz_factor: %.0f\nflops_factor: %.4g\nmajorant_factorisations: %lld\n"
            "majorant_cg_failures: %lld\nmajorant_factor_s: %.3f\nmajorant_nnz_factor: %.0f\n"
            "cg_s: %.3f\nshifted_steps: %lld\ncg_truncated: %lld\nnewton_stagnated: %lld\nline_search_cuts: %lld\n"
            "newton_handovers: %lld\nthreads: %d\npreconditioner_serial_share: %.3f\n"
            "case_fingerprint: %016llx\n",
            cs->name, (long long)pb->P.n, (long long)pb->net.n_arm,
            (long long)s.sys.n_free, delta, mat.sigma_y, peak, peak / mat.sigma_y,
            res->lambda_peak, res->fractured ? "yes" : "no", res->stalled ? "yes" : "no",
            res->stop_reason,
            (long long)res->increments, (long long)res->newton_iterations,
            (long long)res->factorisations, (long long)res->n_fallback,
            (long long)res->step_cuts, (long long)res->gentle_rounds,
            (long long)res->arms_broken, res->crack_tip,
            res->wall, res->t_assembly, res->t_analyze, res->t_factor, res->t_solve,
            pb->t_network, ps_peak_mib(), (long long)res->pcg_iterations,
            (long long)res->pcg_failures, (long long)res->pcg_skipped, (long long)res->solves, res->nnz_tangent,
            res->nnz_factor, res->flops_factor, (long long)res->majorant_factorisations,
            (long long)res->majorant_failures, res->t_majorant_factor,
            res->nnz_majorant_factor, res->t_cg,
            (long long)res->shifted_steps, (long long)res->cg_truncated,
            (long long)res->stagnated, (long long)res->line_search_cuts,
            (long long)res->handovers, res->threads, res->serial_share,
            (unsigned long long)ps_case_fingerprint(cs));
    if (cs->n_j_rings > 0 && pb->P.dim == 2) { /* J of the final state, Eq. 39 */
      double *sig = ps_calloc(4 * (size_t)pb->P.n, sizeof *sig, ctx);
      double *H = ps_calloc(4 * (size_t)pb->P.n, sizeof *H, ctx);
      if (!sig || !H) {
        free(sig);
        free(H);
        ps_outfile_abort(&o);
        status = ps_error(ctx, PS_ERR_NOMEM, "J-integral: out of memory");
        goto cleanup;
      }
      ps_post_stress_tensor(&pb->P, &pb->net, s.sys.T, s.sys.q, sig);
      ps_post_displacement_gradient(&pb->P, &pb->net, &s.st, s.u, H);
      for (int i = 0; i < cs->n_j_rings; i++) {
        double l = cs->j_rings[i];
        double J = ps_post_j_domain(&pb->P, sig, H, cs->j_tip, 0.5 * l, l);
        double Jc = ps_post_j_contour(&pb->P, &pb->net, s.sys.T, s.sys.q, sig, H, cs->j_tip,
                                      l, cs->spacing);
        fprintf(o.f, "j_domain_ring_%.6gm_N_per_m: %.8g\nj_contour_%.6gm_N_per_m: %.8g\n", l,
                J, l, Jc);
        ps_log(ctx, 1, "# J-integral around (%.6g, %.6g), square of half-width %.4g m: "
                       "%.6g N/m (domain form, Eq. 39, q from l/2 to l), %.6g N/m (contour "
                       "form, Eq. 36)\n",
               cs->j_tip[0], cs->j_tip[1], l, J, Jc);
      }
      free(sig);
      free(H);
    }
    PS_CHECK_GOTO(ps_outfile_commit(&o, ctx));
    if (!(res->stalled && !stall_ok))
      PS_CHECK_GOTO(ps_dir_commit(staging, out_dir, ctx));
  }
  if (res->stalled && !stall_ok)
    status = ps_error(ctx, PS_ERR_SOLVER, "%s", stall_msg);
cleanup:
  if (hist) fclose(hist);
  if (status < 0 && staging[0]) {
    size_t n = strlen(ctx->msg);
    snprintf(ctx->msg + n, sizeof ctx->msg - n,
             "\n(earlier results in %s are untouched; this run's partial output is in "
             "%s)",
             out_dir, staging);
  }
  if (keep && status >= 0)
    *keep = s;
  else
    ps_solver_free(&s);
  return status < 0 ? status : PS_OK;
}

int ps_run(ps_problem *pb, double delta, const char *out_dir,
           ps_run_result *res, ps_ctx *ctx) {
  return ps_run_keep(pb, delta, out_dir, res, NULL, ctx);
}

/* "%.8g" of v, or "n/a" when v is not finite (no NaN in outputs) */
static const char *fmt_or_na(double v, char *buf, size_t len) {
  if (isfinite(v))
    snprintf(buf, len, "%.8g", v);
  else
    snprintf(buf, len, "n/a");
  return buf;
}

/* value of "key: value" in a summary.txt, NAN if absent */
static double summary_value(const char *path, const char *key, char *text, size_t len) {
  FILE *f = fopen(path, "r");
  char line[512];
  double v = NAN;
  size_t kl = strlen(key);
  if (!f) return NAN;
  while (fgets(line, sizeof line, f))
    if (!strncmp(line, key, kl) && line[kl] == ':') {
      v = strtod(line + kl + 1, NULL);
      if (text) {
        snprintf(text, len, "%s", line + kl + 2);
        text[strcspn(text, "\n")] = '\0';
      }
      break;
    }
  fclose(f);
  return v;
}

/* Did the run in dir end on an unconverged state (last row of
 * history.csv with converged = 0)? Then *sig = its boundary stress, Pa. */
static int last_attempt_failed(const char *dir, double *sig) {
  char path[1400], line[512], last[512] = "";
  snprintf(path, sizeof path, "%s/history.csv", dir);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  while (fgets(line, sizeof line, f)) snprintf(last, sizeof last, "%s", line);
  fclose(f);
  int step, its, converged;
  double lambda, stress, ratio, res;
  if (sscanf(last, "%d,%lf,%lf,%lf,%d,%lf,%d", &step, &lambda, &stress, &ratio, &its, &res,
             &converged) != 7)
    return 0;
  *sig = stress;
  return converged == 0;
}

/* A finished run of this sweep in dir (same particles, arms and delta)?
 * Then fill *r from its summary.txt. */
static int reuse_run(const ps_problem *pb, const char *dir, double delta,
                     ps_run_result *r) {
  char path[1400], yes[16] = "", fp[32] = "", want[32];
  double sig_last = NAN;
  snprintf(path, sizeof path, "%s/summary.txt", dir);
  snprintf(want, sizeof want, "%016llx", (unsigned long long)ps_case_fingerprint(&pb->cs));
  summary_value(path, "case_fingerprint", fp, sizeof fp);
  if (strcmp(fp, want) != 0) return 0;
  if (summary_value(path, "particles", NULL, 0) != (double)pb->P.n ||
      summary_value(path, "arms", NULL, 0) != (double)pb->net.n_arm ||
      fabs(summary_value(path, "delta_m", NULL, 0) - delta) > 1e-9 * delta)
    return 0;
  memset(r, 0, sizeof *r);
  r->sigma_y = summary_value(path, "sigma_y_Pa", NULL, 0);
  r->sigma_peak = summary_value(path, "sigma_failure_Pa", NULL, 0);
  summary_value(path, "fractured", yes, sizeof yes);
  r->fractured = !strcmp(yes, "yes");
  summary_value(path, "stalled", yes, sizeof yes); /* absent in older runs */
  r->stalled = !strcmp(yes, "yes");
  if (r->fractured && last_attempt_failed(dir, &sig_last) &&
      !failed_attempt_is_fracture(1, sig_last, r->sigma_peak)) {
    r->fractured = 0; /* an older run labelled by the former rule */
    r->stalled = 1;
  }
  r->increments = (ps_int)summary_value(path, "increments", NULL, 0);
  r->newton_iterations = (ps_int)summary_value(path, "newton_iterations", NULL, 0);
  r->arms_broken = (ps_int)summary_value(path, "arms_broken", NULL, 0);
  r->wall = summary_value(path, "wall_s", NULL, 0);
  return isfinite(r->sigma_peak) && isfinite(r->sigma_y) && r->sigma_y > 0;
}

/* Run i of the sweep in staging/delta_cNNNN, or reuse it there when
 * try_reuse and it matches (reuse_run). With may_run = 0 (another process
 * holds the run) only a finished run will do. job > 0 labels a worker's
 * log. Returns ps_run's status, or PS_ERR_SOLVER when the run may not be
 * run here and is not finished. */
static int sweep_run(ps_problem *pb, const char *staging, int i, int try_reuse, int may_run,
                     int job, ps_run_result *res, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  double dc = cs->sweep_delta_over_c[i];
  char path[1300], label[32] = "";
  snprintf(path, sizeof path, "%s/delta_c%.6g", staging, 1.0 / dc);
  if (job > 0) snprintf(label, sizeof label, " (job %d)", job);
  if (try_reuse && reuse_run(pb, path, dc * pb->c, res)) {
    ps_log(ctx, 1, "## griffith run %d/%d%s: delta = c/%.6g: reusing %s\n", i + 1,
           cs->n_sweep, label, 1.0 / dc, path);
    return PS_OK;
  }
  if (!may_run)
    return ps_error(ctx, PS_ERR_SOLVER,
                    "%s is being run by another peristatic process (pid in %s.claim)", path,
                    path);
  ps_log(ctx, 1, "## griffith run %d/%d%s: delta = c/%.6g\n", i + 1, cs->n_sweep, label,
         1.0 / dc);
  return ps_run(pb, dc * pb->c, path, res, ctx);
}

static void claim_path(const ps_problem *pb, const char *staging, int i, char *path,
                       size_t len) {
  snprintf(path, len, "%s/delta_c%.6g.claim", staging, 1.0 / pb->cs.sweep_delta_over_c[i]);
}

/* Claim run i for this process: create staging/delta_cNNNN.claim
 * exclusively (O_EXCL is atomic, so two workers, also of two sweeps in the
 * same folder, never take the same run) holding our pid. A claim whose
 * process is gone (an interrupted sweep) is taken over. Returns 1 when
 * this process got it; release_run removes it when the run is done. */
static int claim_run(const ps_problem *pb, const char *staging, int i) {
  char path[1300];
  claim_path(pb, staging, i, path, sizeof path);
  for (int attempt = 0; attempt < 2; attempt++) {
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
      char buf[32];
      int n = snprintf(buf, sizeof buf, "%ld\n", (long)getpid());
      int ok = write(fd, buf, (size_t)n) == n;
      close(fd);
      return ok;
    }
    FILE *f = fopen(path, "r");
    long pid = 0;
    if (f) {
      if (fscanf(f, "%ld", &pid) != 1) pid = 0;
      fclose(f);
    }
    if (pid <= 0 || (kill((pid_t)pid, 0) == 0 || errno != ESRCH)) return 0; /* alive */
    unlink(path); /* stale: its process is gone */
  }
  return 0;
}

static void release_run(const ps_problem *pb, const char *staging, int i) {
  char path[1300];
  claim_path(pb, staging, i, path, sizeof path);
  unlink(path);
}

/* Share the sweep's runs among `jobs` forked workers writing into staging
 * and wait for them. Each worker (logging to staging/job-N.log) takes the
 * next unclaimed run, largest delta first: those have the most increments,
 * so the longest runs start first and the short ones fill the gaps
 * (longest-processing-time-first scheduling). The table does not depend on
 * which worker ran what. Returns PS_OK, or PS_ERR_SOLVER / PS_ERR_IO naming
 * the job. */
static int run_workers(ps_problem *pb, const char *staging, int jobs, ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  int n = cs->n_sweep, order[PS_MAX_SWEEP];
  for (int k = 0; k < n; k++) order[k] = k;
  for (int k = 1; k < n; k++) /* insertion sort by delta, descending */
    for (int j = k; j > 0 && cs->sweep_delta_over_c[order[j]] >
                               cs->sweep_delta_over_c[order[j - 1]]; j--) {
      int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
  pid_t pids[64];
  fflush(NULL);
  for (int w = 0; w < jobs; w++) {
    pid_t pid = fork();
    if (pid < 0) return ps_error(ctx, PS_ERR_IO, "griffith --jobs: cannot fork a worker");
    if (pid == 0) {
      char logpath[1300];
      snprintf(logpath, sizeof logpath, "%s/job-%d.log", staging, w + 1);
      FILE *log = fopen(logpath, "w");
      ctx->log = log;
      /* the CPUs are shared among the jobs */
      if (pb->threads <= 0) {
        int per_job = ps_cpu_count() / jobs;
        pb->threads = per_job > 1 ? per_job : 1;
      }
      int bad = 0;
      for (int k = 0; k < n; k++) { /* after a failed run, go on with the others */
        ps_run_result r;
        if (!claim_run(pb, staging, order[k])) continue;
        if (sweep_run(pb, staging, order[k], 1, 1, w + 1, &r, ctx) < 0) {
          if (log) fprintf(log, "peristatic: %s\n", ctx->msg);
          bad = 1;
        }
        release_run(pb, staging, order[k]); /* done: later claims just reuse it */
      }
      if (log) fclose(log);
      _exit(bad ? 1 : 0);
    }
    pids[w] = pid;
    ps_log(ctx, 1, "## griffith: job %d started (log %s/job-%d.log)\n", w + 1, staging,
           w + 1);
  }
  int failed = 0;
  for (int w = 0; w < jobs; w++) {
    int st = 0;
    if (waitpid(pids[w], &st, 0) < 0 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) failed = w + 1;
    else ps_log(ctx, 1, "## griffith: job %d finished\n", w + 1);
  }
  if (failed)
    return ps_error(ctx, PS_ERR_SOLVER,
                    "griffith --jobs: job %d failed (see %s/job-%d.log); the runs finished "
                    "so far are in %s, `peristatic griffith --resume -o %s CASE` continues",
                    failed, staging, failed, staging, staging);
  return PS_OK;
}

static int griffith_sweep(ps_problem *pb, const char *out_dir, int resume, int jobs,
                          double *slope, double *intercept, double *r2, int *n_fractured,
                          ps_ctx *ctx);

int ps_griffith(ps_problem *pb, const char *out_dir, int resume, double *slope,
                double *intercept, double *r2, int *n_fractured, ps_ctx *ctx) {
  return griffith_sweep(pb, out_dir, resume, 1, slope, intercept, r2, n_fractured, ctx);
}

int ps_griffith_jobs(ps_problem *pb, const char *out_dir, int resume, int jobs,
                     double *slope, double *intercept, double *r2, int *n_fractured,
                     ps_ctx *ctx) {
  return griffith_sweep(pb, out_dir, resume, jobs, slope, intercept, r2, n_fractured, ctx);
}

static int griffith_sweep(ps_problem *pb, const char *out_dir, int resume, int jobs,
                          double *slope, double *intercept, double *r2, int *n_fractured,
                          ps_ctx *ctx) {
  const ps_case *cs = &pb->cs;
  int n = cs->n_sweep, status = PS_OK, nf = 0;
  double xs[PS_MAX_SWEEP], ys[PS_MAX_SWEEP];
  ps_run_result res[PS_MAX_SWEEP];
  char staging[1100], path[1300], b1[32], b2[32], b3[32];
  *slope = *intercept = *r2 = NAN;
  *n_fractured = 0;
  if (!(pb->c > 0))
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: the Griffith sweep needs the elliptic disk (geometry.type "
                    "disk): delta is swept as a fraction of c",
                    cs->path);
  if (n < 1) return ps_error(ctx, PS_ERR_INPUT, "%s: griffith sweep is empty", cs->path);
  /* a fresh sweep is staged and renamed at the end; a resumed one works in
   * out_dir itself, one atomic folder per run, and reuses finished runs */
  if (resume) {
    snprintf(staging, sizeof staging, "%s", out_dir);
  } else {
    snprintf(staging, sizeof staging, "%s.partial", out_dir);
    PS_CHECK(ps_rm_rf(staging, ctx));
  }
  PS_CHECK(ps_mkdir_p(staging, ctx));
  /* a run whose Newton solve stalls before the crack runs (the paper's
   * delta = c/500: the plate yields) is a row of the table, not an error */
  pb->stall_is_result = 1;
  if (jobs > n) jobs = n;
  if (jobs > 64) jobs = 64;
  if (jobs > 1) PS_CHECK(run_workers(pb, staging, jobs, ctx)); /* then all reused */
  for (int i = 0; i < n; i++) {
    double dc = cs->sweep_delta_over_c[i];
    /* a run another sweep in this folder holds: only its result will do */
    int mine = claim_run(pb, staging, i);
    status = sweep_run(pb, staging, i, resume || jobs > 1, mine, 0, &res[i], ctx);
    if (mine) release_run(pb, staging, i);
    if (status < 0) {
      size_t l = strlen(ctx->msg);
      snprintf(ctx->msg + l, sizeof ctx->msg - l,
               "\n(the runs finished so far are in %s; `peristatic griffith --resume "
               "-o %s CASE` continues there)",
               staging, staging);
      return status;
    }
    if (res[i].fractured) {
      xs[nf] = sqrt(dc);
      ys[nf] = res[i].sigma_peak / res[i].sigma_y;
      nf++;
    }
  }
  *n_fractured = nf;
  double nominal = sqrt(2.0 / (M_PI * pb->mat.yield_strain));
  if (nf >= 2) PS_CHECK(ps_post_line_fit(xs, ys, nf, slope, intercept, r2, ctx));
  ps_outfile o;
  snprintf(path, sizeof path, "%s/griffith.csv", staging);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f, "delta_over_c,sqrt_delta_over_c,sigma_failure_over_sigma_y,fractured,"
               "increments,newton_iterations,arms_broken,wall_s\n");
  for (int i = 0; i < n; i++) {
    double dc = cs->sweep_delta_over_c[i];
    fprintf(o.f, "%.8g,%.8g,%.8g,%s,%lld,%lld,%lld,%.3f\n", dc, sqrt(dc),
            res[i].sigma_peak / res[i].sigma_y,
            res[i].fractured ? "yes" : res[i].stalled ? "stalled" : "no",
            (long long)res[i].increments, (long long)res[i].newton_iterations,
            (long long)res[i].arms_broken, res[i].wall);
  }
  PS_CHECK(ps_outfile_commit(&o, ctx));
  snprintf(path, sizeof path, "%s/griffith_fit.txt", staging);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f,
          "# least-squares line sigma_failure/sigma_y = intercept + slope "
          "sqrt(delta/c)\n# over the runs that fractured (n/a: fewer than two)\n"
          "runs: %d\nfractured: %d\nslope: %s\nintercept: %s\nr2: %s\n"
          "nominal_griffith_slope: %.8g\n"
          "# nominal slope sqrt(2/(pi eps_y)) of Eq. 106/109; see doc/griffith.md\n",
          n, nf, fmt_or_na(*slope, b1, sizeof b1), fmt_or_na(*intercept, b2, sizeof b2),
          fmt_or_na(*r2, b3, sizeof b3), nominal);
  PS_CHECK(ps_outfile_commit(&o, ctx));
  snprintf(path, sizeof path, "%s/griffith.gp", staging);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f,
          "# gnuplot script: sigma_failure/sigma_y against sqrt(delta/c)\n"
          "set terminal pngcairo size 800,600 noenhanced\nset output 'griffith.png'\n"
          "set datafile separator ','\nset key top left\n"
          "set xlabel 'sqrt(delta / c)'\nset ylabel 'sigma_failure / sigma_yield'\n"
          "set title 'Griffith check: %s (slope %s, intercept %s, R^2 %s)'\n"
          "set xrange [0:*]\nset yrange [0:*]\n"
          "plot 'griffith.csv' every ::1 using (strcol(4) eq \"yes\" ? $2 : 1/0):3 with points "
          "pt 7 ps 1.5 title 'fractured', \\\n"
          "     'griffith.csv' every ::1 using (strcol(4) eq \"no\" ? $2 : 1/0):3 with points "
          "pt 6 ps 1.5 title 'no fracture (peak load)', \\\n"
          "     'griffith.csv' every ::1 using (strcol(4) eq \"stalled\" ? $2 : 1/0):3 with "
          "points pt 4 ps 1.5 title 'no fracture: solve stalled (last settled load)', \\\n"
          "     %.10g + %.10g*x title 'least-squares fit' lw 2, \\\n"
          "     %.10g*x title 'nominal Griffith sqrt(2/(pi eps_y)) x' dt 2\n",
          cs->name, fmt_or_na(*slope, b1, sizeof b1), fmt_or_na(*intercept, b2, sizeof b2),
          fmt_or_na(*r2, b3, sizeof b3), isfinite(*intercept) ? *intercept : 0.0,
          isfinite(*slope) ? *slope : 0.0, nominal);
  PS_CHECK(ps_outfile_commit(&o, ctx));
  if (!resume) PS_CHECK(ps_dir_commit(staging, out_dir, ctx));
  if (PS_GNUPLOT[0]) {
    char cmd[2600];
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s' griffith.gp 2>/dev/null", out_dir,
             PS_GNUPLOT);
    if (system(cmd) != 0)
      ps_log(ctx, 1, "# warning: gnuplot failed; the plot script is %s/griffith.gp\n",
             out_dir);
  }
  ps_log(ctx, 1, "## griffith: %d of %d runs fractured; slope %s, intercept %s, R^2 %s "
                 "(nominal slope %.5g)\n",
         nf, n, fmt_or_na(*slope, b1, sizeof b1), fmt_or_na(*intercept, b2, sizeof b2),
         fmt_or_na(*r2, b3, sizeof b3), nominal);
  return status;
}
