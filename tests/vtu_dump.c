/* vtu_dump.c: a .vtu file of peristatic as text, for the shell tests'
 * awk scripts, in the layout of a legacy ASCII VTK file: POINTS n, then
 * "x y z" lines; CELLS n, then "k id..." lines; CELL_TYPES n; POINT_DATA n
 * and CELL_DATA n, each with "SCALARS name double 1" or "VECTORS name
 * double" blocks of value lines; then "FIELD name value" for the data
 * set's FieldData. Numbers with 17 significant digits (exact). Reads the
 * file with the tests' reader (vtu_read.c), which checks it strictly.
 * Usage: vtu_dump FILE.vtu; exit 1 (and the reason on stderr) when the
 * file does not pass. */
#include "vtu_read.h"

#include <stdio.h>
#include <string.h>

static void dump_data(const vtu_file *f, const char *section, long long n) {
  int header = 0;
  for (int k = 0; k < f->n_array; k++) {
    const vtu_array *a = &f->a[k];
    if (strcmp(a->section, section)) continue;
    if (!header++) printf("%s %lld\n", !strcmp(section, "PointData") ? "POINT_DATA" : "CELL_DATA", n);
    if (a->n_comp == 1)
      printf("SCALARS %s double 1\nLOOKUP_TABLE default\n", a->name);
    else
      printf("VECTORS %s double\n", a->name);
    for (size_t i = 0; i < vtu_count(a); i++)
      printf("%.17g%s", vtu_f64(a, i), (int)(i % (size_t)a->n_comp) == a->n_comp - 1 ? "\n" : " ");
  }
}

int main(int argc, char **argv) {
  vtu_file f;
  char why[256];
  if (argc != 2) {
    fprintf(stderr, "usage: vtu_dump FILE.vtu\n");
    return 2;
  }
  if (vtu_read(argv[1], &f, why, sizeof why)) {
    fprintf(stderr, "vtu_dump: %s: %s\n", argv[1], why);
    vtu_free(&f);
    return 1;
  }
  const vtu_array *x = vtu_find(&f, "Points", "Points");
  const vtu_array *conn = vtu_find(&f, "Cells", "connectivity");
  const vtu_array *off = vtu_find(&f, "Cells", "offsets");
  const vtu_array *types = vtu_find(&f, "Cells", "types");
  if (!x || x->n_comp != 3 || !conn || !off || !types) {
    fprintf(stderr, "vtu_dump: %s: no Points or Cells arrays\n", argv[1]);
    vtu_free(&f);
    return 1;
  }
  printf("POINTS %lld\n", f.n_point);
  for (long long i = 0; i < f.n_point; i++)
    printf("%.17g %.17g %.17g\n", vtu_f64(x, 3 * i), vtu_f64(x, 3 * i + 1), vtu_f64(x, 3 * i + 2));
  printf("CELLS %lld\n", f.n_cell);
  int64_t from = 0;
  for (long long c = 0; c < f.n_cell; c++) {
    int64_t to = vtu_i64(off, (size_t)c);
    if (to < from || (size_t)to > vtu_count(conn)) {
      fprintf(stderr, "vtu_dump: %s: cell %lld: bad offsets\n", argv[1], c);
      vtu_free(&f);
      return 1;
    }
    printf("%lld", (long long)(to - from));
    for (int64_t j = from; j < to; j++) printf(" %lld", (long long)vtu_i64(conn, (size_t)j));
    printf("\n");
    from = to;
  }
  printf("CELL_TYPES %lld\n", f.n_cell);
  for (long long c = 0; c < f.n_cell; c++) printf("%lld\n", (long long)vtu_i64(types, (size_t)c));
  dump_data(&f, "PointData", f.n_point);
  dump_data(&f, "CellData", f.n_cell);
  for (int k = 0; k < f.n_array; k++)
    if (!strcmp(f.a[k].section, "FieldData"))
      for (size_t i = 0; i < vtu_count(&f.a[k]); i++)
        printf("FIELD %s %.17g\n", f.a[k].name, vtu_f64(&f.a[k], i));
  vtu_free(&f);
  return 0;
}
