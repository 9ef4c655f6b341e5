/* majorant.c: a one-horizon matrix pre >= K (x^T K x <= x^T pre x for all
 * x) from the last tangent of K, for preconditioning: the arm terms of K,
 * with each positive rank-one family term replaced by arm stiffnesses that
 * bound it by Cauchy-Schwarz,
 *   c (sum_k w_k dl_k)^2 <= c (sum_k |w_k| r0_k) sum_k |w_k| dl_k^2 / r0_k,
 * and each negative one dropped (it only lowers K). A model with arm
 * rotations (threebody) has only negative family terms (-kappa/(2 S_a),
 * on the rotations): they are dropped, and its arm blocks, rotation
 * parts included (ps_asm_assemble_arms), are K's. */
#include "assembly_internal.h"

#include <math.h>
#include <string.h>

int ps_system_assemble_majorant(ps_system *pre, const ps_system *K, ps_ctx *ctx) {
  const ps_network *net = K->net;
  if (pre->net != net || pre->family_coupling || pre->n_free != K->n_free)
    return ps_error(ctx, PS_ERR_INPUT, "majorant: the systems do not match");
  /* pre's tangent: arm stiffnesses D with K's arm geometry, no family
   * terms (pre is never evaluated itself) */
  double *D = pre->tan.D;
  memcpy(D, K->tan.D, (size_t)net->n_arm * sizeof *D);
  for (ps_int c = 0; c < net->n_particle; c++)
    for (int term = 0; term < 2; term++) {
      double cc = term == 0 ? K->tan.c[c] : K->tan.c2[c];
      const double *w = term == 0 ? K->tan.w : K->tan.w2;
      if (!(cc > 0.0)) continue;
      if (K->tan.rot[term]) /* the bound below is for length terms */
        return ps_error(ctx, PS_ERR_INPUT,
                        "majorant: a positive family term on the arm rotations");
      /* S = sum_k |w_k| r0_k; D_k += c S |w_k| / r0_k */
      double S = 0.0;
      for (ps_int k = net->fam_ptr[c]; k < net->fam_ptr[c + 1]; k++)
        S += fabs(w[k]) * net->r0[net->fam_arm[k]];
      for (ps_int k = net->fam_ptr[c]; k < net->fam_ptr[c + 1]; k++) {
        ps_int i = net->fam_arm[k];
        D[i] += cc * S * fabs(w[k]) / net->r0[i];
      }
    }
  ps_asm_assemble_arms(pre, K, D);
  ps_asm_finish_tangent(pre, K->free_body, K->free_proj, -1.0);
  pre->assembled = 1;
  return PS_OK;
}
