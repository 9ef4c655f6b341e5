/* vtu.c: the field files ParaView opens: VTK XML unstructured grids
 * (.vtu: points, VERTEX or LINE cells, Float64 arrays on points, cells and
 * the data set, in one raw appended block, little-endian, UInt64 byte
 * counts) and ParaView data collections (.pvd) that list them as a time
 * series. Written through ps_outfile, so a failed write leaves any
 * earlier file of the same name intact. */
#include "ps_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A value as written: non-finite values become 0 (no nan or inf in the
 * outputs: they would spoil a reader's colour ranges). */
static double finite_or_zero(double v) { return isfinite(v) ? v : 0.0; }

/* Check a name for an XML attribute: not empty, no white space, nothing
 * that would need escaping. */
static int name_ok(const char *name) {
  return name && name[0] && !strpbrk(name, " \t\r\n<>&\"'");
}

/* Check a field descriptor: a good name, n_comp 1 or 3, n_comp_in 1..3
 * (1 for scalars), data present when n > 0. */
static int field_ok(const ps_field *fd, ps_int n) {
  if (!name_ok(fd->name)) return 0;
  if (fd->n_comp != 1 && fd->n_comp != 3) return 0;
  if (fd->n_comp_in < 1 || fd->n_comp_in > 3) return 0;
  if (fd->n_comp == 1 && fd->n_comp_in != 1) return 0;
  return n == 0 || fd->v != NULL;
}

/* The appended block, written a buffer at a time: every number as its
 * little-endian bytes, whatever the host's byte order. */
typedef struct block {
  FILE *f;
  unsigned char buf[8192];
  size_t used;
} block;

static void block_flush(block *b) {
  if (b->used) fwrite(b->buf, 1, b->used, b->f);
  b->used = 0;
}

static void put_le(block *b, uint64_t v, int bytes) {
  if (b->used + (size_t)bytes > sizeof b->buf) block_flush(b);
  for (int k = 0; k < bytes; k++) b->buf[b->used++] = (unsigned char)(v >> (8 * k));
}

static void put_f64(block *b, double v) {
  uint64_t w;
  memcpy(&w, &v, sizeof w);
  put_le(b, w, 8);
}

/* One DataArray: its XML element and its entry in the appended block. */
enum array_kind { A_FIELD, A_POINTS, A_CONN, A_OFFSETS, A_TYPES };
typedef struct array {
  int kind;           /* enum array_kind */
  const ps_field *fd; /* A_FIELD */
  ps_int n;           /* tuples */
  int global;         /* 1: FieldData (the data set's, one tuple) */
} array;

/* components and bytes per component of an array as written */
static int array_comp(const array *a) {
  return a->kind == A_FIELD ? a->fd->n_comp : a->kind == A_POINTS ? 3 : 1;
}
static int array_width(const array *a) { return a->kind == A_TYPES ? 1 : 8; }
static uint64_t array_bytes(const array *a) {
  return (uint64_t)a->n * (uint64_t)array_comp(a) * (uint64_t)array_width(a);
}

/* The <DataArray .../> elements of n arrays, then *off moved past their
 * entries in the block (each a UInt64 byte count, then the values). */
static void arrays_xml(FILE *f, const array *a, int n, uint64_t *off, const char *indent) {
  static const char *const name[] = {NULL, "Points", "connectivity", "offsets", "types"};
  for (int j = 0; j < n; j++) {
    int kind = a[j].kind;
    const char *type = kind == A_TYPES ? "UInt8"
                       : (kind == A_CONN || kind == A_OFFSETS) ? "Int64"
                                                               : "Float64";
    fprintf(f, "%s<DataArray type=\"%s\" Name=\"%s\"", indent, type,
            kind == A_FIELD ? a[j].fd->name : name[kind]);
    if (array_comp(&a[j]) != 1) fprintf(f, " NumberOfComponents=\"%d\"", array_comp(&a[j]));
    if (a[j].global) fprintf(f, " NumberOfTuples=\"%lld\"", (long long)a[j].n);
    fprintf(f, " format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)*off);
    *off += 8 + array_bytes(&a[j]);
  }
}

/* A section (<PointData>, ...) holding n arrays; none: no section, unless
 * always (Points, Cells). */
static void section_xml(FILE *f, const char *tag, const array *a, int n, int always,
                        uint64_t *off) {
  if (n == 0 && !always) return;
  fprintf(f, "      <%s>\n", tag);
  arrays_xml(f, a, n, off, "        ");
  fprintf(f, "      </%s>\n", tag);
}

/* The entry of a in the block: its byte count, then its values. */
static void array_data(block *b, const array *a, const ps_vtu_grid *g) {
  int lines = g->n_line > 0;
  put_le(b, array_bytes(a), 8);
  for (ps_int i = 0; i < a->n; i++) {
    switch (a->kind) {
    case A_POINTS:
      for (int k = 0; k < 3; k++)
        put_f64(b, k < g->dim ? finite_or_zero(g->x[i * g->dim + k]) : 0.0);
      break;
    case A_CONN:
      put_le(b, (uint64_t)(lines ? (i % 2 ? g->lb[i / 2] : g->la[i / 2]) : i), 8);
      break;
    case A_OFFSETS: put_le(b, (uint64_t)((i + 1) * (lines ? 2 : 1)), 8); break;
    case A_TYPES: put_le(b, lines ? 3 : 1, 1); break; /* VTK_LINE, VTK_VERTEX */
    default: {
      const ps_field *fd = a->fd;
      for (int k = 0; k < fd->n_comp; k++)
        put_f64(b, k < fd->n_comp_in ? finite_or_zero(fd->v[i * fd->n_comp_in + k]) : 0.0);
    }
    }
  }
}

/* Check the grid; PS_OK or PS_ERR_INTERNAL (a bug in the caller). */
static int grid_ok(const char *path, const ps_vtu_grid *g, ps_int n_cell, ps_ctx *ctx) {
  if ((g->dim != 2 && g->dim != 3) || g->n_point < 0 || g->n_line < 0 ||
      (g->n_point > 0 && !g->x) || (g->n_line > 0 && (!g->la || !g->lb)) || g->n_pf < 0 ||
      g->n_cf < 0 || g->n_gf < 0 || (g->n_pf && !g->point_fields) ||
      (g->n_cf && !g->cell_fields) || (g->n_gf && !g->global_fields))
    return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtu_write: bad arguments", path);
  for (int j = 0; j < g->n_pf; j++)
    if (!field_ok(&g->point_fields[j], g->n_point))
      return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtu_write: bad point field %d", path, j);
  for (int j = 0; j < g->n_cf; j++)
    if (!field_ok(&g->cell_fields[j], n_cell))
      return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtu_write: bad cell field %d", path, j);
  for (int j = 0; j < g->n_gf; j++)
    if (!field_ok(&g->global_fields[j], 1))
      return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtu_write: bad global field %d", path,
                      j);
  for (ps_int i = 0; i < g->n_line; i++)
    if (g->la[i] < 0 || g->la[i] >= g->n_point || g->lb[i] < 0 || g->lb[i] >= g->n_point)
      return ps_error(ctx, PS_ERR_INTERNAL,
                      "%s: ps_vtu_write: line %lld joins points out of range", path,
                      (long long)i);
  return PS_OK;
}

int ps_vtu_write(const char *path, const ps_vtu_grid *g, ps_ctx *ctx) {
  ps_int n_cell = g->n_line > 0 ? g->n_line : g->n_point; /* else one VERTEX per point */
  PS_CHECK(grid_ok(path, g, n_cell, ctx));
  /* the arrays in the order of the file: FieldData, PointData, CellData,
   * Points, Cells */
  int n_arr = g->n_gf + g->n_pf + g->n_cf + 4, j = 0;
  array *a = ps_calloc((size_t)n_arr, sizeof *a, ctx);
  if (!a) return PS_ERR_NOMEM;
  for (int k = 0; k < g->n_gf; k++)
    a[j++] = (array){A_FIELD, &g->global_fields[k], 1, 1};
  for (int k = 0; k < g->n_pf; k++)
    a[j++] = (array){A_FIELD, &g->point_fields[k], g->n_point, 0};
  for (int k = 0; k < g->n_cf; k++)
    a[j++] = (array){A_FIELD, &g->cell_fields[k], n_cell, 0};
  a[j++] = (array){A_POINTS, NULL, g->n_point, 0};
  a[j++] = (array){A_CONN, NULL, g->n_line > 0 ? 2 * g->n_line : g->n_point, 0};
  a[j++] = (array){A_OFFSETS, NULL, n_cell, 0};
  a[j++] = (array){A_TYPES, NULL, n_cell, 0};

  ps_outfile o;
  int status = ps_outfile_open(&o, path, ctx);
  if (status < 0) {
    free(a);
    return status;
  }
  FILE *f = o.f;
  uint64_t off = 0;
  fprintf(f, "<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
             "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
             "  <UnstructuredGrid>\n");
  if (g->n_gf > 0) {
    fprintf(f, "    <FieldData>\n");
    arrays_xml(f, a, g->n_gf, &off, "      ");
    fprintf(f, "    </FieldData>\n");
  }
  fprintf(f, "    <Piece NumberOfPoints=\"%lld\" NumberOfCells=\"%lld\">\n",
          (long long)g->n_point, (long long)n_cell);
  const array *at = a + g->n_gf;
  section_xml(f, "PointData", at, g->n_pf, 0, &off);
  section_xml(f, "CellData", at + g->n_pf, g->n_cf, 0, &off);
  section_xml(f, "Points", at + g->n_pf + g->n_cf, 1, 1, &off);
  section_xml(f, "Cells", at + g->n_pf + g->n_cf + 1, 3, 1, &off);
  fprintf(f, "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _");
  block b = {.f = f, .used = 0};
  for (j = 0; j < n_arr; j++) array_data(&b, &a[j], g);
  block_flush(&b);
  fprintf(f, "\n  </AppendedData>\n</VTKFile>\n");
  free(a);
  return ps_outfile_commit(&o, ctx);
}

/* the <PDataArray .../> elements of a .pvtu for n fields */
static void pfields_xml(FILE *f, const char *tag, const ps_field *fd, int n) {
  if (n == 0) return;
  fprintf(f, "    <%s>\n", tag);
  for (int j = 0; j < n; j++) {
    fprintf(f, "      <PDataArray type=\"Float64\" Name=\"%s\"", fd[j].name);
    if (fd[j].n_comp != 1) fprintf(f, " NumberOfComponents=\"%d\"", fd[j].n_comp);
    fprintf(f, "/>\n");
  }
  fprintf(f, "    </%s>\n", tag);
}

int ps_pvtu_write(const char *path, const ps_vtu_grid *g, int n_piece,
                  const char *const *piece, ps_ctx *ctx) {
  int bad = n_piece < 1 || !piece || (g->n_pf && !g->point_fields) ||
            (g->n_cf && !g->cell_fields);
  for (int j = 0; !bad && j < g->n_pf; j++) bad = !field_ok(&g->point_fields[j], 0);
  for (int j = 0; !bad && j < g->n_cf; j++) bad = !field_ok(&g->cell_fields[j], 0);
  for (int i = 0; !bad && i < n_piece; i++) bad = !name_ok(piece[i]);
  if (bad) return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_pvtu_write: bad arguments", path);
  ps_outfile o;
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  FILE *f = o.f;
  fprintf(f, "<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
             "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
             "  <PUnstructuredGrid GhostLevel=\"0\">\n");
  pfields_xml(f, "PPointData", g->point_fields, g->n_pf);
  pfields_xml(f, "PCellData", g->cell_fields, g->n_cf);
  fprintf(f, "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" "
             "NumberOfComponents=\"3\"/>\n    </PPoints>\n");
  for (int i = 0; i < n_piece; i++) fprintf(f, "    <Piece Source=\"%s\"/>\n", piece[i]);
  fprintf(f, "  </PUnstructuredGrid>\n</VTKFile>\n");
  return ps_outfile_commit(&o, ctx);
}

int ps_pvd_write(const char *path, int n, const double *time, const char *const *file,
                 ps_ctx *ctx) {
  if (n < 0 || (n > 0 && (!time || !file)))
    return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_pvd_write: bad arguments", path);
  for (int i = 0; i < n; i++)
    if (!name_ok(file[i]) || !isfinite(time[i]))
      return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_pvd_write: bad entry %d", path, i);
  ps_outfile o;
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f, "<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <Collection>\n");
  for (int i = 0; i < n; i++)
    fprintf(o.f, "    <DataSet timestep=\"%.17g\" part=\"0\" file=\"%s\"/>\n", time[i],
            file[i]);
  fprintf(o.f, "  </Collection>\n</VTKFile>\n");
  return ps_outfile_commit(&o, ctx);
}
