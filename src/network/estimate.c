/* estimate.c: the size of a case before it is built: particles, arms,
 * tangent and factor nonzeros, and the memory of `info` and of a run, so
 * that a case beyond the memory limit is refused before anything large is
 * allocated (issue 23).
 *
 * Counts. Stage 1 has the particle count and a neighbour density alone;
 * stage 2 samples PS_ESTIMATE_SAMPLES particles, evenly spread over the
 * index range (deterministic), and counts with the k-d tree:
 *  - arms: the pair (a, b) is an arm when r < alpha max(h_a, h_b) and no
 *    crack cuts it; give each pair to its end with the larger h (ties: the
 *    larger index), which alone decides it with its own horizon; so arms =
 *    sum_a #{b in a's horizon, b given to a, not cut}, whose sample mean
 *    times n estimates the total without bias;
 *  - families: sum_a (m_a + 1)^2 (the assembly's family slots) from the
 *    sampled family sizes, scaled to the mean 2 arms / n;
 *  - tangent pairs (blocks): with family coupling, column a holds the
 *    union of the horizons of a's neighbours (two hops), counted exactly
 *    for the sample when a horizon holds at most PS_EST_EXACT particles,
 *    else as the particles within 2 alpha h_a; without it, 1 + m_a;
 *  - every horizon is first counted without a list (k-d tree boxes
 *    wholly inside the ball count at once: a horizon covering the whole
 *    body costs O(1)); one holding PS_EST_LIST particles or more is not
 *    listed: cracks ignored, half of its neighbours taken as its arms, so
 *    that an absurd horizon is estimated in milliseconds.
 * Free dofs: the tangent's upper triangle is the blocks' d^2 entries over
 * two (d(d+1)/2 on the diagonal) times the fraction of free dofs.
 *
 * Factor nonzeros: CHOLMOD's nested-dissection ordering (METIS) of a
 * matrix of n rows with s = nnz(upper)/n per row (stencil of the horizon),
 * fitted to the measured factors of doc/performance.md and bench/:
 *   2D: nnz(L) = nnz(A) * max(1, 1.39 log2(n / (4.9 s)))
 *       (disks 5k-80k: 4.6 M .. 138 M within 3%; the bond plate with a
 *       hole, one and two horizons, within 4%). Nested dissection in 2D
 *       gives n r^2 log(n / r^2) for a stencil of radius r, s ~ r^2.
 *   3D: nnz(L) = 0.94 s^2 (n / s)^1.45
 *       (cubic boxes 12^3, 20^3, 37^3 at alpha 3.5: 2.2 M, 27.6 M, 465 M
 *       within 7%). Theory: s^2 (n/s)^(4/3) for large n; the measured
 *       exponent 1.45 overestimates beyond the 50k box (safe side).
 * Both are capped at the dense n (n + 1) / 2. Expected accuracy: within
 * ~10% for the compact 2D bodies and cubes they were fitted to; flat or
 * slender bodies have smaller separators and factors (the law
 * overestimates them, up to ~2x); LU (UMFPACK) is taken as 2.5x Cholesky
 * (measured 26.7 M against 10.7 M at 10k).
 *
 * Memory: the arrays of geom, network, assembly and solver as they are
 * allocated (bytes per particle, arm, block, nonzero below), plus the
 * factors: the tangent's in double and (solver.cg_single_precision) a
 * float copy, the majorant's likewise when a run factors it. Checked
 * against peak resident memory (bench/results.csv): elastic disks 5k-80k
 * within -8% .. +1.5%, the 3D boxes 12^3-37^3 within 7%; the runs to
 * fracture hold ~1.45x the elastic peak at 20k-80k (the majorant's
 * factors, the breaking rounds' copies), which PS_EST_NONLINEAR covers
 * (5k-80k within +1% .. +7%). */
#include "ps_network.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* a horizon listed (and cracks applied) up to this many particles */
#define PS_EST_LIST 20000
/* a particle whose own horizon holds more than this many times the
 * sampled mean (plus one) is an outlier the sample may have missed */
#define PS_EST_OUTLIER 10.0
/* two-hop pattern counted exactly up to this many particles per horizon */
#define PS_EST_EXACT 400
/* peak of a plastic / breaking run over the sum of its arrays and factors
 * (bench: 1.45-1.5 at 20k-80k against the elastic runs' 1.0-1.05; the
 * majorant's factors, counted separately, explain a third of it) */
#define PS_EST_NONLINEAR 1.15
/* the process itself (libraries, CHOLMOD's and METIS's workspaces):
 * 8 MiB measured for `info` of a tiny case, ~10 MiB for its run; the
 * elastic disks of 5k-10k particles peak 25-35 MiB above their arrays */
#define PS_EST_BASE_INFO (8 * 1048576.0)
#define PS_EST_BASE_RUN (24 * 1048576.0)

static double factor_nnz(int dim, double n, double nnz, int lu) {
  if (!(n > 0) || !(nnz > 0)) return 0;
  double s = nnz / n, L;
  if (dim == 2)
    L = nnz * fmax(1.0, 1.39 * log2(n / (4.9 * s)));
  else
    L = fmax(nnz, 0.94 * s * s * pow(n / s, 1.45));
  L = fmin(L, 0.5 * n * (n + 1));
  return lu ? 2.5 * L : L;
}

/* free upper-triangle nonzeros of a pattern of `pairs` blocks */
static double upper_nnz(int d, double n, double pairs, double free_fraction) {
  return free_fraction * (d * d * (pairs - n) / 2 + n * d * (d + 1) / 2.0);
}

/* bytes of ps_system_create_pattern for `pairs` blocks, `nnz` free upper
 * nonzeros, family slots sq (0 without family coupling); pattern_only:
 * what `info` touches (it never writes the values, the per-arm work and
 * the work vectors, whose zeroed pages calloc leaves unmapped) */
static double pattern_bytes(int d, double n, double arms, double pairs, double nnz,
                            double sq, double free_fraction, int pattern_only) {
  double dofs = d * n, values = pattern_only ? 0 : 1;
  return dofs * (9 + 16 * free_fraction + 32 * values) /* dof maps, A.p, work */
         + n * 57                             /* pointers, marks, slots, coefs */
         + n * (8.0 * d * d + 40) * values    /* loose particles and groups */
         + 16 * (2 * arms + n)                /* family members and their arms */
         + pairs * (8 + 8.0 * d * d * values) /* bidx, Kfull */
         + arms * (16 + (72 + 16.0 * d) * values) /* slots; lengths, directions,
                                                     tangent */
         + 8 * sq                             /* family slots */
         + (16 + 8 * values) * nnz;           /* A.i, A_src, A.x */
}

/* factor, majorant and memory from the counts in e */
static void finish(ps_estimate *e, const ps_estimate_opts *o) {
  int d = e->dim;
  double n = e->particles, arms = e->arms, ff = o->free_fraction;
  e->dofs = d * n;
  e->free_dofs = ff * e->dofs;
  e->tangent_nnz = upper_nnz(d, n, e->pairs, ff);
  e->factor_nnz = o->iterative ? 0 : factor_nnz(d, e->free_dofs, e->tangent_nnz, o->lu);
  e->majorant_nnz = e->majorant_factor_nnz = 0;
  if (o->majorant) {
    e->majorant_nnz = upper_nnz(d, n, n + 2 * arms, ff);
    e->majorant_factor_nnz = factor_nnz(d, e->free_dofs, e->majorant_nnz, 0);
  }
  e->mem_particles = n * (8.0 * d + 33);
  /* final arrays; while building: the k-d tree (56 n), the candidate list
   * (both directions: n * neighbours pairs of 16 bytes, capacity doubled
   * from 1024) and the families' positions */
  double cand = fmax(n * e->neighbours, 2 * arms);
  double cap = cand > 1024 ? 1024 * pow(2, ceil(log2(cand / 1024))) : 1024;
  double net = 56 * arms + 16 * n;
  e->mem_network = net + 56 * n + 16 * cap + 8 * n;
  double sq = o->family_coupling ? e->family_sq : 0;
  e->mem_pattern = pattern_bytes(d, n, arms, e->pairs, e->tangent_nnz, sq, ff, 0);
  double fbytes = 8 + (o->single_precision ? 4 : 0);
  if (o->lu) fbytes = 12; /* values and row indices, no float copy */
  /* arm states, trial and committed: eps_p, eps_p_trial, stretch,
   * broken, yielding (2 x 42 bytes) */
  double solver = e->factor_nnz * fbytes + e->dofs * 128 + arms * (84 + o->arm_bytes)
                  + (o->family_coupling ? 16.0 * d * (2 * arms + n) : 0); /* G */
  if (o->majorant)
    solver += pattern_bytes(d, n, arms, n + 2 * arms, e->majorant_nnz, 0, ff, 0) +
              e->majorant_factor_nnz * (8 + (o->single_precision ? 4 : 0));
  /* PETSc's AIJ copy of the whole matrix (2 nnz x 12 bytes), the map of
   * its value slots (2 nnz x 8) and a PC of about the matrix's size (AMG
   * hierarchy, incomplete factor: 2 nnz x 12), each rank holding its
   * share of the rows */
  if (o->iterative) solver += e->tangent_nnz * (24.0 + 16.0 + 24.0) / (o->ranks > 1 ? o->ranks : 1);
  e->mem_solver = solver;
  double info = pattern_bytes(d, n, arms, e->pairs, e->tangent_nnz, sq, ff, 1);
  e->mem_build = PS_EST_BASE_INFO + e->mem_particles + fmax(e->mem_network, net + info);
  e->mem_run = e->mem_particles + net + e->mem_pattern + e->mem_solver;
  if (o->majorant) e->mem_run *= PS_EST_NONLINEAR;
  e->mem_run += PS_EST_BASE_RUN;
}

void ps_estimate_density(ps_estimate *e, int dim, double n, double neighbours,
                         const ps_estimate_opts *o) {
  memset(e, 0, sizeof *e);
  e->dim = dim;
  e->stage = 1;
  e->particles = n;
  e->neighbours = fmin(fmax(neighbours, 0), n - 1);
  e->arms = 0.5 * n * e->neighbours;
  e->family_sq = n * (e->neighbours + 1) * (e->neighbours + 1);
  /* two hops: the particles within twice the horizon, 2^N as many, of
   * which ~0.7 are reached (lattices at alpha 3.5-5.1; 1 for wide ones) */
  double two = o->family_coupling ? 0.7 * pow(2, dim) * e->neighbours : e->neighbours;
  e->pairs = n * fmin(n, 1 + two);
  finish(e, o);
}

/* The family of particle c by the arm rule r < alpha max(h_c, h_b), c
 * itself included, cracks ignored: the particles within alpha max(h_c,
 * hcap) (hcap: the largest size expected near c), filtered by the rule,
 * into (*out)[0 .. *cnt). A ball holding PS_EST_LIST particles or more is
 * not listed: *cnt = -1 (the caller estimates without the list). */
static int family_of(const ps_kdtree *t, const ps_particles *p, ps_int c, double alpha,
                     double hcap, ps_int **out, ps_int *cap, ps_int *cnt, ps_ctx *ctx) {
  int dim = p->dim;
  const double *x = &p->x[c * dim];
  ps_int k, m = 0;
  double R0 = alpha * fmax(p->h[c], hcap);
  if (ps_kdtree_count(t, x, R0, PS_EST_LIST) >= PS_EST_LIST) {
    *cnt = -1;
    return PS_OK;
  }
  PS_CHECK(ps_kdtree_radius(t, x, R0, out, cap, &k, ctx));
  for (ps_int j = 0; j < k; j++) {
    ps_int b = (*out)[j];
    double r2 = 0, R = alpha * fmax(p->h[c], p->h[b]);
    for (int i = 0; i < dim; i++) {
      double d = p->x[b * dim + i] - x[i];
      r2 += d * d;
    }
    if (r2 < R * R) (*out)[m++] = b;
  }
  *cnt = m;
  return PS_OK;
}

static int cmp_idx(const void *u, const void *v) {
  ps_int a = *(const ps_int *)u, b = *(const ps_int *)v;
  return a < b ? -1 : a > b;
}

/* the two-hop column of a particle whose family (itself included) is
 * fam[0..k): |union of the families of its members|, hcap the largest
 * size among them; buffers *u and *tmp with their capacities. *count < 0
 * when a member's family is too large to list (family_of). */
static int two_hop(const ps_kdtree *t, const ps_particles *p, double alpha,
                   const ps_int *fam, ps_int k, double hcap, ps_int **u, ps_int *ucap,
                   ps_int **tmp, ps_int *tcap, double *count, ps_ctx *ctx) {
  ps_int nu = 0, c;
  for (ps_int j = 0; j < k; j++) {
    PS_CHECK(family_of(t, p, fam[j], alpha, hcap, tmp, tcap, &c, ctx));
    if (c < 0) {
      *count = -1;
      return PS_OK;
    }
    if (nu + c > *ucap) {
      ps_int nc = 2 * (nu + c);
      PS_CHECK(ps_realloc((void **)u, (size_t)nc, sizeof **u, ctx));
      *ucap = nc;
    }
    memcpy(*u + nu, *tmp, (size_t)c * sizeof **u);
    nu += c;
  }
  qsort(*u, (size_t)nu, sizeof **u, cmp_idx);
  ps_int m = 0;
  for (ps_int j = 0; j < nu; j++) m += j == 0 || (*u)[j] != (*u)[j - 1];
  *count = (double)m;
  return PS_OK;
}

/* sampled sums of stage 2 */
typedef struct {
  double arms, fam, fam2, pairs, neighbours;
  double listed, cut; /* family members listed (a aside), of them cut by a crack */
} est_sums;

/* the largest size among the particles list[0..k) */
static double max_size(const ps_particles *p, const ps_int *list, ps_int k) {
  double h = 0;
  for (ps_int j = 0; j < k; j++) h = fmax(h, p->h[list[j]]);
  return h;
}

/* add particle a's counts to *s: its family (the arm rule, cracks
 * applied), the arms given to it, its tangent column */
static int sample_one(const ps_kdtree *t, const ps_particles *p, ps_int a,
                      double alpha, const ps_crack *cracks, int n_cracks,
                      const ps_estimate_opts *o, ps_int *bufs[3], ps_int caps[3],
                      est_sums *s, ps_ctx *ctx) {
  int dim = p->dim;
  const double *x = &p->x[a * dim];
  ps_int k = ps_kdtree_count(t, x, alpha * p->h[a], p->n), kf = 0;
  double mine = 0, fam = 0, pairs = -1, hloc = p->h[a];
  if (k < PS_EST_LIST) {
    /* the sizes near a bound the horizons that reach it */
    PS_CHECK(ps_kdtree_radius(t, x, alpha * p->h[a], &bufs[0], &caps[0], &k, ctx));
    hloc = max_size(p, bufs[0], k);
    PS_CHECK(family_of(t, p, a, alpha, hloc, &bufs[0], &caps[0], &kf, ctx));
  }
  if (k < PS_EST_LIST && kf < 0) {
    /* a large particle near a: its horizon covers too many to list; the
     * family is at least a's own horizon, the pattern the ball below */
    fam = (double)(k - 1);
    mine = 0.5 * fam;
    kf = 0;
  } else if (k < PS_EST_LIST) {
    ps_int m = 0;
    for (ps_int j = 0; j < kf; j++) {
      ps_int b = bufs[0][j];
      int cut = 0;
      for (int c = 0; c < n_cracks && !cut && b != a; c++)
        cut = ps_crack_cuts(&cracks[c], x, &p->x[b * dim]);
      s->listed += b != a;
      s->cut += cut;
      if (cut) continue;
      bufs[0][m++] = b; /* the family, a itself included */
      if (b == a) continue;
      fam++;
      mine += p->h[b] < p->h[a] || (p->h[b] == p->h[a] && b < a);
    }
    kf = m;
    hloc = max_size(p, bufs[0], kf);
  } else {
    fam = (double)(k - 1);
    mine = 0.5 * fam;
  }
  if (!o->family_coupling)
    pairs = 1 + fam;
  else if (kf > 0 && kf <= PS_EST_EXACT)
    PS_CHECK(two_hop(t, p, alpha, bufs[0], kf, hloc, &bufs[1], &caps[1], &bufs[2], &caps[2],
                     &pairs, ctx));
  if (pairs < 0) /* too many to list: the ball of two horizons */
    pairs = (double)ps_kdtree_count(t, x, 2 * alpha * hloc, p->n);
  s->arms += mine;
  s->fam += fam;
  s->fam2 += (fam + 1) * (fam + 1);
  s->pairs += pairs;
  s->neighbours += (double)(k - 1);
  return PS_OK;
}

int ps_estimate_sample(ps_estimate *e, const ps_particles *p, double alpha,
                       const ps_crack *cracks, int n_cracks,
                       const ps_estimate_opts *o, ps_ctx *ctx) {
  int status = PS_OK;
  ps_kdtree *t = NULL;
  ps_int *bufs[3] = {NULL, NULL, NULL}, caps[3] = {0, 0, 0};
  est_sums s = {0, 0, 0, 0, 0, 0, 0};
  ps_int n = p->n, m = n < PS_ESTIMATE_SAMPLES ? n : PS_ESTIMATE_SAMPLES;
  memset(e, 0, sizeof *e);
  PS_CHECK(ps_cracks_check(cracks, n_cracks, p->dim, ctx));
  e->dim = p->dim;
  e->stage = 2;
  e->particles = (double)n;
  e->sampled = m;
  PS_CHECK_GOTO(ps_kdtree_build(&t, p->x, n, p->dim, ctx));
  for (ps_int i = 0; i < m; i++) {
    ps_int a = (ps_int)(((double)i + 0.5) * (double)n / (double)m);
    PS_CHECK_GOTO(sample_one(t, p, a, alpha, cracks, n_cracks, o, bufs, caps, &s, ctx));
  }
  double scale = (double)n / (double)m;
  e->arms = s.arms * scale;
  e->neighbours = s.neighbours / m;
  /* every particle's own horizon, counted (no list): the sample can miss
   * one outlying particle (a stray far point under Eq. 115, one volume
   * far too large under Eq. 44) whose horizon covers the body. Each arm
   * lies in one or both of its ends' horizons, so sum k_a / 2 bounds the
   * arms from below, less the share f of the sampled candidates that the
   * cracks cut (0 without cracks); a particle whose horizon holds far
   * more than the sampled mean adds its family's (k_a + 1)^2 to the
   * pattern (family coupling) and the family slots. */
  double sum_k = 0, out_sq = 0, big = PS_EST_OUTLIER * (e->neighbours + 1);
  for (ps_int a = 0; a < n; a++) {
    double k = (double)(ps_kdtree_count(t, &p->x[(size_t)a * p->dim], alpha * p->h[a], n) - 1);
    sum_k += k;
    if (k > big) out_sq += (k + 1) * (k + 1);
  }
  /* families scaled to the mean 2 arms / n (the sample counts one-sided
   * horizons): sum (m + 1)^2 with m -> m r */
  double r = s.fam > 0 ? 2 * e->arms / (s.fam * scale) : 1;
  double sum_m2 = s.fam2 - 2 * s.fam - (double)m; /* sum of m^2 */
  e->family_sq = scale * (r * r * sum_m2 + 2 * r * s.fam + (double)m) + out_sq;
  e->pairs = s.pairs * scale;
  double f_cut = s.listed > 0 ? s.cut / s.listed : 0.0;
  e->arms = fmax(e->arms, 0.5 * sum_k * (1 - f_cut));
  if (o->family_coupling)
    e->pairs = fmin(e->pairs + out_sq, (double)n * (double)n);
  else
    e->pairs = fmax(e->pairs, (double)n + 2 * e->arms);
  finish(e, o);
cleanup:
  ps_kdtree_free(&t);
  for (int i = 0; i < 3; i++) free(bufs[i]);
  return status;
}

double ps_memory_limit(double gib, const char *key, const char **what) {
  if (gib > 0) {
    if (what) *what = key ? key : "solver.max_memory_gib";
    return gib * 1073741824.0;
  }
  if (what) *what = "80% of RAM";
  long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || size <= 0) return INFINITY; /* unknown: no limit */
  return 0.8 * (double)pages * (double)size;
}

/* "37 GiB", "812 MiB" */
static void fmt_bytes(char *buf, size_t len, double b) {
  if (b >= 10 * 1073741824.0)
    snprintf(buf, len, "%.0f GiB", b / 1073741824.0);
  else if (b >= 1073741824.0)
    snprintf(buf, len, "%.1f GiB", b / 1073741824.0);
  else
    snprintf(buf, len, "%.0f MiB", ceil(b / 1048576.0));
}

int ps_estimate_check(const ps_estimate *e, double need, double limit_gib,
                      const char *limit_key, const char *where, const char *what,
                      ps_ctx *ctx) {
  const char *lw;
  double limit = ps_memory_limit(limit_gib, limit_key, &lw);
  if (!(need > limit)) return PS_OK;
  char nb[32], lb[32];
  fmt_bytes(nb, sizeof nb, need);
  fmt_bytes(lb, sizeof lb, limit);
  return ps_error(ctx, PS_ERR_INPUT,
                  "%s: %s needs about %s (estimate: %.3g particles, %.3g arms, tangent "
                  "%.3g nonzeros, factor %.3g nonzeros) but the limit is %s (%s); set "
                  "solver.max_memory_gib or --max-memory GIB to raise it",
                  where, what, nb, e->particles, e->arms, e->tangent_nnz, e->factor_nnz,
                  lb, lw);
}

void ps_estimate_print(const ps_estimate *e, FILE *f) {
  fprintf(f,
          "estimate_stage: %d\nestimate_particles: %.0f\nestimate_arms: %.4g\n"
          "estimate_arms_per_particle: %.2f\nestimate_tangent_pairs: %.4g\n"
          "estimate_tangent_nnz: %.4g\nestimate_factor_nnz: %.4g\n",
          e->stage, e->particles, e->arms,
          e->particles > 0 ? 2 * e->arms / e->particles : 0.0, e->pairs, e->tangent_nnz,
          e->factor_nnz);
  if (e->majorant_factor_nnz > 0)
    fprintf(f, "estimate_majorant_factor_nnz: %.4g\n", e->majorant_factor_nnz);
  fprintf(f,
          "estimate_memory_network_MiB: %.0f\nestimate_memory_info_MiB: %.0f\n"
          "estimate_memory_MiB: %.0f\n",
          ceil(e->mem_network / 1048576.0), ceil(e->mem_build / 1048576.0),
          ceil(e->mem_run / 1048576.0));
}
