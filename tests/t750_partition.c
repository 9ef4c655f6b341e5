/* t750_partition.c: the parts of a cloud and their local networks
 * (ps_partition_curve, ps_partition_ghosts, ps_network_build_local), the
 * first brick of the distributed model (doc/design-distributed.md),
 * checked serially against independent computations:
 *  1. every particle in exactly one part, parts of equal counts to within
 *     one, the same parts from a second call (deterministic);
 *  2. a part's ghosts within reach = brute force over all pairs;
 *  3. the network built on a part's particles and its ghosts (reach alpha
 *     max h) has exactly the arms of the global network that touch the
 *     part, with the same reference lengths and weights bit for bit, a
 *     crack included; every global arm is in the part of each of its
 *     ends;
 *  4. a part's ghosts out to 1 and 2 hops (ps_partition_ghost_hops) are
 *     exactly the particles of other parts that a breadth-first search
 *     over the crack-free global network reaches in as many arms, and
 *     among the ghosts within hops alpha max h (fewer where sizes vary);
 *  5. bad requests refused.
 * Clouds: jittered boxes with sizes varying 3x (tests/geomnet.c), 2D with
 * a crack segment and 3D, split into 1, 2, 3, 5 and 8 parts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "geomnet.h"

typedef struct {
  ps_int a, b;           /* global particles, a < b */
  double r0, w_a, w_b;   /* reference length, weights of a's and b's side */
} arm_rec;

static int cmp_rec(const void *u, const void *v) {
  const arm_rec *x = u, *y = v;
  if (x->a != y->a) return x->a < y->a ? -1 : 1;
  return (x->b > y->b) - (x->b < y->b);
}

/* the arms of net (ends through glob: local -> global) with an end among
 * the first n_owned particles (all when n_owned < 0), as records sorted
 * by their global ends */
static arm_rec *records(const ps_network *net, const ps_int *glob, ps_int n_owned, ps_int *n) {
  arm_rec *r = malloc(((size_t)net->n_arm + 1) * sizeof *r);
  ps_int w = 0;
  for (ps_int i = 0; i < net->n_arm; i++) {
    ps_int a = net->a[i], b = net->b[i];
    if (n_owned >= 0 && a >= n_owned && b >= n_owned) continue;
    ps_int ga = glob ? glob[a] : a, gb = glob ? glob[b] : b;
    int swap = ga > gb;
    r[w].a = swap ? gb : ga;
    r[w].b = swap ? ga : gb;
    r[w].r0 = net->r0[i];
    r[w].w_a = swap ? net->A_ba[i] : net->A_ab[i];
    r[w].w_b = swap ? net->A_ab[i] : net->A_ba[i];
    w++;
  }
  qsort(r, (size_t)w, sizeof *r, cmp_rec);
  *n = w;
  return r;
}

/* the particles of parts other than p that a breadth-first search over
 * net reaches from part p's particles in at most `hops` arms, in
 * increasing number, into *out; returns their count */
static ps_int bfs_ghosts(const ps_network *net, const ps_partition *pt, int p, int hops,
                         ps_int **out) {
  ps_int n = net->n_particle, *dist = malloc((size_t)n * sizeof *dist);
  ps_int *queue = malloc((size_t)n * sizeof *queue), q0 = 0, q1 = 0, count = 0;
  for (ps_int a = 0; a < n; a++) dist[a] = -1;
  for (ps_int j = pt->start[p]; j < pt->start[p + 1]; j++) {
    dist[pt->order[j]] = 0;
    queue[q1++] = pt->order[j];
  }
  while (q0 < q1) {
    ps_int a = queue[q0++];
    if (dist[a] == hops) continue;
    for (ps_int k = net->fam_ptr[a]; k < net->fam_ptr[a + 1]; k++) {
      ps_int i = net->fam_arm[k], b = net->a[i] == a ? net->b[i] : net->a[i];
      if (dist[b] < 0) {
        dist[b] = dist[a] + 1;
        queue[q1++] = b;
      }
    }
  }
  *out = malloc(((size_t)n + 1) * sizeof **out);
  for (ps_int b = 0; b < n; b++)
    if (dist[b] > 0) (*out)[count++] = b;
  free(dist);
  free(queue);
  return count;
}

static void check_cloud(const char *name, const ps_particles *P, double alpha,
                        const ps_crack *cracks, int n_cracks, ps_ctx *ctx) {
  ps_kernel K;
  if (ps_kernel_init(&K, P->dim, 2, alpha, ctx)) tg_die("ps_kernel_init", ctx);
  ps_network net;
  if (ps_network_build(&net, P, &K, cracks, n_cracks, ctx)) tg_die("ps_network_build", ctx);
  ps_network open; /* without the cracks: the hops' reach */
  if (ps_network_build(&open, P, &K, NULL, 0, ctx)) tg_die("ps_network_build", ctx);
  ps_int n_all;
  arm_rec *all = records(&net, NULL, -1, &n_all);
  double hmax = 0;
  for (ps_int a = 0; a < P->n; a++) hmax = fmax(hmax, P->h[a]);
  const double reach = alpha * hmax;
  const int parts_list[] = {1, 2, 3, 5, 8};
  for (size_t t = 0; t < sizeof parts_list / sizeof *parts_list; t++) {
    int parts = parts_list[t];
    ps_partition pt, again;
    if (ps_partition_curve(&pt, P, parts, ctx)) tg_die("ps_partition_curve", ctx);
    if (ps_partition_curve(&again, P, parts, ctx)) tg_die("ps_partition_curve", ctx);
    /* 1. a partition */
    ps_int *seen = calloc((size_t)P->n, sizeof *seen);
    int ok = 1;
    for (ps_int j = 0; j < P->n; j++) seen[pt.order[j]]++;
    for (ps_int a = 0; a < P->n; a++) ok &= seen[a] == 1;
    ps_int lo = P->n, hi = 0;
    for (int p = 0; p < parts; p++) {
      ps_int c = pt.start[p + 1] - pt.start[p];
      lo = c < lo ? c : lo;
      hi = c > hi ? c : hi;
      for (ps_int j = pt.start[p]; j < pt.start[p + 1]; j++) ok &= pt.part_of[pt.order[j]] == p;
    }
    ps_check(ok && pt.start[0] == 0 && pt.start[parts] == P->n && hi - lo <= 1,
             "%s, %d parts: every particle in one part, counts %lld..%lld", name, parts,
             (long long)lo, (long long)hi);
    ps_check(!memcmp(pt.order, again.order, (size_t)P->n * sizeof *pt.order),
             "%s, %d parts: the same order from a second call", name, parts);
    ps_partition_free(&again);

    ps_int bad_ghosts = 0, bad_arms = 0, sum_arms = 0, total_ghosts = 0;
    /* 4. ghosts by hops: the network's breadth-first search, among the
     * ghosts within hops alpha max h */
    ps_int bad_hops = 0, n_hops[2] = {0, 0}, n_reach[2] = {0, 0};
    for (int p = 0; p < parts; p++)
      for (int hops = 1; hops <= 2; hops++) {
        ps_int *gh, ngh, *gb, ngb, *ge, nge;
        if (ps_partition_ghost_hops(&pt, P, p, hops, alpha, &gh, &ngh, ctx) ||
            ps_partition_ghosts(&pt, P, p, hops * reach, &ge, &nge, ctx))
          tg_die("ghosts", ctx);
        ngb = bfs_ghosts(&open, &pt, p, hops, &gb);
        bad_hops += ngh != ngb || (ngh && memcmp(gh, gb, (size_t)ngh * sizeof *gh));
        for (ps_int i = 0, j = 0; i < ngh; i++) { /* gh within ge (both increasing) */
          while (j < nge && ge[j] < gh[i]) j++;
          bad_hops += j == nge || ge[j] != gh[i];
        }
        n_hops[hops - 1] += ngh;
        n_reach[hops - 1] += nge;
        free(gh);
        free(gb);
        free(ge);
      }
    ps_check(bad_hops == 0, "%s, %d parts: ghosts by hops = the network's breadth-first search, "
             "within the reach (1 hop %lld, 2 hops %lld ghosts; by the reach %lld, %lld)", name,
             parts, (long long)n_hops[0], (long long)n_hops[1], (long long)n_reach[0],
             (long long)n_reach[1]);
    ps_int *in_parts = calloc((size_t)n_all + 1, sizeof *in_parts);
    for (int p = 0; p < parts; p++) {
      /* 2. ghosts against brute force */
      ps_int *ghost, ng;
      if (ps_partition_ghosts(&pt, P, p, reach, &ghost, &ng, ctx)) tg_die("ghosts", ctx);
      ps_int nb = 0;
      for (ps_int b = 0; b < P->n; b++) {
        if (pt.part_of[b] == p) continue;
        int near = 0;
        for (ps_int j = pt.start[p]; j < pt.start[p + 1] && !near; j++)
          near = tg_d2(&P->x[pt.order[j] * P->dim], &P->x[b * P->dim], P->dim) < reach * reach;
        if (near && (nb >= ng || ghost[nb++] != b)) bad_ghosts++;
      }
      if (nb != ng) bad_ghosts++;
      total_ghosts += ng;
      /* 3. the local network */
      ps_int n_owned = pt.start[p + 1] - pt.start[p], nl = n_owned + ng;
      ps_int *glob = malloc((size_t)nl * sizeof *glob);
      memcpy(glob, &pt.order[pt.start[p]], (size_t)n_owned * sizeof *glob);
      memcpy(glob + n_owned, ghost, (size_t)ng * sizeof *glob);
      ps_particles L;
      if (ps_particles_subset(&L, P, glob, nl, ctx)) tg_die("ps_particles_subset", ctx);
      ps_network ln;
      if (ps_network_build_local(&ln, &L, &K, cracks, n_cracks, n_owned, ctx))
        tg_die("ps_network_build_local", ctx);
      ps_int n_loc;
      arm_rec *loc = records(&ln, glob, n_owned, &n_loc);
      /* the global arms touching the part, in the same (global) order */
      ps_int k = 0;
      for (ps_int i = 0; i < n_all; i++) {
        if (pt.part_of[all[i].a] != p && pt.part_of[all[i].b] != p) continue;
        in_parts[i]++;
        if (k >= n_loc || loc[k].a != all[i].a || loc[k].b != all[i].b ||
            loc[k].r0 != all[i].r0 || loc[k].w_a != all[i].w_a || loc[k].w_b != all[i].w_b)
          bad_arms++;
        k++;
      }
      if (k != n_loc) bad_arms++;
      sum_arms += n_loc;
      free(loc);
      ps_network_free(&ln);
      ps_particles_free(&L);
      free(glob);
      free(ghost);
    }
    ps_int bad_cover = 0;
    for (ps_int i = 0; i < n_all; i++)
      bad_cover += in_parts[i] != (pt.part_of[all[i].a] == pt.part_of[all[i].b] ? 1 : 2);
    ps_check(bad_ghosts == 0, "%s, %d parts: ghosts within alpha max h = brute force (%lld "
             "ghosts in all)", name, parts, (long long)total_ghosts);
    ps_check(bad_arms == 0, "%s, %d parts: local networks hold exactly the global arms of "
             "their parts, r0 and weights bit for bit (%lld arm records, %lld global arms)",
             name, parts, (long long)sum_arms, (long long)n_all);
    ps_check(bad_cover == 0, "%s, %d parts: every global arm in the part of each of its ends",
             name, parts);
    free(in_parts);
    free(seen);
    ps_partition_free(&pt);
  }
  free(all);
  ps_network_free(&net);
  ps_network_free(&open);
}

int main(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  ps_particles P;
  tg_make_box(&P, 2, 40, 30, 1, 1e-3, 7, &ctx);
  /* a crack from the left edge to the middle: it must cut arms */
  ps_crack crack = {.p0 = {-0.001, 0.0145}, .p1 = {0.0205, 0.0145}, .kind = PS_CRACK_SEGMENT};
  ps_kernel K;
  ps_network with, without;
  if (ps_kernel_init(&K, 2, 2, 3.0, &ctx) || ps_network_build(&with, &P, &K, &crack, 1, &ctx) ||
      ps_network_build(&without, &P, &K, NULL, 0, &ctx))
    tg_die("the 2D networks", &ctx);
  ps_check(with.n_arm < without.n_arm, "the crack cuts %lld arms of %lld",
           (long long)(without.n_arm - with.n_arm), (long long)without.n_arm);
  ps_network_free(&with);
  ps_network_free(&without);
  check_cloud("2D jittered box with a crack", &P, 3.0, &crack, 1, &ctx);
  ps_particles_free(&P);
  tg_make_box(&P, 3, 12, 10, 8, 1e-3, 11, &ctx);
  check_cloud("3D jittered box", &P, 3.5, NULL, 0, &ctx);

  /* compact parts: fewer ghosts than slabs of particle numbers (the rows
   * PETSc's default layout gives), 8 parts of the 3D box */
  {
    ps_partition curve, slabs;
    if (ps_partition_curve(&curve, &P, 8, &ctx) || ps_partition_curve(&slabs, &P, 8, &ctx))
      tg_die("ps_partition_curve", &ctx);
    for (ps_int a = 0; a < P.n; a++) slabs.order[a] = a;
    for (int p = 0; p < 8; p++)
      for (ps_int j = slabs.start[p]; j < slabs.start[p + 1]; j++) slabs.part_of[j] = p;
    double hmax = 0;
    for (ps_int a = 0; a < P.n; a++) hmax = fmax(hmax, P.h[a]);
    ps_int gc = 0, gs = 0;
    for (int p = 0; p < 8; p++) {
      ps_int *g, ng;
      if (ps_partition_ghosts(&curve, &P, p, 3.5 * hmax, &g, &ng, &ctx)) tg_die("ghosts", &ctx);
      gc += ng;
      free(g);
      if (ps_partition_ghosts(&slabs, &P, p, 3.5 * hmax, &g, &ng, &ctx)) tg_die("ghosts", &ctx);
      gs += ng;
      free(g);
    }
    ps_check(gc < gs, "3D box, 8 parts: the curve's parts have fewer ghosts than slabs of "
             "particle numbers (%lld against %lld)", (long long)gc, (long long)gs);
    ps_partition_free(&curve);
    ps_partition_free(&slabs);
  }

  /* 5. bad requests */
  ps_partition pt;
  ps_check(ps_partition_curve(&pt, &P, 0, &ctx) == PS_ERR_INPUT,
           "0 parts refused: %s", ctx.msg);
  ps_check(ps_partition_curve(&pt, &P, (int)P.n + 1, &ctx) == PS_ERR_INPUT,
           "more parts than particles refused: %s", ctx.msg);
  if (ps_partition_curve(&pt, &P, 2, &ctx)) tg_die("ps_partition_curve", &ctx);
  ps_int *g, ng;
  ps_check(ps_partition_ghosts(&pt, &P, 2, 1e-3, &g, &ng, &ctx) == PS_ERR_INPUT,
           "ghosts of a part that does not exist refused: %s", ctx.msg);
  ps_check(ps_partition_ghost_hops(&pt, &P, 0, -1, 3.5, &g, &ng, &ctx) == PS_ERR_INPUT &&
               ps_partition_ghost_hops(&pt, &P, 0, 1, 0.0, &g, &ng, &ctx) == PS_ERR_INPUT,
           "ghosts by hops: hops < 0 and alpha 0 refused: %s", ctx.msg);
  ps_partition_free(&pt);
  ps_particles_free(&P);
  return ps_check_summary();
}
