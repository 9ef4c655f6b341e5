/* assembly.c: dof map, two-horizon block pattern, internal forces and the
 * consistent tangent (material D q q^T, geometric (T/l)(I - q q^T), and the
 * rank-one family terms of the mean strain). */
#include "ps_assembly.h"

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

/* position in Kfull of entry (al, be) of block s in column Q */
static inline ps_int kpos(const ps_system *s, ps_int Q, ps_int blk, int al, int be) {
  int d = s->dim;
  ps_int len = s->bptr[Q + 1] - s->bptr[Q];
  return (ps_int)d * d * s->bptr[Q] + (ps_int)be * d * len +
         (blk - s->bptr[Q]) * d + al;
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
  free(s->G[0]);
  free(s->G[1]);
  free(s->tq);
  free(s->tTl);
  free(s->free_body);
  free(s->xw);
  free(s->yw);
  free(s->yw_part);
  free(s->f_part);
  ps_arm_tangent_free(&s->tan);
  memset(s, 0, sizeof *s);
}

#define ALLOC(ptr, n)                                                        \
  do {                                                                       \
    (ptr) = ps_calloc((size_t)(n), sizeof *(ptr), ctx);                      \
    if (!(ptr)) {                                                            \
      status = PS_ERR_NOMEM;                                                 \
      goto cleanup;                                                          \
    }                                                                        \
  } while (0)

int ps_system_create(ps_system *s, const ps_network *net,
                     const unsigned char *fixed, ps_ctx *ctx) {
  return ps_system_create_pattern(s, net, fixed, 1, ctx);
}

int ps_system_create_pattern(ps_system *s, const ps_network *net,
                             const unsigned char *fixed, int family_coupling,
                             ps_ctx *ctx) {
  int status = PS_OK, d = net->dim;
  ps_int n = net->n_particle;
  ps_int *mark = NULL;
  memset(s, 0, sizeof *s);
  s->net = net;
  s->dim = d;
  s->family_coupling = family_coupling;
  s->n_dof = (ps_int)d * n;
  ALLOC(s->fixed, s->n_dof);
  ALLOC(s->free_of_dof, s->n_dof);
  memcpy(s->fixed, fixed, (size_t)s->n_dof);
  for (ps_int j = 0; j < s->n_dof; j++)
    s->free_of_dof[j] = s->fixed[j] ? -1 : s->n_free++;
  if (s->n_free == 0) {
    status = ps_error(ctx, PS_ERR_INPUT, "every dof is prescribed: nothing to solve");
    goto cleanup;
  }
  ALLOC(s->dof_of_free, s->n_free);
  for (ps_int j = 0; j < s->n_dof; j++)
    if (!s->fixed[j]) s->dof_of_free[s->free_of_dof[j]] = j;

  /* members M_a = {a} u family(a), sorted; remember family positions */
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
      s->fam_member_arm[m++] = k; /* position in fam_arm / tan.w */
    }
    if (!placed) {
      s->fam_members[m] = a;
      s->fam_member_arm[m++] = -1;
    }
  }

  /* column Q's particles: union of M_c over c in M_Q (two horizons), or
   * M_Q alone without family terms */
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
    if (pass == 0) ALLOC(s->bidx, nnz); /* marks Q + pass n never collide */
  }
  ps_int nblk = s->bptr[n];
  ALLOC(s->Kfull, (ps_int)d * d * nblk);

  /* arm and diagonal slots */
  ALLOC(s->slot_ab, net->n_arm);
  ALLOC(s->slot_ba, net->n_arm);
  ALLOC(s->slot_diag, n);
  for (ps_int i = 0; i < net->n_arm; i++) {
    s->slot_ab[i] = find_block(s, net->a[i], net->b[i]);
    s->slot_ba[i] = find_block(s, net->b[i], net->a[i]);
  }
  for (ps_int a = 0; a < n; a++) s->slot_diag[a] = find_block(s, a, a);

  /* family slots: block (M[p], M[q]) in column M[q], merge walk */
  ALLOC(s->fam_slot_ptr, n + 1);
  for (ps_int a = 0; a < n && family_coupling; a++) {
    ps_int m = s->fam_members_ptr[a + 1] - s->fam_members_ptr[a];
    s->fam_slot_ptr[a + 1] = s->fam_slot_ptr[a] + m * m;
  }
  ALLOC(s->fam_slot, s->fam_slot_ptr[n] + 1);
  for (ps_int a = 0; a < n && family_coupling; a++) {
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

  /* free-free upper triangle and its gather map */
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
            s->A_src[nnz] = kpos(s, Q, blk, al, be);
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

  ALLOC(s->l, net->n_arm);
  ALLOC(s->dl, net->n_arm);
  ALLOC(s->q, (ps_int)d * net->n_arm);
  ALLOC(s->T, net->n_arm);
  ALLOC(s->tq, (ps_int)d * net->n_arm);
  ALLOC(s->tTl, net->n_arm);
  ALLOC(s->free_body, n);
  ALLOC(s->xw, s->n_dof);
  ALLOC(s->yw, s->n_dof);
  ALLOC(s->yw_part, s->n_dof);
  ALLOC(s->f_part, s->n_dof);
  PS_CHECK_GOTO(ps_arm_tangent_alloc(&s->tan, net, ctx));
cleanup:
  free(mark);
  if (status < 0) ps_system_free(s);
  return status;
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

/* add sign * k (d x d, column-major k[be*d+al]) to block blk of column Q */
static inline void add_block(ps_system *s, ps_int Q, ps_int blk, const double *k,
                             double sign) {
  int d = s->dim;
  ps_int len = s->bptr[Q + 1] - s->bptr[Q];
  double *base = &s->Kfull[(ps_int)d * d * s->bptr[Q] + (blk - s->bptr[Q]) * d];
  for (int be = 0; be < d; be++)
    for (int al = 0; al < d; al++) base[(ps_int)be * d * len + al] += sign * k[be * d + al];
}

/* the d x d arm stiffness D q q^T + (T/l)(I - q q^T), column-major */
static inline void arm_block(int d, const double *q, double D, double Tl, double *kmat) {
  for (int be = 0; be < d; be++)
    for (int al = 0; al < d; al++)
      kmat[be * d + al] = D * q[al] * q[be] + Tl * ((al == be) - q[al] * q[be]);
}

/* Zero dst's Kfull and add the arm terms of src's tangent (geometry tq,
 * tTl) with stiffnesses D. */
static void assemble_arms(ps_system *dst, const ps_system *src, const double *D) {
  const ps_network *net = dst->net;
  int d = dst->dim;
  ps_int nblk = dst->bptr[net->n_particle];
  memset(dst->Kfull, 0, (size_t)(d * d * nblk) * sizeof *dst->Kfull);
  double kmat[9];
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (D[i] == 0.0 && src->tTl[i] == 0.0) continue; /* broken */
    arm_block(d, &src->tq[i * d], D[i], src->tTl[i], kmat);
    ps_int a = net->a[i], b = net->b[i];
    add_block(dst, a, dst->slot_diag[a], kmat, 1.0);
    add_block(dst, b, dst->slot_diag[b], kmat, 1.0);
    add_block(dst, b, dst->slot_ab[i], kmat, -1.0);
    add_block(dst, a, dst->slot_ba[i], kmat, -1.0);
  }
}

/* position in Kfull of particle a's diagonal entry in direction k */
static inline ps_int diag_pos(const ps_system *s, ps_int a, int k) {
  return kpos(s, a, s->slot_diag[a], k, k);
}

/* Finish Kfull and gather the free upper triangle into s->A. A particle
 * whose arms have all broken is a free body (free_body[a]): hold it with
 * a spring (N/m; spring < 0: as stiff as the stiffest dof of Kfull) to
 * keep the tangent nonsingular; it carries no force, so it stays where it
 * is. */
static void finish_tangent(ps_system *s, const unsigned char *free_body, double spring) {
  const ps_network *net = s->net;
  int d = s->dim;
  if (spring < 0) {
    spring = 0.0;
    for (ps_int a = 0; a < net->n_particle; a++)
      for (int k = 0; k < d; k++) spring = fmax(spring, s->Kfull[diag_pos(s, a, k)]);
  }
  for (ps_int a = 0; a < net->n_particle; a++)
    if (free_body[a])
      for (int k = 0; k < d; k++) s->Kfull[diag_pos(s, a, k)] += spring;
  for (ps_int k = 0; k < s->A.p[s->n_free]; k++) s->A.x[k] = s->Kfull[s->A_src[k]];
}

/* g[m x dim] = the gradient of sum_k w[k] l_k (k over particle c's
 * family positions) with respect to the positions of c's m members
 * (fam_members, in that order), with the tangent's directions tq;
 * returns m */
static ps_int family_gradient(const ps_system *s, ps_int c, const double *wt, double *g) {
  const ps_network *net = s->net;
  int d = s->dim;
  const ps_int *Mk = &s->fam_member_arm[s->fam_members_ptr[c]];
  ps_int m = s->fam_members_ptr[c + 1] - s->fam_members_ptr[c], self = -1;
  for (ps_int p = 0; p < m; p++) {
    double *gp = &g[p * d];
    if (Mk[p] < 0) {
      self = p;
      continue;
    }
    ps_int i = net->fam_arm[Mk[p]];
    double w = wt[Mk[p]];
    double sgn = net->a[i] == c ? 1.0 : -1.0; /* unit vector c -> other */
    for (int k = 0; k < d; k++) gp[k] = w * sgn * s->tq[i * d + k];
  }
  double *gs = &g[self * d];
  for (int k = 0; k < d; k++) gs[k] = 0.0;
  for (ps_int p = 0; p < m; p++)
    if (p != self)
      for (int k = 0; k < d; k++) gs[k] -= g[p * d + k];
  return m;
}

/* particle c's rank-one family term `term` (0, 1) of the tangent:
 * returns its coefficient (0: no such term), its m members M and their
 * gradient g[m x dim] (in G[term]) */
static inline double family_term(const ps_system *s, ps_int c, int term, ps_int *m,
                                 const ps_int **M, const double **g) {
  double cc = term == 0 ? s->tan.c[c] : s->tan.c2[c];
  if (cc == 0.0) return 0.0;
  *m = s->fam_members_ptr[c + 1] - s->fam_members_ptr[c];
  *M = &s->fam_members[s->fam_members_ptr[c]];
  *g = &s->G[term][(ps_int)s->dim * s->fam_members_ptr[c]];
  return cc;
}

/* add cc g g^T for particle c's family term (family_term) */
static void add_family_term(ps_system *s, ps_int c, int term) {
  int d = s->dim;
  double kmat[9];
  ps_int m;
  const ps_int *M;
  const double *g;
  double cc = family_term(s, c, term, &m, &M, &g);
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

static void tangent_diagonal(ps_system *s, double *diag);

/* The per-arm and per-particle loops of an evaluation and of the
 * matrix-free product are split into PS_SYSTEM_PARTS parts (halves of the
 * arms and of the particles) for the run's team: the arm geometry and the
 * family gradients write only their own entries; sums over arms (forces,
 * products) of the second part go into a vector of their own (f_part,
 * yw_part), added afterwards (add_second_part), so the sums are the same
 * on one thread or two. */
#define PS_SYSTEM_PARTS 2

/* [*lo, *hi): part `part`'s share of n items */
static inline void part_range(ps_int n, int part, ps_int *lo, ps_int *hi) {
  *lo = n * part / PS_SYSTEM_PARTS;
  *hi = n * (part + 1) / PS_SYSTEM_PARTS;
}

/* y[n] += the second part's sums */
static void add_second_part(double *y, const double *second, ps_int n) {
  for (ps_int k = 0; k < n; k++) y[k] += second[k];
}

typedef struct {
  ps_system *s;
  const ps_arm_state *st;
  const double *X, *u;
  double *f;
  int phase;                  /* 0 geometry, 1 forces, 2 the tangent's data */
  ps_int bad[PS_SYSTEM_PARTS]; /* phase 0: the first arm of a part whose
                                 length is not finite, or -1 */
} eval_job;

static void eval_part(void *arg, int part) {
  eval_job *j = arg;
  ps_system *s = j->s;
  const ps_network *net = s->net;
  const int d = s->dim;
  ps_int i0, i1;
  part_range(net->n_arm, part, &i0, &i1);
  if (j->phase == 0) {
    const double *X = j->X, *u = j->u;
    j->bad[part] = -1;
    for (ps_int i = i0; i < i1; i++) {
      ps_int a = net->a[i], b = net->b[i];
      double l2 = 0.0, dXdu = 0.0, du2 = 0.0;
      double *q = &s->q[i * d];
      for (int k = 0; k < d; k++) {
        double dX = X[b * d + k] - X[a * d + k], du = u[b * d + k] - u[a * d + k];
        q[k] = dX + du;
        l2 += q[k] * q[k];
        dXdu += dX * du;
        du2 += du * du;
      }
      /* the arm length, rounded at zero (ps_arm_length) */
      double r0 = net->r0[i], e2 = PS_ARM_LENGTH_ROUNDING * PS_ARM_LENGTH_ROUNDING * r0 * r0;
      double l = sqrt(l2 + e2);
      if (!isfinite(l) && j->bad[part] < 0) j->bad[part] = i;
      s->l[i] = l;
      /* l - l(r0) = (2 dX.du + du.du)/(l + l(r0)): no cancellation at
       * small strain */
      s->dl[i] = (2.0 * dXdu + du2) / (l + sqrt(r0 * r0 + e2));
      for (int k = 0; k < d; k++) q[k] /= l;
    }
  } else if (j->phase == 1) {
    double *f = part == 0 ? j->f : s->f_part;
    memset(f, 0, (size_t)s->n_dof * sizeof *f);
    for (ps_int i = i0; i < i1; i++) {
      double T = s->T[i];
      if (T == 0.0) continue;
      const double *q = &s->q[i * d];
      for (int k = 0; k < d; k++) {
        f[net->a[i] * d + k] -= T * q[k]; /* dl/dy_a = -q */
        f[net->b[i] * d + k] += T * q[k];
      }
    }
  } else {
    for (ps_int i = i0; i < i1; i++) {
      for (int k = 0; k < d; k++) s->tq[i * d + k] = s->q[i * d + k];
      s->tTl[i] = j->st->broken[i] ? 0.0 : s->T[i] / s->l[i];
    }
  }
}

/* the family gradients of the rank-one terms of the particles of one
 * part (after phase 2: they need tq of every arm; G allocated by the
 * caller) */
static void gradient_part(void *arg, int part) {
  eval_job *j = arg;
  ps_system *s = j->s;
  ps_int c0, c1;
  part_range(s->net->n_particle, part, &c0, &c1);
  for (ps_int c = c0; c < c1; c++)
    for (int term = 0; term < 2; term++) {
      double cc = term == 0 ? s->tan.c[c] : s->tan.c2[c];
      if (cc == 0.0) continue;
      family_gradient(s, c, term == 0 ? s->tan.w : s->tan.w2,
                      &s->G[term][(ps_int)s->dim * s->fam_members_ptr[c]]);
    }
}

int ps_system_eval(ps_system *s, const ps_model *model, ps_arm_state *st,
                   const double *X, const double *u, double *f,
                   double *energy, int want, ps_ctx *ctx) {
  const ps_network *net = s->net;
  int want_tangent = want != PS_EVAL_FORCES;
  int d = s->dim;
  eval_job job = {s, st, X, u, f, 0, {-1, -1}};
  ps_team_run(s->team, PS_SYSTEM_PARTS, eval_part, &job);
  for (int p = 0; p < PS_SYSTEM_PARTS; p++)
    if (job.bad[p] >= 0) {
      ps_int i = job.bad[p];
      return ps_error(ctx, PS_ERR_SOLVER, "arm %lld: particles %lld and %lld: length %g",
                      (long long)i, (long long)net->a[i], (long long)net->b[i], s->l[i]);
    }
  PS_CHECK(model->type->evaluate(model, s->dl, st, s->T, energy,
                                 want_tangent ? &s->tan : NULL, ctx));
  job.phase = 1;
  ps_team_run(s->team, PS_SYSTEM_PARTS, eval_part, &job);
  add_second_part(f, s->f_part, s->n_dof);
  if (!want_tangent) return PS_OK;

  /* keep the tangent's geometry and free bodies */
  s->assembled = 0;
  job.phase = 2;
  ps_team_run(s->team, PS_SYSTEM_PARTS, eval_part, &job);
  ps_int any_free = 0;
  for (ps_int a = 0; a < net->n_particle; a++) {
    int intact = 0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1] && !intact; k++)
      intact = !st->broken[net->fam_arm[k]];
    s->free_body[a] = (unsigned char)!intact;
    any_free += !intact;
  }
  /* the family gradients of the rank-one terms */
  for (int term = 0; term < 2; term++) {
    const double *cc = term == 0 ? s->tan.c : s->tan.c2;
    ps_int any = 0;
    for (ps_int c = 0; cc && c < net->n_particle && !any; c++) any = cc[c] != 0.0;
    if (!any) continue;
    if (!s->family_coupling)
      return ps_error(ctx, PS_ERR_INPUT,
                      "the model has family terms but the tangent pattern has none "
                      "(ps_system_create_pattern with family_coupling 0)");
    if (!s->G[term]) {
      s->G[term] = ps_calloc((size_t)d * (size_t)s->fam_members_ptr[net->n_particle],
                             sizeof *s->G[term], ctx);
      if (!s->G[term]) return PS_ERR_NOMEM;
    }
  }
  ps_team_run(s->team, PS_SYSTEM_PARTS, gradient_part, &job);
  /* the free bodies' spring: the stiffest diagonal entry of K */
  s->spring = 0.0;
  if (any_free) {
    double *diag = s->yw;
    tangent_diagonal(s, diag);
    for (ps_int j = 0; j < s->n_dof; j++) s->spring = fmax(s->spring, diag[j]);
  }
  if (want == PS_EVAL_TANGENT) return ps_system_assemble(s, ctx);
  return PS_OK;
}

int ps_system_assemble(ps_system *s, ps_ctx *ctx) {
  (void)ctx;
  if (s->assembled) return PS_OK;
  assemble_arms(s, s, s->tan.D);
  /* rank-one family terms c_a g_a g_a^T (and a second one, c2 w2) */
  for (ps_int c = 0; c < s->net->n_particle; c++)
    for (int term = 0; term < 2; term++) add_family_term(s, c, term);
  finish_tangent(s, s->free_body, s->spring);
  s->assembled = 1;
  return PS_OK;
}

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
  for (ps_int c = c0; c < c1; c++) {
    ps_int m;
    const ps_int *M;
    const double *g = NULL, *h = NULL;
    double cc = family_term(s, c, 0, &m, &M, &g), ch = family_term(s, c, 1, &m, &M, &h);
    if (cc == 0.0 && ch == 0.0) continue;
    /* both terms in one pass over the members: x and y are read and
     * written once (the family terms are most of the product); a term
     * that is absent is the other's gradient with coefficient 0 (its own
     * may not be allocated), which adds exactly 0 */
    if (cc == 0.0) g = h;
    if (ch == 0.0) h = g;
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

/* the product in PS_SYSTEM_PARTS parts (part 0 into y, part 1 into
 * yw_part) */
typedef struct {
  const ps_system *s;
  const double *x;
  double *y;
} apply_job;

static void apply_part(void *arg, int part) {
  const apply_job *j = arg;
  const ps_system *s = j->s;
  ps_int i0, i1, c0, c1;
  part_range(s->net->n_arm, part, &i0, &i1);
  part_range(s->net->n_particle, part, &c0, &c1);
  double *y = part == 0 ? j->y : s->yw_part;
  if (s->dim == 2) /* constant loop bounds: 1.4x faster */
    apply_terms_dim(s, j->x, y, i0, i1, c0, c1, 2);
  else
    apply_terms_dim(s, j->x, y, i0, i1, c0, c1, 3);
}

static void apply_terms(const ps_system *s, const double *x, double *y) {
  apply_job j = {s, x, y};
  ps_team_run(s->team, PS_SYSTEM_PARTS, apply_part, &j);
  add_second_part(y, s->yw_part, s->n_dof);
}

/* diag[n_dof] = the diagonal of K (no springs) */
static void tangent_diagonal(ps_system *s, double *diag) {
  const ps_network *net = s->net;
  int d = s->dim;
  memset(diag, 0, (size_t)s->n_dof * sizeof *diag);
  double kmat[9];
  for (ps_int i = 0; i < net->n_arm; i++) {
    arm_block(d, &s->tq[i * d], s->tan.D[i], s->tTl[i], kmat);
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
      double cc = family_term(s, c, term, &m, &M, &g);
      if (cc == 0.0) continue;
      for (ps_int p = 0; p < m; p++)
        for (int k = 0; k < d; k++) diag[M[p] * d + k] += cc * g[p * d + k] * g[p * d + k];
    }
}

void ps_system_apply(const ps_system *s, const double *x, double *y) {
  int d = s->dim;
  apply_terms(s, x, y);
  if (s->spring > 0)
    for (ps_int a = 0; a < s->net->n_particle; a++)
      if (s->free_body[a])
        for (int k = 0; k < d; k++) y[a * d + k] += s->spring * x[a * d + k];
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
  ps_operator op = {s->n_free, system_apply, s};
  return op;
}

int ps_system_assemble_majorant(ps_system *pre, const ps_system *K, ps_ctx *ctx) {
  const ps_network *net = K->net;
  if (pre->net != net || pre->family_coupling || pre->n_free != K->n_free)
    return ps_error(ctx, PS_ERR_INPUT, "majorant: the systems do not match");
  /* pre's own per-arm arrays are not used otherwise (its geometry is K's):
   * pre->T holds the arm stiffnesses of the majorant */
  double *D = pre->T;
  memcpy(D, K->tan.D, (size_t)net->n_arm * sizeof *D);
  for (ps_int c = 0; c < net->n_particle; c++)
    for (int term = 0; term < 2; term++) {
      double cc = term == 0 ? K->tan.c[c] : K->tan.c2[c];
      const double *w = term == 0 ? K->tan.w : K->tan.w2;
      if (!(cc > 0.0)) continue; /* negative terms only lower K */
      /* (sum_k w_k x_k)^2 <= (sum_k |w_k| r0_k) (sum_k |w_k| x_k^2 / r0_k) */
      double S = 0.0;
      for (ps_int k = net->fam_ptr[c]; k < net->fam_ptr[c + 1]; k++)
        S += fabs(w[k]) * net->r0[net->fam_arm[k]];
      for (ps_int k = net->fam_ptr[c]; k < net->fam_ptr[c + 1]; k++) {
        ps_int i = net->fam_arm[k];
        D[i] += cc * S * fabs(w[k]) / net->r0[i];
      }
    }
  assemble_arms(pre, K, D);
  finish_tangent(pre, K->free_body, -1.0);
  pre->assembled = 1;
  return PS_OK;
}

void ps_system_coupling(ps_system *s, const double *du, double *out) {
  for (ps_int j = 0; j < s->n_dof; j++) s->xw[j] = s->fixed[j] ? du[j] : 0.0;
  apply_free_rows(s, out);
}
