/* assemble.c: the tangent of the last evaluation as a matrix, for a
 * factorisation:
 *   K = sum_arms [ D q q^T + (T/l)(I - q q^T) ] (x) [[1,-1],[-1,1]]
 *     + sum_a (c_a g_a g_a^T + c2_a h_a h_a^T) + spring P_a on loose particles,
 * scattered into Kfull through the slot maps of pattern.c (no search),
 * then the free upper triangle gathered into A. */
#include "assembly_internal.h"

#include <math.h>
#include <string.h>

/* add sign * k (d x d, column-major k[be*d+al]) to block blk of column Q */
static inline void add_block(ps_system *s, ps_int Q, ps_int blk, const double *k,
                             double sign) {
  int d = s->dim;
  ps_int len = s->bptr[Q + 1] - s->bptr[Q];
  double *base = &s->Kfull[(ps_int)d * d * s->bptr[Q] + (blk - s->bptr[Q]) * d];
  for (int be = 0; be < d; be++)
    for (int al = 0; al < d; al++) base[(ps_int)be * d * len + al] += sign * k[be * d + al];
}

void ps_asm_assemble_arms(ps_system *dst, const ps_system *src, const double *D) {
  const ps_network *net = dst->net;
  int d = dst->dim;
  ps_int nblk = dst->bptr[net->n_particle];
  memset(dst->Kfull, 0, (size_t)(d * d * nblk) * sizeof *dst->Kfull);
  double kmat[9];
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (D[i] == 0.0 && src->tTl[i] == 0.0) continue; /* broken */
    ps_asm_arm_block(d, &src->tq[i * d], D[i], src->tTl[i], kmat);
    if (src->tr) ps_asm_arm_block_rot(&src->tr[2 * i], src->tan.Dr[i], src->tM[i], kmat);
    ps_int a = net->a[i], b = net->b[i];
    add_block(dst, a, dst->slot_diag[a], kmat, 1.0);
    add_block(dst, b, dst->slot_diag[b], kmat, 1.0);
    add_block(dst, b, dst->slot_ab[i], kmat, -1.0);
    add_block(dst, a, dst->slot_ba[i], kmat, -1.0);
  }
}

/* position in Kfull of particle a's diagonal entry in direction k */
static inline ps_int diag_pos(const ps_system *s, ps_int a, int k) {
  return ps_asm_kpos(s, a, s->slot_diag[a], k, k);
}

/* A particle is loose in the directions its intact arms do not span
 * (every direction once they have all broken; mark_free_bodies in
 * evaluate.c): a spring (N/m) along them, spring P_a on a's diagonal
 * block with P_a the projector free_proj, keeps the tangent nonsingular;
 * it carries no force, so it moves no converged state, and the particle
 * stays where it is in those directions. */
void ps_asm_finish_tangent(ps_system *s, const unsigned char *free_body, const double *free_proj,
                           double spring) {
  const ps_network *net = s->net;
  int d = s->dim;
  if (spring < 0) {
    spring = 0.0;
    for (ps_int a = 0; a < net->n_particle; a++)
      for (int k = 0; k < d; k++) spring = fmax(spring, s->Kfull[diag_pos(s, a, k)]);
  }
  for (ps_int a = 0; a < net->n_particle; a++) {
    if (!free_body[a]) continue;
    const double *P = &free_proj[(ps_int)d * d * a];
    for (int be = 0; be < d; be++)
      for (int al = 0; al < d; al++)
        s->Kfull[ps_asm_kpos(s, a, s->slot_diag[a], al, be)] += spring * P[be * d + al];
  }
  for (ps_int k = 0; k < s->A.p[s->n_free]; k++) s->A.x[k] = s->Kfull[s->A_src[k]];
}

/* add cc g g^T for particle c's family term `term` (ps_asm_family_term):
 * block (M[p], M[q]) += cc g_p g_q^T */
static void add_family_term(ps_system *s, ps_int c, int term) {
  int d = s->dim;
  double kmat[9];
  ps_int m;
  const ps_int *M;
  const double *g;
  double cc = ps_asm_family_term(s, c, term, &m, &M, &g);
  if (cc == 0.0) return;
  const ps_int *slot = &s->fam_slot[s->fam_slot_ptr[c]];
  for (ps_int qq = 0; qq < m; qq++) {
    const double *gq = &g[qq * d];
    for (ps_int pp = 0; pp < m; pp++) {
      const double *gp = &g[pp * d];
      for (int be = 0; be < d; be++)
        for (int al = 0; al < d; al++) kmat[be * d + al] = cc * gp[al] * gq[be];
      add_block(s, M[qq], slot[qq * m + pp], kmat, 1.0);
    }
  }
}

ps_int ps_system_first_loose(const ps_system *s, const unsigned char *only) {
  int d = s->dim;
  for (ps_int a = 0; a < s->net->n_particle; a++) {
    if (!s->free_body[a] || (only && !only[a])) continue;
    /* a loose direction with a component along a free dof (one along
     * prescribed dofs alone holds nothing that moves): the free dof most
     * along them */
    const double *P = &s->free_proj[(ps_int)d * d * a];
    int kmax = -1;
    for (int k = 0; k < d; k++)
      if (s->free_of_dof[a * d + k] >= 0 && P[k * d + k] > 1e-12 &&
          (kmax < 0 || P[k * d + k] > P[kmax * d + kmax]))
        kmax = k;
    if (kmax >= 0) return a * d + kmax;
  }
  return -1;
}

int ps_system_assemble(ps_system *s, ps_ctx *ctx) {
  (void)ctx;
  if (s->assembled) return PS_OK;
  ps_asm_assemble_arms(s, s, s->tan.D);
  for (ps_int c = 0; c < s->net->n_particle; c++)
    for (int term = 0; term < 2; term++) add_family_term(s, c, term);
  ps_asm_finish_tangent(s, s->free_body, s->free_proj, s->spring);
  s->assembled = 1;
  return PS_OK;
}
