/* pattern.c: the symbolic part of the system, built once per network: the
 * dof map (dof a * dim + k of particle a, direction k; free dofs numbered
 * in order), each particle's family members M_a = {a} u family(a), the
 * particle-block pattern of K (column Q holds the union of M_c over c in
 * M_Q: every pair of particles that share a family, two horizons; or M_Q
 * alone, one horizon, without family terms), the slot maps that put each
 * arm's and each family's blocks in place without a search, and the
 * free-free upper triangle A with its gather map from Kfull. */
#include "assembly_internal.h"

#include <math.h>

#include <stdlib.h>
#include <string.h>

static int cmp_int(const void *u, const void *v) {
  ps_int a = *(const ps_int *)u, b = *(const ps_int *)v;
  return a < b ? -1 : a > b;
}

/* block index of particle P in column Q, or -1 */
static ps_int find_block(const ps_system *s, ps_int P, ps_int Q) {
  ps_int lo = s->bptr[Q], hi = s->bptr[Q + 1] - 1;
  while (lo <= hi) {
    ps_int mid = lo + (hi - lo) / 2;
    if (s->bidx[mid] == P) return mid;
    if (s->bidx[mid] < P)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

void ps_system_free(ps_system *s) {
  free(s->fixed);
  free(s->free_of_dof);
  free(s->dof_of_free);
  free(s->bptr);
  free(s->bidx);
  free(s->Kfull);
  free(s->slot_ab);
  free(s->slot_ba);
  free(s->slot_diag);
  free(s->fam_slot_ptr);
  free(s->fam_slot);
  free(s->fam_members_ptr);
  free(s->fam_members);
  free(s->fam_member_arm);
  free(s->A.p);
  free(s->A.i);
  free(s->A.x);
  free(s->A_src);
  free(s->l);
  free(s->dl);
  free(s->q);
  free(s->T);
  free(s->l0);
  free(s->u_geom);
  free(s->G[0]);
  free(s->G[1]);
  free(s->tq);
  free(s->tTl);
  free(s->free_body);
  free(s->free_proj);
  free(s->group);
  free(s->group_size);
  free(s->group_pick);
  free(s->group_far);
  free(s->xw);
  free(s->yw);
  free(s->yw_part);
  free(s->f_part);
  free(s->th);
  free(s->M);
  free(s->r);
  free(s->tr);
  free(s->tM);
  ps_arm_tangent_free(&s->tan);
  memset(s, 0, sizeof *s);
}

/* ptr = n zeroed elements, or status = PS_ERR_NOMEM and goto cleanup */
#define ALLOC(ptr, n)                                                        \
  do {                                                                       \
    (ptr) = ps_calloc((size_t)(n), sizeof *(ptr), ctx);                      \
    if (!(ptr)) {                                                            \
      status = PS_ERR_NOMEM;                                                 \
      goto cleanup;                                                          \
    }                                                                        \
  } while (0)

/* the prescribed-dof mask (copied) and the numbering of the free dofs */
static int dof_map(ps_system *s, const unsigned char *fixed, ps_ctx *ctx) {
  int status = PS_OK;
  ALLOC(s->fixed, s->n_dof);
  ALLOC(s->free_of_dof, s->n_dof);
  memcpy(s->fixed, fixed, (size_t)s->n_dof);
  for (ps_int j = 0; j < s->n_dof; j++)
    s->free_of_dof[j] = s->fixed[j] ? -1 : s->n_free++;
  if (s->n_free == 0)
    return ps_error(ctx, PS_ERR_INPUT, "every dof is prescribed: nothing to solve");
  ALLOC(s->dof_of_free, s->n_free);
  for (ps_int j = 0; j < s->n_dof; j++)
    if (!s->fixed[j]) s->dof_of_free[s->free_of_dof[j]] = j;
cleanup:
  return status;
}

/* members M_a = {a} u family(a) in increasing particle order, each with
 * its position in the network's family list (fam_arm, tan.w; -1 for a) */
static int family_members(ps_system *s, ps_ctx *ctx) {
  const ps_network *net = s->net;
  ps_int n = net->n_particle;
  int status = PS_OK;
  ALLOC(s->fam_members_ptr, n + 1);
  for (ps_int a = 0; a < n; a++)
    s->fam_members_ptr[a + 1] =
        s->fam_members_ptr[a] + (net->fam_ptr[a + 1] - net->fam_ptr[a]) + 1;
  ALLOC(s->fam_members, s->fam_members_ptr[n]);
  ALLOC(s->fam_member_arm, s->fam_members_ptr[n]);
  for (ps_int a = 0; a < n; a++) {
    ps_int m = s->fam_members_ptr[a], placed = 0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k], other = net->a[i] == a ? net->b[i] : net->a[i];
      if (!placed && other > a) {
        s->fam_members[m] = a;
        s->fam_member_arm[m++] = -1;
        placed = 1;
      }
      s->fam_members[m] = other;
      s->fam_member_arm[m++] = k;
    }
    if (!placed) {
      s->fam_members[m] = a;
      s->fam_member_arm[m++] = -1;
    }
  }
cleanup:
  return status;
}

/* column Q's particles bidx[bptr[Q] .. bptr[Q+1]), sorted: the union of
 * M_c over c in M_Q (two horizons), or M_Q alone without family terms;
 * counted in a first pass, listed in a second (a particle is marked with
 * Q + pass n, so the marks of the two passes never collide) */
static int block_pattern(ps_system *s, ps_ctx *ctx) {
  ps_int n = s->net->n_particle;
  int status = PS_OK, family_coupling = s->family_coupling;
  ps_int *mark = NULL;
  ALLOC(mark, n);
  for (ps_int a = 0; a < n; a++) mark[a] = -1;
  ALLOC(s->bptr, n + 1);
  for (int pass = 0; pass < 2; pass++) {
    ps_int nnz = 0;
    for (ps_int Q = 0; Q < n; Q++) {
      ps_int cnt = 0;
      for (ps_int m = s->fam_members_ptr[Q]; m < s->fam_members_ptr[Q + 1]; m++) {
        ps_int c = s->fam_members[m];
        ps_int r0 = family_coupling ? s->fam_members_ptr[c] : m;
        ps_int r1 = family_coupling ? s->fam_members_ptr[c + 1] : m + 1;
        for (ps_int r = r0; r < r1; r++) {
          ps_int P = s->fam_members[r];
          if (mark[P] != Q + pass * n) {
            mark[P] = Q + pass * n;
            if (pass == 1) s->bidx[nnz + cnt] = P;
            cnt++;
          }
        }
      }
      if (pass == 1) qsort(&s->bidx[nnz], (size_t)cnt, sizeof(ps_int), cmp_int);
      nnz += cnt;
      if (pass == 0) s->bptr[Q + 1] = nnz;
    }
    if (pass == 0) ALLOC(s->bidx, nnz);
  }
  ALLOC(s->Kfull, (ps_int)s->dim * s->dim * s->bptr[n]);
cleanup:
  free(mark);
  return status;
}

/* the block of each arm (a, b) in column b and (b, a) in column a, each
 * particle's diagonal block, and per family the |M|^2 blocks (M[p], M[q])
 * in column M[q] (a merge walk down the sorted column) */
static int slot_maps(ps_system *s, ps_ctx *ctx) {
  const ps_network *net = s->net;
  ps_int n = net->n_particle;
  int status = PS_OK;
  ALLOC(s->slot_ab, net->n_arm);
  ALLOC(s->slot_ba, net->n_arm);
  ALLOC(s->slot_diag, n);
  for (ps_int i = 0; i < net->n_arm; i++) {
    s->slot_ab[i] = find_block(s, net->a[i], net->b[i]);
    s->slot_ba[i] = find_block(s, net->b[i], net->a[i]);
  }
  for (ps_int a = 0; a < n; a++) s->slot_diag[a] = find_block(s, a, a);
  ALLOC(s->fam_slot_ptr, n + 1);
  for (ps_int a = 0; a < n && s->family_coupling; a++) {
    ps_int m = s->fam_members_ptr[a + 1] - s->fam_members_ptr[a];
    s->fam_slot_ptr[a + 1] = s->fam_slot_ptr[a] + m * m;
  }
  ALLOC(s->fam_slot, s->fam_slot_ptr[n] + 1);
  for (ps_int a = 0; a < n && s->family_coupling; a++) {
    const ps_int *M = &s->fam_members[s->fam_members_ptr[a]];
    ps_int m = s->fam_members_ptr[a + 1] - s->fam_members_ptr[a];
    ps_int *out = &s->fam_slot[s->fam_slot_ptr[a]];
    for (ps_int qq = 0; qq < m; qq++) {
      ps_int Q = M[qq], blk = s->bptr[Q];
      for (ps_int pp = 0; pp < m; pp++) {
        while (s->bidx[blk] < M[pp]) blk++;
        out[qq * m + pp] = blk;
      }
    }
  }
cleanup:
  return status;
}

/* A: the upper triangle of the free-free block (dof CSC, for linsolve),
 * and A_src: each entry's position in Kfull (counted, then listed) */
static int free_triangle(ps_system *s, ps_ctx *ctx) {
  int status = PS_OK, d = s->dim;
  ALLOC(s->A.p, s->n_free + 1);
  for (int pass = 0; pass < 2; pass++) {
    ps_int nnz = 0;
    for (ps_int jf = 0; jf < s->n_free; jf++) {
      ps_int j = s->dof_of_free[jf], Q = j / d;
      int be = (int)(j % d);
      for (ps_int blk = s->bptr[Q]; blk < s->bptr[Q + 1]; blk++)
        for (int al = 0; al < d; al++) {
          ps_int r = s->bidx[blk] * d + al, rf = s->free_of_dof[r];
          if (rf < 0 || rf > jf) continue; /* prescribed, or lower triangle */
          if (pass == 1) {
            s->A.i[nnz] = rf;
            s->A_src[nnz] = ps_asm_kpos(s, Q, blk, al, be);
          }
          nnz++;
        }
      if (pass == 0) s->A.p[jf + 1] = nnz;
    }
    if (pass == 0) {
      ALLOC(s->A.i, nnz);
      ALLOC(s->A.x, nnz);
      ALLOC(s->A_src, nnz);
    }
  }
  s->A.n = s->n_free;
cleanup:
  return status;
}

/* the per-arm and per-dof arrays of evaluations and products */
static int work_arrays(ps_system *s, ps_ctx *ctx) {
  const ps_network *net = s->net;
  int status = PS_OK, d = s->dim;
  ALLOC(s->l, net->n_arm);
  ALLOC(s->dl, net->n_arm);
  ALLOC(s->q, (ps_int)d * net->n_arm);
  ALLOC(s->T, net->n_arm);
  ALLOC(s->l0, net->n_arm);
  ALLOC(s->u_geom, s->n_dof);
  for (ps_int i = 0; i < net->n_arm; i++) {
    double r0 = net->r0[i], e2 = PS_ARM_LENGTH_ROUNDING * PS_ARM_LENGTH_ROUNDING * r0 * r0;
    s->l0[i] = sqrt(r0 * r0 + e2);
  }
  ALLOC(s->tq, (ps_int)d * net->n_arm);
  ALLOC(s->tTl, net->n_arm);
  ALLOC(s->free_body, net->n_particle);
  ALLOC(s->free_proj, (ps_int)d * d * net->n_particle);
  ALLOC(s->group, net->n_particle);
  ALLOC(s->group_size, net->n_particle);
  ALLOC(s->group_pick, 2 * net->n_particle);
  ALLOC(s->group_far, net->n_particle);
  ALLOC(s->xw, s->n_dof);
  ALLOC(s->yw, s->n_dof);
  s->parts = PS_PARTS_DEFAULT;
  ALLOC(s->yw_part, (PS_PARTS_DEFAULT - 1) * s->n_dof);
  ALLOC(s->f_part, (PS_PARTS_DEFAULT - 1) * s->n_dof);
  status = ps_arm_tangent_alloc(&s->tan, net, ctx);
cleanup:
  return status;
}

int ps_system_create(ps_system *s, const ps_network *net,
                     const unsigned char *fixed, ps_ctx *ctx) {
  return ps_system_create_pattern(s, net, fixed, 1, ctx);
}

int ps_system_create_pattern(ps_system *s, const ps_network *net,
                             const unsigned char *fixed, int family_coupling,
                             ps_ctx *ctx) {
  int status = PS_OK;
  memset(s, 0, sizeof *s);
  s->net = net;
  s->dim = net->dim;
  s->family_coupling = family_coupling;
  s->n_dof = (ps_int)net->dim * net->n_particle;
  PS_CHECK_GOTO(dof_map(s, fixed, ctx));
  PS_CHECK_GOTO(family_members(s, ctx));
  PS_CHECK_GOTO(block_pattern(s, ctx));
  PS_CHECK_GOTO(slot_maps(s, ctx));
  PS_CHECK_GOTO(free_triangle(s, ctx));
  PS_CHECK_GOTO(work_arrays(s, ctx));
cleanup:
  if (status < 0) ps_system_free(s);
  return status;
}

int ps_system_set_parts(ps_system *s, int parts, ps_ctx *ctx) {
  if (parts < 1 || parts > PS_PARTS_MAX)
    return ps_error(ctx, PS_ERR_INPUT, "parts must be 1 to %d (got %d)", PS_PARTS_MAX, parts);
  if (parts == s->parts) return PS_OK;
  /* one n_dof at least, so that no size is 0 */
  size_t n = (size_t)(parts > 1 ? parts - 1 : 1) * (size_t)s->n_dof;
  double *yw = ps_calloc(n, sizeof *yw, ctx), *f = ps_calloc(n, sizeof *f, ctx);
  if (!yw || !f) {
    free(yw);
    free(f);
    return PS_ERR_NOMEM;
  }
  free(s->yw_part);
  free(s->f_part);
  s->yw_part = yw;
  s->f_part = f;
  s->parts = parts;
  return PS_OK;
}

void ps_system_dof_name(const ps_system *s, const double *X, ps_int dof,
                        char *buf, size_t len) {
  ps_int a = dof / s->dim;
  const char *ax = "xyz";
  if (s->dim == 2)
    snprintf(buf, len, "particle %lld at (%g, %g), dof %c", (long long)a,
             X[2 * a], X[2 * a + 1], ax[dof % s->dim]);
  else
    snprintf(buf, len, "particle %lld at (%g, %g, %g), dof %c", (long long)a,
             X[3 * a], X[3 * a + 1], X[3 * a + 2], ax[dof % s->dim]);
}

int ps_system_state_list(ps_system *s, ps_state_list *l, ps_ctx *ctx) {
  const size_t na = (size_t)s->net->n_arm, np = (size_t)s->net->n_particle, d = (size_t)s->dim;
  const size_t dbl = sizeof(double);
  if (s->family_coupling)
    for (int term = 0; term < 2; term++)
      if (!s->G[term]) {
        s->G[term] = ps_calloc(d * (size_t)s->fam_members_ptr[np], dbl, ctx);
        if (!s->G[term]) return PS_ERR_NOMEM;
      }
  s->geom_valid = 0; /* a restore writes l, dl, q */
  PS_CHECK(ps_state_add(l, "sys.l", s->l, na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.dl", s->dl, na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.q", s->q, d * na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.T", s->T, na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tan.D", s->tan.D, na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tan.c", s->tan.c, np * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tan.w", s->tan.w, 2 * na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tan.c2", s->tan.c2, np * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tan.w2", s->tan.w2, 2 * na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tan.rot", s->tan.rot, sizeof s->tan.rot, ctx));
  PS_CHECK(ps_state_add(l, "sys.tq", s->tq, d * na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.tTl", s->tTl, na * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.free_body", s->free_body, np, ctx));
  PS_CHECK(ps_state_add(l, "sys.free_proj", s->free_proj, d * d * np * dbl, ctx));
  PS_CHECK(ps_state_add(l, "sys.spring", &s->spring, sizeof s->spring, ctx));
  PS_CHECK(ps_state_add(l, "sys.loose_max", &s->loose_max, sizeof s->loose_max, ctx));
  PS_CHECK(ps_state_add(l, "sys.fragments_max", &s->fragments_max, sizeof s->fragments_max, ctx));
  for (int term = 0; term < 2; term++)
    if (s->G[term])
      PS_CHECK(ps_state_add(l, term ? "sys.G1" : "sys.G0", s->G[term],
                            d * (size_t)s->fam_members_ptr[np] * dbl, ctx));
  if (s->tan.Dr) PS_CHECK(ps_state_add(l, "sys.tan.Dr", s->tan.Dr, na * dbl, ctx));
  if (s->th) {
    PS_CHECK(ps_state_add(l, "sys.th", s->th, na * dbl, ctx));
    PS_CHECK(ps_state_add(l, "sys.M", s->M, na * dbl, ctx));
    PS_CHECK(ps_state_add(l, "sys.r", s->r, 2 * na * dbl, ctx));
    PS_CHECK(ps_state_add(l, "sys.tr", s->tr, 2 * na * dbl, ctx));
    PS_CHECK(ps_state_add(l, "sys.tM", s->tM, na * dbl, ctx));
  }
  return PS_OK;
}
