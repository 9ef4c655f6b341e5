/* mesh_gmsh.c: Gmsh meshes (.msh, any version Gmsh reads) through Gmsh's
 * own C API (gmshc.h, Debian libgmsh-dev; the library is opened when a
 * mesh is read, gmsh_open_library), into the neutral form of
 * mesh_impl.h. The elements of the mesh's top dimension become
 * particles; the physical group of that dimension an element's entity
 * belongs to is its block (0 when none); every physical group is a named
 * set: of its elements (top dimension) or of its nodes (lower
 * dimensions: points, curves, surfaces of a 3D mesh). Unnamed groups are
 * called point_TAG, curve_TAG, surface_TAG, volume_TAG. Built only when
 * configure found Gmsh (HAVE_GMSH).
 *
 * Gmsh picks its reader by the file name and runs .geo scripts (which can
 * start programs), so only a file named *.msh whose text starts with
 * "$MeshFormat" is handed to it. Gmsh keeps its model in the library's own
 * state: each read initialises and finalises it, and its terminal output
 * is off (its last error goes into our message). Gmsh sets the locale
 * (setlocale(LC_ALL, "") with LC_NUMERIC "C"): the process's locale is
 * put back when the read ends. */
#include "config.h"
#include "mesh_impl.h"

#include <gmshc.h>

#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The Gmsh functions used here, from the library opened when a mesh is
 * read (ps_mesh_library_open) */
#define GMSH_FUNCTIONS(X)                                                    \
  X(Free) X(Initialize) X(Finalize) X(Open) X(OptionSetNumber)               \
  X(LoggerGetLastError) X(ModelGetPhysicalGroupsForEntity)                   \
  X(ModelMeshGetElementProperties) X(ModelMeshGetElements)                   \
  X(ModelMeshGetElementTypes) X(ModelMeshGetNodes) X(ModelGetPhysicalName)   \
  X(ModelMeshGetNodesForPhysicalGroup) X(ModelGetEntitiesForPhysicalGroup)   \
  X(ModelGetEntities) X(ModelGetPhysicalGroups)

typedef struct gmsh_api {
  void *lib;
#define GMSH_MEMBER(f) __typeof__(&gmsh##f) f;
  GMSH_FUNCTIONS(GMSH_MEMBER)
#undef GMSH_MEMBER
} gmsh_api;

/* Open the Gmsh library (PS_GMSH_LIBRARY) into *g. */
static int gmsh_open_library(gmsh_api *g, const char *path, ps_ctx *ctx) {
  memset(g, 0, sizeof *g);
  PS_CHECK(ps_mesh_library_open(&g->lib, PS_GMSH_LIBRARY, "Gmsh", "libgmsh-dev", path, ctx));
  const char *missing = NULL;
#define GMSH_SYM(f) ps_mesh_library_sym(g->lib, "gmsh" #f, &g->f, sizeof g->f, &missing);
  GMSH_FUNCTIONS(GMSH_SYM)
#undef GMSH_SYM
  return ps_mesh_library_check(&g->lib, PS_GMSH_LIBRARY, "Gmsh", missing, path, ctx);
}

static const char *const dim_word[] = {"point", "curve", "surface", "volume"};

/* The message of a failed Gmsh call: Gmsh's last error, if any. */
static int gmsh_fail(const gmsh_api *g, const char *path, const char *what,
                     ps_ctx *ctx) {
  char *e = NULL;
  int ierr = 0;
  g->LoggerGetLastError(&e, &ierr);
  int s = ps_error(ctx, PS_ERR_INPUT, "%s: Gmsh could not %s%s%s", path, what,
                   !ierr && e && e[0] ? ": " : "", !ierr && e && e[0] ? e : "");
  if (e) g->Free(e);
  return s;
}

/* Is path a file Gmsh reads as a mesh (*.msh starting "$MeshFormat")? */
static int gmsh_check_file(const char *path, ps_ctx *ctx) {
  if (ps_mesh_format_of_path(path) != PS_MESH_GMSH)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: a Gmsh mesh must be named *.msh (Gmsh chooses how to read a "
                    "file by its name)", path);
  FILE *f = fopen(path, "rb");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open", path);
  char head[12] = {0};
  size_t n = fread(head, 1, 11, f);
  fclose(f);
  if (n < 11 || strncmp(head, "$MeshFormat", 11))
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: not a Gmsh mesh file (it does not start with $MeshFormat; write "
                    "it with gmsh -2 or -3, or File > Export as .msh)", path);
  return PS_OK;
}

/* The elements of one top-dimension entity, in m from index first on */
typedef struct gmsh_entity {
  int tag;
  ps_int first, count;
} gmsh_entity;

/* An entity's block: its physical group of the top dimension (0: none) */
static int gmsh_block(const gmsh_api *g, const char *path, int dim, int tag, int *block,
                      ps_ctx *ctx) {
  int *pt = NULL, ierr = 0;
  size_t np = 0;
  g->ModelGetPhysicalGroupsForEntity(dim, tag, &pt, &np, &ierr);
  if (ierr) return gmsh_fail(g, path, "read the physical groups", ctx);
  *block = np > 0 ? pt[0] : 0;
  int s = PS_OK;
  if (np > 1)
    s = ps_error(ctx, PS_ERR_INPUT,
                 "%s: %s %d is in physical %ss %d and %d: an element belongs to one block "
                 "(put each %s in one physical %s)",
                 path, dim_word[dim], tag, dim_word[dim], pt[0], pt[1], dim_word[dim],
                 dim_word[dim]);
  else if (np == 1 && pt[0] < 0)
    s = ps_error(ctx, PS_ERR_INPUT, "%s: physical %s %d: block ids must be >= 0", path,
                 dim_word[dim], pt[0]);
  g->Free(pt);
  return s;
}

/* Refuse elements of Gmsh type `type` in entity tag (block). */
static int gmsh_refuse_type(const gmsh_api *g, const char *path, int dim, int tag,
                            int block, int type, ps_ctx *ctx) {
  char *name = NULL, blk[96];
  double *local = NULL;
  size_t nlocal = 0;
  int d, order, nn, nprim, ierr = 0;
  g->ModelMeshGetElementProperties(type, &name, &d, &order, &nn, &local, &nlocal, &nprim,
                                    &ierr);
  if (block > 0)
    snprintf(blk, sizeof blk, "physical %s %d", dim_word[dim], block);
  else
    snprintf(blk, sizeof blk, "%s %d (in no physical %s)", dim_word[dim], tag,
             dim_word[dim]);
  int s = ps_error(ctx, PS_ERR_INPUT,
                   "%s: elements of type '%s' (Gmsh type %d) in %s: peristatic takes "
                   "3-node triangles and 4-node quadrangles in 2D, 4-node tetrahedra and "
                   "8-node hexahedra in 3D (first-order elements: Mesh.ElementOrder 1)",
                   path, !ierr && name ? name : "?", type, blk);
  if (name) g->Free(name);
  if (local) g->Free(local);
  return s;
}

/* The elements of entity (dim, tag) into m. */
static int gmsh_entity_elements(const gmsh_api *g, ps_mesh_raw *m, int dim, int tag,
                                int block, ps_ctx *ctx) {
  int *types = NULL, ierr = 0, status = PS_OK;
  size_t ntypes = 0, **etags = NULL, *etags_n = NULL, etags_nn = 0, **ntags = NULL,
         *ntags_n = NULL, ntags_nn = 0;
  g->ModelMeshGetElements(&types, &ntypes, &etags, &etags_n, &etags_nn, &ntags, &ntags_n,
                           &ntags_nn, dim, tag, &ierr);
  if (ierr) return gmsh_fail(g, m->path, "read the elements", ctx);
  for (size_t t = 0; t < ntypes && status == PS_OK; t++) {
    int kind = -1;
    if (dim == 2 && types[t] == 2) kind = PS_ELEM_TRI3;
    if (dim == 2 && types[t] == 3) kind = PS_ELEM_QUAD4;
    if (dim == 3 && types[t] == 4) kind = PS_ELEM_TET4;
    if (dim == 3 && types[t] == 5) kind = PS_ELEM_HEX8;
    if (kind < 0) {
      status = gmsh_refuse_type(g, m->path, dim, tag, block, types[t], ctx);
      break;
    }
    int nn = ps_elem_nodes(kind);
    for (size_t e = 0; e < etags_n[t] && status == PS_OK; e++) {
      ps_int nodes[8];
      for (int j = 0; j < nn; j++) nodes[j] = (ps_int)ntags[t][e * (size_t)nn + (size_t)j];
      status = ps_mesh_raw_add_elem(m, kind, nodes, (ps_int)etags[t][e], block, ctx);
    }
  }
  for (size_t t = 0; t < etags_nn; t++) g->Free(etags[t]);
  for (size_t t = 0; t < ntags_nn; t++) g->Free(ntags[t]);
  g->Free(types);
  g->Free(etags);
  g->Free(etags_n);
  g->Free(ntags);
  g->Free(ntags_n);
  return status;
}

/* The highest dimension that has elements (0 when none). */
static int gmsh_top_dim(const gmsh_api *g, const char *path, int *top, ps_ctx *ctx) {
  *top = 0;
  for (int d = 3; d >= 1 && *top == 0; d--) {
    int *types = NULL, ierr = 0;
    size_t n = 0;
    g->ModelMeshGetElementTypes(&types, &n, d, -1, &ierr);
    if (ierr) return gmsh_fail(g, path, "read the element types", ctx);
    if (n > 0) *top = d;
    g->Free(types);
  }
  return PS_OK;
}

/* All nodes of the model into m. */
static int gmsh_nodes(const gmsh_api *g, ps_mesh_raw *m, ps_ctx *ctx) {
  size_t *tags = NULL, ntags = 0, ncoord = 0, npar = 0;
  double *coord = NULL, *par = NULL;
  int ierr = 0;
  g->ModelMeshGetNodes(&tags, &ntags, &coord, &ncoord, &par, &npar, -1, -1, 0, 0, &ierr);
  if (ierr) return gmsh_fail(g, m->path, "read the nodes", ctx);
  int status = ps_mesh_raw_nodes(m, (ps_int)ntags, ctx);
  if (status == PS_OK && ncoord != 3 * ntags)
    status = ps_error(ctx, PS_ERR_INTERNAL, "%s: Gmsh gave %zu coordinates for %zu nodes",
                      m->path, ncoord, ntags);
  for (size_t i = 0; status == PS_OK && i < ntags; i++) {
    m->node_id[i] = (ps_int)tags[i];
    memcpy(&m->node_x[3 * i], &coord[3 * i], 3 * sizeof *coord);
  }
  g->Free(tags);
  g->Free(coord);
  if (par) g->Free(par);
  return status;
}

/* Physical group (d, tag) as a named group of m. */
static int gmsh_group(const gmsh_api *g, ps_mesh_raw *m, int d, int tag,
                      const gmsh_entity *ent, int n_ent, ps_ctx *ctx) {
  char *name = NULL, dflt[48], kind[32];
  int ierr = 0, status;
  g->ModelGetPhysicalName(d, tag, &name, &ierr);
  if (ierr) return gmsh_fail(g, m->path, "read a physical name", ctx);
  snprintf(dflt, sizeof dflt, "%s_%d", dim_word[d], tag);
  snprintf(kind, sizeof kind, "physical %s", dim_word[d]);
  ps_mesh_group *grp;
  status = ps_mesh_raw_add_group(m, name && name[0] ? name : dflt, kind, d < m->dim, &grp,
                                 ctx);
  if (name) g->Free(name);
  if (status != PS_OK) return status;
  if (d < m->dim) { /* its nodes */
    size_t *nt = NULL, nn = 0, nc = 0;
    double *coord = NULL;
    g->ModelMeshGetNodesForPhysicalGroup(d, tag, &nt, &nn, &coord, &nc, &ierr);
    if (ierr) return gmsh_fail(g, m->path, "read a physical group's nodes", ctx);
    for (size_t i = 0; i < nn && status == PS_OK; i++)
      status = ps_mesh_group_add(grp, (ps_int)nt[i], ctx);
    g->Free(nt);
    g->Free(coord);
    return status;
  }
  int *et = NULL; /* its entities' elements */
  size_t ne = 0;
  g->ModelGetEntitiesForPhysicalGroup(d, tag, &et, &ne, &ierr);
  if (ierr) return gmsh_fail(g, m->path, "read a physical group's entities", ctx);
  for (size_t i = 0; i < ne && status == PS_OK; i++)
    for (int k = 0; k < n_ent && status == PS_OK; k++)
      if (ent[k].tag == et[i])
        for (ps_int e = 0; e < ent[k].count && status == PS_OK; e++)
          status = ps_mesh_group_add(grp, ent[k].first + e, ctx);
  g->Free(et);
  return status;
}

/* The model Gmsh has read into m. */
static int gmsh_model(const gmsh_api *g, ps_mesh_raw *m, int dim, ps_ctx *ctx) {
  int top, ierr = 0, status = PS_OK;
  PS_CHECK(gmsh_top_dim(g, m->path, &top, ctx));
  if (top != dim)
    return ps_error(ctx, PS_ERR_INPUT,
                    top ? "%s: the mesh's elements are %dD but geometry.dim is %d"
                        : "%s: no elements (%d) for geometry.dim %d: mesh it first "
                          "(gmsh -2 or -3)",
                    m->path, top, dim);
  PS_CHECK(gmsh_nodes(g, m, ctx));
  int *dt = NULL;
  size_t ndt = 0;
  g->ModelGetEntities(&dt, &ndt, dim, &ierr);
  if (ierr) return gmsh_fail(g, m->path, "read the entities", ctx);
  gmsh_entity *ent = ps_calloc(ndt / 2 + 1, sizeof *ent, ctx);
  if (!ent) status = PS_ERR_NOMEM;
  for (size_t i = 0; i < ndt / 2 && status == PS_OK; i++) {
    int block = 0;
    ent[i].tag = dt[2 * i + 1];
    ent[i].first = m->n_elem;
    status = gmsh_block(g, m->path, dim, ent[i].tag, &block, ctx);
    if (status == PS_OK) status = gmsh_entity_elements(g, m, dim, ent[i].tag, block, ctx);
    ent[i].count = m->n_elem - ent[i].first;
  }
  g->Free(dt);
  int *pg = NULL;
  size_t npg = 0;
  if (status == PS_OK) {
    g->ModelGetPhysicalGroups(&pg, &npg, -1, &ierr);
    if (ierr) status = gmsh_fail(g, m->path, "read the physical groups", ctx);
  }
  for (size_t i = 0; i < npg / 2 && status == PS_OK; i++)
    if (pg[2 * i] <= dim)
      status = gmsh_group(g, m, pg[2 * i], pg[2 * i + 1], ent, (int)(ndt / 2), ctx);
  if (pg) g->Free(pg);
  free(ent);
  return status;
}

int ps_mesh_read_gmsh(ps_mesh_raw *m, const char *path, int dim, ps_ctx *ctx) {
  PS_CHECK(gmsh_check_file(path, ctx));
  gmsh_api api, *g = &api;
  PS_CHECK(gmsh_open_library(g, path, ctx));
  const char *now = setlocale(LC_ALL, NULL);
  char *locale = ps_calloc(strlen(now ? now : "C") + 1, 1, ctx);
  if (!locale) {
    ps_mesh_library_close(&g->lib);
    return PS_ERR_NOMEM;
  }
  strcpy(locale, now ? now : "C");
  int ierr = 0, status;
  g->Initialize(0, NULL, 0, &ierr);
  if (ierr) {
    status = ps_error(ctx, PS_ERR_INPUT, "%s: Gmsh could not start", path);
  } else {
    g->OptionSetNumber("General.Terminal", 0, &ierr);
    g->Open(path, &ierr);
    status = ierr ? gmsh_fail(g, path, "read the file", ctx) : gmsh_model(g, m, dim, ctx);
    g->Finalize(&ierr);
  }
  setlocale(LC_ALL, locale);
  free(locale);
  ps_mesh_library_close(&g->lib);
  return status;
}
