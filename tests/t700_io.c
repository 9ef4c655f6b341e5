/* t700_io.c: case files and point clouds. Valid inputs under
 * tests/data/io load with the right values; each bad input fails with
 * PS_ERR_INPUT (PS_ERR_IO for a missing file) and a message naming the
 * file, the line and the parameter. The field files: t710_vtu.c. */
#include "check.h"
#include "io/ps_io.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#ifndef PS_TEST_DATA
#error "PS_TEST_DATA must name the tests/data directory"
#endif

#define DATA(f) PS_TEST_DATA "/io/" f

/* Does the message contain every one of the (NULL-terminated) parts? */
static int has_all(const char *msg, const char *const *parts) {
  for (int i = 0; parts[i]; i++)
    if (!strstr(msg, parts[i])) return 0;
  return 1;
}

/* Load a case that must fail with `want`; the message must contain
 * "file:line:" (line > 0) and every one of the parts. */
static void bad_case(const char *file, int want, int line, const char *const *parts) {
  ps_ctx ctx;
  ps_case cs;
  char path[1024], at[256];
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  snprintf(path, sizeof path, "%s/io/%s", PS_TEST_DATA, file);
  int s = ps_case_load(&cs, path, &ctx);
  if (line > 0)
    snprintf(at, sizeof at, "%s:%d: ", file, line);
  else
    snprintf(at, sizeof at, "%s: ", file);
  ps_check(s == want, "%s: status %d (want %d)", file, s, want);
  ps_check(strstr(ctx.msg, at) && has_all(ctx.msg, parts), "%s: message \"%s\" has \"%s\"",
           file, ctx.msg, at);
  ps_check(cs.alpha == 5.1 && !strcmp(cs.name, "case"),
           "%s: a failed load leaves the case unchanged", file);
}

/* Read a cloud that must fail with PS_ERR_INPUT at `line`. */
static void bad_cloud(const char *file, int dim, int line, const char *const *parts) {
  ps_ctx ctx;
  ps_particles p;
  char path[1024], at[256];
  ps_ctx_init(&ctx);
  snprintf(path, sizeof path, "%s/io/%s", PS_TEST_DATA, file);
  int s = ps_cloud_read(&p, path, dim, &ctx);
  if (line > 0)
    snprintf(at, sizeof at, "%s:%d: ", file, line);
  else
    snprintf(at, sizeof at, "%s: ", file);
  ps_check(s == PS_ERR_INPUT, "%s: status %d (want PS_ERR_INPUT)", file, s);
  ps_check(strstr(ctx.msg, at) && has_all(ctx.msg, parts), "%s: message \"%s\" has \"%s\"",
           file, ctx.msg, at);
  ps_check(p.x == NULL && p.n == 0, "%s: nothing allocated on failure", file);
  ps_particles_free(&p);
}

static void test_defaults(void) {
  ps_case cs;
  ps_case_defaults(&cs);
  ps_check(cs.geometry == PS_GEOM_DISK && cs.dim == 2 && cs.load_type == PS_LOAD_EQ116,
           "defaults: disk, 2D, eq116");
  ps_check(isnan(cs.mat.delta) && cs.delta_over_c == 1e-3, "defaults: delta unset, c/1000");
  ps_check(cs.sweep.n == 12, "defaults: 12 sweep values");
  ps_check(cs.solver.cg_forcing_adaptive == 1 && cs.solver.cg_forcing == 100 &&
               cs.solver.cg_forcing_max == 0.5,
           "defaults: adaptive CG forcing, at most 0.5 (the fixed rule's number 100)");
  ps_check_rel(cs.sweep.delta_over_c[11], 1.0 / 3250, 1e-15, "defaults: last sweep 1/3250");
  ps_check(!strcmp(cs.solver.linear, "cholmod") && cs.output.dir[0] == '\0' &&
               cs.output.vtk_every == 10,
           "defaults: cholmod, output.dir empty, vtk_every 10");
  /* the option structs hold their modules' defaults, set nowhere else */
  ps_solver_opts so;
  ps_path_opts po;
  ps_output_opts oo;
  ps_sweep_opts wo;
  memset(&so, 0, sizeof so);
  memset(&po, 0, sizeof po);
  memset(&oo, 0, sizeof oo);
  ps_solver_opts_default(&so);
  ps_path_opts_default(&po);
  ps_output_opts_default(&oo);
  ps_sweep_opts_default(&wo);
  ps_check(!memcmp(&cs.solver, &so, sizeof so) && !memcmp(&cs.path, &po, sizeof po) &&
               !memcmp(&cs.output, &oo, sizeof oo) && !memcmp(&cs.sweep, &wo, sizeof wo),
           "defaults: cs.solver, path, output, sweep are their *_opts_default");
  ps_check(cs.path.load_step == 0.02 && cs.path.max_increments == 2000 &&
               cs.path.stop_tip_advance == 0 && cs.solver.tolerance == 1e-8 &&
               cs.output.verbosity == 1 && cs.max_memory_gib == 0,
           "defaults: load_step 0.02, 2000 increments, tolerance 1e-8, verbosity 1");
}

static void test_full(void) {
  ps_ctx ctx;
  ps_case cs;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  int s = ps_case_load(&cs, DATA("full.yaml"), &ctx);
  ps_check(s == PS_OK, "full.yaml loads (status %d: %s)", s, ctx.msg);
  if (s != PS_OK) return;
  ps_check(!strcmp(cs.name, "plate_test"), "full: name (%s)", cs.name);
  ps_check(!strcmp(cs.file, DATA("full.yaml")) && !strcmp(cs.dir, PS_TEST_DATA "/io"),
           "full: path and dir (%s)", cs.dir);
  ps_check(cs.geometry == PS_GEOM_BOX && cs.dim == 2, "full: box, 2D");
  ps_check(cs.counts[0] == 30 && cs.counts[1] == 10 && cs.counts[2] == 1,
           "full: counts 30 x 10 (x 1)");
  ps_check_rel(cs.spacing, 2e-3, 0, "full: spacing");
  ps_check(!strcmp(cs.lattice, "hex"), "full: lattice hex");
  ps_check_rel(cs.jitter, 0.1, 0, "full: jitter");
  ps_check(cs.seed == 42 && cs.disk.seed == 42, "full: seed 42");
  ps_check(cs.size_rule == PS_SIZE_EQ44 && cs.size_neighbours == 6, "full: sizes");
  ps_check(cs.n_cracks == 2, "full: 2 cracks (got %d)", cs.n_cracks);
  ps_check(cs.cracks[0].p0[0] == 0.01 && cs.cracks[0].p1[1] == 0.005 &&
               cs.cracks[1].p0[1] == 0.01 && cs.cracks[1].p1[0] == 0.03,
           "full: crack end points");
  ps_check_rel(cs.alpha, 4.0, 0, "full: kernel.alpha");
  ps_check(cs.kernel_k == 3, "full: kernel.k");
  ps_check_rel(cs.mat.E, 70e9, 0, "full: material.E");
  ps_check_rel(cs.mat.nu, 0.25, 0, "full: material.nu");
  ps_check(cs.mat.plane == PS_PLANE_STRESS && cs.mat.plastic == 0 &&
               cs.mat.yield_rule == PS_YIELD_DEVIATORIC,
           "full: plane stress, elastic, deviatoric");
  ps_check_rel(cs.mat.yield_strain, 0.003, 0, "full: yield_strain");
  ps_check_rel(cs.mat.delta, 2.5e-6, 0, "full: material.delta");
  ps_check(cs.delta_over_c == 0, "full: delta given -> delta_over_c = 0");
  ps_check_rel(cs.mat.rho, 2700, 0, "full: rho");
  ps_check(cs.load_type == PS_LOAD_BOUNDARY && cs.n_bc == 3, "full: 3 boundary entries");
  ps_check_rel(cs.stress_length, 0.02, 0, "full: stress_length");
  const ps_bc *b = cs.bc;
  ps_check(b[0].line == 33 && b[1].line == 35 && b[2].line == 38,
           "full: entry lines 33, 35, 38 (got %d, %d, %d)", b[0].line, b[1].line, b[2].line);
  ps_check(b[0].sel.hi[0] == 0.001 && isinf(b[0].sel.lo[0]) && b[0].sel.lo[0] < 0 &&
               isinf(b[0].sel.hi[1]) && b[0].sel.block == -1,
           "full: entry 1 select x_max only");
  ps_check(b[0].fix[0] == 1 && b[0].fix[1] == 0 && !b[0].displace_set[0] && !b[0].measure,
           "full: entry 1 fixes x");
  ps_check(b[1].sel.lo[0] == 0.059 && b[1].sel.lo[1] == -1 && b[1].sel.hi[1] == 1,
           "full: entry 2 select");
  ps_check(b[1].displace_set[0] && b[1].displace[0] == 1e-5 && !b[1].displace_set[1] &&
               b[1].measure,
           "full: entry 2 displaces x by 1e-5 and measures");
  ps_check(b[2].sel.block == 2 && b[2].fix[1] && !b[2].fix[0], "full: entry 3 block 2");
  ps_check(!strcmp(cs.solver.linear, "umfpack") && cs.solver.max_iterations == 50 &&
               !cs.solver.line_search,
           "full: solver");
  ps_check_rel(cs.solver.tolerance, 1e-10, 0, "full: tolerance");
  ps_check(!cs.solver.cg_forcing_adaptive && cs.solver.cg_forcing == 50 &&
               cs.solver.cg_forcing_max == 0.25,
           "full: cg_forcing 50 (the fixed rule), cg_forcing_max 0.25");
  ps_check(cs.path.load_step == 0.01 && cs.path.load_step_after_break == 0.001 &&
               cs.path.max_load == 2 && cs.path.max_increments == 100 && cs.path.min_step == 1e-7 &&
               cs.path.stop_crack_tip == 5 && cs.path.stop_load_drop == 0 &&
               cs.path.max_break_rounds == 20,
           "full: path");
  ps_check(!strcmp(cs.output.dir, "out/test_plate") && cs.output.vtk_every == 0 &&
               cs.output.verbosity == 2,
           "full: output");
  ps_check(cs.sweep.n == 12, "full: 12 griffith values (got %d)", cs.sweep.n);
  int ok = cs.sweep.n == 12;
  for (int i = 0; ok && i < 12; i++)
    ok = fabs(cs.sweep.delta_over_c[i] - 1.0 / (500 + 250 * i)) <= 1e-15 / (500 + 250 * i);
  ps_check(ok, "full: griffith delta/c = 1/500, 1/750, ..., 1/3250");
  ps_case_free(&cs);
}

static void test_cloud_case(void) {
  ps_ctx ctx;
  ps_case cs;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  int s = ps_case_load(&cs, DATA("cloud3d.yml"), &ctx);
  ps_check(s == PS_OK, "cloud3d.yml loads (status %d: %s)", s, ctx.msg);
  if (s != PS_OK) return;
  ps_check(!strcmp(cs.name, "cloud3d"), "cloud3d: name from the file (%s)", cs.name);
  ps_check(cs.geometry == PS_GEOM_CLOUD && cs.dim == 3, "cloud3d: cloud, 3D");
  ps_check(!strcmp(cs.cloud_file, DATA("cloud3d.txt")), "cloud3d: file resolved (%s)",
           cs.cloud_file);
  ps_check(cs.n_bc == 2 && cs.bc[0].displace_set[2] && cs.bc[0].displace[2] == -1e-6 &&
               cs.bc[0].displace_set[0] && cs.bc[0].displace[0] == 0 &&
               cs.bc[0].sel.lo[2] == 0.5 && cs.bc[1].fix[2],
           "cloud3d: z components accepted (dim given later)");
  ps_check(cs.mat.delta == 2e-3 && cs.delta_over_c == 0.0, "cloud3d: delta in metres");
  ps_check(cs.sweep.n == 3 && cs.sweep.delta_over_c[2] == 4e-3, "cloud3d: sweep list");

  ps_particles p;
  s = ps_cloud_read(&p, cs.cloud_file, 3, &ctx);
  ps_check(s == PS_OK && p.n == 3 && p.dim == 3, "cloud3d.txt: 3 particles (%s)", ctx.msg);
  if (s == PS_OK)
    ps_check(p.x[5] == 1e-3 && p.volume[2] == 2e-9 && p.block[1] == 3 && p.block[2] == 0,
             "cloud3d.txt: coordinates, volume, block");
  ps_particles_free(&p);
  ps_case_free(&cs);
}

static void test_cloud2d(void) {
  ps_ctx ctx;
  ps_particles p;
  ps_ctx_init(&ctx);
  int s = ps_cloud_read(&p, DATA("cloud2d.txt"), 2, &ctx);
  ps_check(s == PS_OK && p.n == 4 && p.dim == 2, "cloud2d.txt: 4 particles (%s)", ctx.msg);
  if (s == PS_OK) {
    ps_check(p.x[2] == 0.001 && p.x[3] == 0.0 && p.x[5] == 0.001 && p.x[6] == 0.001,
             "cloud2d.txt: coordinates");
    ps_check(p.volume[3] == 1.5e-6 && p.h[0] == 0, "cloud2d.txt: volumes, h unset");
    ps_check(p.block[0] == 0 && p.block[1] == 1 && p.block[2] == 2 && p.block[3] == 0,
             "cloud2d.txt: blocks 0 1 2 0");
  }
  ps_particles_free(&p);
}

static void test_bad_cases(void) {
  ps_ctx ctx;
  ps_case cs;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  int s = ps_case_load(&cs, DATA("no_such_case.yaml"), &ctx);
  ps_check(s == PS_ERR_IO && strstr(ctx.msg, "no_such_case.yaml: cannot open"),
           "missing file: PS_ERR_IO (%s)", ctx.msg);

  bad_case("bad_syntax.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"YAML syntax error", "line 3", NULL});
  bad_case("bad_unknown_top.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"unknown key 'materail'", "material", NULL});
  bad_case("bad_unknown_nested.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"unknown key 'material.Young'", "E", NULL});
  bad_case("bad_E.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"material.E must be > 0 (got -3e9)", NULL});
  bad_case("bad_alpha0.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"kernel.alpha must be > 0", "(got 0)", NULL});
  bad_case("bad_alpha_neg.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"kernel.alpha must be > 0", "(got -1)", NULL});
  bad_case("bad_delta_over_c_box.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"material.delta_over_c needs geometry.type disk", NULL});
  bad_case("bad_nu.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"material.nu", "(-1, 0.5)", "0.5", NULL});
  bad_case("bad_number.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"material.E must be a decimal number (got '2e11x')", NULL});
  bad_case("bad_dup.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"kernel.alpha", "twice", "line 2", NULL});
  bad_case("bad_bc_nofix.yaml", PS_ERR_INPUT, 7,
           (const char *const[]){"loading.boundary", "no fix, displace or traction", NULL});
  bad_case("bad_bc_both.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"loading.boundary", "both fixed and displaced", NULL});
  bad_case("bad_bc_empty_select.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"select", "matches everything", NULL});
  bad_case("bad_no_supports.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"loading.boundary is empty", "no supports", NULL});
  bad_case("bad_z_2d.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"loading.boundary entry 1", "z", "dim is 2", NULL});
  bad_case("bad_eq116_box.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"eq116", "geometry.type disk", NULL});
  bad_case("bad_dim_disk.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"geometry.dim must be 2", "disk", NULL});
  bad_case("bad_counts.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"geometry.counts", "geometry.dim is 3", NULL});
  bad_case("bad_bc_traction.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"entry 1", "traction and a prescribed displacement", NULL});
  bad_case("bad_hole.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"geometry.holes", "[cx, cy, R]", NULL});
  bad_case("bad_j.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"output.j_integral needs both tip", NULL});
  bad_case("bad_small_steps.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.max_small_steps", NULL});
  bad_case("bad_cg_forcing.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.cg_forcing must be adaptive or a number >= 0",
                                 "(got fast)", NULL});
  bad_case("bad_cg_forcing_neg.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.cg_forcing must be adaptive or a number >= 0",
                                 "(got -1)", NULL});
  bad_case("bad_cg_forcing_max.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.cg_forcing_max must be", "(got 1.5)", NULL});
  bad_case("bad_griffith.yaml", PS_ERR_INPUT, 2,
           (const char *const[]){"griffith.denominators", "step", NULL});
}

static void test_bad_clouds(void) {
  bad_cloud("bad_cloud_nan.txt", 2, 3,
            (const char *const[]){"x y volume [block]", "y (field 2",
                                  "is not a finite decimal number (got 'abc')", NULL});
  bad_cloud("bad_cloud_fields.txt", 2, 2,
            (const char *const[]){"x y volume [block]", "5 fields", "0 1e-3 1e-6 1 7", NULL});
  bad_cloud("bad_cloud_volume.txt", 2, 4,
            (const char *const[]){"volume must be > 0", "(got 0)", NULL});
  bad_cloud("bad_cloud_volume_neg.txt", 2, 2,
            (const char *const[]){"volume must be > 0", "(got -1e-6)", NULL});
  bad_cloud("bad_cloud_block.txt", 2, 1, (const char *const[]){"block", "'1.5'", NULL});
  bad_cloud("bad_cloud_empty.txt", 2, 0, (const char *const[]){"no particles", NULL});
  /* a 2D cloud read as 3D: "0 0 1e-6" has too few fields */
  bad_cloud("cloud2d.txt", 3, 2, (const char *const[]){"x y z volume [block]", NULL});

  ps_ctx ctx;
  ps_particles p;
  ps_ctx_init(&ctx);
  int s = ps_cloud_read(&p, DATA("no_such_cloud.txt"), 2, &ctx);
  ps_check(s == PS_ERR_IO && strstr(ctx.msg, "no_such_cloud.txt: cannot open"),
           "missing cloud: PS_ERR_IO (%s)", ctx.msg);
}

/* Issue 23: numbers and integers are plain decimal and in range;
 * geometry keys of another type, kernel and material values that broke a
 * computation downstream, and the bond model's nu are refused at load,
 * each naming file, line and key. */
static void test_bad_values(void) {
  bad_case("bad_hex.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"material.E must be a decimal number (got '0x10')", NULL});
  bad_case("bad_blank_number.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"material.E must be a decimal number (got ' 5.1')", NULL});
  bad_case("bad_inf.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"kernel.alpha must be a decimal number (got '.inf')", NULL});
  bad_case("bad_nan.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"path.max_load must be a decimal number (got 'nan')", NULL});
  bad_case("bad_overflow.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"material.E must be a finite decimal number (got '1e400'",
                                 NULL});
  bad_case("bad_octal.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.max_iterations must be a decimal integer (got '010')",
                                 NULL});
  bad_case("bad_int_range.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.max_iterations must be an integer in 1..2147483647",
                                 "(got 2147483648)", NULL});
  bad_case("bad_long_range.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"geometry.seed must be an integer in 0..", NULL});
  bad_case("bad_counts_range.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"geometry.counts must be an integer in 1..2147483647",
                                 NULL});
  bad_case("bad_counts_total.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"geometry.counts asks for 2.2e+12 particles", NULL});
  bad_case("bad_key_file_disk.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"geometry.file does not apply to geometry.type disk (it is "
                                 "for types cloud and mesh)", NULL});
  bad_case("bad_key_counts_cloud.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"geometry.counts does not apply to geometry.type cloud", NULL});
  bad_case("bad_key_disk_box.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"geometry.n_xi does not apply to geometry.type box (it is "
                                 "for type disk)", NULL});
  /* the first key in the file that does not apply */
  bad_case("bad_key_jitter_cloud.yaml", PS_ERR_INPUT, 5,
           (const char *const[]){"geometry.origin does not apply", NULL});
  bad_case("bad_key_spacing_disk.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"geometry.spacing does not apply to geometry.type disk, the "
                                 "default", NULL});
  bad_case("bad_alpha_big.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"kernel.alpha must be in [0.001, 1000] (got 1.0e155)", NULL});
  bad_case("bad_k_big.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"kernel.k must be an integer in 1..16 (got 2147483647)", NULL});
  bad_case("bad_E_huge.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"material.E must be in [1e-20, 1e+20] (got 1.0e300)", NULL});
  bad_case("bad_yield_strain.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"material.yield_strain must be in [1e-09, 1] (got 2)", NULL});
  bad_case("bad_bond_nu.yaml", PS_ERR_INPUT, 0,
           (const char *const[]){"material.nu = 0.3: bond-based peridynamics has nu = 1/4 in "
                                 "plane strain", "(material.nu is at line 6)", NULL});
  bad_case("bad_memory.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"solver.max_memory_gib must be in (0, ", "(got 0)", NULL});
  bad_case("bad_utf8.yaml", PS_ERR_INPUT, 3,
           (const char *const[]){"YAML read error: invalid leading UTF-8 octet", NULL});
  bad_case("bad_nul.yaml", PS_ERR_INPUT, 4,
           (const char *const[]){"YAML read error: control characters", NULL});

  /* solver.max_memory_gib is read, and is not part of the fingerprint */
  ps_ctx ctx;
  ps_case cs, ref;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  ps_case_defaults(&ref);
  int s = ps_case_load(&cs, DATA("memory.yaml"), &ctx);
  ps_check(s == PS_OK && cs.max_memory_gib == 2.5, "memory.yaml: max_memory_gib 2.5 (%s)",
           ctx.msg);
  ps_check(ps_case_fingerprint(&cs) == ps_case_fingerprint(&ref),
           "memory.yaml: max_memory_gib leaves the fingerprint as it was");
  ps_case_free(&cs);
}

/* Write `n` copies of `unit` and then `tail` into path. */
static void write_repeated(const char *path, const char *unit, long n, const char *tail) {
  FILE *f = fopen(path, "w");
  if (!f) return;
  for (long i = 0; i < n; i++) fputs(unit, f);
  fputs(tail, f);
  fclose(f);
}

/* Size and nesting are refused before libyaml sees the text (its 0.2.5
 * takes quadratic time in the nesting); 32 levels still load. */
static void test_case_limits(void) {
  const char *path = "t700_tmp_case.yaml";
  ps_ctx ctx;
  ps_case cs;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  write_repeated(path, "[", 200000, "\n"); /* libyaml 0.2.5 alone: minutes */
  double t0 = ps_wtime();
  int s = ps_case_load(&cs, path, &ctx);
  double dt = ps_wtime() - t0;
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "t700_tmp_case.yaml:1: nesting deeper than "
                                                "32 levels"),
           "200,000 levels of '[': refused (%s)", ctx.msg);
  /* a guard against the quadratic parse (minutes), not a speed test */
  ps_check_le(dt, 30.0, "200,000 levels of '[': refused before libyaml parses them (s)");
  /* block nesting: "a:" 40 times, each indented one more */
  FILE *f = fopen(path, "w");
  for (int i = 0; f && i < 40; i++) fprintf(f, "%*sa:\n", i, "");
  if (f) fclose(f);
  s = ps_case_load(&cs, path, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "t700_tmp_case.yaml:33: nesting deeper"),
           "40 levels of block mappings: refused at line 33 (%s)", ctx.msg);
  /* the root mapping and 31 lists: 32 levels, read by libyaml */
  f = fopen(path, "w");
  if (f) {
    fputs("name: ", f);
    for (int i = 0; i < 31; i++) fputc('[', f);
    for (int i = 0; i < 31; i++) fputc(']', f);
    fputs("\n", f);
    fclose(f);
  }
  s = ps_case_load(&cs, path, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "name must be a non-empty string"),
           "32 levels: parsed (%s)", ctx.msg);
  /* brackets in quotes, comments and plain scalars are no nesting */
  f = fopen(path, "w");
  if (f) {
    fputs("name: plain  # [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[\n"
          "output: {dir: 'it''s [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[['}  # [[[[[[[[[[[[[[[[[[[[\n",
          f);
    fclose(f);
  }
  s = ps_case_load(&cs, path, &ctx);
  ps_check(s == PS_OK && !strcmp(cs.name, "plain") && !strncmp(cs.output.dir, "it's [[[", 8),
           "brackets in single-quoted scalars and comments are text (%s)", ctx.msg);
  ps_case_defaults(&cs);
  f = fopen(path, "w");
  if (f) {
    fputs("output: {dir: \"a[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[\\\" [[[[[\"}\n", f);
    fclose(f);
  }
  s = ps_case_load(&cs, path, &ctx);
  ps_check(s == PS_OK && !strncmp(cs.output.dir, "a[[[", 4),
           "brackets in double-quoted scalars are text (%s)", ctx.msg);
  ps_case_defaults(&cs);
  /* a file over 1 MiB: refused before parsing */
  write_repeated(path, "# a comment line of a case file that is far too large\n", 20000, "");
  s = ps_case_load(&cs, path, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "t700_tmp_case.yaml: larger than 1 MiB "
                                                "(1080000 bytes)"),
           "a 1 MB file: refused (%s)", ctx.msg);
  remove(path);
}

/* Clouds: every particle keeps its file and line; lines are capped; a
 * file without line breaks is refused at once; every allocation failing
 * in turn gives PS_ERR_NOMEM and a zeroed cloud. */
static void test_cloud_limits(void) {
  bad_cloud("bad_cloud_overflow.txt", 2, 2,
            (const char *const[]){"x (field 1", "is not a finite decimal number (got '1e400')",
                                  NULL});
  bad_cloud("bad_cloud_hex.txt", 2, 3, (const char *const[]){"x (field 1", "'0x10'", NULL});
  bad_cloud("bad_cloud_inf.txt", 2, 2, (const char *const[]){"volume (field 3", "'inf'", NULL});
  bad_cloud("bad_cloud_block_range.txt", 2, 2,
            (const char *const[]){"block", "'99999999999'", NULL});
  bad_cloud("bad_cloud_nul.txt", 2, 3, (const char *const[]){"NUL byte", NULL});

  ps_ctx ctx;
  ps_particles p;
  ps_ctx_init(&ctx);
  int s = ps_cloud_read(&p, DATA("cloud2d.txt"), 2, &ctx);
  ps_check(s == PS_OK && p.source && !strcmp(p.source, DATA("cloud2d.txt")) && p.line &&
               p.line[0] == 2 && p.line[1] == 4 && p.line[2] == 5 && p.line[3] == 6,
           "cloud2d.txt: source and lines 2, 4, 5, 6 of the particles");
  char w[1200];
  if (s == PS_OK)
    ps_check(strstr(ps_particle_where(&p, 2, w, sizeof w), "cloud2d.txt:5: particle 2") != NULL,
             "ps_particle_where names file:line (%s)", w);
  ps_particles_free(&p);

  const char *path = "t700_tmp_cloud.txt";
  write_repeated(path, "0 ", 4000000, "1e-6"); /* 8 MB, no line break */
  double t0 = ps_wtime();
  s = ps_cloud_read(&p, path, 2, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "t700_tmp_cloud.txt:1: line longer than 4096 "
                                                "characters") && !p.x,
           "8 MB without a line break: refused at line 1 (%s)", ctx.msg);
  ps_check_le(ps_wtime() - t0, 30.0,
              "8 MB without a line break: refused at the cap, not read whole (hang guard, s)");
  write_repeated(path, "0 0 1e-6 # a line of a cloud\n", 2000, "");
  long total = -1, nomem = 0, other = 0;
  ps_alloc_countdown(-1);
  s = ps_cloud_read(&p, path, 2, &ctx);
  total = ps_alloc_countdown(-1);
  ps_check(s == PS_OK && p.n == 2000, "2000 particles read with %ld allocations", total);
  ps_particles_free(&p);
  for (long n = 0; n < total; n++) {
    ps_ctx_init(&ctx);
    ps_alloc_countdown(n);
    s = ps_cloud_read(&p, path, 2, &ctx);
    ps_alloc_countdown(-1);
    if (s == PS_ERR_NOMEM && strstr(ctx.msg, "out of memory") && !p.x && !p.source && !p.line)
      nomem++;
    else
      other++;
    ps_particles_free(&p);
  }
  ps_check(nomem == total && other == 0,
           "each of the %ld allocations failing: PS_ERR_NOMEM, a zeroed cloud (%ld other)",
           total, other);
  remove(path);
}

/* Every allocation of a case load failing in turn: PS_ERR_NOMEM, the case
 * unchanged. */
static void test_case_nomem(void) {
  ps_ctx ctx;
  ps_case cs;
  ps_ctx_init(&ctx);
  ps_case_defaults(&cs);
  ps_alloc_countdown(-1);
  int s = ps_case_load(&cs, DATA("full.yaml"), &ctx);
  long total = ps_alloc_countdown(-1), bad = 0;
  ps_check(s == PS_OK && total >= 2, "full.yaml: %ld allocations", total);
  ps_case_free(&cs);
  for (long n = 0; n < total; n++) {
    ps_ctx_init(&ctx);
    ps_case_defaults(&cs);
    ps_alloc_countdown(n);
    s = ps_case_load(&cs, DATA("full.yaml"), &ctx);
    ps_alloc_countdown(-1);
    bad += !(s == PS_ERR_NOMEM && strstr(ctx.msg, "out of memory") && cs.alpha == 5.1);
  }
  ps_check(bad == 0, "full.yaml: each allocation failing gives PS_ERR_NOMEM (%ld did not)", bad);
}

int main(void) {
  test_defaults();
  test_full();
  test_cloud_case();
  test_cloud2d();
  test_bad_cases();
  test_bad_clouds();
  test_bad_values();
  test_case_limits();
  test_cloud_limits();
  test_case_nomem();
  return ps_check_summary();
}
