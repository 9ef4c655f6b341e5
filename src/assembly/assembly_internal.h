/* assembly_internal.h: what the files of src/assembly share and nothing
 * outside it may use: the layout of Kfull (kpos), the d x d block of an
 * arm, a particle's rank-one family term, the split of a loop into
 * s->parts parts, and the functions one file provides to another.
 *   pattern.c   dof map, block pattern, slot maps (symbolic, once)
 *   evaluate.c  arm lengths, tensions (the model), forces, tangent data
 *   assemble.c  the tangent's data into Kfull and the free-free A
 *   operator.c  y = K x without the matrix; the diagonal of K
 *   majorant.c  the one-horizon majorant of K */
#ifndef PS_ASSEMBLY_INTERNAL_H
#define PS_ASSEMBLY_INTERNAL_H

#include "ps_assembly.h"

/* The loops over arms and particles of an evaluation and of the
 * matrix-free product run in s->parts parts on the system's team: part 0
 * writes sums over arms into the caller's vector, part p >= 1 into a
 * vector of its own (f_part, yw_part: [(parts - 1) n_dof], part p's at
 * (p - 1) n_dof), added afterwards in the order of the parts
 * (ps_asm_add_parts), so the sums are formed in the same order on any
 * number of threads. */

/* y[n_dof] += the sums of parts 1 .. parts - 1 in out[(parts - 1) n_dof],
 * y_k = ((y_k + out_1,k) + out_2,k) + ... for each k: the same numbers
 * however the dofs are shared among the team (evaluate.c) */
void ps_asm_add_parts(const ps_system *s, double *y, const double *out);
/* position in Kfull of entry (al, be) of block blk of column Q (the
 * layout of ps_system's Kfull) */
static inline ps_int ps_asm_kpos(const ps_system *s, ps_int Q, ps_int blk, int al, int be) {
  int d = s->dim;
  ps_int len = s->bptr[Q + 1] - s->bptr[Q];
  return (ps_int)d * d * s->bptr[Q] + (ps_int)be * d * len + (blk - s->bptr[Q]) * d + al;
}

/* kmat (d x d, column-major) = the arm stiffness D q q^T + (T/l)(I - q q^T) */
static inline void ps_asm_arm_block(int d, const double *q, double D, double Tl,
                                    double *kmat) {
  for (int be = 0; be < d; be++)
    for (int al = 0; al < d; al++)
      kmat[be * d + al] = D * q[al] * q[be] + Tl * ((al == be) - q[al] * q[be]);
}

/* kmat (2 x 2, column-major) += the rotation part of an arm's stiffness
 * (models with rotations), Dr r r^T - M (p r^T + r p^T), p = (r_y, -r_x)
 * = y/|y|^2: Dr dth dth^T + M d2th/dy2 */
static inline void ps_asm_arm_block_rot(const double *r, double Dr, double M,
                                        double *kmat) {
  double p[2] = {r[1], -r[0]};
  for (int be = 0; be < 2; be++)
    for (int al = 0; al < 2; al++)
      kmat[be * 2 + al] += Dr * r[al] * r[be] - M * (p[al] * r[be] + r[al] * p[be]);
}

/* particle c's rank-one family term `term` (0: c w, 1: c2 w2) of the
 * tangent, c_c g g^T: returns its coefficient (0: no such term), its m
 * members M and their gradient g[m x dim] (in G[term]) */
static inline double ps_asm_family_term(const ps_system *s, ps_int c, int term, ps_int *m,
                                        const ps_int **M, const double **g) {
  double cc = term == 0 ? s->tan.c[c] : s->tan.c2[c];
  if (cc == 0.0) return 0.0;
  *m = s->fam_members_ptr[c + 1] - s->fam_members_ptr[c];
  *M = &s->fam_members[s->fam_members_ptr[c]];
  *g = &s->G[term][(ps_int)s->dim * s->fam_members_ptr[c]];
  return cc;
}

/* assemble.c: zero dst's Kfull and add the arm terms of src's tangent
 * (geometry src->tq, src->tTl) with arm stiffnesses D[n_arm] */
void ps_asm_assemble_arms(ps_system *dst, const ps_system *src, const double *D);

/* assemble.c: finish Kfull (spring P_a on each loose particle's diagonal block; spring
 * < 0: the largest diagonal entry of Kfull) and gather the free upper
 * triangle into s->A */
void ps_asm_finish_tangent(ps_system *s, const unsigned char *free_body, const double *free_proj,
                           double spring);

/* operator.c: diag[n_dof] = the diagonal of the tangent K (no springs) */
void ps_asm_tangent_diagonal(const ps_system *s, double *diag);

#endif
