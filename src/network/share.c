/* share.c: a process's share of a distributed model (ps_share,
 * doc/design-distributed.md): the owned particles of one part, their
 * ghosts, the local network on them and the ownership of its arms. */
#include "ps_network.h"

#include <stdlib.h>
#include <string.h>

void ps_share_free(ps_share *sh) {
  if (!sh) return;
  free(sh->global);
  free(sh->own_arm);
  free(sh->own_particle);
  ps_network_free(&sh->net);
  ps_particles_free(&sh->P);
  memset(sh, 0, sizeof *sh);
}

int ps_share_build(ps_share *sh, const ps_particles *P, const ps_partition *pt, int part,
                   int hops, const ps_kernel *K, const ps_crack *cracks, int n_cracks,
                   ps_ctx *ctx) {
  int status = PS_OK;
  ps_int *ghost = NULL, n_ghost = 0;
  memset(sh, 0, sizeof *sh);
  PS_CHECK(ps_partition_ghost_hops(pt, P, part, hops, K->alpha, &ghost, &n_ghost, ctx));
  sh->part = part;
  sh->n_owned = pt->start[part + 1] - pt->start[part];
  ps_int n = sh->n_owned + n_ghost;
  sh->global = ps_calloc((size_t)n, sizeof *sh->global, ctx);
  sh->own_particle = ps_calloc((size_t)n, 1, ctx);
  if (!sh->global || !sh->own_particle) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  memcpy(sh->global, &pt->order[pt->start[part]], (size_t)sh->n_owned * sizeof *sh->global);
  if (n_ghost) memcpy(sh->global + sh->n_owned, ghost, (size_t)n_ghost * sizeof *ghost);
  memset(sh->own_particle, 1, (size_t)sh->n_owned);
  PS_CHECK_GOTO(ps_particles_subset(&sh->P, P, sh->global, n, ctx));
  PS_CHECK_GOTO(ps_network_build_local(&sh->net, &sh->P, K, cracks, n_cracks, sh->n_owned, ctx));
  sh->own_arm = ps_calloc((size_t)sh->net.n_arm + 1, 1, ctx);
  if (!sh->own_arm) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  for (ps_int i = 0; i < sh->net.n_arm; i++) {
    ps_int ga = sh->global[sh->net.a[i]], gb = sh->global[sh->net.b[i]];
    sh->own_arm[i] = pt->part_of[ga < gb ? ga : gb] == part;
  }
cleanup:
  free(ghost);
  if (status < 0) ps_share_free(sh);
  return status;
}

int ps_share_global_rows(const ps_share *sh, const ps_partition *pt, int dim, ps_int **rows,
                         ps_int *row0, ps_ctx *ctx) {
  ps_int n = sh->P.n;
  ps_int *pos = ps_calloc((size_t)pt->n + 1, sizeof *pos, ctx); /* curve position */
  *rows = ps_calloc((size_t)(n * dim) + 1, sizeof **rows, ctx);
  if (!pos || !*rows) {
    free(pos);
    free(*rows);
    *rows = NULL;
    return PS_ERR_NOMEM;
  }
  for (ps_int j = 0; j < pt->n; j++) pos[pt->order[j]] = j;
  for (ps_int a = 0; a < n; a++)
    for (int c = 0; c < dim; c++) (*rows)[a * dim + c] = pos[sh->global[a]] * dim + c;
  *row0 = pt->start[sh->part] * dim;
  free(pos);
  return PS_OK;
}
