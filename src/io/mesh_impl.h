/* mesh_impl.h: private to the mesh readers (src/io/mesh*.c), not part of
 * ps_mesh.h. A format's reader (mesh_gmsh.c, mesh_exodus.c) describes
 * the mesh in this neutral form: nodes with the file's ids, the elements
 * of the top dimension with their nodes' ids, block and id, and the named
 * groups (of elements or of nodes); mesh.c checks it and makes the
 * particles and sets. Node numbering of the elements: Gmsh's and Exodus
 * II's, which agree for these four (a quadrangle's nodes in turn around
 * it; a hexahedron's bottom face 0-3, then the top face 4-7 above them). */
#ifndef PS_MESH_IMPL_H
#define PS_MESH_IMPL_H

#include "ps_mesh.h"

enum ps_elem_kind { PS_ELEM_TRI3 = 0, PS_ELEM_QUAD4, PS_ELEM_TET4, PS_ELEM_HEX8 };

/* the nodes of an element of each kind */
static inline int ps_elem_nodes(int kind) {
  static const int n[] = {3, 4, 4, 8};
  return n[kind];
}

/* A named group: element indices (into the raw mesh's elements) or the
 * ids of nodes. */
typedef struct ps_mesh_group {
  char name[PS_MESH_NAME_MAX];
  char kind[32];
  int of_nodes;        /* 1: idx are node ids; 0: element indices */
  ps_int n, cap;
  ps_int *idx;
} ps_mesh_group;

typedef struct ps_mesh_raw {
  const char *path;    /* for messages */
  int dim;             /* the elements' dimension: 2 or 3 */
  ps_int n_node;
  ps_int *node_id;     /* [n_node] the file's ids, unique */
  double *node_x;      /* [3 n_node] x, y, z */
  ps_int n_elem, cap_elem;
  int *elem_kind;      /* [n_elem] enum ps_elem_kind */
  ps_int *elem_node;   /* [8 n_elem] node ids (the first ps_elem_nodes) */
  ps_int *elem_id;     /* [n_elem] the file's element id (messages) */
  int *elem_block;     /* [n_elem] block id >= 0 */
  int n_group, cap_group;
  ps_mesh_group *group;
} ps_mesh_raw;

/* Room for n nodes (node_id, node_x zeroed); PS_OK or PS_ERR_NOMEM. */
int ps_mesh_raw_nodes(ps_mesh_raw *m, ps_int n, ps_ctx *ctx);

/* Append an element; PS_OK or PS_ERR_NOMEM. */
int ps_mesh_raw_add_elem(ps_mesh_raw *m, int kind, const ps_int *nodes, ps_int id,
                         int block, ps_ctx *ctx);

/* Append an empty group (name cut to PS_MESH_NAME_MAX - 1 bytes) and
 * return it in *g; PS_OK or PS_ERR_NOMEM. */
int ps_mesh_raw_add_group(ps_mesh_raw *m, const char *name, const char *kind,
                          int of_nodes, ps_mesh_group **g, ps_ctx *ctx);

/* Append an index to a group; PS_OK or PS_ERR_NOMEM. */
int ps_mesh_group_add(ps_mesh_group *g, ps_int idx, ps_ctx *ctx);

/* Free everything of m (safe on a zeroed one). */
void ps_mesh_raw_free(ps_mesh_raw *m);

/* A reader's library is opened when a mesh is read, not linked: libgmsh
 * and libexoIIv2c bring 50 to 90 shared libraries (OpenCASCADE, HDF5,
 * NetCDF, MPI) whose loading slowed every start of peristatic (0.3 s
 * with Gmsh linked). Open the library soname (configure's PS_*_LIBRARY)
 * into *lib, RTLD_NODELETE so that its C++ static objects and exit
 * handlers stay valid after dlclose. PS_OK or PS_ERR_INPUT ("PATH: cannot
 * load the LABEL library SONAME (why): reinstall PACKAGE or re-run
 * configure"). */
int ps_mesh_library_open(void **lib, const char *soname, const char *label,
                         const char *package, const char *path, ps_ctx *ctx);

/* The function `name` of lib into *fn (a function pointer of size
 * bytes, read through a void * as POSIX has it); the first name not found
 * goes to *missing. */
void ps_mesh_library_sym(void *lib, const char *name, void *fn, size_t size,
                         const char **missing);

/* After the symbols: PS_OK when none was missing, else close *lib and
 * refuse ("PATH: the LABEL library SONAME has no NAME (another version
 * than configure found): re-run configure"), PS_ERR_INPUT. */
int ps_mesh_library_check(void **lib, const char *soname, const char *label,
                          const char *missing, const char *path, ps_ctx *ctx);

/* Close a library opened by ps_mesh_library_open (NULL: nothing). */
void ps_mesh_library_close(void **lib);

/* The readers: fill the zeroed *m from path, whose top dimension must be
 * dim (errors name path). PS_OK, PS_ERR_INPUT, PS_ERR_IO, PS_ERR_NOMEM;
 * the caller frees *m in any case. Each exists only when its package was
 * found (HAVE_GMSH, HAVE_EXODUSII). */
int ps_mesh_read_gmsh(ps_mesh_raw *m, const char *path, int dim, ps_ctx *ctx);
int ps_mesh_read_exodus(ps_mesh_raw *m, const char *path, int dim, ps_ctx *ctx);

#endif
