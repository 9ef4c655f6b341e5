/* t730_mesh.c: meshes read into particles (geometry.type mesh,
 * src/io/ps_mesh.h), one particle per element at its centroid with its
 * volume.
 * (a) 2D, Gmsh (the .geo files of tests/data/mesh, their .msh committed): the unit
 *     square in 4 x 4 structured quadrangles (16 particles at the cell
 *     centres ((i + 1/2)/4, (j + 1/2)/4), each of volume 1/16) and in
 *     unstructured triangles in two physical surfaces (blocks 7 and 9):
 *     as many particles as Gmsh's API counts triangles, each triangle's
 *     centroid the mean of its nodes as Gmsh gives them, volumes summing
 *     to 1 and first moments sum V x = sum V y = 1/2 to 1e-12 (exact for
 *     any mesh of the square), the blocks on their side of x = 0.4.
 * (b) 3D: the unit cube in 3 x 3 x 3 structured hexahedra (Gmsh) and in
 *     unstructured tetrahedra (Gmsh): counts, volumes summing to 1 and
 *     first moments 1/2 to 1e-12; a hexahedron with non-planar faces
 *     (Exodus, written here): its volume and centroid against the closed
 *     form of the trilinear map (2x2x2 Gauss is exact there) to 1e-14.
 * (c) Named sets: the physical curve "top" of the structured square picks
 *     exactly its top row; the physical surface "top" of the tetrahedral
 *     cube exactly the tetrahedra with a node on z = 1 (checked on Gmsh's
 *     own nodes, Peridigm's rule for node sets); a top-dimension group
 *     is its elements.
 * (e) Exodus II: the 20 x 10 plate of tests/data/mesh/plate.msh written
 *     here as an .exo (structured QUAD4, node sets left/right/top/bottom,
 *     a side set) gives the same particles (positions to 1e-10 of the
 *     spacing, volumes to 1e-9: Gmsh's transfinite nodes are off i d by
 *     about 1e-12 d) and the same sets as the .msh.
 * (f) Refusals with the file named: a missing file, second-order
 *     triangles (type named, with its block), a 2D mesh read as 3D, a
 *     file not named .msh, a .msh that is not a mesh, an Exodus SPHERE
 *     block, TET10; the message of a reader not built.
 * A reader that configure did not build FAILs its checks unless
 * configure was run --without-gmsh / --without-exodus (PS_GMSH_STATE,
 * PS_EXODUS_STATE "disabled"): then they are skipped, and the test
 * exits 77 (SKIP) when nothing was checked. */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "io/ps_io.h"

#ifdef HAVE_GMSH
#include <gmshc.h>
#endif
#ifdef HAVE_EXODUSII
#include <exodusII.h>
#endif

#define DATA(f) PS_TEST_DATA "/mesh/" f

static int n_checked;

/* Is the reader of format f here? If not: FAIL unless configure left it
 * out on purpose (state "disabled"), then SKIP. */
static int have(int f) {
  const char *state = f == PS_MESH_GMSH ? PS_GMSH_STATE : PS_EXODUS_STATE;
  const char *opt = f == PS_MESH_GMSH ? "gmsh" : "exodus";
  if (ps_mesh_format_built(f)) {
    n_checked++;
    return 1;
  }
  if (!strcmp(state, "disabled"))
    printf("SKIP: the %s reader (configure --without-%s)\n", opt, opt);
  else
    ps_check(0, "the %s reader was not built (configure found no %s): install it "
             "(scripts/install-deps.sh) or configure --without-%s",
             opt, f == PS_MESH_GMSH ? "libgmsh-dev" : "libexodusii-dev", opt);
  return 0;
}

#if defined(HAVE_GMSH) || defined(HAVE_EXODUSII) /* the helpers of the readers' checks */
static int read_mesh(ps_particles *p, ps_mesh_sets *s, const char *path, int format,
                     int dim) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  int st = ps_mesh_read(p, s, path, format, dim, &ctx);
  if (st != PS_OK) printf("  read %s: %s\n", path, ctx.msg);
  return st;
}

/* The read of path fails with a message containing want. */
static void expect_error(const char *path, int format, int dim, int status,
                         const char *want) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_particles p;
  ps_mesh_sets s;
  int st = ps_mesh_read(&p, &s, path, format, dim, &ctx);
  ps_check(st == status && strstr(ctx.msg, want) && strstr(ctx.msg, path),
           "refused (status %d, want %d): '%s' (want '%s' and the file)", st, status,
           ctx.msg, want);
  ps_check(p.n == 0 && p.x == NULL && s.n == 0, "refusal leaves nothing allocated");
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
}

__attribute__((unused)) static double sum_v(const ps_particles *p, int k) {
  double s = 0;
  for (ps_int a = 0; a < p->n; a++) s += p->volume[a] * (k < 0 ? 1.0 : p->x[a * p->dim + k]);
  return s;
}

/* n^dim particles at the cell centres of [0, 1]^dim, each of volume
 * n^-dim, to 1e-10 of a cell: Gmsh places a transfinite mesh's interior
 * nodes to about 1e-12 (not exactly at i/n) */
__attribute__((unused)) static void check_lattice(const ps_particles *p, int n,
                                                 const char *what) {
  int dim = p->dim, cells = dim == 2 ? n * n : n * n * n, bad = 0;
  char *hit = calloc((size_t)cells, 1);
  for (ps_int a = 0; a < p->n; a++) {
    int c = 0, mul = 1;
    for (int k = 0; k < dim; k++) {
      double u = p->x[a * dim + k] * n - 0.5;
      int i = (int)lround(u);
      if (fabs(u - i) > 1e-10 || i < 0 || i >= n) bad++;
      c += mul * (i < 0 ? 0 : i >= n ? n - 1 : i);
      mul *= n;
    }
    hit[c]++;
    if (fabs(p->volume[a] * cells - 1.0) > 1e-10) bad++;
  }
  for (int c = 0; c < cells; c++) bad += hit[c] != 1;
  ps_check(p->n == cells && bad == 0, "%s: %lld particles at the %d cell centres, volume "
           "1/%d each (%d wrong)", what, (long long)p->n, cells, cells, bad);
  free(hit);
}

static const ps_mesh_set *set_of(const ps_mesh_sets *s, const char *name) {
  const ps_mesh_set *m = ps_mesh_set_find(s, name);
  ps_check(m != NULL, "set '%s' found", name);
  return m;
}

#endif

#ifdef HAVE_GMSH
/* Gmsh's own view of a mesh, for independent checks: the elements of
 * dimension dim (count, and per element the mean of its nodes and
 * whether one of them has coordinate k == value). */
typedef struct gmsh_view {
  size_t n;
  size_t *tag;
  double *mean;       /* [3 n] */
  unsigned char *on;  /* [n] */
} gmsh_view;

static void gmsh_view_read(gmsh_view *g, const char *path, int dim, int k, double value) {
  int ierr = 0, *types = NULL;
  size_t nt = 0, **et = NULL, *et_n = NULL, et_nn = 0, **nt_ = NULL, *nt_n = NULL, nt_nn = 0;
  memset(g, 0, sizeof *g);
  gmshInitialize(0, NULL, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshOpen(path, &ierr);
  gmshModelMeshGetElements(&types, &nt, &et, &et_n, &et_nn, &nt_, &nt_n, &nt_nn, dim, -1,
                           &ierr);
  for (size_t t = 0; t < nt; t++) g->n += et_n[t];
  g->tag = calloc(g->n + 1, sizeof *g->tag);
  g->mean = calloc(3 * g->n + 1, sizeof *g->mean);
  g->on = calloc(g->n + 1, 1);
  size_t e = 0;
  for (size_t t = 0; t < nt; t++) {
    size_t nn = nt_n[t] / et_n[t];
    for (size_t i = 0; i < et_n[t]; i++, e++) {
      g->tag[e] = et[t][i];
      for (size_t j = 0; j < nn; j++) {
        double *c = NULL, *pc = NULL;
        size_t nc = 0, npc = 0;
        gmshModelMeshGetNode(nt_[t][i * nn + j], &c, &nc, &pc, &npc, &ierr);
        for (int q = 0; q < 3; q++) g->mean[3 * e + q] += c[q] / (double)nn;
        if (c[k] == value) g->on[e] = 1;
        gmshFree(c);
        if (pc) gmshFree(pc);
      }
    }
    gmshFree(et[t]);
    gmshFree(nt_[t]);
  }
  gmshFree(types);
  gmshFree(et);
  gmshFree(et_n);
  gmshFree(nt_);
  gmshFree(nt_n);
  gmshFinalize(&ierr);
}

static void gmsh_view_free(gmsh_view *g) {
  free(g->tag);
  free(g->mean);
  free(g->on);
}

/* The particles of p match Gmsh's elements one to one (by element id):
 * count, centroids of triangles and tetrahedra = node means; set s =
 * the elements with a node on the plane (NULL: not checked). */
static void check_against_gmsh(const ps_particles *p, const gmsh_view *g,
                               const ps_mesh_set *s, const char *what) {
  size_t bad = 0, bad_set = 0;
  for (ps_int a = 0; a < p->n; a++) {
    size_t e = 0;
    while (e < g->n && g->tag[e] != (size_t)p->line[a]) e++;
    if (e == g->n) {
      bad++;
      continue;
    }
    for (int k = 0; k < p->dim; k++)
      if (fabs(p->x[a * p->dim + k] - g->mean[3 * e + k]) > 1e-14) bad++;
    if (s) {
      int in = 0;
      for (ps_int i = 0; i < s->n; i++) in |= s->particle[i] == a;
      bad_set += in != g->on[e];
    }
  }
  ps_check((size_t)p->n == g->n && bad == 0,
           "%s: %lld particles for Gmsh's %zu elements, each at the mean of its nodes "
           "(%zu off)", what, (long long)p->n, g->n, bad);
  if (s)
    ps_check(bad_set == 0 && s->n > 0,
             "%s: set '%s' = the %lld elements with a node on the plane (%zu differ)",
             what, s->name, (long long)s->n, bad_set);
}

/* The area of the hole of data/cases/plate-gmsh.msh as Gmsh meshed it:
 * the polygon through the nodes of the physical curve "hole" (sorted by
 * angle about their mean: the shoelace formula); -1 when not found. */
static double gmsh_hole_area(const char *path) {
  int ierr = 0, *dt = NULL;
  size_t ndt = 0;
  double area = -1;
  gmshInitialize(0, NULL, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshOpen(path, &ierr);
  gmshModelGetPhysicalGroups(&dt, &ndt, 1, &ierr);
  for (size_t i = 0; i + 1 < ndt; i += 2) {
    char *name = NULL;
    gmshModelGetPhysicalName(dt[i], dt[i + 1], &name, &ierr);
    int hole = name && !strcmp(name, "hole");
    gmshFree(name);
    if (!hole) continue;
    size_t *tags = NULL, nt = 0, nc = 0;
    double *c = NULL;
    gmshModelMeshGetNodesForPhysicalGroup(1, dt[i + 1], &tags, &nt, &c, &nc, &ierr);
    double cx = 0, cy = 0, *ang = calloc(nt + 1, sizeof *ang);
    size_t *ord = calloc(nt + 1, sizeof *ord);
    for (size_t j = 0; j < nt; j++) cx += c[3 * j] / nt, cy += c[3 * j + 1] / nt;
    for (size_t j = 0; j < nt; j++) {
      ang[j] = atan2(c[3 * j + 1] - cy, c[3 * j] - cx);
      ord[j] = j;
    }
    for (size_t j = 1; j < nt; j++) /* insertion sort by angle */
      for (size_t k = j; k > 0 && ang[ord[k]] < ang[ord[k - 1]]; k--) {
        size_t t = ord[k];
        ord[k] = ord[k - 1];
        ord[k - 1] = t;
      }
    area = 0;
    for (size_t j = 0; j < nt; j++) {
      const double *a = &c[3 * ord[j]], *b = &c[3 * ord[(j + 1) % nt]];
      area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
    }
    free(ang);
    free(ord);
    gmshFree(tags);
    gmshFree(c);
  }
  gmshFree(dt);
  gmshFinalize(&ierr);
  return area;
}

static void test_gmsh(void) {
  ps_particles p;
  ps_mesh_sets s;
  /* (a) structured quadrangles */
  if (read_mesh(&p, &s, DATA("square_quad.msh"), PS_MESH_GMSH, 2) == PS_OK) {
    check_lattice(&p, 4, "square_quad.msh");
    ps_check_rel(sum_v(&p, -1), 1.0, 1e-12, "square_quad: sum V = 1");
    /* (c) the physical curve "top": the top row, y = 7/8 */
    const ps_mesh_set *top = set_of(&s, "top");
    int ok = top && top->n == 4;
    for (ps_int i = 0; ok && i < top->n; i++)
      ok = fabs(p.x[2 * top->particle[i] + 1] - 0.875) < 1e-10;
    ps_check(ok, "square_quad: set 'top' (physical curve) = the 4 particles of the top row");
    const ps_mesh_set *sq = set_of(&s, "square");
    ps_check(sq && sq->n == 16, "square_quad: set 'square' (physical surface) = all 16");
    ps_check(!strcmp(top ? top->kind : "", "physical curve"), "set kind named");
    char names[256];
    ps_check(!strcmp(ps_mesh_set_names(&s, names, sizeof names),
                     "bottom, right, top, left, square"),
             "set names listed: %s", names);
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  /* (a) unstructured triangles in two blocks */
  if (read_mesh(&p, &s, DATA("square_tri.msh"), PS_MESH_GMSH, 2) == PS_OK) {
    gmsh_view g;
    gmsh_view_read(&g, DATA("square_tri.msh"), 2, 1, 1.0);
    check_against_gmsh(&p, &g, ps_mesh_set_find(&s, "top"), "square_tri.msh");
    gmsh_view_free(&g);
    ps_check_rel(sum_v(&p, -1), 1.0, 1e-12, "square_tri: sum V = 1");
    ps_check_rel(sum_v(&p, 0), 0.5, 1e-12, "square_tri: sum V x = 1/2");
    ps_check_rel(sum_v(&p, 1), 0.5, 1e-12, "square_tri: sum V y = 1/2");
    int bad = 0, n7 = 0;
    for (ps_int a = 0; a < p.n; a++) {
      n7 += p.block[a] == 7;
      bad += p.block[a] == 7 ? p.x[2 * a] > 0.4 : p.block[a] == 9 ? p.x[2 * a] < 0.4 : 1;
    }
    const ps_mesh_set *left = set_of(&s, "left part");
    ps_check(bad == 0 && n7 > 0 && left && left->n == n7,
             "square_tri: blocks 7 (x < 0.4, %d particles = set 'left part') and 9", n7);
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  /* (b) structured hexahedra */
  if (read_mesh(&p, &s, DATA("cube_hex.msh"), PS_MESH_GMSH, 3) == PS_OK) {
    check_lattice(&p, 3, "cube_hex.msh");
    ps_check_rel(sum_v(&p, -1), 1.0, 1e-12, "cube_hex: sum V = 1");
    const ps_mesh_set *top = set_of(&s, "top");
    int ok = top && top->n == 9;
    for (ps_int i = 0; ok && i < top->n; i++)
      ok = fabs(p.x[3 * top->particle[i] + 2] - 5.0 / 6.0) < 1e-10;
    ps_check(ok, "cube_hex: set 'top' (physical surface) = the 9 particles of the top layer");
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  /* (b) unstructured tetrahedra, (c) the nodes of a physical surface */
  if (read_mesh(&p, &s, DATA("cube_tet.msh"), PS_MESH_GMSH, 3) == PS_OK) {
    gmsh_view g;
    gmsh_view_read(&g, DATA("cube_tet.msh"), 3, 2, 1.0);
    check_against_gmsh(&p, &g, ps_mesh_set_find(&s, "top"), "cube_tet.msh");
    gmsh_view_free(&g);
    ps_check_rel(sum_v(&p, -1), 1.0, 1e-12, "cube_tet: sum V = 1");
    for (int k = 0; k < 3; k++) ps_check_rel(sum_v(&p, k), 0.5, 1e-12, "cube_tet: sum V x_k = 1/2");
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  /* the shipped plate with a hole (data/cases/plate-gmsh.msh, 20 x 10 mm,
   * hole of radius 2 mm): one particle per Gmsh element, and the volumes
   * sum to the plate less the hole as meshed (a polygon of Gmsh's nodes) */
  const char *hole_msh = PS_TEST_DATA "/../../data/cases/plate-gmsh.msh";
  if (read_mesh(&p, &s, hole_msh, PS_MESH_GMSH, 2) == PS_OK) {
    gmsh_view g;
    gmsh_view_read(&g, hole_msh, 2, 1, 0.01);
    /* quadrangles: the centroid is the area's, not the nodes' mean */
    ps_check((size_t)p.n == g.n, "plate-gmsh.msh: %lld particles for Gmsh's %zu elements",
             (long long)p.n, g.n);
    gmsh_view_free(&g);
    double hole = gmsh_hole_area(hole_msh);
    ps_check(hole > 0.99 * 3.141592653589793 * 4e-6 && hole < 3.141592653589793 * 4e-6,
             "plate-gmsh: the meshed hole's polygon area %.9g m^2 lies just inside pi r^2",
             hole);
    ps_check_rel(sum_v(&p, -1), 2e-4 - hole, 1e-12,
                 "plate-gmsh: sum V = W H - the meshed hole's area");
    const ps_mesh_set *hs = set_of(&s, "hole");
    ps_check(hs && hs->n > 0, "plate-gmsh: set 'hole' holds the %lld elements along the hole",
             hs ? (long long)hs->n : 0LL);
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  /* (f) refusals */
  expect_error(DATA("order2.msh"), PS_MESH_GMSH, 2, PS_ERR_INPUT,
               "elements of type 'Triangle 6' (Gmsh type 9) in physical surface 1");
  expect_error(DATA("square_quad.msh"), PS_MESH_GMSH, 3, PS_ERR_INPUT,
               "the mesh's elements are 2D but geometry.dim is 3");
  expect_error(DATA("cube_hex.msh"), PS_MESH_GMSH, 2, PS_ERR_INPUT,
               "the mesh's elements are 3D but geometry.dim is 2");
  expect_error(DATA("missing.msh"), PS_MESH_GMSH, 2, PS_ERR_IO, "cannot open");
  expect_error(DATA("square_quad.geo"), PS_MESH_GMSH, 2, PS_ERR_INPUT,
               "a Gmsh mesh must be named *.msh");
  /* a script named .msh is not handed to Gmsh (a .geo could run programs) */
  FILE *f = fopen("t720_script.msh", "w");
  fputs("System \"touch t720_ran\";\n", f);
  fclose(f);
  expect_error("t720_script.msh", PS_MESH_GMSH, 2, PS_ERR_INPUT,
               "not a Gmsh mesh file (it does not start with $MeshFormat");
  ps_check(access("t720_ran", F_OK) != 0, "the script was not run");
  remove("t720_script.msh");
}
#endif

#ifdef HAVE_EXODUSII
/* An Exodus II file of one element block (type, npe nodes each, conn
 * 1-based), node sets and one side set (n_ss 0 or 1). */
typedef struct exo_spec {
  int dim, nn, ne, npe, block_id;
  const double *x, *y, *z;
  const char *type, *block_name;
  const int *conn;
  int n_ns;
  const char *ns_name[4];
  int ns_len[4];
  const int *ns_node[4];
  int n_ss, ss_len;
  const int *ss_elem, *ss_side;
} exo_spec;

static int write_exo(const char *path, const exo_spec *e) {
  int cpu = 8, io = 8;
  int exo = ex_create(path, EX_CLOBBER, &cpu, &io);
  if (exo < 0) return -1;
  int r = ex_put_init(exo, "t720", e->dim, e->nn, e->ne, 1, e->n_ns, e->n_ss);
  r |= ex_put_coord(exo, e->x, e->y, e->z);
  r |= ex_put_elem_block(exo, e->block_id, e->type, e->ne, e->npe, 0);
  r |= ex_put_elem_conn(exo, e->block_id, e->conn);
  if (e->block_name) r |= ex_put_name(exo, EX_ELEM_BLOCK, e->block_id, e->block_name);
  for (int i = 0; i < e->n_ns; i++) {
    r |= ex_put_node_set_param(exo, 10 + i, e->ns_len[i], 0);
    r |= ex_put_node_set(exo, 10 + i, e->ns_node[i]);
    r |= ex_put_name(exo, EX_NODE_SET, 10 + i, e->ns_name[i]);
  }
  if (e->n_ss) {
    r |= ex_put_side_set_param(exo, 3, e->ss_len, 0);
    r |= ex_put_side_set(exo, 3, e->ss_elem, e->ss_side);
  }
  r |= ex_close(exo);
  return r;
}

/* (e) the plate of plate.msh: 20 x 10 QUAD4 of 1 mm */
enum { NX = 20, NY = 10 };
static double px[(NX + 1) * (NY + 1)], py[(NX + 1) * (NY + 1)];
static int pconn[4 * NX * NY], ns[4][2 * (NX + 1)], ss_elem[NX], ss_side[NX];

static int write_plate(const char *path) {
  const double d = 1e-3;
  for (int j = 0; j <= NY; j++)
    for (int i = 0; i <= NX; i++) {
      px[j * (NX + 1) + i] = i * d;
      py[j * (NX + 1) + i] = j * d;
    }
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      int *c = &pconn[4 * (j * NX + i)], n0 = j * (NX + 1) + i + 1;
      c[0] = n0;
      c[1] = n0 + 1;
      c[2] = n0 + NX + 2;
      c[3] = n0 + NX + 1;
    }
  for (int j = 0; j <= NY; j++) {
    ns[0][j] = j * (NX + 1) + 1;      /* left */
    ns[1][j] = j * (NX + 1) + NX + 1; /* right */
  }
  for (int i = 0; i <= NX; i++) {
    ns[2][i] = NY * (NX + 1) + i + 1; /* top */
    ns[3][i] = i + 1;                 /* bottom */
  }
  for (int i = 0; i < NX; i++) {
    ss_elem[i] = (NY - 1) * NX + i + 1;
    ss_side[i] = 3; /* the side from node 3 to node 4: the top */
  }
  exo_spec e = {.dim = 2, .nn = (NX + 1) * (NY + 1), .ne = NX * NY, .npe = 4, .block_id = 1,
                .x = px, .y = py, .z = NULL, .type = "QUAD4", .block_name = "plate",
                .conn = pconn, .n_ns = 4, .ns_name = {"left", "right", "top", "bottom"},
                .ns_len = {NY + 1, NY + 1, NX + 1, NX + 1},
                .ns_node = {ns[0], ns[1], ns[2], ns[3]}, .n_ss = 1, .ss_len = NX,
                .ss_elem = ss_elem, .ss_side = ss_side};
  return write_exo(path, &e);
}

/* The index of the particle of q at p's particle a (positions within
 * tol), -1 if none. */
static ps_int same_place(const ps_particles *p, ps_int a, const ps_particles *q, double tol) {
  for (ps_int b = 0; b < q->n; b++) {
    int ok = 1;
    for (int k = 0; k < p->dim; k++) ok &= fabs(p->x[a * p->dim + k] - q->x[b * q->dim + k]) <= tol;
    if (ok) return b;
  }
  return -1;
}

static int in_set(const ps_mesh_set *s, ps_int a) {
  for (ps_int i = 0; i < s->n; i++)
    if (s->particle[i] == a) return 1;
  return 0;
}

static void test_exodus(void) {
  ps_particles p, q;
  ps_mesh_sets s, t;
  ps_check(write_plate("t720_plate.exo") == 0, "plate written as t720_plate.exo");
  if (read_mesh(&p, &s, "t720_plate.exo", PS_MESH_EXODUS, 2) == PS_OK) {
    ps_check(p.n == NX * NY && p.block[0] == 1 && p.block[p.n - 1] == 1,
             "plate.exo: %lld particles of block 1", (long long)p.n);
    const ps_mesh_set *sides = set_of(&s, "sideset_3"), *blk = set_of(&s, "plate");
    ps_check(sides && sides->n == NX && blk && blk->n == NX * NY,
             "plate.exo: side set 'sideset_3' = its %d elements, block 'plate' = all", NX);
    int gmsh = ps_mesh_format_built(PS_MESH_GMSH);
    if (gmsh && read_mesh(&q, &t, DATA("plate.msh"), PS_MESH_GMSH, 2) == PS_OK) {
      ps_int bad = 0, bad_set = 0;
      static const char *const names[] = {"left", "right", "top", "bottom"};
      for (ps_int a = 0; a < p.n; a++) {
        ps_int b = same_place(&p, a, &q, 1e-10 * 1e-3);
        if (b < 0 || fabs(p.volume[a] - q.volume[b]) > 1e-9 * q.volume[b]) {
          bad++;
          continue;
        }
        for (int i = 0; i < 4; i++) {
          const ps_mesh_set *u = ps_mesh_set_find(&s, names[i]), *v = ps_mesh_set_find(&t, names[i]);
          bad_set += !u || !v || in_set(u, a) != in_set(v, b);
        }
        bad_set += in_set(sides, a) != in_set(ps_mesh_set_find(&t, "top"), b);
      }
      ps_check(p.n == q.n && bad == 0,
               "plate.exo = plate.msh: the same %lld particles and volumes (%lld differ)",
               (long long)q.n, (long long)bad);
      ps_check(bad_set == 0, "plate.exo = plate.msh: node sets left/right/top/bottom = "
               "the physical curves, the top side set = 'top' (%lld differ)", (long long)bad_set);
    }
    if (gmsh) {
      ps_particles_free(&q);
      ps_mesh_sets_free(&t);
    }
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  remove("t720_plate.exo");

  /* (b) a hexahedron with non-planar faces: the unit square's bottom,
   * vertical edges of heights h_i: V = mean h, x_c = int x H / V,
   * z_c = int H^2 / 2 / V with H the bilinear interpolant of h */
  static const double h[4] = {1.0, 1.5, 0.7, 1.2}; /* at (0,0) (1,0) (1,1) (0,1) */
  double x[8] = {0, 1, 1, 0, 0, 1, 1, 0}, y[8] = {0, 0, 1, 1, 0, 0, 1, 1};
  double z[8] = {0, 0, 0, 0, h[0], h[1], h[2], h[3]};
  int conn[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  exo_spec e = {.dim = 3, .nn = 8, .ne = 1, .npe = 8, .block_id = 4, .x = x, .y = y, .z = z,
                .type = "HEX8", .conn = conn};
  ps_check(write_exo("t720_hex.exo", &e) == 0, "hexahedron written");
  if (read_mesh(&p, &s, "t720_hex.exo", PS_MESH_EXODUS, 3) == PS_OK) {
    double V = (h[0] + h[1] + h[2] + h[3]) / 4;
    /* int x N_i: 1/6 at x_i = 1, 1/12 at x_i = 0 (and y alike) */
    double mx = (h[1] + h[2]) / 6 + (h[0] + h[3]) / 12;
    double my = (h[2] + h[3]) / 6 + (h[0] + h[1]) / 12;
    /* int N_i N_j = a_x a_y, a = 1/3 on the same side, 1/6 across */
    double h2 = 0;
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++) {
        double ax = x[i] == x[j] ? 1.0 / 3 : 1.0 / 6, ay = y[i] == y[j] ? 1.0 / 3 : 1.0 / 6;
        h2 += h[i] * h[j] * ax * ay;
      }
    ps_check_rel(p.volume[0], V, 1e-14, "non-planar hexahedron: V = mean height");
    ps_check_rel(p.x[0], mx / V, 1e-14, "non-planar hexahedron: x_c");
    ps_check_rel(p.x[1], my / V, 1e-14, "non-planar hexahedron: y_c");
    ps_check_rel(p.x[2], h2 / 2 / V, 1e-14, "non-planar hexahedron: z_c");
    ps_check(p.block[0] == 4 && set_of(&s, "block_4"), "unnamed block 4 -> block id 4, set 'block_4'");
  }
  ps_particles_free(&p);
  ps_mesh_sets_free(&s);
  remove("t720_hex.exo");
  /* (f) refusals */
  e.type = "SPHERE";
  e.npe = 1;
  e.ne = 8;
  write_exo("t720_sphere.exo", &e);
  expect_error("t720_sphere.exo", PS_MESH_EXODUS, 3, PS_ERR_INPUT,
               "element block 4 ('block_4') has elements of type SPHERE with 1 nodes");
  remove("t720_sphere.exo");
  e.type = "HEX8";
  e.npe = 8;
  e.ne = 1;
  z[6] = -1.0; /* a corner pushed through the bottom: det J changes sign */
  write_exo("t720_bad.exo", &e);
  expect_error("t720_bad.exo", PS_MESH_EXODUS, 3, PS_ERR_INPUT,
               "element 1 (a hexahedron of block 4) is inverted, twisted or not convex");
  expect_error("t720_bad.exo", PS_MESH_EXODUS, 2, PS_ERR_INPUT,
               "the mesh is 3D but geometry.dim is 2");
  remove("t720_bad.exo");
  expect_error(DATA("square_quad.geo"), PS_MESH_EXODUS, 2, PS_ERR_INPUT,
               "not an Exodus II file");
  expect_error(DATA("missing.exo"), PS_MESH_EXODUS, 2, PS_ERR_IO, "cannot open");
}
#endif

int main(void) {
  char msg[256];
  ps_check(ps_mesh_format_of_path("a/b.MSH") == PS_MESH_GMSH &&
               ps_mesh_format_of_path("x.e") == PS_MESH_EXODUS &&
               ps_mesh_format_of_path("x.gen") == PS_MESH_EXODUS &&
               ps_mesh_format_of_path("x.geo") < 0 && ps_mesh_format_of_path("a.msh/x") < 0,
           "formats by extension");
  ps_check(strstr(ps_mesh_format_missing(PS_MESH_GMSH, msg, sizeof msg),
                  "this peristatic was built without Gmsh support: install libgmsh-dev and "
                  "re-run configure") != NULL &&
               strstr(ps_mesh_format_missing(PS_MESH_EXODUS, msg, sizeof msg),
                      "without Exodus II support: install libexodusii-dev") != NULL,
           "the message of a reader not built");
#ifdef HAVE_GMSH
  if (have(PS_MESH_GMSH)) test_gmsh();
#else
  have(PS_MESH_GMSH);
#endif
#ifdef HAVE_EXODUSII
  if (have(PS_MESH_EXODUS)) test_exodus();
#else
  have(PS_MESH_EXODUS);
#endif
  int rc = ps_check_summary();
  return rc == 0 && n_checked == 0 ? 77 : rc;
}
