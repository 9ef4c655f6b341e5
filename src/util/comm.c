/* comm.c: the reductions of a run over its processes (ps_comm, ps_util.h)
 * and the halo that brings ghosts' values from their owners. The
 * operations themselves are the comm's (MPI in linsolve/petsc.c); a NULL
 * comm is one process. */
#include "ps_util.h"

#include <stdlib.h>
#include <string.h>

void ps_comm_sum(const ps_comm *comm, double *x, int n) {
  if (comm && n > 0) comm->sum(comm->data, x, n);
}

void ps_comm_max(const ps_comm *comm, double *x, int n) {
  if (comm && n > 0) comm->max(comm->data, x, n);
}

void ps_comm_min(const ps_comm *comm, double *x, int n) {
  if (comm && n > 0) comm->min(comm->data, x, n);
}

double ps_comm_sum1(const ps_comm *comm, double x) {
  ps_comm_sum(comm, &x, 1);
  return x;
}

int64_t ps_comm_count(const ps_comm *comm, int64_t n) {
  double x = (double)n;
  ps_comm_sum(comm, &x, 1);
  return (int64_t)x;
}

int ps_comm_any(const ps_comm *comm, int flag) {
  double x = flag != 0;
  ps_comm_max(comm, &x, 1);
  return x != 0.0;
}

void ps_halo_free(ps_halo *h) {
  if (!h) return;
  free(h->scount);
  free(h->send_item);
  free(h->recv_item);
  free(h->sbuf);
  free(h->rbuf);
  memset(h, 0, sizeof *h);
}

typedef struct {
  ps_int global, local;
} numbered;

static int by_global(const void *u, const void *v) {
  const numbered *x = u, *y = v;
  return (x->global > y->global) - (x->global < y->global);
}

/* displacements of counts, their total */
static int prefix(const int *count, int *displ, int n) {
  int t = 0;
  for (int q = 0; q < n; q++) {
    displ[q] = t;
    t += count[q];
  }
  return t;
}

int ps_halo_create(ps_halo *h, const ps_comm *comm, ps_int n_local, ps_int n_owned,
                   const ps_int *global, const int *owner, ps_ctx *ctx) {
  memset(h, 0, sizeof *h);
  const ps_int n_ghost = n_local - n_owned;
  const int P = comm ? comm->size : 1;
  h->size = P;
  if (P == 1 && n_ghost == 0) return PS_OK;
  if (P == 1 || !comm->alltoallv)
    return ps_error(ctx, PS_ERR_INPUT, "%lld ghosts but no processes to bring them from",
                    (long long)n_ghost);
  int status = PS_OK;
  /* [size] ints each: scount sdispl rcount rdispl bcount bdispl ccount cdispl, and the
   * byte counts of the set-up's two exchanges */
  h->scount = ps_calloc((size_t)(12 * P), sizeof *h->scount, ctx);
  numbered *mine = ps_calloc((size_t)n_owned + 1, sizeof *mine, ctx);
  ps_int *ask = ps_calloc((size_t)n_ghost + 1, sizeof *ask, ctx);
  h->recv_item = ps_calloc((size_t)n_ghost + 1, sizeof *h->recv_item, ctx);
  ps_int *asked = NULL;
  /* (every process stops alike: the others would wait in a collective) */
  if (ps_comm_any(comm, !h->scount || !mine || !ask || !h->recv_item)) {
    status = ps_error(ctx, PS_ERR_NOMEM, "out of memory for the halo (here or on another "
                      "process)");
    goto cleanup;
  }
  h->sdispl = h->scount + P;
  h->rcount = h->scount + 2 * P;
  h->rdispl = h->scount + 3 * P;
  h->bcount = h->scount + 4 * P;
  h->bdispl = h->scount + 5 * P;
  h->ccount = h->scount + 6 * P;
  h->cdispl = h->scount + 7 * P;
  int *one = h->scount + 8 * P, *onedispl = h->scount + 9 * P;
  int *b1 = h->scount + 10 * P, *b2 = h->scount + 11 * P;
  /* my requests, grouped by owner in the order of my ghosts (a bad owner
   * fails every process alike) */
  ps_int bad_owner = -1;
  for (ps_int k = 0; k < n_ghost; k++) {
    if (owner[k] < 0 || owner[k] >= P || owner[k] == comm->rank) {
      if (bad_owner < 0) bad_owner = k;
      continue;
    }
    h->rcount[owner[k]]++;
  }
  if (ps_comm_any(comm, bad_owner >= 0)) {
    if (bad_owner < 0)
      status = ps_error(ctx, PS_ERR_INPUT, "another process has a ghost of no other process");
    else
      status = ps_error(ctx, PS_ERR_INPUT, "ghost %lld (particle %lld): owner %d is not "
                        "another process", (long long)bad_owner,
                        (long long)global[n_owned + bad_owner], owner[bad_owner]);
    goto cleanup;
  }
  if (ps_comm_any(comm, (double)n_ghost * sizeof(ps_int) > 2147483647.0)) {
    status = ps_error(ctx, PS_ERR_INPUT, "%lld ghosts here: a process's ghosts exceed one "
                      "halo's 2^31 bytes", (long long)n_ghost);
    goto cleanup;
  }
  prefix(h->rcount, h->rdispl, P);
  for (int q = 0; q < P; q++) one[q] = (int)sizeof(int), onedispl[q] = q * (int)sizeof(int);
  {
    int *fill = h->bcount; /* scratch: the next slot of each owner */
    memcpy(fill, h->rdispl, (size_t)P * sizeof *fill);
    for (ps_int k = 0; k < n_ghost; k++) {
      int slot = fill[owner[k]]++;
      ask[slot] = global[n_owned + k];
      h->recv_item[slot] = n_owned + k;
    }
  }
  /* how many each process asks of me, then which */
  comm->alltoallv(comm->data, h->rcount, one, onedispl, h->scount, one, onedispl);
  int n_send = prefix(h->scount, h->sdispl, P);
  asked = ps_calloc((size_t)n_send + 1, sizeof *asked, ctx);
  h->send_item = ps_calloc((size_t)n_send + 1, sizeof *h->send_item, ctx);
  if (ps_comm_any(comm, !asked || !h->send_item)) {
    status = ps_error(ctx, PS_ERR_NOMEM, "out of memory for the halo (here or on another "
                      "process)");
    goto cleanup;
  }
  for (int q = 0; q < P; q++) {
    b1[q] = h->rcount[q] * (int)sizeof(ps_int);
    b2[q] = h->rdispl[q] * (int)sizeof(ps_int);
    h->ccount[q] = h->scount[q] * (int)sizeof(ps_int);
    h->cdispl[q] = h->sdispl[q] * (int)sizeof(ps_int);
  }
  comm->alltoallv(comm->data, ask, b1, b2, asked, h->ccount, h->cdispl);
  /* the local number of each item asked of me */
  for (ps_int a = 0; a < n_owned; a++) mine[a] = (numbered){global[a], a};
  qsort(mine, (size_t)n_owned, sizeof *mine, by_global);
  int bad = 0;
  for (int k = 0; k < n_send; k++) {
    numbered key = {asked[k], 0}, *hit = bsearch(&key, mine, (size_t)n_owned, sizeof *mine,
                                                 by_global);
    h->send_item[k] = hit ? hit->local : 0;
    bad += !hit;
  }
  if (ps_comm_any(comm, bad)) {
    status = ps_error(ctx, PS_ERR_INPUT, "a ghost was asked of a process that does not own it"
                      " (%d here)", bad);
    goto cleanup;
  }
cleanup:
  free(mine);
  free(ask);
  free(asked);
  if (status < 0) ps_halo_free(h);
  return status;
}

int ps_halo_exchange(ps_halo *h, const ps_comm *comm, double *x, int width, ps_ctx *ctx) {
  if (h->size == 1 || !h->scount) return PS_OK;
  const int P = h->size;
  int n_send = h->sdispl[P - 1] + h->scount[P - 1], n_recv = h->rdispl[P - 1] + h->rcount[P - 1];
  if (width != h->width) {
    int big = (double)(n_send > n_recv ? n_send : n_recv) * width * sizeof(double) > 2147483647.0;
    if (ps_comm_any(comm, big)) /* (every process stops alike) */
      return ps_error(ctx, PS_ERR_INPUT, "a halo of %d and %d items of %d values here: a "
                      "process's exchange exceeds 2^31 bytes", n_send, n_recv, width);
    free(h->sbuf);
    free(h->rbuf);
    h->sbuf = ps_calloc((size_t)n_send * (size_t)width + 1, sizeof *h->sbuf, ctx);
    h->rbuf = ps_calloc((size_t)n_recv * (size_t)width + 1, sizeof *h->rbuf, ctx);
    h->width = 0;
    if (ps_comm_any(comm, !h->sbuf || !h->rbuf))
      return ps_error(ctx, PS_ERR_NOMEM, "out of memory for the halo's exchange (here or on "
                      "another process)");
    for (int q = 0; q < P; q++) {
      const int w = width * (int)sizeof(double);
      h->bcount[q] = h->scount[q] * w;
      h->bdispl[q] = h->sdispl[q] * w;
      h->ccount[q] = h->rcount[q] * w;
      h->cdispl[q] = h->rdispl[q] * w;
    }
    h->width = width;
  }
  for (int k = 0; k < n_send; k++)
    memcpy(&h->sbuf[(size_t)k * width], &x[h->send_item[k] * width], (size_t)width * sizeof *x);
  comm->alltoallv(comm->data, h->sbuf, h->bcount, h->bdispl, h->rbuf, h->ccount, h->cdispl);
  for (int k = 0; k < n_recv; k++)
    memcpy(&x[h->recv_item[k] * width], &h->rbuf[(size_t)k * width], (size_t)width * sizeof *x);
  return PS_OK;
}

int ps_comm_gather(const ps_comm *comm, const double *mine, ps_int n_mine, int width,
                   int to_all, double **all, ps_int *n_all, ps_ctx *ctx) {
  const int P = comm ? comm->size : 1, rank = ps_comm_rank(comm);
  *all = NULL;
  *n_all = 0;
  if (P == 1) {
    *all = ps_calloc((size_t)(n_mine * width) + 1, sizeof **all, ctx);
    if (!*all) return PS_ERR_NOMEM;
    if (n_mine) memcpy(*all, mine, (size_t)(n_mine * width) * sizeof *mine);
    *n_all = n_mine;
    return PS_OK;
  }
  if (!comm->alltoallv)
    return ps_error(ctx, PS_ERR_INPUT, "a gather on a comm without alltoallv");
  /* every process's row count, to all; then the rows to the first */
  double total = ps_comm_sum1(comm, (double)n_mine);
  if (ps_comm_any(comm, total * width * sizeof(double) > 2147483647.0))
    return ps_error(ctx, PS_ERR_INPUT, "%.0f rows of %d values: a gather exceeds 2^31 bytes",
                    total, width);
  int *c = ps_calloc((size_t)(6 * P), sizeof *c, ctx); /* counts and displacements */
  int fail = !c;
  const int gets = to_all || rank == 0;
  if (!fail && gets && !(*all = ps_calloc((size_t)total * width + 1, sizeof **all, ctx)))
    fail = 1;
  if (ps_comm_any(comm, fail)) {
    free(c);
    free(*all);
    *all = NULL;
    return ps_error(ctx, PS_ERR_NOMEM, "out of memory for a gather (here or on another "
                    "process)");
  }
  int *one = c, *onedispl = c + P, *scount = c + 2 * P, *sdispl = c + 3 * P,
      *rcount = c + 4 * P, *rdispl = c + 5 * P;
  for (int q = 0; q < P; q++) one[q] = (int)sizeof(int), onedispl[q] = q * (int)sizeof(int);
  for (int q = 0; q < P; q++) /* to the first only, or to all */
    scount[q] = to_all || q == 0 ? (int)(n_mine * width * (ps_int)sizeof(double)) : 0;
  comm->alltoallv(comm->data, scount, one, onedispl, rcount, one, onedispl);
  for (int q = 0, t = 0; q < P; q++) {
    if (!gets) rcount[q] = 0;
    rdispl[q] = t;
    t += rcount[q];
  }
  comm->alltoallv(comm->data, mine, scount, sdispl, *all, rcount, rdispl);
  if (gets) *n_all = (ps_int)total;
  free(c);
  return PS_OK;
}

