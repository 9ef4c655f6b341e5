/* vtk.c: legacy ASCII VTK (version 3.0) unstructured grids that ParaView
 * opens: points, VERTEX or LINE cells, scalar and vector fields on points
 * and cells. Written through ps_outfile, so a failed write leaves any
 * earlier file of the same name intact. */
#include "ps_io.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* A value as written: non-finite values become 0 (VTK readers reject
 * nan/inf in ASCII files). */
static double finite_or_zero(double v) { return isfinite(v) ? v : 0.0; }

/* Check a field descriptor: a name without white space, n_comp 1 or 3,
 * n_comp_in 1..3 (1 for scalars), data present when n > 0. */
static int field_ok(const ps_field *fd, ps_int n) {
  if (!fd->name || !fd->name[0] || strpbrk(fd->name, " \t\r\n")) return 0;
  if (fd->n_comp != 1 && fd->n_comp != 3) return 0;
  if (fd->n_comp_in < 1 || fd->n_comp_in > 3) return 0;
  if (fd->n_comp == 1 && fd->n_comp_in != 1) return 0;
  return n == 0 || fd->v != NULL;
}

/* Write one SCALARS or VECTORS block of n entries. */
static void write_field(FILE *f, const ps_field *fd, ps_int n) {
  if (fd->n_comp == 1) {
    fprintf(f, "SCALARS %s double 1\nLOOKUP_TABLE default\n", fd->name);
    for (ps_int i = 0; i < n; i++) fprintf(f, "%.9g\n", finite_or_zero(fd->v[i]));
    return;
  }
  fprintf(f, "VECTORS %s double\n", fd->name);
  for (ps_int i = 0; i < n; i++) {
    double c[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < fd->n_comp_in; k++)
      c[k] = finite_or_zero(fd->v[i * fd->n_comp_in + k]);
    fprintf(f, "%.9g %.9g %.9g\n", c[0], c[1], c[2]);
  }
}

int ps_vtk_write(const char *path, int dim, ps_int n_point, const double *x,
                 ps_int n_line, const ps_int *la, const ps_int *lb,
                 const ps_field *point_fields, int n_pf,
                 const ps_field *cell_fields, int n_cf, ps_ctx *ctx) {
  /* argument errors are bugs in the caller, not bad input */
  if ((dim != 2 && dim != 3) || n_point < 0 || n_line < 0 || (n_point > 0 && !x) ||
      (n_line > 0 && (!la || !lb)) || n_pf < 0 || n_cf < 0)
    return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtk_write: bad arguments", path);
  for (int j = 0; j < n_pf; j++)
    if (!field_ok(&point_fields[j], n_point))
      return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtk_write: bad point field %d",
                      path, j);
  ps_int n_cell = n_line > 0 ? n_line : n_point; /* else one VERTEX per point */
  for (int j = 0; j < n_cf; j++)
    if (!field_ok(&cell_fields[j], n_cell))
      return ps_error(ctx, PS_ERR_INTERNAL, "%s: ps_vtk_write: bad cell field %d", path,
                      j);
  for (ps_int i = 0; i < n_line; i++)
    if (la[i] < 0 || la[i] >= n_point || lb[i] < 0 || lb[i] >= n_point)
      return ps_error(ctx, PS_ERR_INTERNAL,
                      "%s: ps_vtk_write: line %lld joins points out of range", path,
                      (long long)i);

  ps_outfile o;
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  FILE *f = o.f;
  fprintf(f, "# vtk DataFile Version 3.0\nperistatic output\nASCII\n"
             "DATASET UNSTRUCTURED_GRID\n");
  fprintf(f, "POINTS %lld double\n", (long long)n_point);
  for (ps_int i = 0; i < n_point; i++) {
    const double *p = &x[i * dim];
    fprintf(f, "%.9g %.9g %.9g\n", finite_or_zero(p[0]), finite_or_zero(p[1]),
            dim == 3 ? finite_or_zero(p[2]) : 0.0);
  }
  if (n_line > 0) {
    fprintf(f, "CELLS %lld %lld\n", (long long)n_line, (long long)(3 * n_line));
    for (ps_int i = 0; i < n_line; i++)
      fprintf(f, "2 %lld %lld\n", (long long)la[i], (long long)lb[i]);
    fprintf(f, "CELL_TYPES %lld\n", (long long)n_line);
    for (ps_int i = 0; i < n_line; i++) fputs("3\n", f);
  } else {
    fprintf(f, "CELLS %lld %lld\n", (long long)n_point, (long long)(2 * n_point));
    for (ps_int i = 0; i < n_point; i++) fprintf(f, "1 %lld\n", (long long)i);
    fprintf(f, "CELL_TYPES %lld\n", (long long)n_point);
    for (ps_int i = 0; i < n_point; i++) fputs("1\n", f);
  }
  if (n_pf > 0) {
    fprintf(f, "POINT_DATA %lld\n", (long long)n_point);
    for (int j = 0; j < n_pf; j++) write_field(f, &point_fields[j], n_point);
  }
  if (n_cf > 0) {
    fprintf(f, "CELL_DATA %lld\n", (long long)n_cell);
    for (int j = 0; j < n_cf; j++) write_field(f, &cell_fields[j], n_cell);
  }
  return ps_outfile_commit(&o, ctx);
}
