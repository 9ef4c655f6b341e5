/* evaluate.c: one evaluation of the system at displacements u: per arm the
 * rounded length l = sqrt(|y_b - y_a|^2 + (e r0)^2) (PS_ARM_LENGTH_ROUNDING),
 * the elongation dl = l - sqrt(r0^2 + (e r0)^2) and the direction q =
 * (y_b - y_a)/l; the tensions T and energy from the model; the internal
 * forces f = dPsi/dy = sum_arms T (dl/dy), dl/dy_a = -q, dl/dy_b = q; and,
 * when asked, the tangent's data: the model's stiffnesses (D, c, w, c2,
 * w2), the arm geometry q and T/l, the family gradients
 *   g_a = sum_{i in family a} w_{a,i} dl_i/dy
 * of the rank-one terms, the loose particles and their spring. The loops over
 * arms and particles run in s->parts parts on the system's team. */
#include "assembly_internal.h"

#include <gsl/gsl_eigen.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  ps_system *s;
  const ps_arm_state *st;
  const double *X, *u;
  double *f;
  int phase;           /* 0 geometry, 1 forces (and, with tangent, the
                          tangent's data) */
  int tangent;
  ps_int bad[PS_PARTS_MAX]; /* phase 0: the first arm of a part whose
                               length is not finite, or -1 */
} eval_job;

/* arms [i0, i1): l, dl, q at y = X + u; the first arm whose length is not
 * finite into j->bad[part]. d is the dimension, a constant where
 * geometry_part inlines this (the same operations in the same order as
 * with a variable d: the same numbers) */
static PS_ALWAYS_INLINE void arm_geometry_dim(eval_job *j, int part, ps_int i0, ps_int i1,
                                              const int d) {
  ps_system *s = j->s;
  const ps_network *net = s->net;
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
    double r0 = net->r0[i], e2 = PS_ARM_LENGTH_ROUNDING * PS_ARM_LENGTH_ROUNDING * r0 * r0;
    double l = sqrt(l2 + e2);
    if (!isfinite(l) && j->bad[part] < 0) j->bad[part] = i;
    s->l[i] = l;
    /* l - l(r0) = (2 dX.du + du.du)/(l + l(r0)): no cancellation at
     * small strain; l(r0) = sqrt(r0^2 + e2) is s->l0 */
    s->dl[i] = (2.0 * dXdu + du2) / (l + s->l0[i]);
    if (s->th) { /* 2D: rotation from dX to y = dX + du, dX x y = dX x du */
      double dX0 = X[b * d] - X[a * d], dX1 = X[b * d + 1] - X[a * d + 1];
      double du0 = u[b * d] - u[a * d], du1 = u[b * d + 1] - u[a * d + 1];
      s->th[i] = atan2(dX0 * du1 - dX1 * du0, dX0 * q[0] + dX1 * q[1]);
      s->r[2 * i] = -q[1] / l2;
      s->r[2 * i + 1] = q[0] / l2;
    }
    for (int k = 0; k < d; k++) q[k] /= l;
  }
}

static void arm_geometry(eval_job *j, int part, ps_int i0, ps_int i1) {
  if (j->s->dim == 2) /* constant loop bounds, unrolled */
    arm_geometry_dim(j, part, i0, i1, 2);
  else
    arm_geometry_dim(j, part, i0, i1, 3);
}

/* f = sum over arms [i0, i1) of T (dl/dy), into j->f (part 0) or part
 * p's n_dof of s->f_part (p >= 1); d as in arm_geometry_dim */
static PS_ALWAYS_INLINE void central_forces_dim(const ps_system *s, double *f, ps_int i0,
                                                ps_int i1, const int d) {
  const ps_network *net = s->net;
  for (ps_int i = i0; i < i1; i++) {
    double T = s->T[i];
    if (T == 0.0) continue;
    const double *q = &s->q[i * d];
    for (int k = 0; k < d; k++) {
      f[net->a[i] * d + k] -= T * q[k]; /* dl/dy_a = -q */
      f[net->b[i] * d + k] += T * q[k];
    }
  }
}

static void arm_forces(eval_job *j, int part, ps_int i0, ps_int i1) {
  ps_system *s = j->s;
  const ps_network *net = s->net;
  double *f = part == 0 ? j->f : s->f_part + (size_t)(part - 1) * (size_t)s->n_dof;
  memset(f, 0, (size_t)s->n_dof * sizeof *f);
  if (s->M) { /* not central: dPsi/dy_b = T q + M r (2D) */
    for (ps_int i = i0; i < i1; i++) {
      double T = s->T[i], Mi = s->M[i];
      if (T == 0.0 && Mi == 0.0) continue;
      const double *q = &s->q[i * 2], *r = &s->r[i * 2];
      for (int k = 0; k < 2; k++) {
        double F = T * q[k] + Mi * r[k];
        f[net->a[i] * 2 + k] -= F;
        f[net->b[i] * 2 + k] += F;
      }
    }
    return;
  }
  if (s->dim == 2)
    central_forces_dim(s, f, i0, i1, 2);
  else
    central_forces_dim(s, f, i0, i1, 3);
}

/* the tangent's arm geometry of arms [i0, i1): tq = q, tTl = T/l (0 for a
 * broken arm) */
static void arm_tangent(eval_job *j, ps_int i0, ps_int i1) {
  ps_system *s = j->s;
  const int d = s->dim;
  memcpy(&s->tq[i0 * d], &s->q[i0 * d], (size_t)((i1 - i0) * d) * sizeof *s->q);
  for (ps_int i = i0; i < i1; i++) {
    s->tTl[i] = j->st->broken[i] ? 0.0 : s->T[i] / s->l[i];
    if (s->tr) {
      s->tr[2 * i] = s->r[2 * i];
      s->tr[2 * i + 1] = s->r[2 * i + 1];
      s->tM[i] = j->st->broken[i] ? 0.0 : s->M[i];
    }
  }
}

static void eval_part(void *arg, int part) {
  eval_job *j = arg;
  ps_int i0, i1;
  ps_part_range(j->s->net->n_arm, part, j->s->parts, &i0, &i1);
  if (j->phase == 0)
    arm_geometry(j, part, i0, i1);
  else {
    arm_forces(j, part, i0, i1);
    if (j->tangent) arm_tangent(j, i0, i1);
  }
}

/* g[m x dim] = the gradient of sum_k w[k] l_k (k over particle c's
 * family positions) with respect to the positions of c's m members
 * (fam_members, in that order), with the tangent's directions dir = tq:
 * w q for a member b (q from c to b), minus their sum for c itself; or,
 * for a family term on the arm rotations (tan.rot), of sum_k w[k] th_k
 * with dir = tr (dth/dy_b = r, dth/dy_a = -r: the same signs) */
static void family_gradient(const ps_system *s, ps_int c, const double *wt,
                            const double *dir, double *g) {
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
    for (int k = 0; k < d; k++) gp[k] = w * sgn * dir[i * d + k];
  }
  double *gs = &g[self * d];
  for (int k = 0; k < d; k++) gs[k] = 0.0;
  for (ps_int p = 0; p < m; p++)
    if (p != self)
      for (int k = 0; k < d; k++) gs[k] -= g[p * d + k];
}

/* the family gradients of the rank-one terms of the particles of one
 * part (they need tq of every arm; G allocated by the caller) */
static void gradient_part(void *arg, int part) {
  eval_job *j = arg;
  ps_system *s = j->s;
  ps_int c0, c1;
  ps_part_range(s->net->n_particle, part, s->parts, &c0, &c1);
  for (ps_int c = c0; c < c1; c++)
    for (int term = 0; term < 2; term++) {
      double cc = term == 0 ? s->tan.c[c] : s->tan.c2[c];
      if (cc == 0.0) continue;
      family_gradient(s, c, term == 0 ? s->tan.w : s->tan.w2,
                      s->tan.rot[term] ? s->tr : s->tq,
                      &s->G[term][(ps_int)s->dim * s->fam_members_ptr[c]]);
    }
}

/* The directions in which no intact arm holds a particle. B_a = the sum
 * over a's intact arms of their stiffness blocks (D q q^T + (T/l)(I - q
 * q^T), plus the rotation part of a model with arm rotations): the
 * particle's own block of K but for the family terms, which lie in the
 * span of the same arms. An eigenvector of B_a whose eigenvalue is at
 * most PS_LOOSE_TOL of B_a's largest in magnitude is a direction in which
 * K's column of a is (to that tolerance) zero: a mechanism of one
 * particle, e.g. one held by collinear arms with no tension on a crack
 * face. Every direction is loose once all arms have broken. The screen:
 * when B_a - PS_LOOSE_TOL trace(B_a) I has a Cholesky factor, every
 * eigenvalue exceeds PS_LOOSE_TOL trace(B_a) >= PS_LOOSE_TOL |lambda|_max,
 * and a is held. */
#define PS_LOOSE_TOL 1e-10

/* 1 when the symmetric d x d matrix M is positive definite (Cholesky) */
static int small_posdef(int d, const double *M) {
  double L[9];
  memcpy(L, M, (size_t)(d * d) * sizeof *L);
  return ps_dense_cholesky(d, L, 0.0);
}

/* the eigenvalues lam[e] and unit eigenvectors vec[e d .. e d + d - 1]
 * of the symmetric d x d matrix S (GSL's Jacobi rotations: no workspace to
 * allocate) */
static void sym_eigen(int d, const double *S, double *lam, double *vec) {
  double a[9], ev[9];
  memcpy(a, S, (size_t)(d * d) * sizeof *a);
  gsl_matrix_view A = gsl_matrix_view_array(a, (size_t)d, (size_t)d);
  gsl_matrix_view V = gsl_matrix_view_array(ev, (size_t)d, (size_t)d);
  gsl_vector_view L = gsl_vector_view_array(lam, (size_t)d);
  unsigned int nrot = 0;
  gsl_eigen_jacobi(&A.matrix, &L.vector, &V.matrix, 100, &nrot);
  for (int e = 0; e < d; e++)
    for (int i = 0; i < d; i++) vec[e * d + i] = ev[i * d + e];
}

/* add v v^T / nn to particle a's spring directions: n n^T for the
 * direction n = v / |v| with nn = |v|^2 (1 for a unit v) */
static void add_direction(ps_system *s, ps_int a, const double *v, double nn) {
  int d = s->dim;
  double *P = &s->free_proj[(ps_int)d * d * a];
  for (int be = 0; be < d; be++)
    for (int al = 0; al < d; al++) P[be * d + al] += v[al] * v[be] / nn;
  if (s->free_body[a] < d) s->free_body[a]++;
}

/* add_direction along v != 0 of any length */
static void add_direction_along(ps_system *s, ps_int a, const double *v) {
  double nn = 0.0;
  for (int k = 0; k < s->dim; k++) nn += v[k] * v[k];
  if (nn > 0) add_direction(s, a, v, nn);
}

static const double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

/* free_body[a] and free_proj (the number of loose directions of a and the
 * projector onto them) from the tangent's arm data, for particles
 * [a0, a1); returns how many of them have any */
static ps_int mark_free_range(ps_system *s, const ps_arm_state *st, ps_int a0, ps_int a1) {
  const ps_network *net = s->net;
  const int d = s->dim;
  ps_int any_free = 0;
  for (ps_int a = a0; a < a1; a++) {
    double B[9] = {0}, kmat[9], *P = &s->free_proj[(ps_int)d * d * a];
    int n = 0;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k];
      if (st->broken[i]) continue;
      ps_asm_arm_block(d, &s->tq[(ps_int)d * i], s->tan.D[i], s->tTl[i], kmat);
      if (s->tr) ps_asm_arm_block_rot(&s->tr[2 * i], s->tan.Dr[i], s->tM[i], kmat);
      for (int m = 0; m < d * d; m++) B[m] += kmat[m];
      n++;
    }
    memset(P, 0, (size_t)(d * d) * sizeof *P);
    s->free_body[a] = 0;
    if (n == 0) { /* a free body: every direction */
      for (int k = 0; k < d; k++) add_direction(s, a, axes[k], 1.0);
      any_free++;
      continue;
    }
    double tr = 0.0, lam[3], vec[9], S[9], big = 0.0;
    for (int k = 0; k < d; k++) tr += B[k * d + k];
    for (int be = 0; be < d; be++)
      for (int al = 0; al < d; al++) S[be * d + al] = 0.5 * (B[be * d + al] + B[al * d + be]);
    for (int k = 0; k < d; k++) S[k * d + k] -= PS_LOOSE_TOL * tr;
    if (tr > 0 && small_posdef(d, S)) continue; /* held */
    for (int k = 0; k < d; k++) S[k * d + k] += PS_LOOSE_TOL * tr;
    sym_eigen(d, S, lam, vec);
    for (int e = 0; e < d; e++) big = fmax(big, fabs(lam[e]));
    for (int e = 0; e < d; e++)
      if (fabs(lam[e]) <= PS_LOOSE_TOL * big) add_direction(s, a, &vec[e * d], 1.0);
    any_free += s->free_body[a] > 0;
  }
  return any_free;
}

typedef struct {
  ps_system *s;
  const ps_arm_state *st;
  ps_int n_free[PS_PARTS_MAX];
} free_job;

static void free_part(void *arg, int part) {
  free_job *j = arg;
  ps_int a0, a1;
  ps_part_range(j->s->net->n_particle, part, j->s->parts, &a0, &a1);
  j->n_free[part] = mark_free_range(j->s, j->st, a0, a1);
}

/* mark_free_range over every particle, in the system's parts (each
 * particle's own data: the same marks on any number of threads); returns
 * how many particles have a loose direction */
static ps_int mark_free_bodies(ps_system *s, const ps_arm_state *st) {
  free_job j = {s, st, {0}};
  ps_team_run(s->team, s->parts, free_part, &j);
  ps_int any_free = 0;
  for (int p = 0; p < s->parts; p++) any_free += j.n_free[p];
  return any_free;
}

/* the root of a's group (union-find with path halving) */
static ps_int group_root(ps_int *parent, ps_int a) {
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

/* Loose groups: particles joined by intact arms into a piece that holds
 * no prescribed dof (a fragment cut off by cracks) move as a rigid body at
 * no cost: its d (d + 1) / 2 rigid modes make K singular although each
 * particle is held. The spring then also acts as a
 * statically determinate support of each such group of two or more
 * particles: in every direction at its first particle p0, across p0-p1 at
 * the particle p1 farthest from p0 and, in 3D, normal to the plane p0 p1
 * p2 at the particle p2 farthest from the line p0 p1 (reference
 * positions X). A determinate support carries no force under a
 * self-equilibrated load, and the internal forces of a free piece are
 * one, so Newton's steps inside the piece are those of K, less its rigid
 * motion. Nothing is marked in a network with no prescribed dof at all.
 * Returns the number of groups supported. */
static ps_int mark_loose_groups(ps_system *s, const ps_arm_state *st, const double *X) {
  const ps_network *net = s->net;
  const int d = s->dim;
  const ps_int n = net->n_particle;
  ps_int *root = s->group, *size = s->group_size, *pick = s->group_pick, marked = 0;
  double *far = s->group_far;
  for (ps_int a = 0; a < n; a++) root[a] = a;
  for (ps_int i = 0; i < net->n_arm; i++) {
    if (st->broken[i]) continue;
    ps_int ra = group_root(root, net->a[i]), rb = group_root(root, net->b[i]);
    if (ra != rb) root[ra > rb ? ra : rb] = ra < rb ? ra : rb; /* the smaller index roots */
  }
  /* root[a]: a's group's root, its smallest index (p0); size[r]: its
   * particles, or -1 once one of them has a prescribed dof */
  for (ps_int a = 0; a < n; a++) {
    root[a] = group_root(root, a);
    size[a] = 0;
  }
  for (ps_int a = 0; a < n; a++) {
    ps_int r = root[a];
    if (size[r] >= 0) size[r]++;
    for (int k = 0; k < d; k++)
      if (s->free_of_dof[a * d + k] < 0) size[r] = -1;
  }
  /* nothing when no group is anchored: a body with no prescribed dof at
   * all keeps its exact (singular) tangent */
  int any = 0, anchored = 0;
  for (ps_int r = 0; r < n; r++) {
    any |= root[r] == r && size[r] >= 2;
    anchored |= root[r] == r && size[r] < 0;
  }
  if (!any || !anchored) return 0;
  /* pick[2 r]: p1, the particle farthest from p0; pick[2 r + 1]: p2 (3D),
   * the particle farthest from the line p0 p1 */
  double e[3] = {0}, v[3], w[3];
  for (int pass = 0; pass < d - 1; pass++) {
    for (ps_int r = 0; r < n; r++) {
      pick[2 * r + pass] = -1;
      far[r] = 0.0;
    }
    for (ps_int a = 0; a < n; a++) {
      ps_int r = root[a];
      if (size[r] < 2) continue;
      double dist = 0.0;
      for (int k = 0; k < d; k++) v[k] = X[a * d + k] - X[r * d + k];
      if (pass == 0) {
        for (int k = 0; k < d; k++) dist += v[k] * v[k];
      } else { /* |(p1 - p0) x (a - p0)|^2 */
        if (pick[2 * r] < 0) continue;
        for (int k = 0; k < 3; k++) e[k] = X[pick[2 * r] * 3 + k] - X[r * 3 + k];
        ps_cross3(e, v, w);
        for (int k = 0; k < 3; k++) dist += w[k] * w[k];
      }
      if (dist > far[r]) {
        far[r] = dist;
        pick[2 * r + pass] = a;
      }
    }
  }
  for (ps_int r = 0; r < n; r++) {
    if (root[r] != r || size[r] < 2 || pick[2 * r] < 0) continue;
    ps_int p1 = pick[2 * r], p2 = d == 3 ? pick[2 * r + 1] : -1;
    for (int k = 0; k < d; k++) add_direction(s, r, axes[k], 1.0);
    for (int k = 0; k < d; k++) e[k] = X[p1 * d + k] - X[r * d + k];
    marked++;
    if (d == 2) { /* across p0-p1 at p1 */
      v[0] = -e[1];
      v[1] = e[0];
      add_direction_along(s, p1, v);
      continue;
    }
    /* 3D: across e at p1 (e x t and e x (e x t), t the axis least along
     * e), the normal of the plane p0 p1 p2 at p2 */
    int m = fabs(e[0]) <= fabs(e[1]) ? (fabs(e[0]) <= fabs(e[2]) ? 0 : 2)
                                     : (fabs(e[1]) <= fabs(e[2]) ? 1 : 2);
    ps_cross3(e, axes[m], v);
    ps_cross3(e, v, w);
    add_direction_along(s, p1, v);
    add_direction_along(s, p1, w);
    if (p2 >= 0) {
      for (int k = 0; k < 3; k++) v[k] = X[p2 * 3 + k] - X[r * 3 + k];
      ps_cross3(e, v, w);
      add_direction_along(s, p2, w);
    }
  }
  return marked;
}

/* G[term] for each rank-one term some particle has (allocated on first
 * use); PS_ERR_INPUT when the pattern has no room for family terms */
static int family_storage(ps_system *s, ps_ctx *ctx) {
  const ps_network *net = s->net;
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
      s->G[term] = ps_calloc((size_t)s->dim * (size_t)s->fam_members_ptr[net->n_particle],
                             sizeof *s->G[term], ctx);
      if (!s->G[term]) return PS_ERR_NOMEM;
    }
  }
  return PS_OK;
}

/* the arrays of a model with rotations (on its first evaluation) */
static int rotation_storage(ps_system *s, ps_ctx *ctx) {
  ps_int na = s->net->n_arm;
  if (s->dim != 2)
    return ps_error(ctx, PS_ERR_INPUT, "a model with arm rotations needs a 2D network");
  s->th = ps_calloc((size_t)na, sizeof *s->th, ctx);
  s->M = ps_calloc((size_t)na, sizeof *s->M, ctx);
  s->r = ps_calloc((size_t)(2 * na), sizeof *s->r, ctx);
  s->tr = ps_calloc((size_t)(2 * na), sizeof *s->tr, ctx);
  s->tM = ps_calloc((size_t)na, sizeof *s->tM, ctx);
  if (!s->tan.Dr) s->tan.Dr = ps_calloc((size_t)na, sizeof *s->tan.Dr, ctx);
  if (!s->th || !s->M || !s->r || !s->tr || !s->tM || !s->tan.Dr) {
    free(s->th), free(s->M), free(s->r), free(s->tr), free(s->tM);
    s->th = s->M = s->r = s->tr = s->tM = NULL;
    return PS_ERR_NOMEM;
  }
  return PS_OK;
}

/* a model with rotations: T and q become the arm's force dPsi/dy_b =
 * T q + M r as a length and a unit direction (ps_system), for the
 * consumers of forces; the evaluation and the tangent are done with them */
static void force_vectors(ps_system *s) {
  for (ps_int i = 0; i < s->net->n_arm; i++) {
    double *q = &s->q[2 * i], F0 = s->T[i] * q[0] + s->M[i] * s->r[2 * i];
    double F1 = s->T[i] * q[1] + s->M[i] * s->r[2 * i + 1], F = hypot(F0, F1);
    s->T[i] = F;
    if (F > 0) {
      q[0] = F0 / F;
      q[1] = F1 / F;
    }
  }
}

typedef struct {
  const ps_system *s;
  double *y;
  const double *out;
} add_job;

/* the dofs of one part of the team's share of ps_asm_add_parts: each y_k
 * sums its parts in their order, whichever thread runs it */
static void add_part(void *arg, int part) {
  const add_job *j = arg;
  const ps_system *s = j->s;
  ps_int k0, k1;
  ps_part_range(s->n_dof, part, s->parts, &k0, &k1);
  size_t n = (size_t)s->n_dof;
  for (ps_int k = k0; k < k1; k++) {
    double v = j->y[k];
    for (int p = 1; p < s->parts; p++) v += j->out[(size_t)(p - 1) * n + (size_t)k];
    j->y[k] = v;
  }
}

void ps_asm_add_parts(const ps_system *s, double *y, const double *out) {
  if (s->parts <= 1) return;
  add_job j = {s, y, out};
  ps_team_run(s->team, s->parts, add_part, &j);
}

int ps_system_eval(ps_system *s, const ps_model *model, ps_arm_state *st,
                   const double *X, const double *u, double *f,
                   double *energy, int want, ps_ctx *ctx) {
  const ps_network *net = s->net;
  int want_tangent = want != PS_EVAL_FORCES;
  if (model->type->rotations && !s->th) PS_CHECK(rotation_storage(s, ctx));
  if (!model->type->rotations && s->th)
    return ps_error(ctx, PS_ERR_INPUT,
                    "the system was evaluated with a model with arm rotations: it cannot "
                    "serve the %s model", model->type->name);
  eval_job job = {s, st, X, u, f, 0, 0, {0}};
  size_t u_bytes = (size_t)s->n_dof * sizeof *u;
  ps_int bad = -1; /* the first bad arm of the parts in order */
  if (!(s->geom_valid && X == s->X_geom && !memcmp(u, s->u_geom, u_bytes))) {
    s->geom_valid = 0;
    ps_team_run(s->team, s->parts, eval_part, &job);
    for (int p = 0; p < s->parts && bad < 0; p++) bad = job.bad[p];
    if (bad < 0 && !model->type->rotations) { /* force_vectors below overwrites q */
      memcpy(s->u_geom, u, u_bytes);
      s->X_geom = X;
      s->geom_valid = 1;
    }
  }
  /* every process fails alike (a collective whether or not this one's
   * geometry was cached) */
  if (ps_comm_any(ctx->comm, bad >= 0)) {
    if (bad < 0) return ps_error(ctx, PS_ERR_SOLVER, "an arm of another process degenerated");
    return ps_error(ctx, PS_ERR_SOLVER, "arm %lld: particles %lld and %lld: length %g",
                    (long long)bad, (long long)net->a[bad], (long long)net->b[bad], s->l[bad]);
  }
  if (model->type->rotations)
    PS_CHECK(model->type->evaluate_rot(model, s->dl, s->th, st, s->T, s->M, energy,
                                       want_tangent ? &s->tan : NULL, ctx));
  else
    PS_CHECK(model->type->evaluate(model, s->dl, st, s->T, energy,
                                   want_tangent ? &s->tan : NULL, ctx));
  job.phase = 1;
  job.tangent = want_tangent;
  if (want_tangent) s->assembled = 0;
  ps_team_run(s->team, s->parts, eval_part, &job);
  ps_asm_add_parts(s, f, s->f_part);
  if (!want_tangent) {
    if (s->M) force_vectors(s);
    return PS_OK;
  }

  /* the tangent's geometry is kept (phase 1); its loose particles and family
   * gradients */
  if (s->M) force_vectors(s);
  ps_int any_free = mark_free_bodies(s, st);
  ps_int fragments = mark_loose_groups(s, st, X), loose = 0;
  any_free += fragments;
  for (ps_int a = 0; a < net->n_particle; a++) loose += s->free_body[a] != 0;
  if (loose > s->loose_max) s->loose_max = loose;
  if (fragments > s->fragments_max) s->fragments_max = fragments;
  PS_CHECK(family_storage(s, ctx));
  ps_team_run(s->team, s->parts, gradient_part, &job);
  /* the loose particles' spring: the stiffest diagonal entry of K (of
   * the run: every process takes the same; the groups cut loose by cracks
   * are found in this process's network only, which step 3 of
   * doc/design-distributed.md must make global) */
  s->spring = 0.0;
  if (ps_comm_any(ctx->comm, any_free != 0)) {
    double *diag = s->yw;
    ps_asm_tangent_diagonal(s, diag);
    for (ps_int j = 0; j < s->n_dof; j++) /* (a ghost's diagonal is partial) */
      if (ps_model_owns_particle(model, j / s->dim)) s->spring = fmax(s->spring, diag[j]);
    ps_comm_max(ctx->comm, &s->spring, 1);
  }
  if (want == PS_EVAL_TANGENT) return ps_system_assemble(s, ctx);
  return PS_OK;
}
