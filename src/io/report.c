/* report.c: the files of a run: summary.txt and history.csv, each from a
 * table of keys/columns that the writer and the reader share, and the
 * J of the final state (Eq. 39, Eq. 36) and K_I, K_II (interaction
 * integral) per crack tip and ring in summary.txt; the defaults of the
 * output options (ps_output_opts.h). The fields of a state are in
 * report_fields.c. */
#include "ps_report.h"

#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

void ps_output_opts_default(ps_output_opts *o) {
  o->dir[0] = '\0';
  o->vtk_every = 10;
  o->fields = 1;
  o->n_j_rings = 0;
  o->j_tip[0] = o->j_tip[1] = 0.0;
  o->j_dir[0] = 1.0;
  o->j_dir[1] = 0.0;
  o->j_crack = -1;
  o->j_tips = PS_J_TIPS_BOTH;
  for (int i = 0; i < PS_MAX_J_RINGS; i++) o->j_rings[i] = 0.0;
  o->checkpoint = 1;
  o->checkpoint_every = 10;
  o->verbosity = 1;
}

const char *ps_fmt_or_na(double v, int digits, char *buf, size_t len) {
  if (isfinite(v))
    snprintf(buf, len, "%.*g", digits, v);
  else
    snprintf(buf, len, "n/a");
  return buf;
}

/* How a value is stored and written. */
enum value_kind {
  V_STR,   /* char array: "%s" */
  V_I64,   /* ps_int: "%lld" */
  V_INT,   /* int: "%d" */
  V_YESNO, /* int flag: "yes" / "no" */
  V_G,     /* double: "%.*g" with `digits` significant digits, n/a */
  V_F,     /* double: "%.*f" with `digits` decimals, n/a */
  V_HEX,   /* uint64_t: "%016llx" */
  V_RATIO  /* derived, written only: sigma_peak / sigma_y, as V_G */
};

typedef struct value_spec {
  const char *key;
  int kind;     /* enum value_kind */
  int digits;   /* V_G, V_F, V_RATIO */
  size_t offset;/* into the record */
  size_t size;  /* V_STR: the array's size */
} value_spec;

/* "key: value" with the value as written (buf of 64 or more bytes; a
 * string is returned as it is). */
static const char *format_value(const value_spec *k, const void *rec, char *buf, size_t len) {
  const char *p = (const char *)rec + k->offset;
  double v;
  switch (k->kind) {
  case V_STR: return p;
  case V_I64: snprintf(buf, len, "%lld", (long long)*(const ps_int *)p); return buf;
  case V_INT: snprintf(buf, len, "%d", *(const int *)p); return buf;
  case V_YESNO: return *(const int *)p ? "yes" : "no";
  case V_HEX:
    snprintf(buf, len, "%016llx", (unsigned long long)*(const uint64_t *)p);
    return buf;
  case V_RATIO: {
    const ps_run_result *r = rec;
    return ps_fmt_or_na(r->sigma_peak / r->sigma_y, k->digits, buf, len);
  }
  case V_G: return ps_fmt_or_na(*(const double *)p, k->digits, buf, len);
  default: /* V_F */
    v = *(const double *)p;
    if (isfinite(v))
      snprintf(buf, len, "%.*f", k->digits, v);
    else
      snprintf(buf, len, "n/a");
    return buf;
  }
}

/* Store text (a value as written, or "" when absent) into the record. */
static void parse_value(const value_spec *k, const char *text, int present, void *rec) {
  char *p = (char *)rec + k->offset, *end;
  double v = NAN;
  if (present) {
    v = strtod(text, &end);
    if (end == text) v = NAN; /* "n/a" */
  }
  switch (k->kind) {
  case V_STR: snprintf(p, k->size, "%s", present ? text : ""); break;
  /* out of range (particles: 1e300) reads as absent: converting it would
   * be undefined */
  case V_I64: *(ps_int *)p = v > -9.2e18 && v < 9.2e18 ? (ps_int)v : -1; break;
  case V_INT: *(int *)p = v > INT_MIN && v < INT_MAX ? (int)v : -1; break;
  case V_YESNO: *(int *)p = present && !strcmp(text, "yes"); break;
  case V_HEX: *(uint64_t *)p = present ? (uint64_t)strtoull(text, NULL, 16) : 0; break;
  case V_RATIO: break; /* derived */
  default: *(double *)p = v; break;
  }
}

#define R(field) offsetof(ps_run_result, field)
#define S(field) offsetof(ps_run_result, solver.field)

/* summary.txt, in this order (bench/run.sh and doc/peristatic.md name
 * these keys) */
static const value_spec summary_keys[] = {
    {"case", V_STR, 0, R(case_name), sizeof(((ps_run_result *)0)->case_name)},
    {"particles", V_I64, 0, R(particles), 0},
    {"arms", V_I64, 0, R(arms), 0},
    {"free_dofs", V_I64, 0, S(n_free), 0},
    {"delta_m", V_G, 10, R(delta), 0},
    {"sigma_y_Pa", V_G, 10, R(sigma_y), 0},
    {"sigma_failure_Pa", V_G, 10, R(sigma_peak), 0},
    {"sigma_failure_over_sigma_y", V_RATIO, 8, 0, 0},
    {"load_factor_at_peak", V_G, 8, R(lambda_peak), 0},
    {"fractured", V_YESNO, 0, R(fractured), 0},
    {"stalled", V_YESNO, 0, R(stalled), 0},
    {"stop_reason", V_STR, 0, R(stop_reason), sizeof(((ps_run_result *)0)->stop_reason)},
    {"increments", V_I64, 0, R(increments), 0},
    {"newton_iterations", V_I64, 0, S(newton_iterations), 0},
    {"factorisations", V_I64, 0, S(factorisations), 0},
    {"umfpack_fallbacks", V_I64, 0, S(n_fallback), 0},
    {"ldl_factorisations", V_I64, 0, S(ldl_factorisations), 0},
    {"step_cuts", V_I64, 0, R(step_cuts), 0},
    {"gentle_rounds", V_I64, 0, R(gentle_rounds), 0},
    {"arms_broken", V_I64, 0, R(arms_broken), 0},
    {"crack_tip_over_c", V_G, 6, R(crack_tip), 0},
    {"wall_s", V_F, 3, R(wall), 0},
    {"assembly_s", V_F, 3, S(t_assembly), 0},
    {"analyze_s", V_F, 3, S(t_analyze), 0},
    {"factor_s", V_F, 3, S(t_factor), 0},
    {"solve_s", V_F, 3, S(t_solve), 0},
    {"network_s", V_F, 3, R(t_network), 0},
    {"peak_memory_MiB", V_F, 1, R(peak_memory_mib), 0},
    {"cg_iterations", V_I64, 0, S(pcg_iterations), 0},
    {"ksp_iterations", V_I64, 0, S(ksp_iterations), 0},
    {"cg_failures", V_I64, 0, S(pcg_failures), 0},
    {"cg_skipped", V_I64, 0, S(pcg_skipped), 0},
    {"solves", V_I64, 0, S(solves), 0},
    {"nnz_tangent_upper", V_F, 0, S(nnz_tangent), 0},
    {"nnz_factor", V_F, 0, S(nnz_factor), 0},
    {"flops_factor", V_G, 4, S(flops_factor), 0},
    {"majorant_factorisations", V_I64, 0, S(majorant_factorisations), 0},
    {"majorant_cg_failures", V_I64, 0, S(majorant_failures), 0},
    {"majorant_factor_s", V_F, 3, S(t_majorant_factor), 0},
    {"majorant_nnz_factor", V_F, 0, S(nnz_majorant_factor), 0},
    {"cg_s", V_F, 3, S(t_cg), 0},
    {"shifted_steps", V_I64, 0, S(shifted_steps), 0},
    {"cg_truncated", V_I64, 0, S(cg_truncated), 0},
    {"gmres_iterations", V_I64, 0, S(gmres_iterations), 0},
    {"newton_stagnated", V_I64, 0, S(stagnated), 0},
    {"line_search_cuts", V_I64, 0, S(line_search_cuts), 0},
    {"newton_handovers", V_I64, 0, S(handovers), 0},
    {"loose_particles_max", V_I64, 0, S(loose_particles), 0},
    {"fragments_max", V_I64, 0, S(fragments), 0},
    {"threads", V_INT, 0, S(threads), 0},
    {"parts", V_INT, 0, S(parts), 0},
    {"processes", V_INT, 0, R(processes), 0},
    {"distributed", V_YESNO, 0, R(distributed), 0},
    {"preconditioner_serial_share", V_F, 3, S(serial_share), 0},
    {"case_fingerprint", V_HEX, 0, R(fingerprint), 0},
};
#define N_SUMMARY_KEYS (sizeof summary_keys / sizeof summary_keys[0])

#undef R
#undef S
#define H(field) offsetof(ps_history_row, field)

/* history.csv's columns, in order */
static const value_spec history_columns[] = {
    {"step", V_I64, 0, H(step), 0},
    {"load_factor", V_G, 10, H(load_factor), 0},
    {"boundary_stress_Pa", V_G, 10, H(boundary_stress), 0},
    {"stress_over_sigma_y", V_G, 10, H(stress_over_sigma_y), 0},
    {"newton_iterations", V_I64, 0, H(newton_iterations), 0},
    {"relative_residual", V_G, 4, H(relative_residual), 0},
    {"converged", V_I64, 0, H(converged), 0},
    {"arms_yielding", V_I64, 0, H(arms_yielding), 0},
    {"arms_broken", V_I64, 0, H(arms_broken), 0},
    {"crack_tip_over_c", V_G, 6, H(crack_tip), 0},
    {"wall_s", V_F, 4, H(wall), 0},
    {"reaction", V_G, 10, H(reaction), 0},
    {"displacement_m", V_G, 10, H(displacement), 0},
    {"broken_energy", V_G, 10, H(broken_energy), 0},
    {"stored_energy", V_G, 10, H(stored_energy), 0},
    {"dissipated_energy", V_G, 10, H(dissipated_energy), 0},
};
#define N_HISTORY_COLUMNS (sizeof history_columns / sizeof history_columns[0])
#undef H

/* The tips of output.j_integral: the given tip and direction (no key
 * prefix), or the ends of crack j_crack (prefixes tip_start_, tip_end_).
 * Returns how many (0: the crack index is beyond geometry.cracks). */
static int j_tips(const ps_case *cs, double tip[2][2], double dir[2][2],
                  const char *prefix[2]) {
  const ps_output_opts *o = &cs->output;
  if (o->j_crack < 0) {
    for (int k = 0; k < 2; k++) {
      tip[0][k] = o->j_tip[k];
      dir[0][k] = o->j_dir[k];
    }
    prefix[0] = "";
    return 1;
  }
  if (o->j_crack >= cs->n_cracks) return 0;
  const ps_crack *c = &cs->cracks[o->j_crack];
  double L = hypot(c->p1[0] - c->p0[0], c->p1[1] - c->p0[1]);
  if (!(L > 0)) return 0;
  int n = 0;
  if (o->j_tips != PS_J_TIPS_END) { /* p0, pointing away from p1 */
    tip[n][0] = c->p0[0];
    tip[n][1] = c->p0[1];
    dir[n][0] = (c->p0[0] - c->p1[0]) / L;
    dir[n][1] = (c->p0[1] - c->p1[1]) / L;
    prefix[n++] = "tip_start_";
  }
  if (o->j_tips != PS_J_TIPS_START) {
    tip[n][0] = c->p1[0];
    tip[n][1] = c->p1[1];
    dir[n][0] = (c->p1[0] - c->p0[0]) / L;
    dir[n][1] = (c->p1[1] - c->p0[1]) / L;
    prefix[n++] = "tip_end_";
  }
  return n;
}

/* J of the final state (Eq. 39 and 36) and K_I, K_II (interaction
 * integral) per tip and ring, in the crack-tip frame, into v (for each
 * tip, each ring: J domain, J contour, K_I, K_II). Of a piece of a
 * distributed state each process sums over its own particles (the first
 * n_owned: their stresses and gradients are complete) and its own arms
 * across the contours (their ends' gradients are too: the share holds
 * two horizons of ghosts when J is asked for, ps_problem_share), and the
 * sums are added over the processes (collective). */
static int j_values(const ps_report_state *s, const ps_case *cs, int nt, double tip[2][2],
                    double dir[2][2], double *v, ps_ctx *ctx) {
  const ps_report_piece *pc = s->piece;
  const ps_network *net = s->net;
  ps_particles own = *s->P; /* the particles the sums run over */
  double *sig = ps_calloc(4 * (size_t)s->P->n + 1, sizeof *sig, ctx);
  double *H = ps_calloc(4 * (size_t)s->P->n + 1, sizeof *H, ctx);
  double *T_own = pc ? ps_calloc((size_t)net->n_arm + 1, sizeof *T_own, ctx) : NULL;
  int bad = !sig || !H || (pc && !T_own);
  if (pc ? ps_comm_any(pc->comm, bad) : bad) {
    free(sig);
    free(H);
    free(T_own);
    return ps_error(ctx, PS_ERR_NOMEM, "J-integral: out of memory (here or on another "
                    "process)");
  }
  const double *T = s->T;
  if (pc) {
    own.n = pc->n_owned;
    for (ps_int i = 0; i < net->n_arm; i++) T_own[i] = pc->own_arm[i] ? s->T[i] : 0.0;
    T = T_own; /* (the contour skips arms with no tension) */
  }
  ps_post_stress_tensor(s->P, net, s->T, s->q, sig);
  ps_post_displacement_gradient(s->P, net, s->st, s->u, H);
  int n = 0;
  for (int t = 0; t < nt; t++)
    for (int i = 0; i < cs->output.n_j_rings; i++) {
      double l = cs->output.j_rings[i];
      v[n++] = ps_post_j_domain_dir(&own, sig, H, tip[t], dir[t], 0.5 * l, l);
      v[n++] = ps_post_j_contour_dir(&own, net, T, s->q, sig, H, tip[t], dir[t], l,
                                     cs->spacing);
      ps_post_k_interaction(&own, sig, H, tip[t], dir[t], 0.5 * l, l, s->mat->E, s->mat->nu,
                            s->mat->plane, &v[n]);
      n += 2;
    }
  if (pc) ps_comm_sum(pc->comm, v, n);
  free(sig);
  free(H);
  free(T_own);
  return PS_OK;
}

/* J and K into f (NULL: computed only, on the processes of a distributed
 * state that do not write) and the log, from j_values */
static int write_j_integral(const ps_report_state *s, const ps_case *cs, FILE *f,
                            ps_ctx *ctx) {
  double tip[2][2], dir[2][2], v[2 * PS_MAX_J_RINGS * 4];
  const char *prefix[2];
  char b[40];
  int nt = j_tips(cs, tip, dir, prefix);
  if (nt == 0) {
    ps_log(ctx, 1, "# J-integral: output.j_integral.crack %d is not a crack segment of "
                   "geometry.cracks (%d given): no J\n",
           cs->output.j_crack, cs->n_cracks);
    return PS_OK;
  }
  PS_CHECK(j_values(s, cs, nt, tip, dir, v, ctx));
  for (int t = 0, n = 0; t < nt; t++)
    for (int i = 0; i < cs->output.n_j_rings; i++, n += 4) {
      double l = cs->output.j_rings[i], J = v[n], Jc = v[n + 1], K[2] = {v[n + 2], v[n + 3]};
      if (f) {
        fprintf(f, "%sj_domain_ring_%.6gm_N_per_m: %s\n", prefix[t], l,
                ps_fmt_or_na(J, 8, b, sizeof b));
        fprintf(f, "%sj_contour_%.6gm_N_per_m: %s\n", prefix[t], l,
                ps_fmt_or_na(Jc, 8, b, sizeof b));
        fprintf(f, "%sk_I_ring_%.6gm_Pa_sqrt_m: %s\n", prefix[t], l,
                ps_fmt_or_na(K[0], 8, b, sizeof b));
        fprintf(f, "%sk_II_ring_%.6gm_Pa_sqrt_m: %s\n", prefix[t], l,
                ps_fmt_or_na(K[1], 8, b, sizeof b));
      }
      ps_log(ctx, 1, "# J-integral around (%.6g, %.6g), crack direction (%.4g, %.4g), "
                     "square of half-width %.4g m: %.6g N/m (domain form, Eq. 39, q from "
                     "l/2 to l), %.6g N/m (contour form, Eq. 36); K_I %.6g, K_II %.6g "
                     "Pa sqrt(m) (interaction integral)\n",
             tip[t][0], tip[t][1], dir[t][0], dir[t][1], l, J, Jc, K[0], K[1]);
    }
  return PS_OK;
}

int ps_report_write_summary(const char *dir, const ps_run_result *res, const ps_case *cs,
                            const ps_report_state *state, ps_ctx *ctx) {
  char path[1400], buf[64];
  ps_outfile o;
  const ps_report_piece *pc = state ? state->piece : NULL;
  const int writes = !pc || ps_comm_rank(pc->comm) == 0, with_j =
      state && cs->output.n_j_rings > 0 && state->P->dim == 2;
  if (!writes) return with_j ? write_j_integral(state, cs, NULL, ctx) : PS_OK;
  snprintf(path, sizeof path, "%s/summary.txt", dir);
  int status = ps_outfile_open(&o, path, ctx);
  if (status < 0) { /* (the others sum J all the same) */
    if (pc && with_j) write_j_integral(state, cs, NULL, ctx);
    return status;
  }
  for (size_t i = 0; i < N_SUMMARY_KEYS; i++)
    fprintf(o.f, "%s: %s\n", summary_keys[i].key,
            format_value(&summary_keys[i], res, buf, sizeof buf));
  if (with_j && (status = write_j_integral(state, cs, o.f, ctx)) < 0) {
    ps_outfile_abort(&o);
    return status;
  }
  return ps_outfile_commit(&o, ctx);
}

/* The next line of f into line[len] without its line break ("\n" or
 * "\r\n"); a line longer than len - 1 is skipped whole (its tail is no
 * line of its own). Returns 0 at the end of the file. */
static int read_line(FILE *f, char *line, size_t len) {
  while (fgets(line, (int)len, f)) {
    size_t n = strlen(line);
    if (n > 0 && line[n - 1] != '\n' && !feof(f)) { /* too long: skip the rest */
      int c;
      while ((c = getc(f)) != EOF && c != '\n') continue;
      continue;
    }
    line[strcspn(line, "\r\n")] = '\0';
    return 1;
  }
  return 0;
}

int ps_report_read_summary(const char *dir, ps_run_result *res) {
  char path[1400], line[512];
  unsigned char found[N_SUMMARY_KEYS] = {0};
  snprintf(path, sizeof path, "%s/summary.txt", dir);
  memset(res, 0, sizeof *res);
  FILE *f = fopen(path, "r");
  if (f) {
    while (read_line(f, line, sizeof line))
      for (size_t i = 0; i < N_SUMMARY_KEYS; i++) {
        size_t kl = strlen(summary_keys[i].key);
        if (found[i] || strncmp(line, summary_keys[i].key, kl) || line[kl] != ':') continue;
        char *text = line + kl + 1;
        if (*text == ' ') text++;
        parse_value(&summary_keys[i], text, 1, res);
        found[i] = 1;
        break;
      }
    fclose(f);
  }
  for (size_t i = 0; i < N_SUMMARY_KEYS; i++)
    if (!found[i]) parse_value(&summary_keys[i], "", 0, res);
  return f ? 0 : -1;
}

size_t ps_report_history_header(char *buf, size_t len, const char *const *reaction_names,
                                int n_reactions, int dim) {
  size_t n = 0;
#define PS_PUT(...) n += (size_t)snprintf(buf + (n < len ? n : len), n < len ? len - n : 0, __VA_ARGS__)
  for (size_t i = 0; i < N_HISTORY_COLUMNS; i++) PS_PUT("%s%s", i ? "," : "", history_columns[i].key);
  for (int g = 0; g < n_reactions; g++)
    for (int k = 0; k < dim; k++) PS_PUT(",reaction_%s_%c", reaction_names[g], 'x' + k);
  PS_PUT("\n");
#undef PS_PUT
  return n;
}

int ps_report_history_open(ps_report_history *h, const char *dir,
                           const char *const *reaction_names, int n_reactions, int dim,
                           ps_ctx *ctx) {
  char path[1400];
  snprintf(h->dir, sizeof h->dir, "%s", dir);
  h->n_reactions = n_reactions;
  h->dim = dim;
  snprintf(path, sizeof path, "%s/history.csv", dir);
  size_t need = ps_report_history_header(NULL, 0, reaction_names, n_reactions, dim) + 1;
  char *head = ps_calloc(need, 1, ctx);
  if (!head) return PS_ERR_NOMEM;
  ps_report_history_header(head, need, reaction_names, n_reactions, dim);
  h->f = fopen(path, "w");
  int bad = !h->f || fputs(head, h->f) < 0;
  free(head);
  if (bad) return ps_error(ctx, PS_ERR_IO, "%s: cannot open for writing", path);
  return PS_OK;
}

void ps_report_history_row(ps_report_history *h, const ps_history_row *row) {
  char buf[64];
  if (!h->f) return;
  for (size_t i = 0; i < N_HISTORY_COLUMNS; i++)
    fprintf(h->f, "%s%s", i ? "," : "", format_value(&history_columns[i], row, buf, sizeof buf));
  for (int j = 0; j < h->n_reactions * h->dim; j++)
    fprintf(h->f, ",%s", ps_fmt_or_na(row->reactions ? row->reactions[j] : NAN, 10, buf,
                                      sizeof buf));
  fprintf(h->f, "\n");
  fflush(h->f); /* tail -f history.csv follows the run */
}

int ps_report_history_close(ps_report_history *h, ps_ctx *ctx) {
  if (!h->f) return PS_OK;
  int bad = ferror(h->f);
  bad |= fclose(h->f) != 0;
  h->f = NULL;
  if (bad) return ps_error(ctx, PS_ERR_IO, "%s/history.csv: write failed", h->dir);
  return PS_OK;
}

/* The leading columns of a history.csv line that read as numbers, into
 * *row; returns how many. */
static size_t parse_history_row(const char *line, ps_history_row *row) {
  const char *p = line;
  size_t n = 0;
  for (; n < N_HISTORY_COLUMNS; n++) {
    char *end, text[64];
    size_t w = strcspn(p, ",\n");
    if (w >= sizeof text) break;
    memcpy(text, p, w);
    text[w] = '\0';
    strtod(text, &end);
    if (end == text) break; /* empty, or n/a */
    parse_value(&history_columns[n], text, 1, row);
    if (p[w] != ',') {
      n++;
      break;
    }
    p += w + 1;
  }
  return n;
}

int ps_report_last_attempt_failed(const char *dir, double *sigma) {
  char path[1400], line[512], last[512] = "";
  ps_history_row row;
  snprintf(path, sizeof path, "%s/history.csv", dir);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  while (read_line(f, line, sizeof line)) snprintf(last, sizeof last, "%s", line);
  fclose(f);
  memset(&row, 0, sizeof row);
  size_t need = 0; /* the columns up to `converged` must be there */
  while (history_columns[need].offset != offsetof(ps_history_row, converged)) need++;
  if (parse_history_row(last, &row) <= need) return 0;
  *sigma = row.boundary_stress;
  return row.converged == 0;
}
