/* t370_fracture.c: breaking in the bond and state models (material.fracture).
 *
 * 1. Calibration, against quadrature that knows nothing of the closed
 *    forms in model/breaking.c: the micromodulus c(xi) is read back from
 *    the model's arms (c = k xi / (V_a V_b) with full volumes and no
 *    surface correction), and GSL's adaptive quadrature of the continuum
 *    integrals checks (a) that c reproduces the continuum's energy under
 *    isotropic expansion (2D: 2 K s^2; 3D: 9/2 K s^2) and (b) that the
 *    critical stretch or micropotential the model derives from G_c makes
 *    the energy of all arms crossing a unit crack, each at the criterion,
 *    equal G_c. The crossing integral is taken over the depth z of one end
 *    below the crack, the arm length xi and its angle (2D) or polar angle
 *    (3D), not in the reduced one-dimensional form the derivation uses.
 *    Tolerance 1e-7: the quadrature's own relative tolerance is 1e-10.
 * 2. The breaking mechanism on a 2D lattice: under u_y = eps y with eps =
 *    1.5 s0 exactly the arms whose stretch exceeds s0 break, none in
 *    compression; with max_count the max_count arms of largest stretch;
 *    st->broken_energy is the sum of 1/2 k dl^2 of the broken arms (bond,
 *    to 1e-12; state at nu = 1/3, whose dilatation term is zero: the sum
 *    of 2 b kv dl^2, 1e-10); a broken state-model arm leaves the
 *    dilatation (theta of its particles equals the sum over the intact
 *    arms, 1e-12); the state model's arm energy at nu = 1/4 is the
 *    energy lost when the arm alone breaks (1e-8).
 * 3. At nu = 1/3 in plane stress the state model stores the PMB bond
 *    model's energy (1e-10: K - 2G is zero only to round-off).
 * 4. Refusals: a critical stretch <= 0 and the energy criterion for the
 *    state model are errors naming the parameter. */
#include <gsl/gsl_integration.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "model/ps_model.h"

#define DX 1.0e-3
#define M_FACTOR 3.015

typedef struct {
  ps_particles P;
  ps_network net;
  ps_model model;
} lattice;

/* a set-up step failed: not a check */
static void die(const ps_ctx *ctx) {
  fprintf(stderr, "t370 set-up failed: %s\n", ctx->msg);
  exit(2);
}

/* an n^dim square lattice of spacing DX, horizon M_FACTOR DX, arms to the
 * horizon, and a model of `type` with mat */
static int make(lattice *L, const ps_model_type *type, int dim, int n, ps_material mat,
                ps_ctx *ctx) {
  memset(L, 0, sizeof *L);
  ps_int counts[3] = {n, n, dim == 3 ? n : 1};
  if (ps_geom_box(&L->P, dim, counts, DX, "square", 0.0, 1, ctx)) die(ctx);
  for (ps_int a = 0; a < L->P.n; a++) L->P.h[a] = DX;
  ps_kernel K;
  if (ps_kernel_init(&K, dim, 2, ps_model_lattice_reach(type, M_FACTOR), ctx)) die(ctx);
  if (ps_network_build(&L->net, &L->P, &K, NULL, 0, ctx)) die(ctx);
  mat.horizon = M_FACTOR * DX;
  mat.spacing = DX;
  if (ps_material_finish(&mat, dim, ctx)) die(ctx);
  return ps_model_create(&L->model, type, &L->P, &L->net, &mat, ctx);
}

static void unmake(lattice *L) {
  ps_model_free(&L->model);
  ps_network_free(&L->net);
  ps_particles_free(&L->P);
}

/* ---- quadrature ---- */

typedef struct {
  int dim, energy;   /* energy: 1 for the micropotential criterion */
  double c0, delta;  /* c(xi) = c0 or c0 (1 - xi/delta) */
  int conical;
  double s0, wc;
  double z, xi;      /* outer variables */
} qpar;

static double micromodulus(const qpar *q, double xi) {
  return q->conical ? q->c0 * (1.0 - xi / q->delta) : q->c0;
}

/* the micropotential of an arm of length xi at the criterion */
static double w_crit(const qpar *q, double xi) {
  return q->energy ? q->wc : 0.5 * micromodulus(q, xi) * q->s0 * q->s0 * xi;
}

static gsl_integration_workspace *ws[3];

static double integrate(double (*f)(double, void *), void *p, double a, double b, int level) {
  gsl_function F = {f, p};
  double r, err;
  gsl_integration_qags(&F, a, b, 0.0, 1e-10, 1000, ws[level], &r, &err);
  return r;
}

/* innermost: the angle. 2D: the partner at angle phi from the crack line
 * is across when xi sin(phi) > z; area element xi dxi dphi. 3D: polar
 * angle theta from the normal, across when xi cos(theta) > z; volume
 * element 2 pi xi^2 sin(theta) dxi dtheta. */
static double f_angle(double ang, void *p) {
  qpar *q = p;
  return q->dim == 2 ? w_crit(q, q->xi) * q->xi
                     : 2.0 * M_PI * q->xi * q->xi * sin(ang) * w_crit(q, q->xi);
}

static double f_xi(double xi, void *p) {
  qpar *q = p;
  q->xi = xi;
  if (q->dim == 2) return integrate(f_angle, q, asin(q->z / xi), M_PI - asin(q->z / xi), 2);
  return integrate(f_angle, q, 0.0, acos(q->z / xi), 2);
}

static double f_z(double z, void *p) {
  qpar *q = p;
  q->z = z;
  return integrate(f_xi, q, z, q->delta, 1);
}

/* energy per unit crack area of the arms across it, each at the criterion */
static double crossing_energy(qpar *q) { return integrate(f_z, q, 0.0, q->delta, 0); }

/* 1/2 int w(s xi) dV over the horizon, s = 1: the energy density under
 * isotropic expansion by a unit stretch */
static double f_expand(double xi, void *p) {
  const qpar *q = p;
  double shell = q->dim == 2 ? 2.0 * M_PI * xi : 4.0 * M_PI * xi * xi;
  return 0.5 * 0.5 * micromodulus(q, xi) * xi * shell;
}

static void calibration(int dim, int conical, int energy) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  char label[96];
  snprintf(label, sizeof label, "bond %dD, %s micromodulus, %s criterion", dim,
           conical ? "conical" : "constant", energy ? "energy" : "stretch");
  double Gc = 7.0;
  ps_material mat = {.E = 72e9, .yield_strain = 2e-3, .nu = dim == 2 ? 1.0 / 3.0 : 0.25, .rho = 1.0,
                     .plane = dim == 2 ? PS_PLANE_STRESS : PS_SOLID_3D,
                     .micromodulus = conical ? PS_MICRO_CONICAL : PS_MICRO_CONSTANT,
                     .full_volumes = 1, .surface_correction = 0,
                     .fracture = energy ? PS_FRACTURE_ENERGY : PS_FRACTURE_STRETCH,
                     .fracture_energy = Gc};
  lattice L;
  if (make(&L, ps_model_bond, dim, dim == 2 ? 9 : 7, mat, &ctx)) {
    ps_check(0, "%s: model created (%s)", label, ctx.msg);
    return;
  }
  /* c0 from the arms: c(xi) = k xi / (V_a V_b), divided by the cone */
  qpar q = {.dim = dim, .energy = energy, .delta = L.model.mat.horizon, .conical = conical,
            .s0 = L.model.mat.critical_stretch, .wc = L.model.mat.critical_micropotential};
  double cmin = INFINITY, cmax = 0;
  for (ps_int i = 0; i < L.net.n_arm; i++) {
    double xi = L.net.r0[i];
    double c = L.model.arm_k[i] * xi / (L.P.volume[L.net.a[i]] * L.P.volume[L.net.b[i]]);
    if (conical) c /= 1.0 - xi / q.delta;
    cmin = fmin(cmin, c);
    cmax = fmax(cmax, c);
  }
  q.c0 = cmax;
  ps_check_le((cmax - cmin) / cmax, 1e-12, "c0 is the same on every arm");
  double K = L.model.mat.K, W = integrate(f_expand, &q, 0.0, q.delta, 0);
  char what[160];
  snprintf(what, sizeof what, "%s: c(xi) gives the continuum's expansion energy", label);
  ps_check_rel(W, dim == 2 ? 2.0 * K : 4.5 * K, 1e-7, what);
  snprintf(what, sizeof what, "%s: the crossing arms at the criterion hold G_c", label);
  ps_check_rel(crossing_energy(&q), Gc, 1e-7, what);
  unmake(&L);
}

/* ---- the breaking mechanism ---- */

static void apply_strain(const lattice *L, double eps, double *dl) {
  int N = L->net.dim;
  for (ps_int i = 0; i < L->net.n_arm; i++) {
    const double *xa = &L->P.x[L->net.a[i] * N], *xb = &L->P.x[L->net.b[i] * N];
    double d2 = 0;
    for (int k = 0; k < N; k++) {
      double d = (xb[k] - xa[k]) * (k == 1 ? 1.0 + eps : 1.0);
      d2 += d * d;
    }
    dl[i] = sqrt(d2) - L->net.r0[i];
  }
}

static void mechanism(const ps_model_type *type) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  const char *name = type->name;
  double s0 = 1e-3;
  ps_material mat = {.E = 72e9, .yield_strain = 2e-3, .nu = 1.0 / 3.0, .rho = 1.0, .plane = PS_PLANE_STRESS,
                     .micromodulus = PS_MICRO_CONSTANT, .full_volumes = 1,
                     .fracture = PS_FRACTURE_STRETCH, .critical_stretch = s0};
  lattice L;
  if (make(&L, type, 2, 10, mat, &ctx)) {
    ps_check(0, "%s: model created (%s)", name, ctx.msg);
    return;
  }
  ps_int na = L.net.n_arm;
  ps_arm_state st;
  ps_arm_tangent tan;
  if (ps_arm_state_alloc(&st, na, &ctx) || ps_arm_tangent_alloc(&tan, &L.net, &ctx)) abort();
  double *dl = calloc((size_t)na, sizeof *dl), *T = calloc((size_t)na, sizeof *T), E;
  /* compression: nothing breaks */
  apply_strain(&L, -1.5 * s0, dl);
  type->evaluate(&L.model, dl, &st, T, &E, NULL, &ctx);
  ps_int nb = -1;
  int status = ps_model_break_arms(&L.model, &st, 0, &nb, &ctx);
  ps_check(status == PS_OK && nb == 0, "%s: no arm breaks in compression (%lld broke)", name,
           (long long)nb);
  /* tension: exactly the arms with s > s0 (that carry force) */
  apply_strain(&L, 1.5 * s0, dl);
  type->evaluate(&L.model, dl, &st, T, &E, NULL, &ctx);
  ps_int want = 0;
  double smax = -1, energy = 0;
  for (ps_int i = 0; i < na; i++) {
    double s = dl[i] / L.net.r0[i];
    int carries = L.model.arm_k[i] > 0;
    want += carries && s > s0;
    if (carries && s > s0) energy += 0.5 * L.model.arm_k[i] * dl[i] * dl[i];
    if (carries && s > smax) smax = s;
  }
  ps_arm_state keep;
  if (ps_arm_state_alloc(&keep, na, &ctx)) abort();
  ps_arm_state_copy(&keep, &st);
  status = ps_model_break_arms(&L.model, &st, 1, &nb, &ctx);
  ps_int first = -1, count = 0;
  for (ps_int i = 0; i < na; i++)
    if (st.broken[i]) first = i, count++;
  ps_check(status == PS_OK && nb == 1 && count == 1 &&
               dl[first] / L.net.r0[first] >= smax * (1 - 1e-15),
           "%s: max_count 1 breaks one arm of the largest stretch", name);
  ps_arm_state_copy(&st, &keep);
  status = ps_model_break_arms(&L.model, &st, 0, &nb, &ctx);
  ps_check(status == PS_OK && nb == want && want > 0 && want < na,
           "%s: the %lld arms with s > s0 break (%lld broke of %lld)", name, (long long)want,
           (long long)nb, (long long)na);
  int exact = 1;
  for (ps_int i = 0; i < na; i++)
    exact &= st.broken[i] == (L.model.arm_k[i] > 0 && dl[i] / L.net.r0[i] > s0);
  ps_check(exact, "%s: broken exactly where s > s0", name);
  if (type == ps_model_bond)
    ps_check_rel(st.broken_energy, energy, 1e-12, "bond: broken_energy = sum 1/2 k dl^2");
  else /* nu = 1/3: K = 2G, no dilatation term; the pair term 2 b kv e^2 */
    ps_check_rel(st.broken_energy, energy * 4.0 * 6.0 * L.model.mat.G /
                                       (M_PI * pow(L.model.mat.horizon, 4)), 1e-10,
                 "state at nu = 1/3: broken_energy = sum 2 b kv dl^2 (b = 6G/(pi delta^4))");
  /* broken arms carry nothing and leave the dilatation */
  type->evaluate(&L.model, dl, &st, T, &E, &tan, &ctx);
  int zero = 1;
  for (ps_int i = 0; i < na; i++) zero &= !st.broken[i] || (T[i] == 0.0 && tan.D[i] == 0.0);
  ps_check(zero, "%s: broken arms carry no force and no stiffness", name);
  if (type == ps_model_state) {
    double worst = 0;
    for (ps_int a = 0; a < L.net.n_particle; a++) {
      double s = 0;
      for (ps_int k = L.net.fam_ptr[a]; k < L.net.fam_ptr[a + 1]; k++) {
        ps_int i = L.net.fam_arm[k];
        if (!st.broken[i]) s += L.model.arm_k[i] * dl[i];
      }
      double theta = 2.0 / (M_PI * pow(L.model.mat.horizon, 3)) * s / L.P.volume[a];
      worst = fmax(worst, fabs(L.model.epsbar[a] - theta) / (fabs(theta) + 1e-30));
    }
    ps_check_le(worst, 1e-12, "state: theta sums the intact arms only");
  }
  ps_arm_state_free(&keep);
  ps_arm_state_free(&st);
  ps_arm_tangent_free(&tan);
  free(dl);
  free(T);
  unmake(&L);
}

/* At nu = 1/3 in plane stress K = 2G, the state model's dilatation term
 * vanishes and its pair term 4 b delta/xi V_a V_b e is the PMB force with
 * c = 4 b delta = 24 G/(pi delta^3) = 9 E/(pi delta^3): the two models
 * store the same energy (the state model's extra arms beyond the horizon
 * carry nothing with full volumes). */
static void state_is_pmb(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_material mat = {.E = 72e9, .yield_strain = 2e-3, .nu = 1.0 / 3.0, .rho = 1.0,
                     .plane = PS_PLANE_STRESS, .micromodulus = PS_MICRO_CONSTANT,
                     .full_volumes = 1};
  lattice B, S;
  if (make(&B, ps_model_bond, 2, 9, mat, &ctx) || make(&S, ps_model_state, 2, 9, mat, &ctx))
    die(&ctx);
  double e[2];
  lattice *L[2] = {&B, &S};
  for (int k = 0; k < 2; k++) {
    ps_int na = L[k]->net.n_arm;
    ps_arm_state st;
    if (ps_arm_state_alloc(&st, na, &ctx)) die(&ctx);
    double *dl = calloc((size_t)na, sizeof *dl), *T = calloc((size_t)na, sizeof *T);
    apply_strain(L[k], 2e-3, dl);
    L[k]->model.type->evaluate(&L[k]->model, dl, &st, T, &e[k], NULL, &ctx);
    free(dl);
    free(T);
    ps_arm_state_free(&st);
  }
  ps_check(B.net.n_arm < S.net.n_arm, "state has the arms beyond the horizon (%lld < %lld)",
           (long long)B.net.n_arm, (long long)S.net.n_arm);
  ps_check_rel(e[1], e[0], 1e-10, "nu = 1/3 plane stress: state energy = PMB energy");
  unmake(&B);
  unmake(&S);
}

/* The state model's arm energy (state_arm_energy) is what the stored
 * energy loses when that arm alone breaks at fixed displacements, the
 * dilatation term included: at nu = 1/4 (K - 2G = E/15 in plane stress:
 * the term is not zero) under a strain that varies over the lattice (so
 * that theta differs from particle to particle), Psi(intact) - Psi(arm i
 * broken) against arm_energy(i) for every arm in tension (1e-8 of the
 * arm's energy: a difference of two sums of the whole lattice's energy,
 * some 1e3 times larger, in double precision). */
static void state_arm_energy(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  ps_material mat = {.E = 72e9, .yield_strain = 2e-3, .nu = 0.25, .rho = 1.0,
                     .plane = PS_PLANE_STRESS, .fracture = PS_FRACTURE_STRETCH,
                     .critical_stretch = 1e-3};
  lattice L;
  if (make(&L, ps_model_state, 2, 9, mat, &ctx)) die(&ctx);
  ps_int na = L.net.n_arm;
  ps_arm_state st;
  if (ps_arm_state_alloc(&st, na, &ctx)) die(&ctx);
  double *dl = calloc((size_t)na, sizeof *dl), *T = calloc((size_t)na, sizeof *T);
  /* u = (1e-4 x y / DX, 2e-3 y + 5e-4 x^2 / DX) in units of DX */
  for (ps_int i = 0; i < na; i++) {
    const double *xa = L.P.x + 2 * L.net.a[i], *xb = L.P.x + 2 * L.net.b[i];
    double u[2][2];
    const double *x[2] = {xa, xb};
    for (int k = 0; k < 2; k++) {
      u[k][0] = 1e-4 * x[k][0] * x[k][1] / DX;
      u[k][1] = 2e-3 * x[k][1] + 5e-4 * x[k][0] * x[k][0] / DX;
    }
    double dx = xb[0] + u[1][0] - xa[0] - u[0][0], dy = xb[1] + u[1][1] - xa[1] - u[0][1];
    dl[i] = hypot(dx, dy) - L.net.r0[i];
  }
  double E0, E1, worst = 0;
  int n = 0;
  for (ps_int i = 0; i < na; i++) {
    if (!(L.model.arm_k[i] > 0)) continue;
    ps_model_state->evaluate(&L.model, dl, &st, T, &E0, NULL, &ctx);
    if (!(st.stretch[i] > 0)) continue;
    double w = ps_model_state->arm_energy(&L.model, &st, i);
    st.broken[i] = 1;
    ps_model_state->evaluate(&L.model, dl, &st, T, &E1, NULL, &ctx);
    st.broken[i] = 0;
    worst = fmax(worst, fabs(E0 - E1 - w) / w);
    n++;
  }
  ps_check(n > 100 && worst <= 1e-8,
           "state, nu = 1/4: arm_energy = the energy lost when the arm alone breaks, worst "
           "%.2e over %d arms in tension", worst, n);
  free(dl);
  free(T);
  ps_arm_state_free(&st);
  unmake(&L);
}

static void refusals(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  lattice L;
  ps_material mat = {.E = 72e9, .yield_strain = 2e-3, .nu = 1.0 / 3.0, .rho = 1.0, .plane = PS_PLANE_STRESS,
                     .fracture = PS_FRACTURE_STRETCH, .critical_stretch = -1e-3};
  int st = make(&L, ps_model_bond, 2, 5, mat, &ctx);
  ps_check(st == PS_ERR_INPUT && strstr(ctx.msg, "critical stretch"),
           "a critical stretch <= 0 is refused: %s", ctx.msg);
  unmake(&L);
  ps_ctx_init(&ctx);
  mat.critical_stretch = 0;
  mat.fracture = PS_FRACTURE_ENERGY;
  mat.fracture_energy = 5.0;
  mat.nu = 0.3;
  st = make(&L, ps_model_state, 2, 5, mat, &ctx);
  ps_check(st == PS_ERR_INPUT && strstr(ctx.msg, "energy is for the bond model"),
           "the energy criterion on the state model is refused: %s", ctx.msg);
  unmake(&L);
}

int main(void) {
  for (int k = 0; k < 3; k++) ws[k] = gsl_integration_workspace_alloc(1000);
  for (int dim = 2; dim <= 3; dim++)
    for (int conical = 0; conical <= 1; conical++)
      for (int energy = 0; energy <= 1; energy++) calibration(dim, conical, energy);
  mechanism(ps_model_bond);
  mechanism(ps_model_state);
  state_is_pmb();
  state_arm_energy();
  refusals();
  for (int k = 0; k < 3; k++) gsl_integration_workspace_free(ws[k]);
  return ps_check_summary();
}
