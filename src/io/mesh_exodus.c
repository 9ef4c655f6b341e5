/* mesh_exodus.c: Exodus II meshes (.exo, .e, .g, .gen) through the
 * Exodus II C API (exodusII.h, Debian libexodusii-dev), into the neutral
 * form of mesh_impl.h, as Peridigm's ExodusDiscretization reads them: the
 * elements of every element block become particles, the block's id is
 * their block id; every element block (named, or block_ID), node set
 * (named, or nodelist_ID: the elements that have one of its nodes,
 * Peridigm's rule) and side set (named, or sideset_ID: the elements whose
 * sides it lists) is a named set. Element types: TRI/TRI3/TRIANGLE and
 * QUAD/QUAD4 in 2D files, TET/TETRA/TET4/TETRA4 and HEX/HEX8 in 3D ones;
 * Peridigm's SPHERE blocks (particles already) and the higher-order
 * TET10/HEX20 are refused. Built only when configure found the library
 * (HAVE_EXODUSII), which is opened when a mesh is read. The library's messages are left at its default
 * (quiet): errors are reported here from its status codes. */
#include "config.h"
#include "mesh_impl.h"

#include <exodusII.h>

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The longest name read (the file's names are at most 32 characters
 * unless it says otherwise; ex_set_max_name_length raises ours) */
#define EXO_NAME 256

/* The Exodus II functions used here, from the library opened when a mesh
 * is read (ps_mesh_library_open) */
#define EXO_FUNCTIONS(X)                                                     \
  X(open_int) X(close) X(set_int64_status) X(set_max_name_length) X(get_init) \
  X(get_coord) X(get_id_map) X(get_elem_blk_ids) X(get_elem_block)           \
  X(get_elem_conn) X(get_name) X(get_node_set_ids) X(get_node_set_param)     \
  X(get_node_set) X(get_side_set_ids) X(get_side_set_param) X(get_side_set)

typedef struct exo_api {
  void *lib;
#define EXO_MEMBER(f) __typeof__(&ex_##f) f;
  EXO_FUNCTIONS(EXO_MEMBER)
#undef EXO_MEMBER
} exo_api;

/* Open the Exodus II library (PS_EXODUS_LIBRARY) into *ex. */
static int exo_open_library(exo_api *ex, const char *path, ps_ctx *ctx) {
  memset(ex, 0, sizeof *ex);
  PS_CHECK(ps_mesh_library_open(&ex->lib, PS_EXODUS_LIBRARY, "Exodus II", "libexodusii-dev",
                                path, ctx));
  const char *missing = NULL;
#define EXO_SYM(f) ps_mesh_library_sym(ex->lib, "ex_" #f, &ex->f, sizeof ex->f, &missing);
  EXO_FUNCTIONS(EXO_SYM)
#undef EXO_SYM
  return ps_mesh_library_check(&ex->lib, PS_EXODUS_LIBRARY, "Exodus II", missing, path, ctx);
}

/* The element kind of an Exodus type name with nn nodes in a dim-D file;
 * -1 if peristatic does not take it. */
static int exo_kind(const char *type, int64_t nn, int dim) {
  char t[EXO_NAME];
  size_t i = 0;
  for (; type[i] && i + 1 < sizeof t; i++) t[i] = (char)toupper((unsigned char)type[i]);
  t[i] = '\0';
  if (dim == 2 && nn == 3 &&
      (!strcmp(t, "TRI") || !strcmp(t, "TRI3") || !strcmp(t, "TRIANGLE")))
    return PS_ELEM_TRI3;
  if (dim == 2 && nn == 4 && (!strcmp(t, "QUAD") || !strcmp(t, "QUAD4")))
    return PS_ELEM_QUAD4;
  if (dim == 3 && nn == 4 &&
      (!strcmp(t, "TET") || !strcmp(t, "TETRA") || !strcmp(t, "TET4") ||
       !strcmp(t, "TETRA4")))
    return PS_ELEM_TET4;
  if (dim == 3 && nn == 8 && (!strcmp(t, "HEX") || !strcmp(t, "HEX8")))
    return PS_ELEM_HEX8;
  return -1;
}

/* The name of entity id of a type, or dflt_ID when it has none. */
static int exo_name(const exo_api *ex, int exo, ex_entity_type type, int64_t id,
                    const char *dflt, char *name, const char *path, ps_ctx *ctx) {
  char buf[EXO_NAME + 1] = {0};
  if (ex->get_name(exo, type, id, buf) < 0)
    return ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the name of %s %lld", path, dflt,
                    (long long)id);
  if (buf[0])
    snprintf(name, PS_MESH_NAME_MAX, "%s", buf);
  else
    snprintf(name, PS_MESH_NAME_MAX, "%s_%lld", dflt, (long long)id);
  return PS_OK;
}

/* The file's counts */
typedef struct exo_init {
  int64_t dim, nodes, elems, blocks, node_sets, side_sets;
} exo_init;

/* Nodes and element ids: coordinates of the nodes 1..n, the element map. */
static int exo_nodes(const exo_api *ex, int exo, ps_mesh_raw *m, const exo_init *in,
                     int64_t *elem_id, ps_ctx *ctx) {
  PS_CHECK(ps_mesh_raw_nodes(m, in->nodes, ctx));
  double *c = ps_calloc((size_t)(3 * in->nodes + 3), sizeof *c, ctx);
  if (!c) return PS_ERR_NOMEM;
  double *x = c, *y = c + in->nodes, *z = in->dim == 3 ? c + 2 * in->nodes : NULL;
  int status = PS_OK;
  if (in->nodes > 0 && ex->get_coord(exo, x, y, z) < 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the node coordinates", m->path);
  for (int64_t i = 0; status == PS_OK && i < in->nodes; i++) {
    m->node_id[i] = i + 1;
    m->node_x[3 * i] = x[i];
    m->node_x[3 * i + 1] = y[i];
    m->node_x[3 * i + 2] = z ? z[i] : 0.0;
  }
  free(c);
  if (status == PS_OK && in->elems > 0 && ex->get_id_map(exo, EX_ELEM_MAP, elem_id) < 0)
    for (int64_t e = 0; e < in->elems; e++) elem_id[e] = e + 1;
  return status;
}

/* One element block into m and as a named set. */
static int exo_block(const exo_api *ex, int exo, ps_mesh_raw *m, int64_t id, int dim,
                     const int64_t *elem_id, ps_ctx *ctx) {
  char type[EXO_NAME + 1] = {0}, name[PS_MESH_NAME_MAX];
  int64_t n = 0, nn = 0, nattr = 0;
  if (ex->get_elem_block(exo, id, type, &n, &nn, &nattr) < 0)
    return ps_error(ctx, PS_ERR_INPUT, "%s: cannot read element block %lld", m->path,
                    (long long)id);
  PS_CHECK(exo_name(ex, exo, EX_ELEM_BLOCK, id, "block", name, m->path, ctx));
  ps_mesh_group *g;
  PS_CHECK(ps_mesh_raw_add_group(m, name, "element block", 0, &g, ctx));
  if (n == 0) return PS_OK;
  int kind = exo_kind(type, nn, dim);
  if (kind < 0)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: element block %lld ('%s') has elements of type %s with %lld "
                    "nodes: "
                    "peristatic takes TRI3 and QUAD4 in 2D files, TET4 and HEX8 in 3D ones",
                    m->path, (long long)id, name, type, (long long)nn);
  if (id < 0 || id > 2147483647)
    return ps_error(ctx, PS_ERR_INPUT, "%s: element block id %lld: block ids must be in "
                    "0..2147483647", m->path, (long long)id);
  int64_t *conn = ps_calloc((size_t)(n * nn), sizeof *conn, ctx);
  if (!conn) return PS_ERR_NOMEM;
  int status = PS_OK;
  if (ex->get_elem_conn(exo, id, conn) < 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the elements of block %lld",
                      m->path, (long long)id);
  for (int64_t e = 0; e < n && status == PS_OK; e++) {
    ps_int nodes[8];
    for (int j = 0; j < nn; j++) nodes[j] = conn[e * nn + j];
    ps_int index = m->n_elem;
    status = ps_mesh_raw_add_elem(m, kind, nodes, elem_id[index], (int)id, ctx);
    if (status == PS_OK) status = ps_mesh_group_add(g, index, ctx);
  }
  free(conn);
  return status;
}

/* Node set or side set id as a named set. */
static int exo_set(const exo_api *ex, int exo, ps_mesh_raw *m, int64_t id, int side,
                   ps_ctx *ctx) {
  char name[PS_MESH_NAME_MAX];
  int64_t n = 0, ndf = 0;
  int r = side ? ex->get_side_set_param(exo, id, &n, &ndf)
               : ex->get_node_set_param(exo, id, &n, &ndf);
  if (r < 0)
    return ps_error(ctx, PS_ERR_INPUT, "%s: cannot read %s set %lld", m->path,
                    side ? "side" : "node", (long long)id);
  PS_CHECK(exo_name(ex, exo, side ? EX_SIDE_SET : EX_NODE_SET, id,
                    side ? "sideset" : "nodelist", name, m->path, ctx));
  ps_mesh_group *g;
  PS_CHECK(ps_mesh_raw_add_group(m, name, side ? "side set" : "node set", !side, &g, ctx));
  if (n == 0) return PS_OK;
  int64_t *list = ps_calloc((size_t)(2 * n), sizeof *list, ctx);
  if (!list) return PS_ERR_NOMEM;
  r = side ? ex->get_side_set(exo, id, list, list + n) : ex->get_node_set(exo, id, list);
  int status = PS_OK;
  if (r < 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: cannot read %s set %lld", m->path,
                      side ? "side" : "node", (long long)id);
  /* side sets list elements 1..n (the order of the blocks), node sets
   * nodes 1..n */
  for (int64_t i = 0; i < n && status == PS_OK; i++)
    status = ps_mesh_group_add(g, side ? list[i] - 1 : list[i], ctx);
  free(list);
  return status;
}

/* The open file's blocks and sets into m. */
static int exo_model(const exo_api *ex, int exo, ps_mesh_raw *m, int dim, ps_ctx *ctx) {
  exo_init in;
  char title[MAX_LINE_LENGTH + 1];
  if (ex->get_init(exo, title, &in.dim, &in.nodes, &in.elems, &in.blocks, &in.node_sets,
                  &in.side_sets) < 0)
    return ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the Exodus II header", m->path);
  if (in.dim != dim)
    return ps_error(ctx, PS_ERR_INPUT, "%s: the mesh is %lldD but geometry.dim is %d",
                    m->path, (long long)in.dim, dim);
  int64_t nid = in.blocks > in.node_sets ? in.blocks : in.node_sets;
  if (in.side_sets > nid) nid = in.side_sets;
  int64_t *elem_id = ps_calloc((size_t)in.elems + 1, sizeof *elem_id, ctx);
  int64_t *ids = ps_calloc((size_t)nid + 1, sizeof *ids, ctx);
  int status = elem_id && ids ? PS_OK : PS_ERR_NOMEM;
  if (status == PS_OK) status = exo_nodes(ex, exo, m, &in, elem_id, ctx);
  if (status == PS_OK && in.blocks > 0 && ex->get_elem_blk_ids(exo, ids) < 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the element blocks", m->path);
  for (int64_t b = 0; b < in.blocks && status == PS_OK; b++)
    status = exo_block(ex, exo, m, ids[b], dim, elem_id, ctx);
  if (status == PS_OK && m->n_elem != in.elems)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: the blocks hold %lld elements, the header "
                      "says %lld", m->path, (long long)m->n_elem, (long long)in.elems);
  if (status == PS_OK && in.node_sets > 0 && ex->get_node_set_ids(exo, ids) < 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the node sets", m->path);
  for (int64_t s = 0; s < in.node_sets && status == PS_OK; s++)
    status = exo_set(ex, exo, m, ids[s], 0, ctx);
  if (status == PS_OK && in.side_sets > 0 && ex->get_side_set_ids(exo, ids) < 0)
    status = ps_error(ctx, PS_ERR_INPUT, "%s: cannot read the side sets", m->path);
  for (int64_t s = 0; s < in.side_sets && status == PS_OK; s++)
    status = exo_set(ex, exo, m, ids[s], 1, ctx);
  free(elem_id);
  free(ids);
  return status;
}

int ps_mesh_read_exodus(ps_mesh_raw *m, const char *path, int dim, ps_ctx *ctx) {
  exo_api api, *ex = &api;
  PS_CHECK(exo_open_library(ex, path, ctx));
  int cpu_ws = sizeof(double), io_ws = 0, status;
  float version = 0;
  int exo = ex->open_int(path, EX_READ, &cpu_ws, &io_ws, &version, EX_API_VERS_NODOT);
  if (exo < 0) {
    status = ps_error(ctx, PS_ERR_INPUT, "%s: not an Exodus II file (the Exodus library "
                      "cannot open it)", path);
  } else {
    ex->set_int64_status(exo, EX_ALL_INT64_API);
    ex->set_max_name_length(exo, EXO_NAME);
    status = exo_model(ex, exo, m, dim, ctx);
    ex->close(exo);
  }
  ps_mesh_library_close(&ex->lib);
  return status;
}
