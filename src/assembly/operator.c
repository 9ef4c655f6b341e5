/* operator.c: the tangent of the last evaluation applied without the
 * matrix, as CG uses it:
 *   y = sum_arms [ (D - T/l) q (q . (x_b - x_a)) + (T/l)(x_b - x_a) ] at b
 *       (minus at a)
 *     + sum_a (c_a g_a (g_a . x) + c2_a h_a (h_a . x))  + spring P_a x_a (loose particles),
 * O(arms + family members) per product instead of the two-horizon
 * matrix's nonzeros; in s->parts parts on the system's team (shares of
 * the arms and of the families). Also the diagonal of K. */
#include "assembly_internal.h"

#include <string.h>

/* the arm and family terms of y = K x (no springs) of the arms [i0, i1)
 * and the families of the particles [c0, c1), y zeroed first; d is the
 * dimension, a constant where apply_part inlines this */
static PS_ALWAYS_INLINE void apply_terms_dim(const ps_system *s, const double *x, double *y,
                                             ps_int i0, ps_int i1, ps_int c0, ps_int c1,
                                             const int d) {
  const ps_network *net = s->net;
  memset(y, 0, (size_t)s->n_dof * sizeof *y);
  for (ps_int i = i0; i < i1; i++) {
    double D = s->tan.D[i], Tl = s->tTl[i];
    if (D == 0.0 && Tl == 0.0) continue;
    const double *q = &s->tq[i * d];
    const double *xa = &x[net->a[i] * d], *xb = &x[net->b[i] * d];
    double *ya = &y[net->a[i] * d], *yb = &y[net->b[i] * d];
    double qv = 0.0;
    for (int k = 0; k < d; k++) qv += q[k] * (xb[k] - xa[k]);
    for (int k = 0; k < d; k++) {
      double kv = (D - Tl) * q[k] * qv + Tl * (xb[k] - xa[k]);
      yb[k] += kv;
      ya[k] -= kv;
    }
  }
  if (s->tr) /* models with rotations (2D): Dr r r^T - M (p r^T + r p^T) */
    for (ps_int i = i0; i < i1; i++) {
      double Dr = s->tan.Dr[i], Mi = s->tM[i];
      if (Dr == 0.0 && Mi == 0.0) continue;
      const double *r = &s->tr[i * 2];
      const double *xa = &x[net->a[i] * 2], *xb = &x[net->b[i] * 2];
      double dx0 = xb[0] - xa[0], dx1 = xb[1] - xa[1];
      double p0 = r[1], p1 = -r[0];
      double rv = r[0] * dx0 + r[1] * dx1, pv = p0 * dx0 + p1 * dx1;
      double k0 = Dr * r[0] * rv - Mi * (p0 * rv + r[0] * pv);
      double k1 = Dr * r[1] * rv - Mi * (p1 * rv + r[1] * pv);
      y[net->b[i] * 2] += k0;
      y[net->b[i] * 2 + 1] += k1;
      y[net->a[i] * 2] -= k0;
      y[net->a[i] * 2 + 1] -= k1;
    }
  for (ps_int c = c0; c < c1; c++) {
    ps_int m;
    const ps_int *M;
    const double *g = NULL, *h = NULL;
    double cc = ps_asm_family_term(s, c, 0, &m, &M, &g);
    double ch = ps_asm_family_term(s, c, 1, &m, &M, &h);
    if (cc == 0.0 && ch == 0.0) continue;
    if (ch == 0.0) { /* one term (the fibre model's total reading): the
                        loops below without the second, which would add
                        a zero to each entry */
      double gx = 0.0;
      for (ps_int p = 0; p < m; p++)
        for (int k = 0; k < d; k++) gx += g[p * d + k] * x[M[p] * d + k];
      gx *= cc;
      for (ps_int p = 0; p < m; p++)
        for (int k = 0; k < d; k++) y[M[p] * d + k] += gx * g[p * d + k];
      continue;
    }
    /* both terms in one pass over the members: x and y are read and
     * written once (the family terms are most of the product); a term
     * that is absent is the other's gradient with coefficient 0 (its own
     * may not be allocated), which adds exactly 0 */
    if (cc == 0.0) g = h;
    double gx = 0.0, hx = 0.0;
    for (ps_int p = 0; p < m; p++)
      for (int k = 0; k < d; k++) {
        double xv = x[M[p] * d + k];
        gx += g[p * d + k] * xv;
        hx += h[p * d + k] * xv;
      }
    gx *= cc;
    hx *= ch;
    for (ps_int p = 0; p < m; p++)
      for (int k = 0; k < d; k++) y[M[p] * d + k] += gx * g[p * d + k] + hx * h[p * d + k];
  }
}

/* the product in s->parts parts (part 0 into y, part p >= 1 into its
 * n_dof of yw_part) */
typedef struct {
  const ps_system *s;
  const double *x;
  double *y;
} apply_job;

static void apply_part(void *arg, int part) {
  const apply_job *j = arg;
  const ps_system *s = j->s;
  ps_int i0, i1, c0, c1;
  ps_part_range(s->net->n_arm, part, s->parts, &i0, &i1);
  ps_part_range(s->net->n_particle, part, s->parts, &c0, &c1);
  double *y = part == 0 ? j->y : s->yw_part + (size_t)(part - 1) * (size_t)s->n_dof;
  if (s->dim == 2) /* constant loop bounds, unrolled */
    apply_terms_dim(s, j->x, y, i0, i1, c0, c1, 2);
  else
    apply_terms_dim(s, j->x, y, i0, i1, c0, c1, 3);
}

void ps_asm_tangent_diagonal(const ps_system *s, double *diag) {
  const ps_network *net = s->net;
  int d = s->dim;
  memset(diag, 0, (size_t)s->n_dof * sizeof *diag);
  double kmat[9];
  for (ps_int i = 0; i < net->n_arm; i++) {
    ps_asm_arm_block(d, &s->tq[i * d], s->tan.D[i], s->tTl[i], kmat);
    if (s->tr) ps_asm_arm_block_rot(&s->tr[2 * i], s->tan.Dr[i], s->tM[i], kmat);
    for (int k = 0; k < d; k++) {
      diag[net->a[i] * d + k] += kmat[k * d + k];
      diag[net->b[i] * d + k] += kmat[k * d + k];
    }
  }
  for (ps_int c = 0; c < net->n_particle; c++)
    for (int term = 0; term < 2; term++) {
      ps_int m;
      const ps_int *M;
      const double *g;
      double cc = ps_asm_family_term(s, c, term, &m, &M, &g);
      if (cc == 0.0) continue;
      for (ps_int p = 0; p < m; p++)
        for (int k = 0; k < d; k++) diag[M[p] * d + k] += cc * g[p * d + k] * g[p * d + k];
    }
}

void ps_system_apply(const ps_system *s, const double *x, double *y) {
  int d = s->dim;
  apply_job j = {s, x, y};
  ps_team_run(s->team, s->parts, apply_part, &j);
  ps_asm_add_parts(s, y, s->yw_part);
  if (s->spring > 0)
    for (ps_int a = 0; a < s->net->n_particle; a++) {
      if (!s->free_body[a]) continue;
      const double *P = &s->free_proj[(ps_int)d * d * a];
      for (int al = 0; al < d; al++) {
        double Px = 0.0;
        for (int be = 0; be < d; be++) Px += P[be * d + al] * x[a * d + be];
        y[a * d + al] += s->spring * Px;
      }
    }
}

/* y[n_free] = the free rows of K s->xw (through s->yw) */
static void apply_free_rows(ps_system *s, double *y) {
  ps_system_apply(s, s->xw, s->yw);
  for (ps_int k = 0; k < s->n_free; k++) y[k] = s->yw[s->dof_of_free[k]];
}

void ps_system_apply_free(ps_system *s, const double *x, double *y) {
  memset(s->xw, 0, (size_t)s->n_dof * sizeof *s->xw);
  for (ps_int k = 0; k < s->n_free; k++) s->xw[s->dof_of_free[k]] = x[k];
  apply_free_rows(s, y);
}

static void system_apply(void *sys, const double *x, double *y) {
  ps_system_apply_free((ps_system *)sys, x, y);
}

ps_operator ps_system_operator(ps_system *s) {
  ps_operator op = {s->n_free, system_apply, s, NULL};
  return op;
}

void ps_system_coupling(ps_system *s, const double *du, double *out) {
  for (ps_int j = 0; j < s->n_dof; j++) s->xw[j] = s->fixed[j] ? du[j] : 0.0;
  apply_free_rows(s, out);
}
