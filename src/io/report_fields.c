/* report_fields.c: the fields of a state, for ParaView and for scripts:
 * particles_NNNN.vtu and arms_NNNN.vtu (ps_vtu_write), the time series
 * that lists them (particles.pvd, arms.pvd) and particles.csv, with damage
 * (Eq. 119), arm strains and the PD stress tensor (Fallah et al. Eq. 24). */
#include "ps_report.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Per-particle and per-arm quantities of a state for the field files. */
typedef struct fields {
  double *phi;     /* [n] damage, Eq. 119 */
  double *pstrain; /* [n] arm strain of largest magnitude / eps_y */
  double *pplast;  /* [n] largest plastic elongation / delta */
  double *astrain, *aplast, *abroken; /* [n_arm] */
  double *scomp;   /* [6 n] stress components, component-major */
} fields;

static const char *const stress_name[6] = {"stress_xx", "stress_yy", "stress_xy",
                                           "stress_zz", "stress_yz", "stress_xz"};

static void fields_free(fields *F) {
  free(F->phi);
  free(F->pstrain);
  free(F->pplast);
  free(F->astrain);
  free(F->aplast);
  free(F->abroken);
  free(F->scomp);
}

static int fields_compute(fields *F, const ps_report_state *s, ps_ctx *ctx) {
  const ps_network *net = s->net;
  const ps_particles *P = s->P;
  int d = P->dim, ncomp = d == 2 ? 3 : 6; /* xx yy xy [zz yz xz] */
  static const int cij[6][2] = {{0, 0}, {1, 1}, {0, 1}, {2, 2}, {1, 2}, {0, 2}};
  ps_int n = P->n, na = net->n_arm;
  F->phi = ps_calloc((size_t)n, sizeof(double), ctx);
  F->pstrain = ps_calloc((size_t)n, sizeof(double), ctx);
  F->pplast = ps_calloc((size_t)n, sizeof(double), ctx);
  F->astrain = ps_calloc((size_t)na, sizeof(double), ctx);
  F->aplast = ps_calloc((size_t)na, sizeof(double), ctx);
  F->abroken = ps_calloc((size_t)na, sizeof(double), ctx);
  double *sigma = ps_calloc((size_t)(n * d * d), sizeof(double), ctx);
  F->scomp = ps_calloc((size_t)(n * 6), sizeof(double), ctx);
  if (!F->phi || !F->pstrain || !F->pplast || !F->astrain || !F->aplast || !F->abroken ||
      !sigma || !F->scomp) {
    free(sigma);
    return PS_ERR_NOMEM;
  }
  ps_post_damage(net, s->st, F->phi);
  double ey = s->mat->yield_strain, delta = s->mat->delta;
  for (ps_int i = 0; i < na; i++) {
    F->astrain[i] = s->dl[i] / net->r0[i] / ey;
    F->aplast[i] = isfinite(delta) ? ps_arm_plastic_strain(s->st, i, s->mat->yield_rule) *
                                         net->r0[i] / delta
                                   : 0.0;
    F->abroken[i] = s->st->broken[i];
    if (s->st->broken[i]) continue;
    ps_int e[2] = {net->a[i], net->b[i]};
    for (int k = 0; k < 2; k++) {
      if (fabs(F->astrain[i]) > fabs(F->pstrain[e[k]])) F->pstrain[e[k]] = F->astrain[i];
      if (F->aplast[i] > F->pplast[e[k]]) F->pplast[e[k]] = F->aplast[i];
    }
  }
  /* PD stress tensor, Eq. 24 of Fallah et al. (2020) */
  ps_post_stress_tensor(P, net, s->T, s->q, sigma);
  for (int c = 0; c < ncomp; c++)
    for (ps_int a = 0; a < n; a++)
      F->scomp[c * n + a] = sigma[a * d * d + cij[c][0] * d + cij[c][1]];
  free(sigma);
  return PS_OK;
}

static int write_particles_csv(const char *dir, const ps_report_state *s, const fields *F,
                               ps_ctx *ctx) {
  const ps_particles *P = s->P;
  int d = P->dim, ncomp = d == 2 ? 3 : 6;
  ps_int n = P->n;
  char path[1400];
  ps_outfile o;
  snprintf(path, sizeof path, "%s/particles.csv", dir);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f, d == 2 ? "id,x,y,ux,uy,damage,volume,mass,h,block"
                      : "id,x,y,z,ux,uy,uz,damage,volume,mass,h,block");
  for (int c = 0; c < ncomp; c++) fprintf(o.f, ",%s_Pa", stress_name[c]);
  fprintf(o.f, "\n");
  for (ps_int a = 0; a < n; a++) {
    fprintf(o.f, "%lld", (long long)a);
    for (int k = 0; k < d; k++) fprintf(o.f, ",%.10g", P->x[a * d + k]);
    for (int k = 0; k < d; k++) fprintf(o.f, ",%.10g", s->u[a * d + k]);
    fprintf(o.f, ",%.6g,%.6g,%.6g,%.6g,%d", F->phi[a], P->volume[a],
            s->mat->rho * P->volume[a], P->h[a], P->block[a]);
    for (int c = 0; c < ncomp; c++) fprintf(o.f, ",%.6g", F->scomp[c * n + a]);
    fprintf(o.f, "\n");
  }
  return ps_outfile_commit(&o, ctx);
}

void ps_report_series_free(ps_report_series *series) {
  free(series->step);
  series->step = NULL;
  series->n = series->cap = 0;
}

/* dir/NAME.pvd for NAME = particles and arms: every step of the series
 * (time = the step) with its NAME_NNNN.vtu. */
static int write_series(const char *dir, const ps_report_series *sr, ps_ctx *ctx) {
  static const char *const kind[2] = {"particles", "arms"};
  enum { LEN = 40 };
  int status = PS_OK, n = sr->n;
  double *time = ps_calloc((size_t)n + 1, sizeof *time, ctx);
  char *names = ps_calloc((size_t)n + 1, LEN, ctx);
  const char **file = ps_calloc((size_t)n + 1, sizeof *file, ctx);
  char path[1400];
  if (!time || !names || !file) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  for (int k = 0; k < 2; k++) {
    for (int i = 0; i < n; i++) {
      time[i] = sr->step[i];
      snprintf(names + (size_t)i * LEN, LEN, "%s_%04d.vtu", kind[k], sr->step[i]);
      file[i] = names + (size_t)i * LEN;
    }
    snprintf(path, sizeof path, "%s/%s.pvd", dir, kind[k]);
    PS_CHECK_GOTO(ps_pvd_write(path, n, time, file, ctx));
  }
cleanup:
  free(time);
  free(names);
  free(file);
  return status;
}

/* step into the series (a step equal to the last one is that entry,
 * written again) and the .pvd files rewritten */
static int series_add(const char *dir, ps_report_series *sr, int step, ps_ctx *ctx) {
  if (sr->n > 0 && step < sr->step[sr->n - 1])
    return ps_error(ctx, PS_ERR_INTERNAL, "%s: field step %d after step %d", dir, step,
                    sr->step[sr->n - 1]);
  if (sr->n == 0 || step > sr->step[sr->n - 1]) {
    if (sr->n == sr->cap) {
      int cap = sr->cap ? 2 * sr->cap : 16;
      void *p = sr->step;
      PS_CHECK(ps_realloc(&p, (size_t)cap, sizeof *sr->step, ctx));
      sr->step = p;
      sr->cap = cap;
    }
    sr->step[sr->n++] = step;
  }
  return write_series(dir, sr, ctx);
}

int ps_report_series_add(const char *dir, ps_report_series *series, int step, ps_ctx *ctx) {
  return series_add(dir, series, step, ctx);
}

int ps_report_write_fields(const char *dir, int step, int final, const ps_report_state *s,
                           ps_report_series *series, ps_ctx *ctx) {
  const ps_particles *P = s->P;
  const ps_network *net = s->net;
  int d = P->dim, ncomp = d == 2 ? 3 : 6, status = PS_OK;
  ps_int n = P->n;
  char path[1400];
  fields F;
  memset(&F, 0, sizeof F);
  PS_CHECK_GOTO(fields_compute(&F, s, ctx));
  ps_field pf[11] = {{"displacement", 3, s->u, d},
                     {"damage", 1, F.phi, 1},
                     {"arm_strain_over_eps_y", 1, F.pstrain, 1},
                     {"plastic_elongation_over_delta", 1, F.pplast, 1},
                     {"h", 1, P->h, 1}};
  int npf = 5;
  for (int c = 0; c < ncomp; c++) {
    ps_field fc = {stress_name[c], 1, &F.scomp[c * n], 1};
    pf[npf++] = fc;
  }
  ps_field af[3] = {{"arm_strain_over_eps_y", 1, F.astrain, 1},
                    {"plastic_elongation_over_delta", 1, F.aplast, 1},
                    {"broken", 1, F.abroken, 1}};
  double lambda = s->lambda, step_value = step;
  ps_field gf[2] = {{"load_factor", 1, &lambda, 1}, {"step", 1, &step_value, 1}};
  ps_vtu_grid g = {.dim = d, .n_point = n, .x = P->x, .point_fields = pf, .n_pf = npf,
                   .global_fields = gf, .n_gf = 2};
  snprintf(path, sizeof path, "%s/particles_%04d.vtu", dir, step);
  PS_CHECK_GOTO(ps_vtu_write(path, &g, ctx));
  g.n_line = net->n_arm;
  g.la = net->a;
  g.lb = net->b;
  g.cell_fields = af;
  g.n_cf = 3;
  snprintf(path, sizeof path, "%s/arms_%04d.vtu", dir, step);
  PS_CHECK_GOTO(ps_vtu_write(path, &g, ctx));
  if (series) PS_CHECK_GOTO(series_add(dir, series, step, ctx));
  if (final) PS_CHECK_GOTO(write_particles_csv(dir, s, &F, ctx));
cleanup:
  fields_free(&F);
  return status;
}
