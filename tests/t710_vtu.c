/* t710_vtu.c: the field files' writers (src/io/vtu.c), read back by the
 * tests' own reader (tests/vtu_read.c, written from the file format):
 * every value of a .vtu bit for bit (non-finite values as 0, 2D padded
 * with z = 0), the cells (VERTEX per point, or lines), the data set's
 * FieldData, the layout of the appended block; the XML well-formed
 * (xmllint --noout on the header and on a .pvd when xmllint is
 * installed; the reader's own tag check always); bad arguments refused;
 * nothing left behind by a failed write. */
#include "check.h"
#include "io/ps_io.h"
#include "vtu_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* the same bits (so -0.0 is not 0.0, and every digit counts) */
static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* 1 when xmllint is on the PATH */
static int have_xmllint(void) { return system("command -v xmllint >/dev/null 2>&1") == 0; }

/* xmllint --noout on path: 1 well-formed, 0 not */
static int xmllint_ok(const char *path) {
  char cmd[512];
  snprintf(cmd, sizeof cmd, "xmllint --noout '%s'", path);
  return system(cmd) == 0;
}

/* The header of a .vtu (everything before <AppendedData) closed by
 * </VTKFile>, into path: well-formed XML when the header is (the raw
 * block itself is not XML text). */
static int write_head(const vtu_file *f, const char *path) {
  FILE *o = fopen(path, "w");
  if (!o) return 0;
  fwrite(f->bytes, 1, f->head_len, o);
  fputs("</VTKFile>\n", o);
  return fclose(o) == 0;
}

static void check_xml(const vtu_file *f, const char *what) {
  if (!have_xmllint()) {
    ps_check(1, "%s: xmllint not installed: the reader's tag check only", what);
    return;
  }
  const char *head = "t710_head.xml";
  ps_check(write_head(f, head) && xmllint_ok(head), "%s: header well-formed (xmllint)", what);
  remove(head);
}

/* 4 points, 3 lines, 2D: fields with NaN and inf, padded vectors, the
 * data set's load factor */
static void test_lines(void) {
  const char *path = "t710_lines.vtu";
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  double x[8] = {0, 0, 1, 0, 0, 1, 1, 1e-300};
  double u[8] = {0.1, 0.2, NAN, -0.0, 1.0 / 3.0, 0, 1, -INFINITY};
  double s[4] = {1, 2, INFINITY, 4};
  ps_int la[3] = {0, 1, 2}, lb[3] = {1, 3, 3};
  double cs[3] = {5, 6.5e-17, -7};
  double lambda = 0.1 + 0.2, step = 7;
  ps_field pf[2] = {{"displacement", 3, u, 2}, {"damage", 1, s, 1}};
  ps_field cf[1] = {{"broken", 1, cs, 1}};
  ps_field gf[2] = {{"load_factor", 1, &lambda, 1}, {"step", 1, &step, 1}};
  ps_vtu_grid g = {.dim = 2, .n_point = 4, .x = x, .n_line = 3, .la = la, .lb = lb,
                   .point_fields = pf, .n_pf = 2, .cell_fields = cf, .n_cf = 1,
                   .global_fields = gf, .n_gf = 2};
  remove(path);
  int st = ps_vtu_write(path, &g, &ctx);
  ps_check(st == PS_OK, "lines: written (%s)", ctx.msg);
  ps_check(access("t710_lines.vtu.tmp", F_OK) != 0, "lines: no .tmp left");
  vtu_file f;
  char why[256] = "";
  int r = vtu_read(path, &f, why, sizeof why);
  ps_check(r == 0, "lines: reads back: header, offsets, byte counts, closing tags (%s)", why);
  if (r == 0) {
    ps_check(f.n_point == 4 && f.n_cell == 3 && f.n_array == 9,
             "lines: 4 points, 3 cells, 9 arrays (got %lld, %lld, %d)", f.n_point, f.n_cell,
             f.n_array);
    const vtu_array *a = vtu_find(&f, "Points", "Points");
    int ok = a && a->n_comp == 3 && vtu_count(a) == 12 && !strcmp(a->type, "Float64");
    for (int i = 0; ok && i < 4; i++)
      ok = same_bits(vtu_f64(a, 3 * i), x[2 * i]) && same_bits(vtu_f64(a, 3 * i + 1), x[2 * i + 1]) &&
           same_bits(vtu_f64(a, 3 * i + 2), 0.0);
    ps_check(ok, "lines: points bit for bit, z = 0");
    const double want_u[12] = {0.1, 0.2, 0, 0, -0.0, 0, 1.0 / 3.0, 0, 0, 1, 0, 0};
    a = vtu_find(&f, "PointData", "displacement");
    ok = a && a->n_comp == 3 && vtu_count(a) == 12;
    for (int i = 0; ok && i < 12; i++) ok = same_bits(vtu_f64(a, (size_t)i), want_u[i]);
    ps_check(ok, "lines: displacement bit for bit, padded, nan and -inf written as 0");
    const double want_s[4] = {1, 2, 0, 4};
    a = vtu_find(&f, "PointData", "damage");
    ok = a && a->n_comp == 1 && vtu_count(a) == 4;
    for (int i = 0; ok && i < 4; i++) ok = same_bits(vtu_f64(a, (size_t)i), want_s[i]);
    ps_check(ok, "lines: damage bit for bit, inf written as 0");
    a = vtu_find(&f, "CellData", "broken");
    ok = a && vtu_count(a) == 3;
    for (int i = 0; ok && i < 3; i++) ok = same_bits(vtu_f64(a, (size_t)i), cs[i]);
    ps_check(ok, "lines: cell data bit for bit");
    const vtu_array *conn = vtu_find(&f, "Cells", "connectivity");
    const vtu_array *off = vtu_find(&f, "Cells", "offsets");
    const vtu_array *ty = vtu_find(&f, "Cells", "types");
    ok = conn && off && ty && vtu_count(conn) == 6 && !strcmp(conn->type, "Int64") &&
         !strcmp(off->type, "Int64") && !strcmp(ty->type, "UInt8");
    for (int i = 0; ok && i < 3; i++)
      ok = vtu_i64(conn, 2 * (size_t)i) == la[i] && vtu_i64(conn, 2 * (size_t)i + 1) == lb[i] &&
           vtu_i64(off, (size_t)i) == 2 * (i + 1) && vtu_i64(ty, (size_t)i) == 3;
    ps_check(ok, "lines: connectivity, end offsets, types VTK_LINE (3)");
    const vtu_array *lf = vtu_find(&f, "FieldData", "load_factor");
    const vtu_array *sf = vtu_find(&f, "FieldData", "step");
    ps_check(lf && sf && vtu_count(lf) == 1 && same_bits(vtu_f64(lf, 0), lambda) &&
                 vtu_count(sf) == 1 && vtu_f64(sf, 0) == 7,
             "lines: FieldData load_factor (bit for bit) and step");
    check_xml(&f, "lines");
  }
  vtu_free(&f);
  remove(path);
}

/* 1000 3D points as vertices, values of every kind of bits (the block
 * spans several of the writer's buffers) */
static void test_vertices(void) {
  const char *path = "t710_vertices.vtu";
  enum { N = 1000 };
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  double *x = malloc(3 * N * sizeof *x), *v = malloc(N * sizeof *v);
  uint64_t seed = 0x9E3779B97F4A7C15u;
  for (int i = 0; i < 3 * N + N; i++) {
    double d;
    do { /* random bits, finite values only */
      seed = seed * 6364136223846793005u + 1442695040888963407u;
      uint64_t w = seed ^ (seed >> 29);
      memcpy(&d, &w, sizeof d);
    } while (!isfinite(d));
    if (i < 3 * N)
      x[i] = d;
    else
      v[i - 3 * N] = d;
  }
  ps_field pf[1] = {{"h", 1, v, 1}};
  ps_vtu_grid g = {.dim = 3, .n_point = N, .x = x, .point_fields = pf, .n_pf = 1};
  int st = ps_vtu_write(path, &g, &ctx);
  ps_check(st == PS_OK, "vertices: written (%s)", ctx.msg);
  vtu_file f;
  char why[256] = "";
  int r = vtu_read(path, &f, why, sizeof why);
  ps_check(r == 0, "vertices: reads back (%s)", why);
  if (r == 0) {
    const vtu_array *a = vtu_find(&f, "Points", "Points"), *h = vtu_find(&f, "PointData", "h");
    int ok = f.n_point == N && f.n_cell == N && a && h && vtu_count(a) == 3 * N &&
             vtu_count(h) == N && !vtu_find(&f, "FieldData", "load_factor");
    for (int i = 0; ok && i < 3 * N; i++) ok = same_bits(vtu_f64(a, (size_t)i), x[i]);
    for (int i = 0; ok && i < N; i++) ok = same_bits(vtu_f64(h, (size_t)i), v[i]);
    ps_check(ok, "vertices: %d points and a scalar of random bits, bit for bit", N);
    const vtu_array *conn = vtu_find(&f, "Cells", "connectivity");
    const vtu_array *off = vtu_find(&f, "Cells", "offsets");
    const vtu_array *ty = vtu_find(&f, "Cells", "types");
    ok = conn && off && ty && vtu_count(conn) == N && vtu_count(off) == N && vtu_count(ty) == N;
    for (int i = 0; ok && i < N; i++)
      ok = vtu_i64(conn, (size_t)i) == i && vtu_i64(off, (size_t)i) == i + 1 &&
           vtu_i64(ty, (size_t)i) == 1;
    ps_check(ok, "vertices: one VTK_VERTEX (1) cell per point");
    check_xml(&f, "vertices");
  }
  vtu_free(&f);
  remove(path);

  /* no points: a valid empty grid */
  ps_vtu_grid e = {.dim = 2};
  st = ps_vtu_write(path, &e, &ctx);
  r = st == PS_OK ? vtu_read(path, &f, why, sizeof why) : -1;
  ps_check(r == 0 && f.n_point == 0 && f.n_cell == 0 && f.n_array == 4,
           "empty grid: written and read back (%s)", why);
  vtu_free(&f);
  remove(path);
  free(x);
  free(v);
}

/* a copy of the bytes of src with `from` (its first occurrence, in the
 * header) replaced by `to` and the last `cut` bytes dropped, into dst */
static int tamper(const vtu_file *src, const char *dst, const char *from, const char *to,
                  size_t cut) {
  FILE *o = fopen(dst, "wb");
  if (!o) return 0;
  const char *text = (const char *)src->bytes;
  const char *at = from ? strstr(text, from) : NULL;
  size_t n = src->len - cut;
  if (at && (size_t)(at - text) < src->head_len) {
    size_t k = (size_t)(at - text);
    fwrite(text, 1, k, o);
    fputs(to, o);
    fwrite(text + k + strlen(from), 1, n - k - strlen(from), o);
  } else {
    fwrite(text, 1, n, o);
  }
  return fclose(o) == 0;
}

/* the reader is no rubber stamp: each defect of a good file is caught */
static void test_reader_strict(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  double x[6] = {0, 0, 1, 0, 2, 0}, v[3] = {1, 2, 3};
  ps_field pf[1] = {{"damage", 1, v, 1}};
  ps_vtu_grid g = {.dim = 2, .n_point = 3, .x = x, .point_fields = pf, .n_pf = 1};
  vtu_file good, f;
  char why[256] = "";
  int r = ps_vtu_write("t710_good.vtu", &g, &ctx) == PS_OK &&
          vtu_read("t710_good.vtu", &good, why, sizeof why) == 0;
  ps_check(r, "strict reader: a good file reads (%s)", why);
  static const struct {
    const char *from, *to;
    size_t cut;
    const char *what;
  } bad[] = {{"offset=\"32\"", "offset=\"40\"", 0, "an offset moved"},
             {"header_type=\"UInt64\"", "header_type=\"UInt32\"", 0, "UInt32 headers"},
             {"NumberOfPoints=\"3\"", "NumberOfPoints=\"4\"", 0, "a point count"},
             {"</PointData>", "</CellData>", 0, "unbalanced tags"},
             {NULL, NULL, 12, "a truncated file"},
             {NULL, NULL, 40, "a truncated block"}};
  for (size_t k = 0; r && k < sizeof bad / sizeof bad[0]; k++) {
    why[0] = '\0';
    int ok = tamper(&good, "t710_bad_copy.vtu", bad[k].from, bad[k].to, bad[k].cut) &&
             vtu_read("t710_bad_copy.vtu", &f, why, sizeof why) != 0;
    vtu_free(&f);
    ps_check(ok, "strict reader: %s is caught (%s)", bad[k].what, why);
  }
  if (r) vtu_free(&good);
  remove("t710_good.vtu");
  remove("t710_bad_copy.vtu");
}

static void test_bad(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  double x[4] = {0, 0, 1, 0}, v[2] = {1, 2};
  ps_int la[1] = {0}, lb[1] = {2};
  ps_field quote[1] = {{"a\"b", 1, v, 1}}, lt[1] = {{"a<b", 1, v, 1}};
  ps_vtu_grid g = {.dim = 2, .n_point = 2, .x = x, .point_fields = quote, .n_pf = 1};
  ps_check(ps_vtu_write("t710_bad.vtu", &g, &ctx) == PS_ERR_INTERNAL,
           "a field name with a quote is refused (%s)", ctx.msg);
  g.point_fields = lt;
  ps_check(ps_vtu_write("t710_bad.vtu", &g, &ctx) == PS_ERR_INTERNAL,
           "a field name with '<' is refused");
  g.n_pf = 0;
  g.n_line = 1;
  g.la = la;
  g.lb = lb;
  ps_check(ps_vtu_write("t710_bad.vtu", &g, &ctx) == PS_ERR_INTERNAL &&
               strstr(ctx.msg, "out of range"),
           "a line to a point out of range is refused (%s)", ctx.msg);
  ps_check(access("t710_bad.vtu", F_OK) != 0 && access("t710_bad.vtu.tmp", F_OK) != 0,
           "refused: nothing written");
  g.n_line = 0;
  ps_check(ps_vtu_write("no_such_dir_t710/x.vtu", &g, &ctx) == PS_ERR_IO,
           "an unwritable path gives PS_ERR_IO (%s)", ctx.msg);
}

static void test_pvd(void) {
  const char *path = "t710.pvd";
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  double t[3] = {1, 10, 12.5};
  const char *file[3] = {"particles_0001.vtu", "particles_0010.vtu", "particles_0012.vtu"};
  int st = ps_pvd_write(path, 3, t, file, &ctx);
  ps_check(st == PS_OK, "pvd: written (%s)", ctx.msg);
  double rt[8];
  char rf[8][256], why[256] = "";
  int n = pvd_read(path, rt, rf, 8, why, sizeof why);
  int ok = n == 3;
  for (int i = 0; ok && i < 3; i++) ok = same_bits(rt[i], t[i]) && !strcmp(rf[i], file[i]);
  ps_check(ok, "pvd: 3 DataSets read back, times and files in order (%d; %s)", n, why);
  if (have_xmllint())
    ps_check(xmllint_ok(path), "pvd: well-formed (xmllint)");
  st = ps_pvd_write(path, 0, NULL, NULL, &ctx);
  n = pvd_read(path, rt, rf, 8, why, sizeof why);
  ps_check(st == PS_OK && n == 0, "pvd: an empty collection (%d; %s)", n, why);
  const char *bad[1] = {"a b.vtu"};
  ps_check(ps_pvd_write(path, 1, t, bad, &ctx) == PS_ERR_INTERNAL,
           "pvd: a file name with a space is refused (%s)", ctx.msg);
  double nan_t[1] = {NAN};
  ps_check(ps_pvd_write(path, 1, nan_t, file, &ctx) == PS_ERR_INTERNAL,
           "pvd: a time that is not finite is refused");
  remove(path);
}

int main(void) {
  test_lines();
  test_vertices();
  test_reader_strict();
  test_bad();
  test_pvd();
  return ps_check_summary();
}
