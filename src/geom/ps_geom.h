/* ps_geom.h: particle clouds and their generators: regular/jittered boxes,
 * the hexagonal lattice, the elliptic crack disk (Olsson et al. 2021,
 * Eq. 114), particle sizes (Eq. 115) and a k-d tree for neighbour queries.
 * Units: SI (m); in 2D volumes are areas per unit thickness (m^2). */
#ifndef PS_GEOM_H
#define PS_GEOM_H

#include "../util/ps_util.h"

/* A particle cloud in N = dim dimensions. */
typedef struct ps_particles {
  int dim;          /* N = 2 or 3 */
  ps_int n;         /* number of particles */
  double *x;        /* reference positions, x[a*dim + k], m */
  double *volume;   /* quadrature volume V_a (m^N; m^2 per metre in 2D) */
  double *h;        /* particle size h_a, m (horizon = alpha h_a) */
  int *block;       /* block id per particle (0 unless given) */
  /* elliptic disk only (NULL otherwise): zone ring index i_xi in [0, n_xi)
   * and the flag "in the boundary zone" (outermost ring of zones). */
  int *zone_xi;
  unsigned char *in_boundary_zone;
  /* point cloud or mesh only (NULL otherwise): the file it was read from
   * and the line of each particle in it (a mesh: the id of its element),
   * so that messages name file:line or file: element id */
  char *source;
  ps_int *line;
  int line_is_element; /* 1: line[a] is a mesh element's id, not a line */
} ps_particles;

/* Allocate a cloud of n particles in dim dimensions (all arrays zeroed).
 * Returns PS_OK or PS_ERR_NOMEM / PS_ERR_INPUT (dim not 2 or 3). */
int ps_particles_alloc(ps_particles *p, int dim, ps_int n, ps_ctx *ctx);
/* Free all arrays; safe on a zeroed or already freed cloud. */
void ps_particles_free(ps_particles *p);

/* *out = the particles ids[0 .. n) of P, in that order (positions,
 * volumes, sizes, blocks; not the disk's zones or a cloud's file lines).
 * Returns PS_OK, PS_ERR_INPUT (n < 1) or PS_ERR_NOMEM. */
int ps_particles_subset(ps_particles *out, const ps_particles *P, const ps_int *ids, ps_int n,
                        ps_ctx *ctx);

/* Where particle a comes from, for messages: "cloud.txt:37: particle 36"
 * for a point cloud (source and line set), "plate.msh: element 37:
 * particle 36" for a mesh (line_is_element), else "particle 36". Writes at
 * most len bytes to buf and returns buf. */
const char *ps_particle_where(const ps_particles *p, ps_int a, char *buf, size_t len);

/* "(x, y)" or "(x, y, z)" of particle a (%g), into buf; returns buf. */
const char *ps_particle_at(const ps_particles *p, ps_int a, char *buf, size_t len);

/* Two particles closer than PS_COINCIDE times their size (the larger h;
 * Eq. 115: the mean distance of the nearest neighbours) coincide: no arm
 * can join them (a zero or round-off length), whatever the size rule. */
#define PS_COINCIDE 1e-9

/* The error for coincident particles a and b, naming the pair (lower
 * index first) and the point: "particles 12 and 13 coincide (at (x, y))",
 * for a point cloud "cloud.txt:14: particles 12 and 13 coincide (at (x,
 * y)), the first at line 13". Returns PS_ERR_INPUT. */
int ps_error_coincide(ps_ctx *ctx, const ps_particles *p, ps_int a, ps_int b);

/* Every coordinate finite? PS_OK, or PS_ERR_INPUT naming the first particle
 * that is not (with its cloud file and line). */
int ps_particles_check(const ps_particles *p, ps_ctx *ctx);

/* Remove the particles inside any of the n holes, the open circles (2D:
 * holes[i] = {cx, cy, R}) or balls (3D: {cx, cy, cz, R}) |x - c| < R,
 * keeping the order of the rest (and their cloud lines). Returns PS_OK,
 * PS_ERR_INPUT (no particle left). */
int ps_geom_cut_holes(ps_particles *p, const double (*holes)[4], int n, ps_ctx *ctx);

/* Box on a lattice: counts[k] particles along axis k, spacing d (m), lower
 * corner at the origin. lattice: "square" (cubic in 3D) or "hex" (2D only,
 * rows offset by d/2 and spaced d sqrt(3)/2). jitter in [0, 0.5): each
 * particle moved uniformly by up to jitter*d per axis (GSL mt19937, seed).
 * Volumes: d^N (square) or d^2 sqrt(3)/2 (hex). Sizes h are NOT set: call
 * ps_geom_sizes_eq115. Returns PS_OK, PS_ERR_INPUT, PS_ERR_NOMEM. */
int ps_geom_box(ps_particles *p, int dim, const ps_int counts[3], double d,
                const char *lattice, double jitter, unsigned long seed,
                ps_ctx *ctx);

/* The distance between the rows of ps_geom_box's lattice of spacing d
 * (m): d sqrt(3)/2 for "hex", d for "square". */
double ps_geom_row_spacing(const char *lattice, double d);

/* Parameters of the elliptic crack disk (section 10.2 of the paper). */
typedef struct ps_disk_params {
  double c;          /* half crack length, m (paper: 1/24) */
  int n_eta, n_xi;   /* zones along eta in (0, pi) and xi in (xi_min, xi_max) */
  int per_zone;      /* particles per zone edge (paper: 5, so 5x5) */
  double xi_min, xi_max; /* default (-pi, pi): see doc/model.md */
  double jitter;     /* in [0, 0.5): shift within the sub-cell, fraction */
  unsigned long seed;
  /* refinement at the crack tips (+-c, 0): a sub-cell whose centre lies
   * within refine_radius (m) of a tip is split into refine_tips^2 (1: no
   * refinement, the default; radius 0: none either) */
  int refine_tips;
  double refine_radius;
} ps_disk_params;

/* Fill *dp with the paper's Table 1 defaults (c = 1/24, 20 x 40 zones, 5x5,
 * no tip refinement). */
void ps_disk_params_default(ps_disk_params *dp);

/* The number of particles ps_geom_disk makes of *dp (valid parameters). */
double ps_geom_disk_count(const ps_disk_params *dp);

/* The elliptic disk of Eq. 114 with a crack between the foci: each zone of
 * the (xi, eta) grid holds per_zone^2 particles at sub-cell centres,
 * jittered within their sub-cell; the volume of a particle is the exact
 * area of its sub-cell, c^2 int int (sinh^2 xi + sin^2 eta). A sub-cell
 * near a tip (refine_tips, refine_radius) is split into refine_tips^2
 * equal (xi, eta) cells, each a particle likewise (its area exact, its
 * jitter a fraction of its own cell). Marks the
 * outermost ring of zones as boundary zone. Sizes are NOT set.
 * Returns PS_OK, PS_ERR_INPUT, PS_ERR_NOMEM. */
int ps_geom_disk(ps_particles *p, const ps_disk_params *dp, ps_ctx *ctx);

/* Eq. 116 (plane strain: kappa = 3 - 4 nu; plane stress: (3 - nu)/(1 + nu)):
 * displacement (u, v) at (x, y) of the elliptic-crack plate under the
 * equibiaxial remote stress S, shear modulus G, evaluated on the principal
 * branch (xi >= 0, eta in (-pi, pi]) of z = c cosh(xi + i eta). */
void ps_geom_eq116(double x, double y, double c, double S, double G,
                   double kappa, double *u, double *v);

/* Elliptic coordinates (xi >= 0, eta in (-pi, pi]) of (x, y): principal
 * branch of the complex arccosh of (x + i y)/c. */
void ps_geom_elliptic_coords(double x, double y, double c, double *xi,
                             double *eta);

/* Perimeter of the ellipse xi = const (semi-axes c cosh xi, c sinh xi),
 * by the complete elliptic integral of the second kind (GSL). */
double ps_geom_ellipse_perimeter(double c, double xi);

/* Particle sizes by Eq. 115: h_a = sum over the n nearest neighbours of
 * |x_b - x_a| / (2 n). Returns PS_OK, PS_ERR_INPUT (fewer than n+1
 * particles, or coincident particles), PS_ERR_NOMEM. */
int ps_geom_sizes_eq115(ps_particles *p, int n_nearest, ps_ctx *ctx);

/* Particle sizes by Eq. 44 from the volume: h = (N V / (2 (N-1) pi))^(1/N). */
void ps_geom_sizes_eq44(ps_particles *p);

/* ---- parts of a cloud (partition.c) ---- */

/* The particles split into `parts` compact parts along a space-filling
 * curve (Morton order of the reference positions; doc/design-distributed.md):
 * part p holds order[start[p] .. start[p+1]), counts equal to within one. */
typedef struct ps_partition {
  int parts;
  ps_int n;         /* particles */
  ps_int *order;    /* [n] particle numbers in curve order */
  ps_int *start;    /* [parts + 1] */
  int *part_of;     /* [n] the part of each particle */
} ps_partition;

/* Split the cloud P into parts (1 .. P->n). Deterministic: the same cloud
 * gives the same parts anywhere. Returns PS_OK, PS_ERR_INPUT (parts out of
 * range) or PS_ERR_NOMEM. */
int ps_partition_curve(ps_partition *pt, const ps_particles *P, int parts, ps_ctx *ctx);
/* The ghosts of part `part`: the particles of other parts closer than
 * reach (m) to one of its particles, in increasing number, into *ghost
 * (allocated here, *n_ghost of them). For a network with arms r < alpha
 * max(h_a, h_b), reach = alpha max h holds every arm of the part's
 * particles; twice that, every family term of its neighbours. Returns
 * PS_OK, PS_ERR_INPUT (part out of range, reach not >= 0) or PS_ERR_NOMEM. */
int ps_partition_ghosts(const ps_partition *pt, const ps_particles *P, int part, double reach,
                        ps_int **ghost, ps_int *n_ghost, ps_ctx *ctx);
/* The ghosts of part `part` out to `hops` arms of a network whose arms
 * are r < alpha max(h_a, h_b) (ps_network_build, cracks aside): the
 * particles of other parts reached from the part's in at most hops such
 * steps, in increasing number, into *ghost (allocated here, *n_ghost of
 * them). The same arm test as the network's (squared distances against
 * (alpha h)^2 of either end), so on a cloud without cracks they are the
 * network's hops exactly; a crack only removes arms, so it leaves a
 * superset. Where the sizes vary this is far fewer particles than
 * ps_partition_ghosts at hops alpha max h (the paper's disk on 2 parts:
 * doc/parallel.md). Returns PS_OK, PS_ERR_INPUT (part out of range, hops
 * < 0, alpha not > 0) or PS_ERR_NOMEM. */
int ps_partition_ghost_hops(const ps_partition *pt, const ps_particles *P, int part, int hops,
                            double alpha, ps_int **ghost, ps_int *n_ghost, ps_ctx *ctx);
void ps_partition_free(ps_partition *pt);

/* ---- k-d tree over a cloud (static, built once) ---- */
typedef struct ps_kdtree ps_kdtree;

/* Build a k-d tree over n points x[i*dim + k]. The points are not copied:
 * keep x alive. Returns PS_OK or PS_ERR_NOMEM. */
int ps_kdtree_build(ps_kdtree **tree, const double *x, ps_int n, int dim,
                    ps_ctx *ctx);
void ps_kdtree_free(ps_kdtree **tree);

/* All points within distance < radius of point q; appends their indices to
 * *out (grown with ps_realloc; *cap is its capacity) and sets *count.
 * Returns PS_OK or PS_ERR_NOMEM. */
int ps_kdtree_radius(const ps_kdtree *t, const double *q, double radius,
                     ps_int **out, ps_int *cap, ps_int *count, ps_ctx *ctx);

/* The number of points within distance < radius of q, counted without
 * listing them (a box wholly inside the ball counts at once, so a ball
 * that covers the whole cloud costs O(1)); the count stops at cap (the
 * result is then cap, a lower bound). Allocates nothing. */
ps_int ps_kdtree_count(const ps_kdtree *t, const double *q, double radius, ps_int cap);

/* The k nearest points to point index i (itself excluded), distances in
 * dist[0..k-1] ascending, indices in idx. Returns the number found (< k
 * when the tree has fewer than k+1 points). */
int ps_kdtree_knn(const ps_kdtree *t, ps_int i, int k, ps_int *idx,
                  double *dist);

#endif
