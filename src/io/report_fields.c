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

/* particles.csv's numbers of particle a but its number and mass, as a
 * row: x (d), u (d), damage, volume, h, block, the stress components */
static int csv_width(int d) { return 2 * d + 4 + (d == 2 ? 3 : 6); }
static void csv_row(const ps_report_state *s, const fields *F, ps_int a, double *row) {
  const ps_particles *P = s->P;
  int d = P->dim, ncomp = d == 2 ? 3 : 6, j = 0;
  for (int k = 0; k < d; k++) row[j++] = P->x[a * d + k];
  for (int k = 0; k < d; k++) row[j++] = s->u[a * d + k];
  row[j++] = F->phi[a];
  row[j++] = P->volume[a];
  row[j++] = P->h[a];
  row[j++] = P->block[a];
  for (int c = 0; c < ncomp; c++) row[j++] = F->scomp[c * P->n + a];
}

/* dir/particles.csv: particle a's row (csv_row) at rows[a * width], a = 0
 * .. n - 1, with the material's density rho for the mass */
static int write_particles_csv(const char *dir, int d, double rho, ps_int n,
                               const double *rows, ps_ctx *ctx) {
  int ncomp = d == 2 ? 3 : 6, w = csv_width(d);
  char path[1400];
  ps_outfile o;
  snprintf(path, sizeof path, "%s/particles.csv", dir);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f, d == 2 ? "id,x,y,ux,uy,damage,volume,mass,h,block"
                      : "id,x,y,z,ux,uy,uz,damage,volume,mass,h,block");
  for (int c = 0; c < ncomp; c++) fprintf(o.f, ",%s_Pa", stress_name[c]);
  fprintf(o.f, "\n");
  for (ps_int a = 0; a < n; a++) {
    const double *r = rows + a * w, *u = r + d, *rest = r + 2 * d;
    fprintf(o.f, "%lld", (long long)a);
    for (int k = 0; k < d; k++) fprintf(o.f, ",%.10g", r[k]);
    for (int k = 0; k < d; k++) fprintf(o.f, ",%.10g", u[k]);
    fprintf(o.f, ",%.6g,%.6g,%.6g,%.6g,%d", rest[0], rest[1], rho * rest[1], rest[2],
            (int)rest[3]);
    for (int c = 0; c < ncomp; c++) fprintf(o.f, ",%.6g", rest[4 + c]);
    fprintf(o.f, "\n");
  }
  return ps_outfile_commit(&o, ctx);
}

/* particles.csv of the state: the whole model's rows, or a piece's own
 * rows gathered to the first process (each row led by its particle's
 * number) and written there in the whole model's order */
static int particles_csv(const char *dir, const ps_report_state *s, const fields *F,
                         ps_ctx *ctx) {
  const ps_report_piece *pc = s->piece;
  int d = s->P->dim, w = csv_width(d), status = PS_OK;
  ps_int n = pc ? pc->n_owned : s->P->n, n_all = 0;
  double *rows = ps_calloc((size_t)(n * (w + 1)) + 1, sizeof *rows, ctx), *all = NULL,
         *order = NULL;
  if (!pc) {
    if (!rows) return PS_ERR_NOMEM;
    for (ps_int a = 0; a < n; a++) csv_row(s, F, a, rows + a * w);
    status = write_particles_csv(dir, d, s->mat->rho, n, rows, ctx);
    free(rows);
    return status;
  }
  if (ps_comm_any(pc->comm, !rows)) {
    free(rows);
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory for particles.csv (here or on another "
                    "process)");
  }
  for (ps_int a = 0; a < n; a++) {
    rows[a * (w + 1)] = (double)pc->global[a];
    csv_row(s, F, a, rows + a * (w + 1) + 1);
  }
  PS_CHECK_GOTO(ps_comm_gather(pc->comm, rows, n, w + 1, 0, &all, &n_all, ctx));
  if (ps_comm_rank(pc->comm) == 0) {
    if (!(order = ps_calloc((size_t)(n_all * w) + 1, sizeof *order, ctx))) status = PS_ERR_NOMEM;
    for (ps_int k = 0; order && k < n_all; k++) {
      ps_int a = (ps_int)all[k * (w + 1)];
      if (a < 0 || a >= n_all) {
        status = ps_error(ctx, PS_ERR_INTERNAL, "particles.csv: particle %lld of %lld",
                          (long long)a, (long long)n_all);
        break;
      }
      memcpy(order + a * w, all + k * (w + 1) + 1, (size_t)w * sizeof *order);
    }
    if (status == PS_OK) status = write_particles_csv(dir, d, s->mat->rho, n_all, order, ctx);
  }
  if (ps_comm_any(pc->comm, status < 0) && status >= 0)
    status = ps_error(ctx, PS_ERR_IO, "%s/particles.csv: not written (the first process "
                      "failed)", dir);
cleanup:
  free(rows);
  free(all);
  free(order);
  return status;
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
      snprintf(names + (size_t)i * LEN, LEN, "%s_%04d.%s", kind[k], sr->step[i],
               sr->pvtu ? "pvtu" : "vtu");
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

/* A piece's own arms (the first n of net's that own_arm marks) and
 * their cell fields, compacted into la, lb and c[3][n] */
static ps_int own_arms(const ps_network *net, const unsigned char *own_arm, const fields *F,
                       ps_int *la, ps_int *lb, double *c) {
  ps_int n = 0, na = net->n_arm;
  for (ps_int i = 0; i < na; i++)
    if (own_arm[i]) {
      la[n] = net->a[i];
      lb[n] = net->b[i];
      c[n] = F->astrain[i];
      c[na + n] = F->aplast[i];
      c[2 * na + n] = F->abroken[i];
      n++;
    }
  return n;
}

/* the field files of one step: the whole model's, or a piece's and, on
 * the first process, the .pvtu files of all pieces */
static int write_step(const char *dir, int step, const ps_report_state *s, ps_vtu_grid *g,
                      const fields *F, ps_field *af, ps_ctx *ctx) {
  const ps_report_piece *pc = s->piece;
  const ps_network *net = s->net;
  char path[1400];
  static const char *const kind[2] = {"particles", "arms"};
  if (!pc) {
    snprintf(path, sizeof path, "%s/particles_%04d.vtu", dir, step);
    PS_CHECK(ps_vtu_write(path, g, ctx));
    g->n_line = net->n_arm;
    g->la = net->a;
    g->lb = net->b;
    g->cell_fields = af;
    g->n_cf = 3;
    snprintf(path, sizeof path, "%s/arms_%04d.vtu", dir, step);
    return ps_vtu_write(path, g, ctx);
  }
  const int rank = ps_comm_rank(pc->comm), P = pc->comm ? pc->comm->size : 1;
  ps_int na = net->n_arm, n = g->n_point;
  ps_int *la = ps_calloc((size_t)na + 1, sizeof *la, ctx);
  ps_int *lb = ps_calloc((size_t)na + 1, sizeof *lb, ctx);
  double *c = ps_calloc((size_t)(3 * na) + 1, sizeof *c, ctx);
  char *names = NULL;
  int status = !la || !lb || !c ? PS_ERR_NOMEM : PS_OK;
  if (status == PS_OK) {
    g->n_point = pc->n_owned; /* the own particles: the first of P */
    snprintf(path, sizeof path, "%s/particles_%04d_p%d.vtu", dir, step, rank);
    status = ps_vtu_write(path, g, ctx);
    g->n_point = n;
  }
  if (status == PS_OK) {
    g->n_line = own_arms(net, pc->own_arm, F, la, lb, c);
    g->la = la;
    g->lb = lb;
    for (int k = 0; k < 3; k++) af[k].v = c + k * na;
    g->cell_fields = af;
    g->n_cf = 3;
    snprintf(path, sizeof path, "%s/arms_%04d_p%d.vtu", dir, step, rank);
    status = ps_vtu_write(path, g, ctx);
  }
  enum { LEN = 48 };
  if (status == PS_OK && rank == 0 && !(names = ps_calloc((size_t)P, LEN, ctx)))
    status = PS_ERR_NOMEM;
  const char **piece = names ? ps_calloc((size_t)P, sizeof *piece, ctx) : NULL;
  if (names && !piece) status = PS_ERR_NOMEM;
  for (int k = 0; piece && status == PS_OK && k < 2; k++) {
    for (int q = 0; q < P; q++) {
      snprintf(names + (size_t)q * LEN, LEN, "%s_%04d_p%d.vtu", kind[k], step, q);
      piece[q] = names + (size_t)q * LEN;
    }
    snprintf(path, sizeof path, "%s/%s_%04d.pvtu", dir, kind[k], step);
    g->n_cf = k ? 3 : 0; /* (the particles have no cell fields) */
    status = ps_pvtu_write(path, g, P, piece, ctx);
  }
  free(piece);
  free(names);
  free(la);
  free(lb);
  free(c);
  if (ps_comm_any(pc->comm, status < 0) && status >= 0)
    status = ps_error(ctx, PS_ERR_IO, "%s: the field files of step %d: another process "
                      "failed", dir, step);
  return status;
}

int ps_report_write_fields(const char *dir, int step, int final, const ps_report_state *s,
                           ps_report_series *series, ps_ctx *ctx) {
  const ps_particles *P = s->P;
  int d = P->dim, ncomp = d == 2 ? 3 : 6, status = PS_OK;
  ps_int n = P->n;
  fields F;
  memset(&F, 0, sizeof F);
  status = fields_compute(&F, s, ctx);
  if (s->piece && ps_comm_any(s->piece->comm, status < 0) && status >= 0)
    status = ps_error(ctx, PS_ERR_NOMEM, "out of memory for the fields on another process");
  if (status < 0) goto cleanup;
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
  PS_CHECK_GOTO(write_step(dir, step, s, &g, &F, af, ctx));
  if (series && (!s->piece || ps_comm_rank(s->piece->comm) == 0)) {
    series->pvtu = s->piece != NULL;
    status = series_add(dir, series, step, ctx);
  }
  if (s->piece && ps_comm_any(s->piece->comm, status < 0) && status >= 0)
    status = ps_error(ctx, PS_ERR_IO, "%s: the .pvd files: the first process failed", dir);
  if (status < 0) goto cleanup;
  if (final) PS_CHECK_GOTO(particles_csv(dir, s, &F, ctx));
cleanup:
  fields_free(&F);
  return status;
}
