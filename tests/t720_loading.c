/* t720_loading.c: loading.boundary beyond constant displacements, and
 * path.steps.
 * (1) Patch test of a displacement field: u = c + G (x - x0) prescribed on
 *     a skin eight spacings wide of a square-lattice box of the elastic
 *     fibre model (exact for homogeneous deformation more than two
 *     horizons plus a spacing inside, t300): the free interior follows the
 *     same field to 1e-12 of its size (round-off), the skin holds it to round-off
 *     (1e-15, closed form). A quadratic (bending) field's prescribed
 *     values match the closed form to round-off. A rigid rotation of a
 *     stretched box (a gradient field, exact at load factor 1) leaves
 *     every arm's tension as it was (1b).
 * (2) path.steps: the load controller's targets from a list, with a cut
 *     between two entries; a run's history.csv load factors are the list.
 * (3) A uniaxial tension box with named supports: the reactions of the
 *     top and bottom rows are equal and opposite to the Newton tolerance
 *     (a free body), the top one is the reaction column (boundary stress
 *     times its length), a free component reports none.
 * (4) The same loading written as 101 entries (one per top particle)
 *     gives the same displacements, bit for bit.
 * (5) Tractions on hex and square boxes: each layer carries the traction
 *     times its edge's length (rows of the hex lattice are sqrt(3)/2 d
 *     apart: a spacing-based layer would carry 0.87 or 1.73 of it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "common.h"

#define TMP "t720_tmp"

static void die_ctx(const char *what, const ps_ctx *ctx) {
  fprintf(stderr, "%s: %s\n", what, ctx->msg);
  exit(1);
}

static void write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f || fputs(text, f) < 0 || fclose(f)) {
    fprintf(stderr, "cannot write %s\n", path);
    exit(1);
  }
}

/* Load text as a case (through a file) and set up its problem. */
static void setup_text(const char *name, const char *text, ps_problem *pb) {
  char path[256];
  ps_ctx ctx;
  ps_case cs;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  snprintf(path, sizeof path, TMP "/%s.yaml", name);
  write_text(path, text);
  if (ps_case_load(&cs, path, &ctx)) die_ctx("case", &ctx);
  if (ps_problem_setup(pb, &cs, &ctx)) die_ctx("setup", &ctx);
  ps_case_free(&cs);
  pb->threads = 1;
}

/* ---- (1) ---- */

static const char *const patch_case =
    "geometry: {type: box, dim: 2, counts: [24, 24], spacing: 1.0e-3, lattice: square,\n"
    "           sizes: eq44}\n"
    "kernel: {alpha: 3.0}\n"
    "material: {E: 210.0e9, nu: 0.3, plane: strain, plastic: false}\n"
    "loading:\n"
    "  type: boundary\n"
    "  boundary:\n"
    "%s"
    "path: {steps: [0.5, 1.0]}\n"
    "output: {fields: false}\n";

/* the field: c + G (x - x0), a strain and a small rotation */
static const double C[2] = {2e-6, -1e-6}, G[2][2] = {{1.0e-3, 4e-4}, {-2e-4, -5e-4}},
                    X0[2] = {0.012, 0.010};

static double affine(int k, const double *x) {
  return C[k] + G[k][0] * (x[0] - X0[0]) + G[k][1] * (x[1] - X0[1]);
}

/* The patch case with u = c + g (x - x0) prescribed on a skin 8 spacings
 * wide, into text[len]. */
static void skin_case(char *text, size_t len, const double c[2], const double g[2][2]) {
  char entries[2048] = "";
  const char *strips[4] = {"{x_max: 0.008}", "{x_min: 0.016}", "{y_max: 0.008}",
                           "{y_min: 0.016}"};
  for (int i = 0; i < 4; i++) {
    size_t n = strlen(entries);
    snprintf(entries + n, sizeof entries - n,
             "    - select: %s\n"
             "      displace:\n"
             "        x: {value: %.17g, gradient: [%.17g, %.17g]}\n"
             "        y: {value: %.17g, gradient: [%.17g, %.17g]}\n"
             "      about: [%.17g, %.17g]\n",
             strips[i], c[0], g[0][0], g[0][1], c[1], g[1][0], g[1][1], X0[0], X0[1]);
  }
  snprintf(text, len, patch_case, entries);
}

static void patch_test(void) {
  char text[4096];
  skin_case(text, sizeof text, C, G);
  ps_problem pb;
  setup_text("patch", text, &pb);
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 1 : 0;
  ps_run_result res;
  ps_solver *s = NULL;
  if (ps_run_keep(&pb, pb.mat.delta, NULL, &res, &s, &ctx)) die_ctx("patch run", &ctx);
  const double *u = ps_solver_u(s);
  double umax = 0, err_free = 0, err_skin = 0;
  ps_int n_free = 0, n_skin = 0;
  for (ps_int a = 0; a < pb.P.n; a++)
    for (int k = 0; k < 2; k++) {
      double want = affine(k, &pb.P.x[2 * a]), e = fabs(u[2 * a + k] - want);
      umax = fmax(umax, fabs(want));
      if (pb.fixed[2 * a + k]) {
        err_skin = fmax(err_skin, e / fabs(want));
        n_skin++;
      } else {
        err_free = fmax(err_free, e);
        n_free++;
      }
    }
  printf("# patch: %lld free and %lld prescribed components; max |u - field| %.3g of "
         "max |u| %.3g (free), prescribed %.3g relative\n",
         (long long)n_free, (long long)n_skin, err_free / umax, umax, err_skin);
  ps_check(n_free == 2 * 64 && n_skin == 2 * (576 - 64),
           "patch: the skin is 8 spacings wide (%lld free components)", (long long)n_free);
  ps_check_le(err_skin, 1e-15, "patch: the skin holds c + G (x - x0) (closed form)");
  ps_check_le(err_free / umax, 1e-12, "patch: the interior follows the field (round-off)");
  ps_check(!strcmp(res.stop_reason, "the last of path.steps = 1 reached: no fracture"),
           "patch: the path ends at the last of path.steps (%s)", res.stop_reason);
  ps_solver_free(s);
  ps_problem_free(&pb);
}

/* The arm tensions at load factor 1 of the skin field u = (F - I)(x - x0)
 * (the patch test's skin, the box's interior free) into T[n_arm]; its
 * largest interior displacement error against the field into *err
 * (relative to the largest displacement). */
static double *skin_field_tensions(const char *name, const double F[2][2], double *err,
                                   ps_int *n_arm) {
  char text[4096];
  const double zero[2] = {0, 0}, g[2][2] = {{F[0][0] - 1, F[0][1]}, {F[1][0], F[1][1] - 1}};
  skin_case(text, sizeof text, zero, g);
  ps_problem pb;
  setup_text(name, text, &pb);
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = getenv("PS_TEST_VERBOSE") ? 1 : 0;
  ps_run_result res;
  ps_solver *s = NULL;
  if (ps_run_keep(&pb, pb.mat.delta, NULL, &res, &s, &ctx)) die_ctx(name, &ctx);
  const double *u = ps_solver_u(s);
  double umax = 0, e = 0;
  for (ps_int a = 0; a < pb.P.n; a++) {
    const double dx = pb.P.x[2 * a] - X0[0], dy = pb.P.x[2 * a + 1] - X0[1];
    const double want[2] = {(F[0][0] - 1) * dx + F[0][1] * dy,
                            F[1][0] * dx + (F[1][1] - 1) * dy};
    for (int k = 0; k < 2; k++) {
      umax = fmax(umax, fabs(want[k]));
      e = fmax(e, fabs(u[2 * a + k] - want[k]));
    }
  }
  *err = e / umax;
  *n_arm = pb.net.n_arm;
  double *T = malloc(sizeof *T * (size_t)pb.net.n_arm);
  memcpy(T, ps_solver_arm_tension(s), sizeof *T * (size_t)pb.net.n_arm);
  ps_solver_free(s);
  ps_problem_free(&pb);
  return T;
}

/* (1b) A rigid rotation adds no arm force: the skin field of a uniform
 * stretch (1 + e) I, and of the same stretch turned by theta, (1 + e) R
 * (a gradient field about x0, exact at load factor 1), give the interior
 * the field (round-off) and every arm the same tension (objectivity of
 * the arm law), to 1e-9 of the largest (lengths of 1e-3 m turned by 0.05
 * rad lose about 1e-13 of their strain of 1e-3 to round-off). A body in a
 * pure rotation is stress-free: its reactions vanish and Newton's
 * relative residual |r_free| / |reactions| has no scale, so the rotation
 * is tested on a stretched box. */
static void rotation_test(void) {
  const double e = 1e-3, th = 0.05, c = cos(th), sn = sin(th);
  const double Fs[2][2] = {{1 + e, 0}, {0, 1 + e}};
  const double Fr[2][2] = {{(1 + e) * c, -(1 + e) * sn}, {(1 + e) * sn, (1 + e) * c}};
  double err_s, err_r;
  ps_int ns, nr;
  double *Ts = skin_field_tensions("stretch", Fs, &err_s, &ns);
  double *Tr = skin_field_tensions("rotation", Fr, &err_r, &nr);
  double tmax = 0, dmax = 0;
  for (ps_int i = 0; i < ns && ns == nr; i++) {
    tmax = fmax(tmax, fabs(Ts[i]));
    dmax = fmax(dmax, fabs(Tr[i] - Ts[i]));
  }
  printf("# rotation by %g rad of a stretch of %g: interior errors %.3g, %.3g; max |T| %.4g N, "
         "max |T_rotated - T| %.3g N\n", th, e, err_s, err_r, tmax, dmax);
  ps_check_le(err_r, 1e-12, "rotation: the interior turns with the skin (round-off)");
  ps_check(ns == nr && tmax > 0 && dmax <= 1e-9 * tmax,
           "rotation: every arm's tension is the unturned stretch's (max difference %.3g N "
           "of %.3g N)", dmax, tmax);
  free(Ts);
  free(Tr);
}

/* a bending field, u_x = -k (x-x0)(y-y0), u_y = k (x-x0)^2 / 2, with a
 * value and gradient on top: the prescribed values in closed form */
static void bending_values(void) {
  const double k = 0.5, x0 = 0.012, y0 = 0.004;
  char text[4096], entries[1024];
  snprintf(entries, sizeof entries,
           "    - select: {y_max: 0.003}\n"
           "      fix: [x, y]\n"
           "    - select: {y_min: 0.021}\n"
           "      displace:\n"
           "        x: {value: 1e-6, gradient: [0, 2e-4], hessian: [[0, %g], [%g, 0]]}\n"
           "        y: {hessian: [[%g, 0], [0, 0]]}\n"
           "      about: [%g, %g]\n",
           -k, -k, k, x0, y0);
  snprintf(text, sizeof text, patch_case, entries);
  ps_problem pb;
  setup_text("bending", text, &pb);
  double err = 0;
  ps_int n = 0;
  for (ps_int a = 0; a < pb.P.n; a++) {
    const double *x = &pb.P.x[2 * a];
    if (x[1] < 0.021) continue;
    double dx = x[0] - x0, dy = x[1] - y0;
    double ux = 1e-6 + 2e-4 * dy - k * dx * dy, uy = 0.5 * k * dx * dx;
    err = fmax(err, fabs(pb.ubar[2 * a] - ux) / fabs(ux));
    if (uy != 0) err = fmax(err, fabs(pb.ubar[2 * a + 1] - uy) / fabs(uy));
    n += pb.fixed[2 * a] && pb.fixed[2 * a + 1];
  }
  ps_check(n == 3 * 24, "bending: the top three rows are prescribed (%lld)", (long long)n);
  ps_check_le(err, 1e-14, "bending: prescribed values = closed form (relative)");
  ps_problem_free(&pb);
}

/* ---- (2) ---- */

static void steps_controller(void) {
  double list[4] = {0.1, 0.25, 0.5, 1.0};
  ps_path_opts o;
  ps_path_opts_default(&o);
  o.steps = list;
  o.n_steps = 4;
  o.max_load = 1.0;
  const ps_step_control_type *t = ps_step_control_load;
  void *st = calloc(1, t->size);
  t->init(st, &o);
  /* accepted, accepted, a cut between 0.1 and 0.25, then back up */
  double want[] = {0.1, 0.25, 0.175, 0.25, 0.4, 0.5, 1.0}, got[7];
  double lambda = 0.0;
  got[0] = lambda = t->target(st, lambda, &o);
  t->accept(st, 0, &o);
  got[1] = t->target(st, lambda, &o);
  double dl = t->cut(st, &o);
  got[2] = lambda = t->target(st, lambda, &o);
  t->accept(st, 0, &o);
  got[3] = lambda = t->target(st, lambda, &o);
  t->accept(st, 0, &o); /* two in a row: the increment doubles, 0.15 */
  for (int i = 4; i < 7; i++) {
    got[i] = lambda = t->target(st, lambda, &o);
    t->accept(st, 0, &o);
  }
  int ok = dl == 0.075;
  for (int i = 0; i < 7; i++) ok &= fabs(got[i] - want[i]) <= 1e-15;
  ps_check(ok, "path.steps: targets %g %g (cut to %g) %g %g %g %g %g", got[0], got[1], dl,
           got[2], got[3], got[4], got[5], got[6]);
  ps_check(got[0] == 0.1 && got[1] == 0.25 && got[3] == 0.25 && got[5] == 0.5 &&
               got[6] == 1.0,
           "path.steps: the entries are hit exactly");
  free(st);
}

/* ---- history.csv ---- */

typedef struct table {
  int n_col, n_row;
  char col[64][64];
  double v[64][64]; /* [row][col] */
} table;

static void read_table(const char *path, table *t) {
  FILE *f = fopen(path, "r");
  char line[8192];
  memset(t, 0, sizeof *t);
  if (!f || !fgets(line, sizeof line, f)) {
    fprintf(stderr, "cannot read %s\n", path);
    exit(1);
  }
  for (char *tok = strtok(line, ",\n"); tok && t->n_col < 64; tok = strtok(NULL, ",\n"))
    snprintf(t->col[t->n_col++], sizeof t->col[0], "%s", tok);
  while (t->n_row < 64 && fgets(line, sizeof line, f)) {
    int c = 0;
    for (char *tok = strtok(line, ",\n"); tok && c < 64; tok = strtok(NULL, ",\n"))
      t->v[t->n_row][c++] = strtod(tok, NULL);
    t->n_row++;
  }
  fclose(f);
}

static int column(const table *t, const char *name) {
  for (int c = 0; c < t->n_col; c++)
    if (!strcmp(t->col[c], name)) return c;
  ps_check(0, "history.csv has a column %s", name);
  return 0;
}

/* ---- (3), (4) ---- */

static const char *const tension_case =
    "geometry: {type: box, dim: 2, counts: [100, 8], spacing: 1.0e-3, lattice: square}\n"
    "kernel: {alpha: 3.0}\n"
    "material: {E: 210.0e9, nu: 0.3, plane: strain, plastic: false}\n"
    "loading:\n"
    "  type: boundary\n"
    "  stress_length: 0.1\n"
    "  boundary:\n"
    "    - select: {y_max: 0.001}\n"
    "      fix: [x, y]\n"
    "%s"
    "%s"
    "path: {steps: [0.1, 0.25, 0.5, 1.0]}\n"
    "output: {fields: false}\n";

static void tension(void) {
  char text[32768], top[20000] = "";
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ctx.verbosity = 0;
  ps_run_result res;
  /* (3) two named entries */
  snprintf(text, sizeof text, tension_case, "      name: bottom\n",
           "    - select: {y_min: 0.007}\n"
           "      displace: {y: 2.0e-6}\n"
           "      measure: true\n"
           "      name: top\n");
  ps_problem pa, pm;
  setup_text("tension", text, &pa);
  ps_solver *sa = NULL, *sm = NULL;
  if (ps_run_keep(&pa, pa.mat.delta, TMP "/tension", &res, &sa, &ctx))
    die_ctx("tension run", &ctx);
  table t;
  read_table(TMP "/tension/history.csv", &t);
  const double list[4] = {0.1, 0.25, 0.5, 1.0};
  int lf = column(&t, "load_factor"), ok = t.n_row == 4;
  for (int i = 0; ok && i < 4; i++) ok = t.v[i][lf] == list[i];
  ps_check(ok, "history.csv load_factor is path.steps exactly (%d rows)", t.n_row);
  int rc = column(&t, "reaction"), tx = column(&t, "reaction_top_x"),
      ty = column(&t, "reaction_top_y"), bx = column(&t, "reaction_bottom_x"),
      by = column(&t, "reaction_bottom_y");
  double worst_pair = 0, worst_col = 0, worst_x = 0, top_x = 0;
  for (int i = 0; i < t.n_row; i++) {
    const double *r = t.v[i];
    worst_pair = fmax(worst_pair, fabs(r[ty] + r[by]) / fabs(r[ty]));
    worst_col = fmax(worst_col, fabs(r[ty] - r[rc]) / fabs(r[rc]));
    worst_x = fmax(worst_x, fabs(r[bx]) / fabs(r[by]));
    top_x = fmax(top_x, fabs(r[tx]));
  }
  printf("# tension: reaction_top_y %.10g N/m at load factor 1 (reaction column %.10g); "
         "|top + bottom| / top %.2g, |bottom_x| / |bottom_y| %.2g\n",
         t.v[3][ty], t.v[3][rc], worst_pair, worst_x);
  ps_check(t.v[3][ty] > 0 && t.v[3][by] < 0, "tension: top pulled up, bottom held down");
  ps_check_le(worst_pair, 1e-7, "free body: top and bottom reactions equal and opposite");
  ps_check_le(worst_col, 2e-9, "reaction_top_y = boundary stress x stress_length");
  ps_check_le(worst_x, 1e-7, "the bottom's x reaction vanishes (no load along x)");
  ps_check(top_x == 0, "the top's free x components report no reaction");

  /* (4) the top row as 100 entries of one particle each */
  for (int i = 0; i < 100; i++) {
    size_t n = strlen(top);
    snprintf(top + n, sizeof top - n,
             "    - select: {x_min: %.17g, x_max: %.17g, y_min: 0.007}\n"
             "      displace: {y: 2.0e-6}\n"
             "      measure: true\n",
             i * 1e-3, (i + 1) * 1e-3);
  }
  snprintf(text, sizeof text, tension_case, "", top);
  setup_text("tension_many", text, &pm);
  ps_check(pm.cs.n_bc == 101, "101 boundary entries accepted (%d)", pm.cs.n_bc);
  if (ps_run_keep(&pm, pm.mat.delta, TMP "/tension_many", &res, &sm, &ctx))
    die_ctx("tension run (101 entries)", &ctx);
  ps_int same = pa.P.n == pm.P.n;
  const double *ua = ps_solver_u(sa), *um = ps_solver_u(sm);
  for (ps_int j = 0; same && j < 2 * pa.P.n; j++)
    same = ua[j] == um[j] && pa.fixed[j] == pm.fixed[j] && pa.ubar[j] == pm.ubar[j];
  ps_check(same, "101 entries: the same supports and displacements, bit for bit");
  table t2;
  read_table(TMP "/tension_many/history.csv", &t2);
  int wall = column(&t, "wall_s");
  same = t2.n_row == t.n_row && t2.n_col == t.n_col - 4;
  for (int i = 0; same && i < t.n_row; i++)
    for (int c = 0; c < t2.n_col; c++)
      if (c != wall) same &= t.v[i][c] == t2.v[i][c];
  ps_check(same, "101 entries: history.csv as with two (but wall_s and the named reactions)");
  /* the fingerprint: path.steps and fields enter it, names do not */
  ps_case c;
  if (ps_case_copy(&c, &pa.cs, &ctx)) die_ctx("case copy", &ctx);
  uint64_t f0 = ps_case_fingerprint(&pa.cs);
  snprintf(c.bc[0].name, sizeof c.bc[0].name, "base");
  int fp_ok = ps_case_fingerprint(&c) == f0;
  c.path.steps[1] = 0.3;
  fp_ok &= ps_case_fingerprint(&c) != f0;
  c.path.steps[1] = 0.25;
  fp_ok &= ps_case_fingerprint(&c) == f0;
  c.bc[1].gradient_n[1] = 2;
  c.bc[1].gradient[1][0] = 1e-4;
  fp_ok &= ps_case_fingerprint(&c) != f0;
  ps_check(fp_ok && pa.cs.path.steps[1] == 0.25 && !strcmp(pa.cs.bc[0].name, "bottom"),
           "fingerprint: path.steps and fields change it, names do not; a copy is its own");
  ps_case_free(&c);
  ps_solver_free(sa);
  ps_solver_free(sm);
  ps_problem_free(&pa);
  ps_problem_free(&pm);
}

/* ---- (5) ---- */

/* sum of fext's component k over all particles */
static double fext_sum(const ps_problem *pb, int k) {
  double sum = 0;
  for (ps_int a = 0; a < pb->P.n; a++) sum += pb->fext[a * pb->P.dim + k];
  return sum;
}

/* A traction is a force per length of edge, whatever the lattice: on a
 * hex box (rows dy = sqrt(3)/2 d apart, d between a row's particles)
 * the top layer (one row, or two when the selection is a spacing thick)
 * must carry t_y times the width counts[0] d, the right layer (one or
 * two particles a row, above the bottom grip) t_x times the height of
 * the rows it holds, dy each; on a square box as before, t times the
 * edge's particles d. Exact up to round-off (1e-12). */
static void hex_traction(void) {
  const double d = 1.0e-3, dy = d * sqrt(3.0) / 2.0, ty = 1.0e6, tx = 2.0e6;
  const struct {
    const char *lattice;
    double jitter, top, right; /* selection widths in spacings */
  } runs[] = {{"hex", 0.0, 1.0, 1.0}, {"hex", 0.0, 0.5, 0.6}, {"hex", 0.1, 1.0, 1.0},
              {"square", 0.0, 0.5, 0.5}};
  for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
    int hex = !strcmp(runs[r].lattice, "hex");
    double h = hex ? dy : d, width = 20 * d;
    double xmax = hex ? 20.0 * d : 19.5 * d, ymax = 11.5 * h;
    char text[2048];
    snprintf(text, sizeof text,
             "geometry: {type: box, dim: 2, counts: [20, 12], spacing: 1.0e-3, lattice: %s, "
             "jitter: %g, seed: 3}\n"
             "material: {model: bond, E: 72.0e9, nu: 0.3333333333333333, plane: stress, "
             "horizon_factor: 3.015, plastic: false}\n"
             "loading:\n  type: boundary\n  boundary:\n"
             "    - select: {y_max: %.17g}\n      fix: [x, y]\n"
             "    - select: {y_min: %.17g}\n      traction: {y: %g}\n"
             "    - select: {x_min: %.17g, y_min: %.17g}\n      traction: {x: %g}\n",
             runs[r].lattice, runs[r].jitter, h, ymax - runs[r].top * d - 0.3 * runs[r].jitter * d,
             ty, xmax - runs[r].right * d - 0.3 * runs[r].jitter * d, 1.5 * h, tx);
    ps_problem pb;
    setup_text("traction", text, &pb);
    /* the right layer starts above the bottom grip's rows: its height is
     * that of the rows it holds */
    double fy = fext_sum(&pb, 1), fx = fext_sum(&pb, 0), rows = 0;
    unsigned char seen[12] = {0};
    for (ps_int a = 0; a < pb.P.n; a++)
      if (pb.fext[2 * a] != 0.0) {
        long j = lround(pb.P.x[2 * a + 1] / h - 0.5);
        if (j >= 0 && j < 12 && !seen[j]) rows += (seen[j] = 1);
      }
    double ey = fabs(fy - ty * width) / (ty * width), ex = fabs(fx - tx * rows * h) / (tx * rows * h);
    ps_check(ey <= 1e-12,
             "traction on the top layer (%s lattice, jitter %g, %g spacing(s) deep): "
             "force / (t_y width) - 1 = %.2g", runs[r].lattice, runs[r].jitter, runs[r].top, ey);
    ps_check(rows >= 8 && ex <= 1e-12,
             "traction on the right layer (%s lattice, jitter %g, %g spacing(s) deep): "
             "force / (t_x x its %g rows' height) - 1 = %.2g", runs[r].lattice, runs[r].jitter,
             runs[r].right, rows, ex);
    ps_problem_free(&pb);
  }
}

int main(void) {
  mkdir(TMP, 0777);
  patch_test();
  rotation_test();
  bending_values();
  steps_controller();
  tension();
  hex_traction();
  return ps_check_summary();
}
