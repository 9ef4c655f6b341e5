/* ps_network.h: the arm network of Olsson et al. (2021): neighbour search
 * with the arm rule r < alpha max(h_a, h_b), pre-crack cuts, the kernel of
 * Eq. 112 normalised by Eq. 54, and the arm weights of Eq. 70
 * A_ab = -(m_a m_b / rho_a^2) dW_ab/dr = -V_a V_b f'(r/h_a) / h_a^(N+1)
 * (uniform density, m = rho V). */
#ifndef PS_NETWORK_H
#define PS_NETWORK_H

#include "../geom/ps_geom.h"

/* The polynomial kernel of Eq. 112: f(u) = (1 - u^2/alpha^2)^k / Z for
 * u <= alpha, 0 beyond, with Z such that int f(u) 2(N-1) pi u^(N-1) du = 1
 * (Eq. 54). */
typedef struct ps_kernel {
  int dim;      /* N */
  int k;        /* exponent (paper: 2) */
  double alpha; /* horizon in units of h (paper: 5.1) */
  double Z;     /* normalisation of Eq. 112 */
} ps_kernel;

/* Set up the kernel; Z by GSL adaptive quadrature of Eq. 112's denominator.
 * Returns PS_OK, or PS_ERR_INPUT for alpha <= 0, k < 1, dim not 2/3, or a
 * quadrature that fails (alpha or k so large that Eq. 54 overflows; the
 * message names kernel.alpha and kernel.k). */
int ps_kernel_init(ps_kernel *K, int dim, int k, double alpha, ps_ctx *ctx);
/* Closed form of Z for k = 2 (Eq. 113 without its stray C):
 * 2 (N-1) pi alpha^N (1/N - 2/(N+2) + 1/(N+4)). */
double ps_kernel_Z_k2(int dim, double alpha);
/* f(u) and f'(u) = df/du of Eq. 112. */
double ps_kernel_f(const ps_kernel *K, double u);
double ps_kernel_df(const ps_kernel *K, double u);

/* A pre-crack or a hole's boundary: arms whose segment crosses it are not
 * created (ps_crack_cuts states the rule at its edges).
 *  - PS_CRACK_SEGMENT (2D): the open segment (p0, p1); the zero value, so
 *    a zeroed struct (or {{x0, y0}, {x1, y1}}) with p0, p1 set is a
 *    segment;
 *  - PS_CRACK_POLYGON (3D): a planar polygon of n vertices v[0..n)
 *    (geometry.cracks), set up by ps_crack_polygon, which also stores its
 *    plane (centroid o, unit normal nrm, in-plane axes e1, e2) and the
 *    vertices' coordinates uv in (e1, e2);
 *  - PS_CRACK_SPHERE (3D): a hole's ball |x - p0| < radius
 *    (geometry.holes), set up by ps_crack_sphere. */
#define PS_CRACK_MAX_VERTICES 16
enum ps_crack_kind { PS_CRACK_SEGMENT = 0, PS_CRACK_POLYGON = 1, PS_CRACK_SPHERE = 2 };
typedef struct ps_crack {
  double p0[3], p1[3]; /* segment: end points (x, y), m; sphere: p0 the centre */
  int kind;            /* enum ps_crack_kind (after p0, p1: {{x0, y0}, {x1, y1}}
                          initialises a segment) */
  double radius;       /* sphere: R, m */
  int n;               /* polygon: vertices, 3..PS_CRACK_MAX_VERTICES */
  double v[PS_CRACK_MAX_VERTICES][3];  /* polygon: vertices in order, m */
  double o[3], nrm[3], e1[3], e2[3];    /* polygon: its plane's frame */
  double uv[PS_CRACK_MAX_VERTICES][2]; /* polygon: vertices in the plane, m */
} ps_crack;

/* The tolerance of ps_crack_cuts, relative to the arm's length. */
#define PS_CRACK_TOUCH 1e-9
/* A crack polygon is planar when every vertex lies within PS_CRACK_FLAT s
 * of its plane, and not degenerate when its area exceeds PS_CRACK_FLAT
 * s^2, s = the largest distance of a vertex from the vertices' centroid. */
#define PS_CRACK_FLAT 1e-6

/* Set *cr to the polygon of the n points v (m, in order around it; the
 * even-odd rule decides its interior, so a self-crossing outline is
 * allowed and means what the crossing-number test says). Its plane: the
 * vertices' centroid o and the unit normal of Newell's area vector
 * A = 1/2 sum_i v_i x v_(i+1), whose length is the (projected) area; the
 * vertices are then projected onto that plane (they lie within
 * PS_CRACK_FLAT s of it). Returns PS_OK, or PS_ERR_INPUT with a message
 * (no file or line: the caller adds them) and *bad the point at fault
 * (0-based) or -1 for the polygon as a whole: n outside 3..16, a
 * coordinate not finite, zero area (|A| <= PS_CRACK_FLAT s^2: the points
 * coincide or lie on a line), not planar (the vertex farthest from the
 * plane). */
int ps_crack_polygon(ps_crack *cr, int n, const double (*v)[3], int *bad, ps_ctx *ctx);

/* Set *cr to the sphere of centre c[3] and radius R > 0 (m). */
void ps_crack_sphere(ps_crack *cr, const double *c, double R);

/* Each of the n cracks of the form of a dim-dimensional body: segments
 * in 2D, polygons (3..16 points) and spheres in 3D. PS_OK, or PS_ERR_INPUT
 * naming the first that is not ("crack 2: a segment in a 3D network"):
 * ps_crack_cuts reads 2 coordinates of a segment's arm, 3 of the others'. */
int ps_cracks_check(const ps_crack *cracks, int n, int dim, ps_ctx *ctx);

/* The axis-aligned box lo..hi (dim coordinates, m) that holds every point
 * where the crack can cut an arm. */
void ps_crack_bounds(const ps_crack *cr, int dim, double lo[3], double hi[3]);

/* The arm network. Arm i joins particles a[i] < b[i]. Each particle's
 * family (the arms incident to it) is stored CSR-wise: fam_arm[fam_ptr[p]
 * .. fam_ptr[p+1]) are arm indices, in increasing order of the other end. */
typedef struct ps_network {
  int dim;
  ps_int n_particle, n_arm;
  ps_int *a, *b;     /* end particles */
  double *r0;        /* reference length, m */
  double *A_ab;      /* weight of a's side (m^(N-1)), may be 0 */
  double *A_ba;      /* weight of b's side */
  ps_int *fam_ptr;   /* [n_particle + 1] */
  ps_int *fam_arm;   /* [2 n_arm] */
  ps_int *n_arm0;    /* arms per particle at creation (damage, Eq. 119) */
  double max_h_ratio;/* largest h / smallest h */
} ps_network;

/* Build the network: arms r < alpha max(h_a, h_b), none crossing a crack
 * (segments in 2D, polygons and spheres in 3D), weights of Eq. 70 from the
 * kernel. Returns PS_OK, PS_ERR_INPUT (a crack of the other dimension;
 * no arm at all; a particle left without arms; two particles closer than
 * PS_COINCIDE max(h_a, h_b), ps_error_coincide; a coordinate not finite;
 * a non-positive size or volume: each message names the particles, with
 * their cloud file and line), PS_ERR_NOMEM. */
int ps_network_build(ps_network *net, const ps_particles *p,
                     const ps_kernel *K, const ps_crack *cracks, int n_cracks,
                     ps_ctx *ctx);
void ps_network_free(ps_network *net);

/* The network of one part of a cloud (doc/design-distributed.md): p holds
 * the part's n_owned particles first, then its ghosts
 * (ps_partition_ghost_hops, at least one hop). Every arm with an owned end is
 * the global network's arm (the same r0 and weights, ends in p's
 * numbering); arms between two ghosts are those the ghosts have among
 * themselves. As ps_network_build, except that only the owned particles
 * must have arms (a ghost at the layer's edge may have none here). */
int ps_network_build_local(ps_network *net, const ps_particles *p, const ps_kernel *K,
                           const ps_crack *cracks, int n_cracks, ps_int n_owned,
                           ps_ctx *ctx);

/* A process's share of a distributed model (doc/design-distributed.md,
 * share.c): the particles of one part of a partition (owned) and their
 * ghosts, the network on them, and what the share owns. Each arm of the
 * whole network is owned by exactly one share: the one owning its end of
 * the lower global number (arms between two ghosts are never owned), so
 * sums over owned arms and particles of all shares are the whole model's
 * (ps_model.own_arm, own_particle). */
typedef struct ps_share {
  int part;
  ps_int n_owned;              /* owned particles: local 0 .. n_owned - 1 */
  ps_int *global;              /* [P.n] global number of each local particle */
  ps_particles P;              /* owned, then ghosts in increasing number */
  ps_network net;              /* the local network (ps_network_build_local) */
  unsigned char *own_arm;      /* [net.n_arm] 1: the share's arm */
  unsigned char *own_particle; /* [P.n] 1: owned */
} ps_share;

/* The share of part `part` of pt over the whole cloud P with ghosts out
 * to `hops` arms (ps_partition_ghost_hops with the kernel's alpha;
 * ps_model_share_horizons, 1 to 3 by the model: ps_problem_share), and
 * its network with the kernel and cracks of the whole one. Returns
 * PS_OK, PS_ERR_INPUT (part out of range, hops < 0, the network's
 * errors) or PS_ERR_NOMEM (*sh then empty). */
int ps_share_build(ps_share *sh, const ps_particles *P, const ps_partition *pt, int part,
                   int hops, const ps_kernel *K, const ps_crack *cracks, int n_cracks,
                   ps_ctx *ctx);
void ps_share_free(ps_share *sh);
/* The rows of the whole system (dim per particle, particles in pt's curve
 * order, so that each part's rows are one range) of the share's dofs:
 * *rows[sh->P.n * dim] (allocated here); its own rows are *row0 ..
 * *row0 + n_owned * dim - 1. PS_OK or PS_ERR_NOMEM. */
int ps_share_global_rows(const ps_share *sh, const ps_partition *pt, int dim, ps_int **rows,
                         ps_int *row0, ps_ctx *ctx);

/* Does the crack cut the arm x-y? x and y hold 2 (segment) or 3
 * (polygon, sphere) coordinates; tol = PS_CRACK_TOUCH |y - x|.
 * Segment (2D): the crack is the open segment (p0, p1): the arm is cut
 * when its ends lie on opposite sides of the crack's line, each farther
 * than tol from it, and the point where it meets that line lies inside the
 * segment by more than tol from either end. So an arm through an end point
 * of the crack (a crack tip on a lattice point, up to round-off) is kept,
 * deterministically and whichever way the arm is walked, and an arm with
 * an end on the crack's line (within tol) is not cut by it. (Tips on
 * lattice points: the edge-cracked plates of data/cases, whose networks
 * this rule leaves as they were; the disk's foci hold no particle and no
 * arm passes within 1e-6 of its length of them. doc/model.md.)
 * Polygon (3D), the same rule one dimension up: the crack is the open
 * polygon (its interior): the arm is cut when its ends lie on opposite
 * sides of the polygon's plane, each farther than tol from it, and the
 * point where it meets the plane lies inside the polygon (crossing
 * number, even-odd, in the plane's coordinates uv) and farther than tol
 * from every edge. An arm with an end on the plane (within tol), or
 * through an edge or a vertex (within tol), is kept.
 * Sphere (3D hole): the arm is cut when its closest distance to the
 * centre is below the radius, |x + t (y - x) - p0| < R for some t in
 * [0, 1] (exact; an arm that only touches the sphere is kept).
 * Polygon and sphere take the arm's ends in a fixed order (the
 * lexicographically smaller first), so the answer does not depend on
 * which way it is walked, to the bit. Exposed for the tests. */
int ps_crack_cuts(const ps_crack *cr, const double *x, const double *y);

/* ---- size estimate before allocation (estimate.c) ---- */

/* What the run will build, for the estimate. */
typedef struct ps_estimate_opts {
  int family_coupling;  /* two-horizon tangent (fibre, state); 0: arms only */
  int majorant;         /* a run also factors the one-horizon majorant */
  int single_precision; /* float copies of the factors (solver) */
  int lu;               /* solver.linear umfpack: LU, not Cholesky */
  double free_fraction; /* free dofs / all dofs (1 when not known) */
  double arm_bytes;     /* per-arm bytes the model adds to the common arm
                           states (critical stretches, the three-body
                           model's rotations and moments) */
  int iterative;        /* solver.linear petsc with an iterative PC: no
                           factor; PETSc's copy of the whole matrix,
                           its row maps and a PC about its size */
  int ranks;            /* MPI ranks sharing PETSc's matrix and PC (1:
                           one process) */
} ps_estimate_opts;

/* Sizes and memory of a case before it is built. Counts are doubles: an
 * absurd case must not overflow them. Memory in bytes. */
typedef struct ps_estimate {
  int dim;
  int stage;             /* 1: from the counts and a density; 2: sampled */
  ps_int sampled;        /* particles sampled (stage 2) */
  double particles, dofs, free_dofs;
  double neighbours;     /* mean particles within a particle's horizon */
  double arms;
  double family_sq;      /* sum over particles of (family size + 1)^2 */
  double pairs;          /* tangent blocks: coupled particle pairs, both
                            triangles and the diagonal */
  double tangent_nnz;    /* free upper triangle of the tangent */
  double factor_nnz;     /* nnz(L) of its factor (LU: L + U) */
  double majorant_nnz, majorant_factor_nnz; /* one horizon (0: none) */
  double mem_particles;  /* the cloud */
  double mem_network;    /* the network and, while it is built, its k-d
                            tree and candidate list (the peak) */
  double mem_pattern;    /* the assembly of the tangent in a run (info
                            builds its pattern alone, without values) */
  double mem_solver;     /* the rest of a run: majorant system, arm state,
                            factors, vectors */
  double mem_build;      /* peak of `info`: particles, network, pattern
                            (the memory it writes) */
  double mem_run;        /* peak of one run */
} ps_estimate;

/* Stage 1, from the counts alone (nothing allocated): n particles in dim
 * dimensions, each with about `neighbours` others within its horizon
 * (e.g. alpha^N for Eq. 44 sizes, pi m^2 for a lattice horizon of m
 * spacings in 2D; capped at n - 1). */
void ps_estimate_density(ps_estimate *e, int dim, double n, double neighbours,
                         const ps_estimate_opts *o);

/* Stage 2, from the particles and their sizes, before the network: the
 * arms, families and tangent pairs of a deterministic sample of at most
 * PS_ESTIMATE_SAMPLES particles (k-d tree counts; a horizon that covers
 * the whole body costs O(log n) per particle), the cracks applied to the
 * arms; then the factor and memory. Allocates a k-d tree (O(n)) and
 * small buffers. Returns PS_OK, PS_ERR_NOMEM, PS_ERR_INPUT (a crack of
 * the other dimension, ps_cracks_check). */
#define PS_ESTIMATE_SAMPLES 512
int ps_estimate_sample(ps_estimate *e, const ps_particles *p, double alpha,
                       const ps_crack *cracks, int n_cracks,
                       const ps_estimate_opts *o, ps_ctx *ctx);

/* What a case's estimate is checked for (ps_problem_setup_sized): nothing,
 * what `info` builds (mem_build), or a run (mem_run). */
enum ps_estimate_purpose { PS_ESTIMATE_NONE = 0, PS_ESTIMATE_INFO = 1, PS_ESTIMATE_RUN = 2 };

/* The memory limit in bytes: gib GiB when gib > 0, else 80% of the
 * physical memory (sysconf); *what gets key (where gib came from:
 * "--max-memory"; NULL: "solver.max_memory_gib") or "80% of RAM" for
 * messages (what may be NULL). */
double ps_memory_limit(double gib, const char *key, const char **what);

/* Refuse a need above the limit: PS_OK, or PS_ERR_INPUT with "<where>: this
 * case needs about 37 GiB (estimate: 1.2e9 arms, factor 3.1e9 nonzeros)
 * but the limit is 19 GiB (80% of RAM); set solver.max_memory_gib or
 * --max-memory GIB to raise it". `need` is one of e's mem_ sums (times
 * the jobs of a sweep); `what` says for what ("a run", "info");
 * limit_gib and limit_key as ps_memory_limit's. */
int ps_estimate_check(const ps_estimate *e, double need, double limit_gib,
                      const char *limit_key, const char *where, const char *what, ps_ctx *ctx);

/* The estimate as "key: value" lines (estimate_particles, estimate_arms,
 * estimate_tangent_nnz, estimate_factor_nnz, estimate_memory_MiB, ...). */
void ps_estimate_print(const ps_estimate *e, FILE *f);

#endif
