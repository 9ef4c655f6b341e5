/* ps_mesh.h: finite-element meshes read into particles (geometry.type
 * mesh): one particle per element of the mesh's top dimension, at the
 * element's centroid with its volume (2D: its area, m^2 per metre of
 * thickness, as point clouds give it), as Peridigm converts hexahedra and
 * tetrahedra to spheres; the mesh's element blocks (Gmsh: physical groups
 * of the top dimension) are the particles' block ids, and its named
 * groups (Gmsh physical groups, Exodus element blocks, node sets and side
 * sets) are named sets of particles that loading.boundary selects
 * (`select: {set: top}`). One reader file per format (mesh_gmsh.c,
 * mesh_exodus.c) fills the neutral description of mesh_impl.h; mesh.c
 * turns it into particles and sets, so a third format is one file. The
 * readers are optional: configure builds those whose Debian package it
 * finds (HAVE_GMSH, HAVE_EXODUSII in config.h). */
#ifndef PS_MESH_H
#define PS_MESH_H

#include "../geom/ps_geom.h"

enum ps_mesh_format { PS_MESH_GMSH = 0, PS_MESH_EXODUS = 1, PS_MESH_N_FORMATS = 2 };

/* The longest set name kept, bytes with the NUL (longer names are cut) */
#define PS_MESH_NAME_MAX 64

/* A named set of particles: the elements of a group of the mesh (a Gmsh
 * physical group of the top dimension, an Exodus element block or the
 * elements of a side set), or the elements that have a node in a group
 * of nodes (a lower-dimensional Gmsh physical group, an Exodus node set:
 * Peridigm's rule for node sets on a converted mesh). */
typedef struct ps_mesh_set {
  char name[PS_MESH_NAME_MAX];
  char kind[32];        /* "physical curve", "node set", ... (messages) */
  ps_int n;
  ps_int *particle;     /* [n] increasing particle indices */
} ps_mesh_set;

typedef struct ps_mesh_sets {
  int n;
  ps_mesh_set *set;     /* [n] in the file's order */
} ps_mesh_sets;

/* The format's name in case files ("gmsh", "exodus"), NULL for another
 * value. */
const char *ps_mesh_format_name(int format);

/* The format a file name's extension implies: .msh -> PS_MESH_GMSH;
 * .exo, .e, .g, .gen -> PS_MESH_EXODUS (any case); -1 for any other. */
int ps_mesh_format_of_path(const char *path);

/* Was the reader of this format built (configure found its package)? */
int ps_mesh_format_built(int format);

/* The refusal of a format whose reader was not built: "this peristatic
 * was built without Gmsh support: install libgmsh-dev and re-run
 * configure" (into msg[size]); returns msg. */
const char *ps_mesh_format_missing(int format, char *msg, size_t size);

/* Read the mesh at path (format: enum ps_mesh_format) into particles *p
 * (dim coordinates per particle; the mesh's top dimension must be dim)
 * and its named sets into *sets. p->source is a copy of path, p->line[a]
 * the id of particle a's element (p->line_is_element = 1), p->block[a]
 * its block id. Supported elements: 3-node triangles and 4-node
 * quadrangles (2D, the mesh in a plane z = const), 4-node tetrahedra and
 * 8-node hexahedra (3D); any other element of the top dimension is
 * refused naming its type and block. Volumes and centroids are exact for
 * the straight-sided element: triangles and tetrahedra in closed form, a
 * quadrangle as its two triangles, a hexahedron (the trilinear map) by
 * 2x2x2 Gauss quadrature of det J and x det J (exact: det J is of degree
 * at most 2 in each reference coordinate). An element of zero volume,
 * or a quadrangle or hexahedron whose det J changes sign (inverted,
 * twisted or not convex) is refused naming the element. Errors name the
 * file ("plate.msh: ..."). Returns PS_OK, PS_ERR_INPUT (not a mesh of
 * that format, a reader not built, bad elements), PS_ERR_IO (cannot
 * open), PS_ERR_NOMEM; on failure *p and *sets are zeroed (safe to
 * free). */
int ps_mesh_read(ps_particles *p, ps_mesh_sets *sets, const char *path, int format,
                 int dim, ps_ctx *ctx);

/* The (first) set called name, NULL if none. Gmsh allows one name for
 * groups of different dimensions: app/setup.c refuses such a name. */
const ps_mesh_set *ps_mesh_set_find(const ps_mesh_sets *sets, const char *name);

/* The names of the sets, ", "-separated, into buf[size] (cut with "..."
 * when too long; "none" without sets); returns buf. */
const char *ps_mesh_set_names(const ps_mesh_sets *sets, char *buf, size_t size);

/* Free the sets; safe on zeroed or freed sets. */
void ps_mesh_sets_free(ps_mesh_sets *sets);

#endif
