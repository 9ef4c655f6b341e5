/* mesh.c: a mesh read by a format's reader (mesh_gmsh.c, mesh_exodus.c,
 * in the neutral form of mesh_impl.h) made into particles and named sets
 * (ps_mesh.h): each element's centroid and volume, its block, and the
 * sets of particles of the mesh's groups. Also the list of formats, which
 * of them configure built, and the neutral form's helpers. */
#include "config.h"
#include "mesh_impl.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#ifdef HAVE_GMSH
#define PS_GMSH_READER ps_mesh_read_gmsh
#else
#define PS_GMSH_READER NULL
#endif
#ifdef HAVE_EXODUSII
#define PS_EXODUS_READER ps_mesh_read_exodus
#else
#define PS_EXODUS_READER NULL
#endif

typedef int (*mesh_reader)(ps_mesh_raw *m, const char *path, int dim, ps_ctx *ctx);

static const struct {
  const char *name, *label, *package;
  const char *ext[4];
  mesh_reader read; /* NULL: not built */
} formats[PS_MESH_N_FORMATS] = {
    {"gmsh", "Gmsh", "libgmsh-dev", {"msh", NULL, NULL, NULL}, PS_GMSH_READER},
    {"exodus", "Exodus II", "libexodusii-dev", {"exo", "e", "g", "gen"}, PS_EXODUS_READER}};

const char *ps_mesh_format_name(int format) {
  return format >= 0 && format < PS_MESH_N_FORMATS ? formats[format].name : NULL;
}

int ps_mesh_format_of_path(const char *path) {
  const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
  if (!dot || (slash && dot < slash)) return -1;
  for (int f = 0; f < PS_MESH_N_FORMATS; f++)
    for (int i = 0; i < 4 && formats[f].ext[i]; i++)
      if (!strcasecmp(dot + 1, formats[f].ext[i])) return f;
  return -1;
}

int ps_mesh_format_built(int format) {
  return format >= 0 && format < PS_MESH_N_FORMATS && formats[format].read != NULL;
}

const char *ps_mesh_format_missing(int format, char *msg, size_t size) {
  if (format < 0 || format >= PS_MESH_N_FORMATS)
    snprintf(msg, size, "unknown mesh format %d", format);
  else
    snprintf(msg, size,
             "this peristatic was built without %s support: install %s and re-run "
             "configure",
             formats[format].label, formats[format].package);
  return msg;
}

/* ---- the readers' libraries (mesh_impl.h), when a reader is built ---- */
#if defined(HAVE_GMSH) || defined(HAVE_EXODUSII)
#include <dlfcn.h>

int ps_mesh_library_open(void **lib, const char *soname, const char *label,
                         const char *package, const char *path, ps_ctx *ctx) {
  *lib = dlopen(soname, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (*lib) return PS_OK;
  const char *e = dlerror();
  return ps_error(ctx, PS_ERR_INPUT,
                  "%s: cannot load the %s library %s (%s): reinstall %s or re-run "
                  "configure", path, label, soname, e ? e : "no reason given", package);
}

void ps_mesh_library_sym(void *lib, const char *name, void *fn, size_t size,
                         const char **missing) {
  void *sym = dlsym(lib, name);
  if (!sym && !*missing) *missing = name;
  if (size == sizeof sym) memcpy(fn, &sym, sizeof sym);
}

int ps_mesh_library_check(void **lib, const char *soname, const char *label,
                          const char *missing, const char *path, ps_ctx *ctx) {
  if (!missing) return PS_OK;
  ps_mesh_library_close(lib);
  return ps_error(ctx, PS_ERR_INPUT,
                  "%s: the %s library %s has no %s (another version than configure "
                  "found): re-run configure", path, label, soname, missing);
}

void ps_mesh_library_close(void **lib) {
  if (*lib) dlclose(*lib);
  *lib = NULL;
}
#endif

/* ---- the neutral form's helpers (mesh_impl.h) ---- */

int ps_mesh_raw_nodes(ps_mesh_raw *m, ps_int n, ps_ctx *ctx) {
  m->node_id = ps_calloc((size_t)(n > 0 ? n : 1), sizeof *m->node_id, ctx);
  m->node_x = ps_calloc((size_t)(n > 0 ? n : 1) * 3, sizeof *m->node_x, ctx);
  if (!m->node_id || !m->node_x) return PS_ERR_NOMEM;
  m->n_node = n;
  return PS_OK;
}

int ps_mesh_raw_add_elem(ps_mesh_raw *m, int kind, const ps_int *nodes, ps_int id,
                         int block, ps_ctx *ctx) {
  if (m->n_elem == m->cap_elem) {
    ps_int cap = m->cap_elem ? 2 * m->cap_elem : 1024;
    void *k = m->elem_kind, *nd = m->elem_node, *i = m->elem_id, *b = m->elem_block;
    if (ps_realloc(&k, (size_t)cap, sizeof *m->elem_kind, ctx)) return PS_ERR_NOMEM;
    m->elem_kind = k;
    if (ps_realloc(&nd, (size_t)cap * 8, sizeof *m->elem_node, ctx)) return PS_ERR_NOMEM;
    m->elem_node = nd;
    if (ps_realloc(&i, (size_t)cap, sizeof *m->elem_id, ctx)) return PS_ERR_NOMEM;
    m->elem_id = i;
    if (ps_realloc(&b, (size_t)cap, sizeof *m->elem_block, ctx)) return PS_ERR_NOMEM;
    m->elem_block = b;
    m->cap_elem = cap;
  }
  ps_int e = m->n_elem++;
  m->elem_kind[e] = kind;
  for (int j = 0; j < 8; j++)
    m->elem_node[8 * e + j] = j < ps_elem_nodes(kind) ? nodes[j] : 0;
  m->elem_id[e] = id;
  m->elem_block[e] = block;
  return PS_OK;
}

int ps_mesh_raw_add_group(ps_mesh_raw *m, const char *name, const char *kind,
                          int of_nodes, ps_mesh_group **g, ps_ctx *ctx) {
  if (m->n_group == m->cap_group) {
    int cap = m->cap_group ? 2 * m->cap_group : 16;
    void *p = m->group;
    if (ps_realloc(&p, (size_t)cap, sizeof *m->group, ctx)) return PS_ERR_NOMEM;
    m->group = p;
    m->cap_group = cap;
  }
  *g = &m->group[m->n_group++];
  memset(*g, 0, sizeof **g);
  snprintf((*g)->name, sizeof (*g)->name, "%s", name);
  snprintf((*g)->kind, sizeof (*g)->kind, "%s", kind);
  (*g)->of_nodes = of_nodes;
  return PS_OK;
}

int ps_mesh_group_add(ps_mesh_group *g, ps_int idx, ps_ctx *ctx) {
  if (g->n == g->cap) {
    ps_int cap = g->cap ? 2 * g->cap : 64;
    void *p = g->idx;
    if (ps_realloc(&p, (size_t)cap, sizeof *g->idx, ctx)) return PS_ERR_NOMEM;
    g->idx = p;
    g->cap = cap;
  }
  g->idx[g->n++] = idx;
  return PS_OK;
}

void ps_mesh_raw_free(ps_mesh_raw *m) {
  free(m->node_id);
  free(m->node_x);
  free(m->elem_kind);
  free(m->elem_node);
  free(m->elem_id);
  free(m->elem_block);
  for (int i = 0; i < m->n_group; i++) free(m->group[i].idx);
  free(m->group);
  memset(m, 0, sizeof *m);
}

/* ---- sets ---- */

const ps_mesh_set *ps_mesh_set_find(const ps_mesh_sets *sets, const char *name) {
  for (int i = 0; i < sets->n; i++)
    if (!strcmp(sets->set[i].name, name)) return &sets->set[i];
  return NULL;
}

const char *ps_mesh_set_names(const ps_mesh_sets *sets, char *buf, size_t size) {
  size_t used = 0;
  buf[0] = '\0';
  if (sets->n == 0) snprintf(buf, size, "none");
  for (int i = 0; i < sets->n; i++) {
    int w = snprintf(buf + used, size - used, "%s%s", i ? ", " : "", sets->set[i].name);
    if (w < 0 || (size_t)w >= size - used) {
      if (size > 4) snprintf(buf + size - 4, 4, "...");
      break;
    }
    used += (size_t)w;
  }
  return buf;
}

void ps_mesh_sets_free(ps_mesh_sets *sets) {
  for (int i = 0; i < sets->n; i++) free(sets->set[i].particle);
  free(sets->set);
  memset(sets, 0, sizeof *sets);
}

/* ---- element geometry: centroid c[3] and signed volume ---- */

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* signed area of the triangle (a, b, c) in the xy plane */
static double tri_area(const double *a, const double *b, const double *c) {
  return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
}

/* Signed volume of an element whose nodes are x[i][0..2]; *valid = 0
 * when a quadrangle's or hexahedron's det J changes sign. */
static double elem_geometry(int kind, const double (*x)[3], double *c, int *valid) {
  *valid = 1;
  c[0] = c[1] = c[2] = 0.0;
  if (kind == PS_ELEM_TRI3 || kind == PS_ELEM_TET4) {
    int n = ps_elem_nodes(kind);
    for (int i = 0; i < n; i++)
      for (int k = 0; k < 3; k++) c[k] += x[i][k] / n;
    if (kind == PS_ELEM_TRI3) return tri_area(x[0], x[1], x[2]);
    double a[3], b[3], d[3], axb[3];
    for (int k = 0; k < 3; k++) {
      a[k] = x[1][k] - x[0][k];
      b[k] = x[2][k] - x[0][k];
      d[k] = x[3][k] - x[0][k];
    }
    cross3(a, b, axb);
    return (axb[0] * d[0] + axb[1] * d[1] + axb[2] * d[2]) / 6.0;
  }
  if (kind == PS_ELEM_QUAD4) {
    /* det J of the bilinear map at each corner has the sign of the
     * corner's turn: all alike for a convex, untwisted quadrangle */
    int pos = 0, neg = 0;
    for (int i = 0; i < 4; i++) {
      double t = tri_area(x[(i + 3) % 4], x[i], x[(i + 1) % 4]);
      pos += t > 0;
      neg += t < 0;
    }
    *valid = pos == 4 || neg == 4;
    double a1 = tri_area(x[0], x[1], x[2]), a2 = tri_area(x[0], x[2], x[3]);
    double A = a1 + a2;
    for (int k = 0; k < 2; k++)
      c[k] = (a1 * (x[0][k] + x[1][k] + x[2][k]) + a2 * (x[0][k] + x[2][k] + x[3][k])) /
             (3.0 * A);
    return A;
  }
  /* hexahedron: the trilinear map on [-1, 1]^3; 2x2x2 Gauss points for
   * the integrals, the corners and Gauss points for the sign of det J */
  static const double s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / sqrt(3.0);
  double V = 0.0, m[3] = {0, 0, 0};
  int pos = 0, neg = 0;
  for (int q = 0; q < 16; q++) {
    double r = q < 8 ? g : 1.0; /* q < 8: Gauss points, then the corners */
    double xi[3] = {r * s[q % 8][0], r * s[q % 8][1], r * s[q % 8][2]};
    double J[3][3] = {{0}}, p[3] = {0, 0, 0};
    for (int i = 0; i < 8; i++) {
      double f[3];
      for (int j = 0; j < 3; j++) f[j] = 1.0 + xi[j] * s[i][j];
      double N = f[0] * f[1] * f[2] / 8.0;
      double dN[3] = {s[i][0] * f[1] * f[2] / 8.0, s[i][1] * f[0] * f[2] / 8.0,
                      s[i][2] * f[0] * f[1] / 8.0};
      for (int k = 0; k < 3; k++) {
        p[k] += N * x[i][k];
        for (int j = 0; j < 3; j++) J[k][j] += x[i][k] * dN[j];
      }
    }
    double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                 J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                 J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    pos += det > 0;
    neg += det < 0;
    if (q < 8) {
      V += det;
      for (int k = 0; k < 3; k++) m[k] += det * p[k];
    }
  }
  *valid = pos == 16 || neg == 16;
  for (int k = 0; k < 3; k++) c[k] = m[k] / V;
  return V;
}

/* ---- the neutral form into particles and sets ---- */

typedef struct node_key {
  ps_int id, index;
} node_key;

static int cmp_node_key(const void *a, const void *b) {
  const node_key *x = a, *y = b;
  return (x->id > y->id) - (x->id < y->id);
}

static int cmp_ps_int(const void *a, const void *b) {
  ps_int x = *(const ps_int *)a, y = *(const ps_int *)b;
  return (x > y) - (x < y);
}

/* the index of node id in the sorted keys, -1 if absent */
static ps_int node_index(const node_key *key, ps_int n, ps_int id) {
  node_key k = {id, 0};
  const node_key *f = bsearch(&k, key, (size_t)n, sizeof *key, cmp_node_key);
  return f ? f->index : -1;
}

/* Particles from the elements: centroid, volume, block, element id. */
static int mesh_particles(const ps_mesh_raw *m, const node_key *key, ps_particles *p,
                          int dim, ps_ctx *ctx) {
  static const char *const kind_name[] = {"triangle", "quadrangle", "tetrahedron",
                                          "hexahedron"};
  const char *path = m->path;
  /* a 2D mesh lies in a plane z = const (to 1e-10 of its size) */
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (ps_int i = 0; i < m->n_node; i++)
    for (int k = 0; k < 3; k++) {
      lo[k] = fmin(lo[k], m->node_x[3 * i + k]);
      hi[k] = fmax(hi[k], m->node_x[3 * i + k]);
    }
  double size = fmax(hi[0] - lo[0], hi[1] - lo[1]);
  PS_CHECK(ps_particles_alloc(p, dim, m->n_elem, ctx));
  size_t len = strlen(path) + 1;
  p->source = ps_calloc(len, 1, ctx);
  p->line = ps_calloc((size_t)m->n_elem, sizeof *p->line, ctx);
  if (!p->source || !p->line) return PS_ERR_NOMEM;
  memcpy(p->source, path, len);
  p->line_is_element = 1;
  double z0 = NAN;
  for (ps_int e = 0; e < m->n_elem; e++) {
    int kind = m->elem_kind[e], nn = ps_elem_nodes(kind);
    double x[8][3];
    for (int j = 0; j < nn; j++) {
      ps_int id = m->elem_node[8 * e + j], i = node_index(key, m->n_node, id);
      if (i < 0)
        return ps_error(ctx, PS_ERR_INPUT,
                        "%s: element %lld (block %d) refers to node %lld, which the file "
                        "does not define", path, (long long)m->elem_id[e], m->elem_block[e],
                        (long long)id);
      memcpy(x[j], &m->node_x[3 * i], sizeof x[j]);
      if (dim == 2) {
        if (isnan(z0)) z0 = x[j][2];
        if (!(fabs(x[j][2] - z0) <= 1e-10 * size))
          return ps_error(ctx, PS_ERR_INPUT,
                          "%s: a 2D mesh must lie in a plane z = const: element %lld has "
                          "node %lld at z = %g, the first node at z = %g",
                          path, (long long)m->elem_id[e], (long long)id, x[j][2], z0);
      }
    }
    double c[3];
    int valid;
    double v = elem_geometry(kind, (const double(*)[3])x, c, &valid);
    if (!(fabs(v) > 0) || !isfinite(v) || !valid)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s: element %lld (a %s of block %d) %s: a mesh of valid elements "
                      "is needed",
                      path, (long long)m->elem_id[e], kind_name[kind], m->elem_block[e],
                      !(fabs(v) > 0) || !isfinite(v)
                          ? (dim == 2 ? "has no area" : "has no volume")
                          : "is inverted, twisted or not convex");
    for (int k = 0; k < dim; k++) p->x[e * dim + k] = c[k];
    p->volume[e] = fabs(v);
    p->block[e] = m->elem_block[e];
    p->line[e] = m->elem_id[e];
  }
  return PS_OK;
}

/* The particles of group g (sorted, unique) into s. */
static int mesh_set(const ps_mesh_raw *m, const node_key *key, const ps_mesh_group *g,
                    unsigned char *mark, ps_mesh_set *s, ps_ctx *ctx) {
  memcpy(s->name, g->name, sizeof s->name);
  memcpy(s->kind, g->kind, sizeof s->kind);
  s->particle = ps_calloc((size_t)(g->of_nodes ? m->n_elem : g->n) + 1, sizeof *s->particle,
                          ctx);
  if (!s->particle) return PS_ERR_NOMEM;
  if (!g->of_nodes) {
    for (ps_int i = 0; i < g->n; i++) {
      if (g->idx[i] < 0 || g->idx[i] >= m->n_elem)
        return ps_error(ctx, PS_ERR_INPUT, "%s: %s '%s' lists element %lld of %lld",
                        m->path, g->kind, g->name, (long long)g->idx[i] + 1,
                        (long long)m->n_elem);
      s->particle[i] = g->idx[i];
    }
    qsort(s->particle, (size_t)g->n, sizeof *s->particle, cmp_ps_int);
    for (ps_int i = 0; i < g->n; i++)
      if (s->n == 0 || s->particle[s->n - 1] != s->particle[i])
        s->particle[s->n++] = s->particle[i];
    return PS_OK;
  }
  /* Peridigm's rule: the elements that have a node of the group */
  memset(mark, 0, (size_t)m->n_node);
  for (ps_int i = 0; i < g->n; i++) {
    ps_int k = node_index(key, m->n_node, g->idx[i]);
    if (k < 0)
      return ps_error(ctx, PS_ERR_INPUT, "%s: %s '%s' lists node %lld, which the file "
                      "does not define", m->path, g->kind, g->name, (long long)g->idx[i]);
    mark[k] = 1;
  }
  for (ps_int e = 0; e < m->n_elem; e++) {
    int hit = 0;
    for (int j = 0; j < ps_elem_nodes(m->elem_kind[e]) && !hit; j++)
      hit = mark[node_index(key, m->n_node, m->elem_node[8 * e + j])];
    if (hit) s->particle[s->n++] = e;
  }
  return PS_OK;
}

/* The neutral form m into particles and sets. */
static int mesh_build(const ps_mesh_raw *m, ps_particles *p, ps_mesh_sets *sets, int dim,
                      ps_ctx *ctx) {
  int status = PS_OK;
  unsigned char *mark = NULL;
  if (m->n_elem == 0)
    return ps_error(ctx, PS_ERR_INPUT, "%s: no %dD elements: no particles", m->path, dim);
  node_key *key = ps_calloc((size_t)m->n_node + 1, sizeof *key, ctx);
  if (!key) return PS_ERR_NOMEM;
  for (ps_int i = 0; i < m->n_node; i++) {
    key[i].id = m->node_id[i];
    key[i].index = i;
  }
  qsort(key, (size_t)m->n_node, sizeof *key, cmp_node_key);
  for (ps_int i = 1; i < m->n_node; i++)
    if (key[i].id == key[i - 1].id) {
      status = ps_error(ctx, PS_ERR_INPUT, "%s: node %lld is defined twice", m->path,
                        (long long)key[i].id);
      goto cleanup;
    }
  PS_CHECK_GOTO(mesh_particles(m, key, p, dim, ctx));
  mark = ps_calloc((size_t)m->n_node + 1, 1, ctx);
  sets->set = ps_calloc((size_t)m->n_group + 1, sizeof *sets->set, ctx);
  if (!mark || !sets->set) {
    status = PS_ERR_NOMEM;
    goto cleanup;
  }
  for (int i = 0; i < m->n_group; i++) {
    sets->n++;
    PS_CHECK_GOTO(mesh_set(m, key, &m->group[i], mark, &sets->set[i], ctx));
  }
cleanup:
  free(key);
  free(mark);
  return status;
}

int ps_mesh_read(ps_particles *p, ps_mesh_sets *sets, const char *path, int format,
                 int dim, ps_ctx *ctx) {
  memset(p, 0, sizeof *p);
  memset(sets, 0, sizeof *sets);
  if (dim != 2 && dim != 3)
    return ps_error(ctx, PS_ERR_INPUT, "%s: meshes are 2D or 3D (got dim %d)", path, dim);
  if (!ps_mesh_format_built(format)) {
    char msg[256];
    return ps_error(ctx, PS_ERR_INPUT, "%s: %s", path,
                    ps_mesh_format_missing(format, msg, sizeof msg));
  }
  FILE *f = fopen(path, "rb");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  fclose(f);
  ps_mesh_raw m;
  memset(&m, 0, sizeof m);
  m.path = path;
  m.dim = dim;
  int status = formats[format].read(&m, path, dim, ctx);
  if (status == PS_OK) status = mesh_build(&m, p, sets, dim, ctx);
  ps_mesh_raw_free(&m);
  if (status != PS_OK) {
    ps_particles_free(p);
    ps_mesh_sets_free(sets);
  }
  return status;
}
