/* ps_io.h: input and output. Case files (YAML via libyaml) into a ps_case,
 * point clouds ("x y [z] volume [block]" per line), and results as CSV and
 * VTK XML files that ParaView opens (.vtu grids listed as time series in
 * .pvd collections). Every output is written to a temporary name and
 * renamed when complete (ps_outfile), so a failed run leaves earlier
 * results intact. */
#ifndef PS_IO_H
#define PS_IO_H

#include "../model/ps_model.h"
/* the option structs of the layers that take them, each in a header that
 * needs nothing but the C library (never ps_solver.h or ps_path.h) */
#include "../app/ps_sweep_opts.h"
#include "../nonlinear/ps_solver_opts.h"
#include "../path/ps_path_opts.h"
#include "ps_output_opts.h"
#include "ps_mesh.h"

enum ps_geometry_type { PS_GEOM_DISK = 0, PS_GEOM_BOX = 1, PS_GEOM_CLOUD = 2, PS_GEOM_MESH = 3 };
enum ps_size_rule { PS_SIZE_EQ115 = 0, PS_SIZE_EQ44 = 1 };
enum ps_load_type { PS_LOAD_EQ116 = 0, PS_LOAD_BOUNDARY = 1 };

#define PS_MAX_CRACKS 16
#define PS_MAX_HOLES 16
/* loading.boundary entries' names: letters, digits and '_', shorter than
 * this (they become history.csv columns reaction_<name>_x ...) */
#define PS_BC_NAME_SIZE 48

/* Case files are checked before libyaml parses them (Debian's libyaml
 * 0.2.5 takes time quadratic in the nesting depth):
 * at most this many bytes (the shipped cases are a few KB) and this many
 * levels of nested lists and mappings (they use about 6). */
#define PS_CASE_MAX_BYTES ((size_t)1 << 20)
#define PS_CASE_MAX_DEPTH 32

/* The largest coordinate (m) a case (cracks, holes, origin, the J
 * contour's tip) or a point cloud may give: squared distances of points
 * within it stay finite ("case.yaml:9: coordinates beyond 1e150 m"). */
#define PS_MAX_COORD 1e150

/* Ranges of the kernel and horizon keys (checked when a case is read).
 * kernel.alpha and material.horizon_factor are horizons in particle
 * sizes or lattice spacings (the paper: 5.1; Fallah et al.: 3): beyond
 * 1000 every particle would have millions of arms, and below 0.001 none;
 * Eq. 54's quadrature (ps_kernel_init) is accurate to 1e-14 over the
 * whole range (it fails from alpha = 1e100 in 3D, 1e155 in 2D). kernel.k
 * is the exponent of Eq. 112 (the paper: 2): up to 16, the weights still
 * reach the horizon's outer half (the quadrature itself holds to 1e6). */
#define PS_ALPHA_MIN 1e-3
#define PS_ALPHA_MAX 1e3
#define PS_KERNEL_K_MAX 16
/* geometry.counts: particles in all (ps_geom_box's limit; per axis: an int) */
#define PS_MAX_PARTICLES ((ps_int)1 << 40)
/* solver.max_memory_gib: at most this many GiB (about 1 PiB) */
#define PS_MAX_MEMORY_GIB 1e6

/* A particle selection: all bounds that are set must hold (inclusive);
 * block >= 0 also requires that block id, a set name membership of that
 * named set of the mesh (geometry.type mesh). Bounds unset are +-inf. */
typedef struct ps_select {
  double lo[3], hi[3]; /* x_min, y_min, z_min / x_max, y_max, z_max */
  int block;           /* -1: any */
  char set[PS_MESH_NAME_MAX]; /* "": any */
} ps_select;

/* One boundary condition entry of `loading.boundary`. A displaced
 * component k is prescribed at load factor 1 as a field of the reference
 * position x, polynomial of degree <= 2 about the point x0 = about:
 *   ubar_k(x) = displace[k] + sum_j gradient[k][j] (x_j - x0_j)
 *               + 1/2 sum_jl hessian[k][j][l] (x_j - x0_j) (x_l - x0_l)
 * (a constant when neither gradient nor hessian is given), and scaled by
 * the load factor as a whole. */
typedef struct ps_bc {
  ps_select sel;
  int fix[3];          /* 1: this component held at zero */
  int displace_set[3]; /* 1: this component prescribed */
  double displace[3];  /* prescribed displacement at load factor 1 (its
                          constant part, `value`), m */
  int gradient_n[3];   /* numbers given in this component's gradient (0:
                          none; else the case's dim) */
  double gradient[3][3]; /* d ubar_k / d x_j, dimensionless (m/m) */
  int hessian_n[3];    /* rows given in this component's hessian (0: none) */
  double hessian[3][3][3]; /* d2 ubar_k / d x_j d x_l, symmetric, 1/m */
  int about_n;         /* numbers given in `about` (0: x0 = 0) */
  double about[3];     /* x0, m */
  int traction_set[3]; /* 1: a traction on this component */
  double traction[3];  /* traction at load factor 1, Pa: the selected
                          particles carry the body force traction / layer
                          (force traction V_a / layer), layer = the
                          selection's thickness, geometry.spacing */
  int measure;         /* 1: reactions of these particles give the
                          boundary stress (along the displaced component) */
  char name[PS_BC_NAME_SIZE]; /* "" or the entry's name: history.csv
                          reports the reactions on its particles */
  int line;            /* line in the case file (messages) */
  int field_line, about_line; /* lines of the first field key and of about
                          (messages; 0: none) */
} ps_bc;

/* ubar_k at the reference position x[dim] of an entry's displaced
 * component k (the formula above), m. */
double ps_bc_displacement(const ps_bc *bc, int k, const double *x, int dim);

typedef struct ps_case {
  char file[1024];     /* the case file as given */
  char dir[1024];      /* its directory (relative paths resolve here) */
  char name[128];      /* case name (default: file name without .yaml) */

  /* geometry */
  int geometry;        /* enum ps_geometry_type */
  int dim;             /* 2 or 3 (disk: 2) */
  ps_disk_params disk; /* geometry.type = disk */
  ps_int counts[3];    /* box: particles per axis */
  double spacing;      /* box: lattice spacing d, m */
  char lattice[16];    /* box: "square" | "hex" */
  double jitter;       /* box: fraction of d */
  double origin[3];    /* box: corner of the first cell, m (default 0) */
  int n_holes;
  double holes[PS_MAX_HOLES][4]; /* box, cloud: holes, m, the centre in
                          holes[i][0..dim) and the radius R in
                          holes[i][dim] (2D circles (cx, cy, R), 3D
                          spheres (cx, cy, cz, R)): particles inside are
                          removed, arms across cut */
  unsigned long seed;  /* jitter seed (box; geometry.seed also sets
                          disk.seed) */
  char cloud_file[1024]; /* cloud, mesh: path (resolved against dir) */
  int mesh_format;     /* mesh: enum ps_mesh_format (geometry.format, else
                          from the file's extension; -1 before the cross
                          checks settle it) */
  const ps_particles *given_particles; /* cloud: particles given by the
                          caller (the library's peristatic_set_particles;
                          borrowed, copied at set-up) instead of a file;
                          NULL otherwise */
  int size_rule;       /* enum ps_size_rule (default eq115) */
  int size_neighbours; /* n of Eq. 115 (default 5) */
  int n_cracks;
  ps_crack cracks[PS_MAX_CRACKS]; /* geometry.cracks: 2D segments, 3D planar
                          polygons; the disk adds its own */

  /* kernel */
  double alpha;        /* default 5.1 */
  int kernel_k;        /* default 2 */

  /* material */
  char model[32];      /* "fibre" (default) | "bond" | "state" */
  double horizon_factor; /* bond, state: horizon delta = m * geometry.spacing
                            (box) or m * the cloud's mean spacing
                            (sum V / n)^(1/N), default m = 3 (Fallah et
                            al.); material.horizon gives delta in m */
  ps_material mat;     /* E, nu, plane, yield_strain, plastic, delta, rho */
  double delta_over_c; /* disk: delta given as a fraction of c (0: unset) */

  /* loading */
  int load_type;       /* enum ps_load_type (disk default eq116) */
  int n_bc;
  ps_bc *bc;           /* [n_bc] loading.boundary, owned by the case
                          (ps_case_free; copies by ps_case_copy) */
  double stress_length;/* boundary: length (2D) or area (3D) dividing the
                          measured reaction; 0: from the bounding box */

  /* solver: the Newton and linear solves (solver.* but max_memory_gib),
   * defaults ps_solver_opts_default */
  ps_solver_opts solver;
  double max_memory_gib; /* solver.max_memory_gib: refuse a case whose
                          estimated memory (ps_estimate_*,
                          src/network/ps_network.h) exceeds it, GiB; 0
                          (default): 80% of the machine's RAM. A limit
                          of the set-up (src/app/setup.c), not a setting
                          of the solver */
  const char *max_memory_key; /* where max_memory_gib came from, for
                          messages: NULL (the case's
                          solver.max_memory_gib) or "--max-memory" */

  /* path following (path.*), defaults ps_path_opts_default */
  ps_path_opts path;

  /* output (output.*), defaults ps_output_opts_default */
  ps_output_opts output;

  /* griffith sweep (griffith.*), defaults ps_sweep_opts_default */
  ps_sweep_opts sweep;
} ps_case;

/* Fill every field with its documented default (disk of Table 1, fibre
 * model with Table 1's material, delta = c/1000); the option structs by
 * their modules' *_opts_default. No list is allocated (bc and path.steps
 * are NULL): whatever *cs held before is overwritten, not freed. */
void ps_case_defaults(ps_case *cs);

/* A case owns two lists on the heap: the boundary entries (cs->bc) and
 * path.steps (cs->path.steps). ps_case_free frees them and leaves *cs
 * with none (n_bc = path.n_steps = 0), safe to free again; a plain
 * struct copy (ps_case c = *cs) shares them and must not be freed as
 * well. ps_case_copy makes *dst an independent copy of *src (dst's own
 * lists are not freed: call it on a fresh or freed case). Returns PS_OK
 * or PS_ERR_NOMEM (then *dst holds no lists). */
void ps_case_free(ps_case *cs);
int ps_case_copy(ps_case *dst, const ps_case *src, ps_ctx *ctx);

/* Append a copy of *bc to cs->bc (the array grows by one). Returns PS_OK
 * or PS_ERR_NOMEM (cs unchanged). */
int ps_case_add_bc(ps_case *cs, const ps_bc *bc, ps_ctx *ctx);

/* Read a YAML case file over the defaults. Errors name the file and line:
 * "case.yaml:14: material.E must be > 0 (got -3e9)". Unknown keys, keys
 * of another geometry type, wrong types, numbers that are not plain
 * decimal and impossible values are errors; a file over
 * PS_CASE_MAX_BYTES or nested deeper than PS_CASE_MAX_DEPTH is refused
 * before libyaml parses it. Lists the file gives (loading.boundary,
 * path.steps) replace and free those *cs held. Returns PS_OK,
 * PS_ERR_INPUT, PS_ERR_IO, PS_ERR_NOMEM; on failure *cs is unchanged. */
int ps_case_load(ps_case *cs, const char *path, ps_ctx *ctx);

/* ps_case_load from text[len] (a copy of the file's text, at most
 * PS_CASE_MAX_BYTES): `name` stands for the file in messages and gives the
 * default case name; relative paths inside resolve against the current
 * folder. Returns as ps_case_load. */
int ps_case_load_text(ps_case *cs, const char *text, size_t len, const char *name,
                      ps_ctx *ctx);

/* A 64-bit hash (FNV-1a) of everything in the case that determines a run's
 * result: the algorithm version, geometry, sizes, cracks, kernel,
 * material, loading, the Newton tolerance and stagnation rule, the CG
 * settings that change converged states (a fixed cg_forcing, cg_truncate
 * off) and the load path; not delta, the Griffith list, the output
 * settings, the CG settings that change only speed, nor
 * solver.max_memory_gib (a limit). See src/io/fingerprint.c. Written to summary.txt so that `griffith --resume` only
 * reuses runs of the same case. */
uint64_t ps_case_fingerprint(const ps_case *cs);

/* The algorithm version that ps_case_fingerprint hashes
 * (doc/algorithm-versions.md). */
int ps_algorithm_version(void);

/* The fingerprint a checkpoint must match to be continued by this case
 * (src/io/checkpoint.c): ps_case_fingerprint with path.max_increments
 * left out (a run that reached it may be continued with a larger one),
 * and every solver setting it leaves out added (the linear solver and
 * the CG settings: they change a run's bits, and a restart must repeat
 * them). delta is not in it: the checkpoint holds the run's own. */
uint64_t ps_case_restart_fingerprint(const ps_case *cs);

/* The parts of the restart fingerprint, for saying which one differs:
 * h[k] is ps_case_restart_fingerprint of the default case with part k of
 * cs in it (names: ps_case_restart_parts, NULL-terminated: "geometry",
 * "material" (with the kernel), "loading", "solver", "path"). */
#define PS_RESTART_PARTS 5
extern const char *const ps_case_restart_parts[PS_RESTART_PARTS + 1];
void ps_case_restart_part_fingerprints(const ps_case *cs, uint64_t h[PS_RESTART_PARTS]);

/* Is s a plain decimal number, the only kind case files and point clouds
 * take: an optional sign, digits with an optional fraction (or a fraction
 * alone), an optional exponent, and nothing else (no blanks, hex, inf,
 * nan, '_')? Without a fraction or exponent, no leading zero ("010"
 * would be octal 8 to YAML 1.1; "0", "0.5", "0e3" are fine). With
 * integer != 0: a sign and digits only, without a leading zero. Whether the value fits a
 * double or long is the caller's check (strtod/strtol and ERANGE). */
int ps_is_decimal(const char *s, int integer);

/* The longest line of a point cloud, characters (a file without line
 * breaks is refused at once, not read whole). */
#define PS_CLOUD_MAX_LINE 4096

/* Read a point cloud: one particle per line, "x y [z] volume [block]" (dim
 * coordinates, then the volume in m^N, then an optional integer block id);
 * '#' starts a comment, blank lines are skipped. Numbers are decimal
 * (ps_is_decimal) and finite; lines at most PS_CLOUD_MAX_LINE characters.
 * Errors name file:line ("cloud.txt:12: x (field 1 of 'x y volume
 * [block]') is not a finite decimal number (got '1e400')"). p->source is
 * a copy of path and p->line[a] the line of particle a (for messages:
 * ps_particle_where). Returns PS_OK, PS_ERR_INPUT, PS_ERR_IO (cannot open,
 * a read error), PS_ERR_NOMEM; on failure *p is zeroed (safe to
 * ps_particles_free). */
int ps_cloud_read(ps_particles *p, const char *path, int dim, ps_ctx *ctx);

/* A named array for output: n_comp values per point or cell. */
typedef struct ps_field {
  const char *name;
  int n_comp;          /* 1 (scalar) or 3 (vector; 2D data padded with 0) */
  const double *v;     /* [n * n_comp_in] */
  int n_comp_in;       /* components stored per entry in v (1, 2 or 3) */
} ps_field;

/* An unstructured grid for ps_vtu_write: points, their cells (a VERTEX
 * per point, or lines) and named arrays on the points, the cells and the
 * data set as a whole. */
typedef struct ps_vtu_grid {
  int dim;                     /* 2 or 3 coordinates per point in x (2D: z = 0) */
  ps_int n_point;
  const double *x;             /* [n_point * dim] */
  ps_int n_line;               /* 0: one VERTEX cell per point; else LINE cells */
  const ps_int *la, *lb;       /* [n_line] the points each line joins */
  const ps_field *point_fields;/* [n_pf], n_point entries each */
  int n_pf;
  const ps_field *cell_fields; /* [n_cf], one entry per cell */
  int n_cf;
  const ps_field *global_fields; /* [n_gf] scalars, one entry each: the data
                                  set's FieldData (e.g. the load factor) */
  int n_gf;
} ps_vtu_grid;

/* A VTK XML unstructured grid (.vtu) at path: the points (padded to 3
 * coordinates), the cells, and every field as a Float64 DataArray (names
 * without white space or XML specials; vectors have 3 components, padded
 * with 0), all in one raw appended block (little-endian, each array a
 * UInt64 byte count then its values; cells as Int64 connectivity and end
 * offsets, UInt8 types). Non-finite values are written as 0. Written
 * atomically (ps_outfile). Returns PS_OK, PS_ERR_IO, PS_ERR_NOMEM, or
 * PS_ERR_INTERNAL for bad arguments. */
int ps_vtu_write(const char *path, const ps_vtu_grid *g, ps_ctx *ctx);

/* A parallel VTK XML unstructured grid (.pvtu) at path: the grid g's
 * point and cell arrays (names and components; g's data are not read,
 * nor its data set's fields, which each piece carries) and its n_piece
 * pieces, .vtu files written by ps_vtu_write with those arrays (names
 * relative to the folder of path, as in ps_pvd_write), which ParaView
 * opens as one data set. Written atomically. Returns PS_OK, PS_ERR_IO,
 * or PS_ERR_INTERNAL for bad arguments. */
int ps_pvtu_write(const char *path, const ps_vtu_grid *g, int n_piece,
                  const char *const *piece, ps_ctx *ctx);

/* A ParaView data collection (.pvd) at path listing n files (names
 * relative to the folder of path, without white space or XML specials)
 * with their times (finite), in the order given. Written atomically.
 * Returns PS_OK, PS_ERR_IO, or PS_ERR_INTERNAL for bad arguments. */
int ps_pvd_write(const char *path, int n, const double *time, const char *const *file,
                 ps_ctx *ctx);

#endif
