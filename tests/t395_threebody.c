/* t395_threebody.c: the three-body model (model/threebody.c,
 * doc/design-threebody.md) on square lattices.
 *
 * 1. Homogeneous strain (1e-6) far from the surfaces: the PD stress of the
 *    centre particle (post's Eq. 24 with the arm force vectors T q + M r)
 *    against the continuum's C:eps, plane stress nu in {0.1, 0.2, 0.25,
 *    0.3}, plane strain nu in {0.1, 0.2, 0.25}, five states (uniaxial x,
 *    uniaxial y, pure shear xy, pure shear at 45 degrees, biaxial),
 *    partial volumes with the lattice factor beta. Measured: the energy
 *    density sigma:eps/2 against 1/2 eps:C:eps, and the stress error
 *    |sigma - C:eps| / |C:eps| (Frobenius).
 *    - horizon factor 4: every state within 2% (energy and stress);
 *    - horizon factor 3: uniaxial and biaxial within 2%; the two shear
 *      states are split by the square lattice's cubic anisotropy, which no
 *      pair (c, kappa) removes: the energy errors are -/+ (lambda/G) (A/B -
 *      3)/(A/B + 1) (design note, section 2; A = 1/4 sum k n_x^4, B = 1/4
 *      sum k n_x^2 n_y^2 over the lattice offsets, computed here), checked
 *      to 0.05% (absolute), and they exceed 2% at plane strain 0.25.
 *    The energy is the same after a rigid rotation of 0.3 rad (1e-8).
 *    On the hex lattice (factor 3; six-fold symmetry makes the fourth
 *    moments isotropic) every state within 0.1%.
 * 1b. The tangent of the intact model (square lattice, surface
 *    correction, displacements of 1e-2 spacings and a 0.4 rad rotation)
 *    equals central differences (1e-6; t200 checks broken arms, jittered
 *    lattices and clouds).
 * 2. Rigid motions (0.3, 2.5, 3.1 rad plus a translation) of a free patch
 *    with 15% of its arms broken: forces <= 1e-11 of those of a 1e-3
 *    strain (round-off: positions to 2e-16 against strains of 1e-3, over
 *    some 30 arms a particle; measured 1.4e-12 to 2.9e-12, as the design
 *    note's prototype, 2.8e-12), energy <= 1e-12 of its energy.
 * 3. Breaking by the micropotential: w_c = 3 G_c / (2 delta^3) and the
 *    per-arm s0 of 1/2 c R xi s0^2 = w_c; under isotropic compression with
 *    a shear whose energy alone passes w_c no arm breaks; in tension they
 *    do, and the broken energy is their micropotential.
 * 4. Refusals, by the model and (naming the file and line) by the case
 *    file: nu > 1/3 in plane stress, nu > 1/4 in plane strain, 3D, a
 *    critical stretch. */
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "assembly/ps_assembly.h"
#include "check.h"
#include "io/ps_io.h"
#include "post/ps_post.h"

#define DX 1.0e-3
#define E_MOD 70.0e9

typedef struct {
  ps_particles P;
  ps_network net;
  ps_model model;
  ps_arm_state st;
  ps_system sys;
  int n;
} lattice;

static void die(const ps_ctx *ctx) {
  fprintf(stderr, "t395 set-up failed: %s\n", ctx->msg);
  exit(2);
}

/* an n x n square lattice, horizon m spacings, the threebody model with mat
 * (E, nu, plane, fracture set by the caller); returns the model's status */
static const char *lattice_kind = "square";

static int make(lattice *L, int n, double m, ps_material mat, ps_ctx *ctx) {
  memset(L, 0, sizeof *L);
  L->n = n;
  ps_int counts[3] = {n, n, 1};
  if (ps_geom_box(&L->P, 2, counts, DX, lattice_kind, 0.0, 1, ctx)) die(ctx);
  for (ps_int a = 0; a < L->P.n; a++) L->P.h[a] = DX;
  ps_kernel K;
  if (ps_kernel_init(&K, 2, 2, ps_model_lattice_reach(ps_model_threebody, m), ctx)) die(ctx);
  if (ps_network_build(&L->net, &L->P, &K, NULL, 0, ctx)) die(ctx);
  mat.horizon = m * DX;
  mat.spacing = DX;
  mat.rho = 2700;
  mat.yield_strain = 1e-3; /* unused: elastic */
  if (ps_material_finish(&mat, 2, ctx)) die(ctx);
  int status = ps_model_create(&L->model, ps_model_threebody, &L->P, &L->net, &mat, ctx);
  if (status) return status;
  if (ps_arm_state_alloc(&L->st, L->net.n_arm, ctx)) die(ctx);
  unsigned char *fixed = calloc((size_t)(2 * L->P.n), 1);
  if (ps_system_create(&L->sys, &L->net, fixed, ctx)) die(ctx);
  free(fixed);
  return PS_OK;
}

static void unmake(lattice *L) {
  ps_system_free(&L->sys);
  ps_arm_state_free(&L->st);
  ps_model_free(&L->model);
  ps_network_free(&L->net);
  ps_particles_free(&L->P);
}

/* u = R(phi) (I + e) X + shift - X, e = [[e0, e2], [e2, e1]] */
static void deform(const lattice *L, const double *e, double phi, double *u) {
  double c = cos(phi), s = sin(phi);
  for (ps_int a = 0; a < L->P.n; a++) {
    double x0 = L->P.x[2 * a], x1 = L->P.x[2 * a + 1];
    double z0 = x0 + e[0] * x0 + e[2] * x1, z1 = x1 + e[2] * x0 + e[1] * x1;
    u[2 * a] = c * z0 - s * z1 + 0.37 * DX - x0;
    u[2 * a + 1] = s * z0 + c * z1 - 0.21 * DX - x1;
  }
}

/* A/B of the square lattice's offsets, weights v xi V (partial volumes) */
static double lattice_AB(double m) {
  double A = 0, B = 0;
  for (int j = -8; j <= 8; j++)
    for (int i = -8; i <= 8; i++) {
      double xi = hypot(i, j);
      if (xi == 0) continue;
      double v = ps_partial_volume(xi, m, 1.0);
      if (v <= 0) continue;
      double nx = i / xi, ny = j / xi;
      A += v * xi * nx * nx * nx * nx;
      B += v * xi * nx * nx * ny * ny;
    }
  return A / B;
}

static const char *state_name[5] = {"ux", "uy", "sh-xy", "sh-45", "biax"};
static const double states[5][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, -1, 0}, {1, 1, 0}};

static void homogeneous(double m, int plane, double nu) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  lattice L;
  ps_material mat = {.E = E_MOD, .nu = nu, .plane = plane, .surface_correction = 0};
  int n = (int)ceil(4 * (m + 0.5)) + 3; /* the centre two reaches from the edges */
  if (make(&L, n, m, mat, &ctx)) die(&ctx);
  ps_int centre = 0, nd = 2 * L.P.n;
  double xc = 0, yc = 0, best = 1e300;
  for (ps_int a = 0; a < L.P.n; a++) xc += L.P.x[2 * a] / L.P.n, yc += L.P.x[2 * a + 1] / L.P.n;
  for (ps_int a = 0; a < L.P.n; a++) {
    double r = hypot(L.P.x[2 * a] - xc, L.P.x[2 * a + 1] - yc);
    if (r < best) best = r, centre = a;
  }
  int hex = !strcmp(lattice_kind, "hex");
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f);
  double *sig = calloc((size_t)(4 * L.P.n), sizeof *sig);
  const ps_material *mt = &L.model.mat;
  double lam = mt->K - mt->G, G = mt->G, C11 = lam + 2 * G, C12 = lam;
  double AB = lattice_AB(m), split = (lam / G) * (AB - 3) / (AB + 1);
  double amp = 1e-6;
  for (int k = 0; k < 5; k++) {
    double e[3] = {amp * states[k][0], amp * states[k][1], amp * states[k][2]}, E0, E1;
    double sc[4] = {C11 * e[0] + C12 * e[1], 2 * G * e[2], 2 * G * e[2], C12 * e[0] + C11 * e[1]};
    double Wc = 0.5 * (sc[0] * e[0] + sc[3] * e[1] + 2 * sc[1] * e[2]);
    deform(&L, e, 0.0, u);
    ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E0, PS_EVAL_FORCES, &ctx);
    ps_post_stress_tensor(&L.P, &L.net, L.sys.T, L.sys.q, sig);
    const double *s = &sig[4 * centre];
    double W = 0.5 * (s[0] * e[0] + s[3] * e[1] + (s[1] + s[2]) * e[2]);
    double num = 0, den = 0;
    for (int j = 0; j < 4; j++) {
      num += (s[j] - sc[j]) * (s[j] - sc[j]);
      den += sc[j] * sc[j];
    }
    double ew = W / Wc - 1, es = sqrt(num / den);
    deform(&L, e, 0.3, u);
    ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E1, PS_EVAL_FORCES, &ctx);
    double drot = fabs(E1 - E0) / E0;
    char what[200];
    snprintf(what, sizeof what,
             "factor %g, plane %s nu=%.2f, %s: energy %+.2f%%, stress %.2f%%, rotated 0.3 "
             "rad: |dE|/E %.1e",
             m, plane == PS_PLANE_STRESS ? "stress" : "strain", nu, state_name[k], 100 * ew,
             100 * es, drot);
    int shear = k == 2 || k == 3;
    if (hex) /* six-fold symmetry: isotropic fourth moments, beta exact */
      ps_check(fabs(ew) <= 1e-3 && es <= 1e-3 && drot <= 1e-8, "hex lattice, %s (within 0.1%%)",
               what);
    else if (m >= 4 || !shear)
      ps_check(fabs(ew) <= 0.02 && es <= 0.02 && drot <= 1e-8, "%s (within 2%%)", what);
    else {
      double want = k == 2 ? -split : split;
      ps_check(fabs(ew - want) <= 5e-4 && drot <= 1e-8,
               "%s: the lattice split %+.2f%% (A/B = %.4f) to 0.05%%", what, 100 * want, AB);
    }
  }
  free(u);
  free(f);
  free(sig);
  unmake(&L);
}

/* dense copy of the upper-triangle CSC tangent */
static void dense(const ps_csc *A, ps_int nd, double *Kd) {
  memset(Kd, 0, (size_t)(nd * nd) * sizeof *Kd);
  for (ps_int j = 0; j < nd; j++)
    for (ps_int k = A->p[j]; k < A->p[j + 1]; k++) {
      Kd[A->i[k] * nd + j] = A->x[k];
      Kd[j * nd + A->i[k]] = A->x[k];
    }
}

/* the tangent of the intact model (no arm broken) against central
 * differences, at random displacements of 1e-2 spacings and a rotation of
 * 0.4 rad, on the square lattice with the surface correction (t200 checks
 * broken arms, jittered lattices and clouds) */
static void tangent_intact(int plane, double nu) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  lattice L;
  ps_material mat = {.E = E_MOD, .nu = nu, .plane = plane, .surface_correction = 1};
  if (make(&L, 8, 3.0, mat, &ctx)) die(&ctx);
  ps_int nd = 2 * L.P.n;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f);
  double *fp = calloc((size_t)nd, sizeof *fp), *fm = calloc((size_t)nd, sizeof *fm);
  double *Kd = calloc((size_t)(nd * nd), sizeof *Kd), E;
  unsigned long seed = 777;
  double c = cos(0.4), sn = sin(0.4);
  for (ps_int a = 0; a < L.P.n; a++) {
    double y[2];
    for (int k = 0; k < 2; k++) {
      seed = seed * 6364136223846793005ul + 1442695040888963407ul;
      y[k] = L.P.x[2 * a + k] + 1e-2 * DX * ((double)(seed >> 11) / 9007199254740992.0 - 0.5);
    }
    u[2 * a] = c * y[0] - sn * y[1] - L.P.x[2 * a];
    u[2 * a + 1] = sn * y[0] + c * y[1] - L.P.x[2 * a + 1];
  }
  ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E, PS_EVAL_TANGENT, &ctx);
  dense(&L.sys.A, nd, Kd);
  double h = 1e-7 * DX, num = 0, den = 0;
  for (ps_int j = 0; j < nd; j++) {
    double u0 = u[j];
    u[j] = u0 + h;
    ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, fp, &E, PS_EVAL_FORCES, &ctx);
    u[j] = u0 - h;
    ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, fm, &E, PS_EVAL_FORCES, &ctx);
    u[j] = u0;
    for (ps_int r = 0; r < nd; r++) {
      double kfd = (fp[r] - fm[r]) / (2 * h);
      num += (kfd - Kd[r * nd + j]) * (kfd - Kd[r * nd + j]);
      den += Kd[r * nd + j] * Kd[r * nd + j];
    }
  }
  char what[160];
  snprintf(what, sizeof what,
           "intact lattice, plane %s nu=%.2f, turned 0.4 rad: tangent vs central differences "
           "(rel. Frobenius)", plane == PS_PLANE_STRESS ? "stress" : "strain", nu);
  ps_check_le(sqrt(num / den), 1e-6, what);
  free(u);
  free(f);
  free(fp);
  free(fm);
  free(Kd);
  unmake(&L);
}

/* rigid motions of a free patch with broken arms */
static void rigid(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  lattice L;
  ps_material mat = {.E = E_MOD, .nu = 0.2, .plane = PS_PLANE_STRESS, .surface_correction = 1};
  if (make(&L, 12, 3.0, mat, &ctx)) die(&ctx);
  ps_int nd = 2 * L.P.n;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f), E;
  unsigned long seed = 12345;
  ps_int nb = 0;
  for (ps_int i = 0; i < L.net.n_arm; i++) {
    seed = seed * 6364136223846793005ul + 1442695040888963407ul;
    L.st.broken[i] = (seed >> 33) % 100 < 15;
    nb += L.st.broken[i];
  }
  double e3[3] = {1e-3, 0, 0};
  deform(&L, e3, 0.0, u);
  ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E, PS_EVAL_FORCES, &ctx);
  double fref = 0, Eref = E;
  for (ps_int j = 0; j < nd; j++) fref = fmax(fref, fabs(f[j]));
  double phis[3] = {0.3, 2.5, 3.1};
  for (int k = 0; k < 3; k++) {
    double e0[3] = {0, 0, 0};
    deform(&L, e0, phis[k], u);
    ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E, PS_EVAL_FORCES, &ctx);
    double fm = 0;
    for (ps_int j = 0; j < nd; j++) fm = fmax(fm, fabs(f[j]));
    ps_check(fm <= 1e-11 * fref && fabs(E) <= 1e-12 * Eref,
             "rigid rotation %.1f rad + translation, %lld of %lld arms broken, free edges: "
             "max |f| %.1e, energy %.1e (of a 1e-3 strain's)",
             phis[k], (long long)nb, (long long)L.net.n_arm, fm / fref, fabs(E) / Eref);
  }
  free(u);
  free(f);
  unmake(&L);
}

static void breaking(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  lattice L;
  double Gc = 10.0;
  ps_material mat = {.E = E_MOD, .nu = 0.25, .plane = PS_PLANE_STRESS, .surface_correction = 1,
                     .fracture = PS_FRACTURE_ENERGY, .fracture_energy = Gc};
  if (make(&L, 14, 3.0, mat, &ctx)) die(&ctx);
  double delta = 3.0 * DX, wc = L.model.mat.critical_micropotential;
  double c = L.model.work[0]; /* the model's c (beta included) */
  double worst = 0;
  for (ps_int i = 0; i < L.net.n_arm; i++) {
    /* k = v R xi V V: c R = c k / (v xi V V); on this lattice v = 1 inside */
    if (L.net.r0[i] > 2.4 * DX) continue;
    double R = L.model.arm_k[i] / (L.net.r0[i] * DX * DX * DX * DX);
    double s0 = sqrt(2 * wc / (c * R * L.net.r0[i]));
    worst = fmax(worst, fabs(L.model.arm_s0[i] / s0 - 1));
  }
  ps_check(fabs(wc / (1.5 * Gc / pow(delta, 3)) - 1) <= 1e-14 && worst <= 1e-12,
           "G_c = %g J/m^2: w_c = 3 G_c / (2 delta^3) = %.6g, per-arm s0 from 1/2 c R xi s0^2 "
           "= w_c (%.1e)", Gc, wc, worst);
  ps_int nd = 2 * L.P.n, nbroken = 0;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f), E;
  /* compression -1e-3 with a shear whose energy alone is past w_c */
  double s_c = sqrt(2 * wc / (c * 2 * DX)); /* about the critical stretch */
  double e1[3] = {-8 * s_c, -8 * s_c, 6 * s_c}; /* s <= -2 s_c; shear: w ~ 3.6 w_c */
  deform(&L, e1, 0.0, u);
  ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E, PS_EVAL_FORCES, &ctx);
  ps_model_break_arms(&L.model, &L.st, 0, &nbroken, &ctx);
  ps_int npos = 0;
  for (ps_int i = 0; i < L.net.n_arm; i++) npos += L.sys.dl[i] > 0;
  ps_check(nbroken == 0 && npos == 0 && E > 0,
           "compressed (all arms shorter) and sheared past w_c in shear energy: no arm "
           "breaks");
  double e2[3] = {3 * s_c, 0, 0};
  deform(&L, e2, 0.0, u);
  ps_system_eval(&L.sys, &L.model, &L.st, L.P.x, u, f, &E, PS_EVAL_FORCES, &ctx);
  /* the micropotential of each arm past w_c, from the energy definition */
  double want = 0;
  ps_int nwant = 0;
  for (ps_int i = 0; i < L.net.n_arm; i++)
    if (ps_model_stretch_excess(&L.model, &L.st, i) > 0) {
      nwant++;
      want += 0.5 * c * L.model.arm_k[i] * L.st.stretch[i] * L.st.stretch[i];
    }
  ps_model_break_arms(&L.model, &L.st, 0, &nbroken, &ctx);
  ps_check(nbroken > 0 && nbroken == nwant && fabs(L.st.broken_energy / want - 1) < 1e-12,
           "uniaxial tension 3 s_c: %lld arms past w_c break, broken energy %.4g J/m",
           (long long)nbroken, L.st.broken_energy);
  free(u);
  free(f);
  unmake(&L);
}

/* a case file with the threebody model and the lines given */
static int load_case(const char *lines, ps_ctx *ctx) {
  char path[] = "/tmp/t395_XXXXXX";
  int fd = mkstemp(path);
  if (fd < 0) return -100;
  FILE *fp = fdopen(fd, "w");
  fprintf(fp,
          "name: t395\n"
          "geometry:\n"
          "  type: box\n"
          "%s"
          "  spacing: 1.0e-3\n"
          "material:\n"
          "  model: threebody\n"
          "  E: 70.0e9\n"
          "  horizon_factor: 3\n"
          "%s"
          "loading:\n"
          "  type: boundary\n"
          "  boundary:\n"
          "    - select: {y_max: 0.0025}\n"
          "      fix: [x, y]\n",
          strstr(lines, "dim: 3") ? "  dim: 3\n  counts: [10, 10, 10]\n"
                                  : "  dim: 2\n  counts: [10, 10]\n",
          lines);
  fclose(fp);
  ps_case cs;
  ps_case_defaults(&cs); /* ps_case_load reads over the defaults */
  int s = ps_case_load(&cs, path, ctx);
  unlink(path);
  return s;
}

static void refusals(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  lattice L;
  ps_material m1 = {.E = E_MOD, .nu = 0.35, .plane = PS_PLANE_STRESS};
  int s = make(&L, 8, 3.0, m1, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "nu <= 1/3 in plane stress"),
           "model: plane stress nu = 0.35 refused: %s", ctx.msg);
  ps_particles_free(&L.P), ps_network_free(&L.net);
  ps_material m2 = {.E = E_MOD, .nu = 0.3, .plane = PS_PLANE_STRAIN};
  s = make(&L, 8, 3.0, m2, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "1/4 in plane strain"),
           "model: plane strain nu = 0.3 refused: %s", ctx.msg);
  ps_particles_free(&L.P), ps_network_free(&L.net);
  ps_material m3 = {.E = E_MOD, .nu = 0.25, .plane = PS_PLANE_STRAIN,
                    .fracture = PS_FRACTURE_STRETCH, .critical_stretch = 1e-3};
  s = make(&L, 8, 3.0, m3, &ctx);
  ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "micropotential"),
           "model: a critical stretch refused: %s", ctx.msg);
  ps_particles_free(&L.P), ps_network_free(&L.net);
  ps_material m4 = {.E = E_MOD, .nu = 0.2505, .plane = PS_PLANE_STRAIN};
  s = make(&L, 8, 3.0, m4, &ctx); /* within the 1e-3 tolerance: kappa = 0 */
  ps_check(s == PS_OK && L.model.work[1] == 0.0,
           "model: plane strain nu = 0.2505 accepted with kappa = 0");
  if (s == PS_OK) unmake(&L);
  /* 3D, by the model */
  {
    ps_particles P;
    ps_network net;
    ps_model model;
    ps_int counts[3] = {5, 5, 5};
    if (ps_geom_box(&P, 3, counts, DX, "square", 0.0, 1, &ctx)) die(&ctx);
    for (ps_int a = 0; a < P.n; a++) P.h[a] = DX;
    ps_kernel K;
    if (ps_kernel_init(&K, 3, 2, ps_model_lattice_reach(ps_model_threebody, 2.0), &ctx)) die(&ctx);
    if (ps_network_build(&net, &P, &K, NULL, 0, &ctx)) die(&ctx);
    ps_material m5 = {.E = E_MOD, .nu = 0.2, .rho = 1, .yield_strain = 1e-3, .horizon = 2 * DX, .spacing = DX};
    if (ps_material_finish(&m5, 3, &ctx)) die(&ctx);
    s = ps_model_create(&model, ps_model_threebody, &P, &net, &m5, &ctx);
    ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, "2D only"), "model: 3D refused: %s",
             ctx.msg);
    ps_network_free(&net);
    ps_particles_free(&P);
  }
  /* the case file: file and line */
  const struct {
    const char *lines, *want;
  } cases[] = {
      {"  plane: stress\n  nu: 0.35\n", ":12: material.nu = 0.35: the threebody model"},
      {"  plane: strain\n  nu: 0.3\n", ":12: material.nu = 0.3: the threebody model"},
      {"  nu: 0.2\n# dim: 3\n", ":4: material.model threebody is 2D only"},
      {"  plane: stress\n  nu: 0.2\n  fracture: {critical_stretch: 1.0e-3}\n",
       ":13: material.fracture: the threebody model breaks by its arm micropotential"},
      {"  plane: stress\n  nu: 0.2\n  fracture: {fracture_energy: 10, criterion: stretch}\n",
       ":13: material.fracture: the threebody"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    s = load_case(cases[k].lines, &ctx);
    ps_check(s == PS_ERR_INPUT && strstr(ctx.msg, cases[k].want), "case file refusal: %s",
             ctx.msg);
  }
  s = load_case("  plane: stress\n  nu: 0.3333\n  fracture: {fracture_energy: 10}\n", &ctx);
  ps_check(s == PS_OK, "case file: plane stress nu = 0.3333 with fracture_energy accepted "
                       "(criterion energy, the threebody default)");
}

int main(void) {
  double nus[4] = {0.1, 0.2, 0.25, 0.3};
  for (int f = 0; f < 2; f++)
    for (int k = 0; k < 4; k++) {
      homogeneous(f == 0 ? 4.0 : 3.0, PS_PLANE_STRESS, nus[k]);
      if (nus[k] <= 0.25) homogeneous(f == 0 ? 4.0 : 3.0, PS_PLANE_STRAIN, nus[k]);
    }
  lattice_kind = "hex";
  homogeneous(3.0, PS_PLANE_STRESS, 0.25);
  homogeneous(3.0, PS_PLANE_STRAIN, 0.2);
  lattice_kind = "square";
  tangent_intact(PS_PLANE_STRESS, 0.2);
  tangent_intact(PS_PLANE_STRAIN, 0.25);
  rigid();
  breaking();
  refusals();
  return ps_check_summary();
}
