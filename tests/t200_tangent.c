/* t200_tangent.c: the assembled tangent equals a central finite-difference
 * Jacobian of the internal forces, and is symmetric, on a small irregular
 * variable-size network with yielded arms, arms in compression and broken
 * arms (2D plane strain, 2D plane stress and 3D), for the fibre model and
 * (elastic, broken and compressed arms) the bond and state models, these
 * also on a point cloud as app/setup.c sets one up (the horizon as a
 * length, arms within ps_model_cloud_reach of uniform sizes, partial
 * volumes from each particle's cell V^(1/N), which differ between the two
 * ends of an arm, and arms broken by a critical stretch on top of the
 * random ones). The threebody model (arm rotations, non-central forces)
 * likewise, in plane stress and plane strain (nu 0.2), at kappa = 0 (plane
 * stress 1/3) and on the cloud (the micropotential criterion instead of the
 * critical stretch), its deformed state turned by 0.4 rad, 15% of its arms
 * broken and one particle left with two collinear arms. Also: T = dPsi/dl (the
 * energy is the potential of the forces), zero force at rest and under a
 * rigid rotation. Tolerance 1e-6 on the relative Frobenius error: central
 * differences with step 1e-7 of the spacing have truncation error ~1e-10
 * and round-off ~1e-9 here. For the models with family terms, the
 * one-horizon majorant P used as a preconditioner (solver.majorant)
 * bounds the tangent: P - K is positive semidefinite (smallest eigenvalue
 * >= -1e-12 ||P||, round-off), and for the elastic fibre model at rest the
 * Rayleigh quotients x^T K x / x^T P x of random x lie in
 * [min(G(N+2)/(NK), NK/(G(N+2))), 1] (the bound in ps_assembly.h).
 * The matrix-free product (ps_system_apply, what CG uses) equals the
 * assembled matrix's product to 1e-13 (round-off of sums in another
 * order), with prescribed dofs and a free body (a particle whose arms
 * all broke, held by a spring), and so does the coupling K_fp du_p of the
 * predictor; evaluations of forces alone in between do not change it.
 * And an arm crushed to zero length (crushed_arm below), and a particle
 * held by collinear arms only (loose_particle), and a fragment of three
 * particles cut off (loose_group). */
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "assembly/ps_assembly.h"
#include "check.h"

typedef struct {
  ps_particles P;
  ps_network net;
  ps_model model;
  ps_arm_state st;
  ps_system sys;
} fixture;

/* cloud (horizon models only): the set-up of a point cloud (app/setup.c),
 * with the horizon as a length: every h the mean spacing, arms within
 * ps_model_cloud_reach, cell sizes of the partial volumes from the
 * volumes (mat.spacing = 0; they grow along x, so the two ends of an arm
 * see different partial volumes), and breaking by a critical stretch. */
static void setup_cloud(fixture *F, const ps_model_type *type, int rule, int dim, int plane,
                        double nu, int cloud, ps_ctx *ctx) {
  memset(F, 0, sizeof *F);
  ps_int counts[3] = {7, 6, dim == 3 ? 5 : 1};
  if (ps_geom_box(&F->P, dim, counts, 1.0e-3, "square", 0.3, 7, ctx)) abort();
  if (ps_geom_sizes_eq115(&F->P, 5, ctx)) abort();
  /* variable sizes: grow h and V along x (factor up to 1.8) */
  for (ps_int a = 0; a < F->P.n; a++) {
    double s = 1.0 + 0.8 * F->P.x[a * dim] / 7.0e-3;
    F->P.h[a] *= s;
    F->P.volume[a] *= pow(s, dim);
  }
  ps_material mat = {.E = 2.1e11, .nu = nu, .plane = plane,
                     .yield_strain = 2.0e-3, .plastic = 1, .delta = 1.0,
                     .rho = 7800, .yield_rule = rule};
  if (type != ps_model_fibre) { /* lattice models: elastic, horizon 3 spacings */
    mat.plastic = 0;
    mat.horizon = 3.0e-3;
    mat.spacing = 1.0e-3;
    mat.surface_correction = 1;
  }
  double alpha = dim == 3 ? 3.0 : 3.5;
  if (cloud) { /* the horizon in m on a cloud of graded cells */
    mat.horizon = dim == 3 ? 2.6e-3 : 3.0e-3;
    mat.spacing = 0.0;
    mat.fracture = PS_FRACTURE_STRETCH;
    mat.critical_stretch = 2.0e-3;
    double hm = ps_mean_spacing(&F->P), dx_max = 0;
    for (ps_int a = 0; a < F->P.n; a++) dx_max = fmax(dx_max, ps_cell_size(&mat, &F->P, a));
    for (ps_int a = 0; a < F->P.n; a++) F->P.h[a] = hm;
    alpha = ps_model_cloud_reach(type, &mat, dx_max) / hm;
  }
  ps_kernel K;
  if (ps_kernel_init(&K, dim, 2, alpha, ctx)) abort();
  if (ps_network_build(&F->net, &F->P, &K, NULL, 0, ctx)) abort();
  if (ps_material_finish(&mat, dim, ctx)) abort();
  if (type->rotations && cloud) { /* threebody: the micropotential criterion,
                                     w_c of a 1 mm arm at stretch 2e-3 */
    mat.fracture = PS_FRACTURE_ENERGY;
    mat.critical_micropotential =
        0.5 * 12.0 * mat.K / (M_PI * pow(mat.horizon, 3)) * 4e-6 * 1e-3;
  }
  if (ps_model_create(&F->model, type, &F->P, &F->net, &mat, ctx)) abort();
  if (ps_arm_state_alloc(&F->st, F->net.n_arm, ctx)) abort();
  unsigned char *fixed = calloc((size_t)(dim * F->P.n), 1);
  if (ps_system_create(&F->sys, &F->net, fixed, ctx)) abort();
  free(fixed);
}

static void setup(fixture *F, const ps_model_type *type, int rule, int dim, int plane,
                  double nu, ps_ctx *ctx) {
  setup_cloud(F, type, rule, dim, plane, nu, 0, ctx);
}

static void teardown(fixture *F) {
  ps_system_free(&F->sys);
  ps_arm_state_free(&F->st);
  ps_model_free(&F->model);
  ps_network_free(&F->net);
  ps_particles_free(&F->P);
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

/* smallest and largest eigenvalue of the symmetric n x n matrix Kd */
static void eig_range(ps_int n, const double *Kd, double *lmin, double *lmax) {
  gsl_matrix *M = gsl_matrix_alloc((size_t)n, (size_t)n);
  for (ps_int r = 0; r < n; r++)
    for (ps_int c = 0; c < n; c++) gsl_matrix_set(M, r, c, Kd[r * n + c]);
  gsl_vector *ev = gsl_vector_alloc((size_t)n);
  gsl_eigen_symm_workspace *w = gsl_eigen_symm_alloc((size_t)n);
  gsl_eigen_symm(M, ev, w);
  *lmin = gsl_vector_min(ev);
  *lmax = gsl_vector_max(ev);
  gsl_eigen_symm_free(w);
  gsl_vector_free(ev);
  gsl_matrix_free(M);
}

/* P = the majorant of the tangent last assembled in F->sys (at the same
 * state), dense [nd x nd]; returns the smallest eigenvalue of P - Kd
 * relative to max |P|, and P in Pd */
static double majorant_gap(fixture *F, const double *Kd, double *Pd, ps_ctx *ctx) {
  ps_int nd = F->sys.n_dof;
  unsigned char *fixed = calloc((size_t)nd, 1);
  ps_system pre;
  if (ps_system_create_pattern(&pre, &F->net, fixed, 0, ctx)) abort();
  free(fixed);
  if (ps_system_assemble_majorant(&pre, &F->sys, ctx)) abort();
  dense(&pre.A, nd, Pd);
  ps_system_free(&pre);
  double pmax = 0, lmin, lmax;
  double *M = calloc((size_t)(nd * nd), sizeof *M);
  for (ps_int k = 0; k < nd * nd; k++) {
    pmax = fmax(pmax, fabs(Pd[k]));
    M[k] = Pd[k] - Kd[k];
  }
  eig_range(nd, M, &lmin, &lmax);
  free(M);
  return lmin / pmax;
}

/* y[n_dof] = Kfull x[n_dof], straight from the block layout */
static void kfull_product(const ps_system *S, const double *x, double *y) {
  int d = S->dim;
  memset(y, 0, (size_t)S->n_dof * sizeof *y);
  for (ps_int Q = 0; Q < S->net->n_particle; Q++) {
    ps_int len = S->bptr[Q + 1] - S->bptr[Q];
    for (ps_int blk = S->bptr[Q]; blk < S->bptr[Q + 1]; blk++)
      for (int be = 0; be < d; be++)
        for (int al = 0; al < d; al++)
          y[S->bidx[blk] * d + al] +=
              S->Kfull[d * d * S->bptr[Q] + be * d * len + (blk - S->bptr[Q]) * d + al] *
              x[Q * d + be];
  }
}

static double rel_diff(ps_int n, const double *a, const double *b) {
  double num = 0, den = 0;
  for (ps_int k = 0; k < n; k++) {
    num += (a[k] - b[k]) * (a[k] - b[k]);
    den += b[k] * b[k];
  }
  return den > 0 ? sqrt(num / den) : sqrt(num);
}

/* S = a system on F's network with the particles at x < 2 mm prescribed */
static void clamp_left(fixture *F, ps_system *S, ps_ctx *ctx) {
  int d = F->net.dim;
  unsigned char *fixed = calloc((size_t)(d * F->P.n), 1);
  for (ps_int a = 0; a < F->P.n; a++)
    for (int k = 0; k < d; k++) fixed[a * d + k] = F->P.x[a * d] < 2.0e-3;
  if (ps_system_create(S, &F->net, fixed, ctx)) abort();
  free(fixed);
}

/* The matrix-free tangent against the assembled one at the state (u, F->st),
 * on a system with the particles at x < 2 mm prescribed and particle 1 a
 * free body */
static void check_matrix_free(fixture *F, double *u, const char *label, ps_ctx *ctx) {
  ps_int nd = F->sys.n_dof;
  for (ps_int k = F->net.fam_ptr[1]; k < F->net.fam_ptr[2]; k++)
    F->st.broken[F->net.fam_arm[k]] = 1;
  ps_system S;
  clamp_left(F, &S, ctx);
  double *f = calloc((size_t)nd, sizeof *f), *x = calloc((size_t)nd, sizeof *x);
  double *y = calloc((size_t)nd, sizeof *y), *yref = calloc((size_t)nd, sizeof *y);
  double *u2 = calloc((size_t)nd, sizeof *u2), E;
  ps_int nf = S.n_free;
  double *xf = calloc((size_t)nf, sizeof *xf), *yf = calloc((size_t)nf, sizeof *yf);
  double *yf_ref = calloc((size_t)nf, sizeof *yf);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  for (ps_int j = 0; j < nd; j++) {
    x[j] = gsl_rng_uniform(rng) - 0.5;
    u2[j] = u[j] * (1.0 + 0.2 * gsl_rng_uniform(rng));
  }
  for (ps_int k = 0; k < nf; k++) xf[k] = x[S.dof_of_free[k]];
  gsl_rng_free(rng);
  /* the operator's data, then forces elsewhere, then the matrix */
  if (ps_system_eval(&S, &F->model, &F->st, F->P.x, u, f, &E, PS_EVAL_OPERATOR, ctx)) abort();
  if (ps_system_eval(&S, &F->model, &F->st, F->P.x, u2, f, &E, PS_EVAL_FORCES, ctx)) abort();
  ps_system_apply(&S, x, y);
  ps_system_apply_free(&S, xf, yf);
  if (ps_system_assemble(&S, ctx)) abort();
  kfull_product(&S, x, yref);
  ps_csc_symv(&S.A, xf, yf_ref);
  double e_full = rel_diff(nd, y, yref), e_free = rel_diff(nf, yf, yf_ref);
  /* the coupling of prescribed increments */
  for (ps_int j = 0; j < nd; j++) x[j] = S.fixed[j] ? x[j] : 0.0;
  kfull_product(&S, x, yref);
  for (ps_int k = 0; k < nf; k++) yf_ref[k] = yref[S.dof_of_free[k]];
  ps_system_coupling(&S, x, yf);
  double e_coupling = rel_diff(nf, yf, yf_ref);
  ps_check(S.spring > 0 && nf < nd && e_full <= 1e-13 && e_free <= 1e-13 &&
               e_coupling <= 1e-13,
           "%s: matrix-free K x = assembled K x (all dofs %.1e, free %.1e, coupling "
           "%.1e; free body spring %.3g N/m)",
           label, e_full, e_free, e_coupling, S.spring);
  ps_system_free(&S);
  free(f);
  free(x);
  free(y);
  free(yref);
  free(u2);
  free(xf);
  free(yf);
  free(yf_ref);
}

static void run_case_cloud(const ps_model_type *type, int rule, int dim, int plane, double nu,
                           int cloud, const char *label) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  fixture F;
  setup_cloud(&F, type, rule, dim, plane, nu, cloud, &ctx);
  ps_int nd = F.sys.n_dof;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f);
  double *fp = calloc((size_t)nd, sizeof *fp), *fm = calloc((size_t)nd, sizeof *fm);
  double *Kd = calloc((size_t)(nd * nd), sizeof *Kd);
  double E0;
  /* rest state: zero forces */
  ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 0, &ctx);
  double fbig = 0;
  for (ps_int j = 0; j < nd; j++) fbig = fbig > fabs(f[j]) ? fbig : fabs(f[j]);
  ps_check(fbig == 0.0 && E0 == 0.0, "%s: zero force and energy at rest", label);

  /* rigid rotation by 0.3 rad + translation: zero force (large rotation) */
  for (ps_int a = 0; a < F.P.n; a++) {
    const double *x = &F.P.x[a * dim];
    double c = cos(0.3), s = sin(0.3);
    u[a * dim] = c * x[0] - s * x[1] - x[0] + 1e-3;
    u[a * dim + 1] = s * x[0] + c * x[1] - x[1] - 2e-3;
  }
  ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 0, &ctx);
  double fn = 0, Tscale = 2.1e11 * 1e-3 * pow(1e-3, dim - 1);
  for (ps_int j = 0; j < nd; j++) fn = fmax(fn, fabs(f[j]));
  ps_check_le(fn / Tscale, 1e-9, "rigid rotation: max force / (E d^(N-1) 1e-3)");

  /* deformed state: tension in x (yields), compression in y, noise */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  for (ps_int a = 0; a < F.P.n; a++) {
    const double *x = &F.P.x[a * dim];
    u[a * dim] = 3.1e-3 * x[0] + 0.4e-3 * x[1] + 2e-7 * gsl_rng_uniform(rng);
    u[a * dim + 1] = -1.2e-3 * x[1] + 2e-7 * gsl_rng_uniform(rng);
    if (dim == 3) u[a * dim + 2] = 0.7e-3 * x[2] + 2e-7 * gsl_rng_uniform(rng);
  }
  /* committed plastic strains and broken arms */
  for (ps_int i = 0; i < F.net.n_arm; i++) {
    F.st.eps_p[i] = 1.0e-3 * (gsl_rng_uniform(rng) - 0.3);
    F.st.eps_p[F.net.n_arm + i] = 1.0e-3 * (gsl_rng_uniform(rng) - 0.3); /* b side */
    F.st.broken[i] = gsl_rng_uniform(rng) < (type->rotations ? 0.15 : 0.05);
  }
  ps_int n_collinear = 0;
  if (type->rotations) {
    /* a model with arm rotations: the deformed state turned by 0.4 rad
     * (finite rotation), larger displacement noise (1e-2 of the spacing),
     * and one particle left with two collinear arms (its x neighbours) */
    for (ps_int a = 0; a < F.P.n; a++) {
      double *ua = &u[a * dim], yx = F.P.x[a * dim] + ua[0], yy = F.P.x[a * dim + 1] + ua[1];
      yx += 1e-5 * (gsl_rng_uniform(rng) - 0.5);
      yy += 1e-5 * (gsl_rng_uniform(rng) - 0.5);
      double c = cos(0.4), sn = sin(0.4);
      ua[0] = c * yx - sn * yy - F.P.x[a * dim];
      ua[1] = sn * yx + c * yy - F.P.x[a * dim + 1];
    }
    ps_int p = 3 + 7 * 2; /* an interior particle: keep its two arms along x
                             to its nearest x neighbours */
    for (ps_int k = F.net.fam_ptr[p]; k < F.net.fam_ptr[p + 1]; k++) {
      ps_int i = F.net.fam_arm[k], o = F.net.a[i] == p ? F.net.b[i] : F.net.a[i];
      int keep = (o == p - 1 || o == p + 1);
      F.st.broken[i] = (unsigned char)!keep;
      n_collinear += keep;
    }
  }
  gsl_rng_free(rng);
  ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 1, &ctx);
  ps_int n_crit = 0;
  if (cloud) { /* break the arms past the critical stretch, then evaluate */
    if (ps_model_break_arms(&F.model, &F.st, 0, &n_crit, &ctx)) abort();
    ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 1, &ctx);
    ps_int n_side = 0;
    for (ps_int i = 0; F.model.arm_side && i < F.net.n_arm; i++)
      n_side += F.model.arm_side[i] != F.model.arm_side[F.net.n_arm + i];
    ps_check(n_crit > 0 && (type != ps_model_state || n_side > 0),
             "%s: %lld arms broken by the critical stretch; %lld arms whose ends see "
             "different partial volumes (state)",
             label, (long long)n_crit, (long long)n_side);
  }
  ps_int ny = 0, nc = 0, nb = 0, nearkink = 0;
  for (ps_int i = 0; i < F.net.n_arm; i++) {
    if (F.st.broken[i]) {
      nb++;
      continue;
    }
    double eps = F.sys.dl[i] / F.net.r0[i];
    double e = eps - F.st.eps_p[i];
    ny += F.st.yielding[i];
    nc += type->rotations ? F.sys.dl[i] < 0 : F.sys.T[i] < 0; /* rotations: T q is
                                                                 the force vector */
    if (rule == PS_YIELD_TOTAL && fabs(fabs(e) - 2.0e-3) < 1e-7) nearkink++;
  }
  ps_check((ny > 0 || type != ps_model_fibre) && nc > 0 && nb > 0 && nearkink == 0 &&
               (!type->rotations || (n_collinear == 2 && nb >= 0.15 * F.net.n_arm)),
           "%s: %lld arms, %lld yielding, %lld in compression, %lld broken, none on "
           "the kink%s",
           label, (long long)F.net.n_arm, (long long)ny, (long long)nc, (long long)nb,
           type->rotations ? "; turned by 0.4 rad, a particle with two collinear arms" : "");
  /* dense copy of the analytic tangent (all dofs free) */
  dense(&F.sys.A, nd, Kd);
  /* symmetry of Kfull (both triangles assembled independently) */
  double asym = 0, knorm = 0;
  int d = dim;
  const ps_system *S = &F.sys;
  for (ps_int Q = 0; Q < F.P.n; Q++)
    for (ps_int blk = S->bptr[Q]; blk < S->bptr[Q + 1]; blk++) {
      ps_int P = S->bidx[blk], len = S->bptr[Q + 1] - S->bptr[Q];
      ps_int blkT = -1;
      for (ps_int b2 = S->bptr[P]; b2 < S->bptr[P + 1]; b2++)
        if (S->bidx[b2] == Q) blkT = b2;
      ps_int lenT = S->bptr[P + 1] - S->bptr[P];
      for (int al = 0; al < d; al++)
        for (int be = 0; be < d; be++) {
          double v = S->Kfull[d * d * S->bptr[Q] + be * d * len + (blk - S->bptr[Q]) * d + al];
          double vt = S->Kfull[d * d * S->bptr[P] + al * d * lenT + (blkT - S->bptr[P]) * d + be];
          asym += (v - vt) * (v - vt);
          knorm += v * v;
        }
    }
  ps_check_le(sqrt(asym / knorm), 1e-13, "symmetry ||K - K^T|| / ||K||");

  /* central differences */
  double hstep = 1e-10; /* 1e-7 of the 1 mm spacing */
  double num = 0, den = 0;
  double Ep, Em, dE_fd, dE_an = 0;
  for (ps_int j = 0; j < nd; j++) {
    double u0 = u[j];
    u[j] = u0 + hstep;
    ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, fp, &Ep, 0, &ctx);
    u[j] = u0 - hstep;
    ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, fm, &Em, 0, &ctx);
    u[j] = u0;
    for (ps_int r = 0; r < nd; r++) {
      double kfd = (fp[r] - fm[r]) / (2 * hstep);
      num += (kfd - Kd[r * nd + j]) * (kfd - Kd[r * nd + j]);
      den += Kd[r * nd + j] * Kd[r * nd + j];
    }
    if (j == 3) { /* energy: dPsi/du_j = f_j */
      dE_fd = (Ep - Em) / (2 * hstep);
      dE_an = f[j];
      ps_check_rel(dE_fd, dE_an, 1e-6, "dPsi/du (central difference) = internal force");
    }
  }
  ps_check_le(sqrt(num / den), 1e-6, "tangent vs central differences (rel. Frobenius)");
  check_matrix_free(&F, u, label, &ctx);
  ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 1, &ctx); /* free body too */
  dense(&F.sys.A, nd, Kd);
  if (type->family_coupling) { /* the majorant preconditioner */
    double *Pd = calloc((size_t)(nd * nd), sizeof *Pd);
    ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 1, &ctx);
    ps_check(majorant_gap(&F, Kd, Pd, &ctx) >= -1e-12,
             "%s: majorant P - K positive semidefinite (yielded, broken, compressed)", label);
    if (type == ps_model_fibre && rule == PS_YIELD_TOTAL) {
      /* at rest, elastic: x^T K x / x^T P x in [min(r, 1/r), 1], r = G(N+2)/(NK) */
      memset(u, 0, (size_t)nd * sizeof *u);
      memset(F.st.broken, 0, (size_t)F.net.n_arm);
      memset(F.st.eps_p, 0, 2 * (size_t)F.net.n_arm * sizeof *F.st.eps_p);
      ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E0, 1, &ctx);
      dense(&F.sys.A, nd, Kd);
      double gap = majorant_gap(&F, Kd, Pd, &ctx);
      double lo = F.model.mat.G * (dim + 2) / (dim * F.model.mat.K);
      if (lo > 1) lo = 1 / lo; /* N K < G(N+2): the family term is negative and
                                  dropped, K >= (N K / G(N+2)) P */
      double rmin = 1e300, rmax = -1e300;
      gsl_rng *r2 = gsl_rng_alloc(gsl_rng_mt19937);
      gsl_rng_set(r2, 5);
      for (int t = 0; t < 40; t++) {
        for (ps_int j = 0; j < nd; j++) u[j] = gsl_rng_uniform(r2) - 0.5;
        double xk = 0, xp = 0;
        for (ps_int r = 0; r < nd; r++)
          for (ps_int c = 0; c < nd; c++) {
            xk += u[r] * Kd[r * nd + c] * u[c];
            xp += u[r] * Pd[r * nd + c] * u[c];
          }
        rmin = fmin(rmin, xk / xp);
        rmax = fmax(rmax, xk / xp);
      }
      gsl_rng_free(r2);
      ps_check(gap >= -1e-12 && rmin >= lo * (1 - 1e-12) && rmax <= 1 + 1e-12,
               "%s at rest: x^T K x / x^T P x in [%.4f, %.4f], bound [%.4f, 1]", label, rmin,
               rmax, lo);
    }
    free(Pd);
  }
  free(u);
  free(f);
  free(fp);
  free(fm);
  free(Kd);
  teardown(&F);
}

static void run_case(const ps_model_type *type, int rule, int dim, int plane, double nu,
                     const char *label) {
  run_case_cloud(type, rule, dim, plane, nu, 0, label);
}

/* An arm crushed to (nearly) zero length, as at a crack tip where a
 * perfectly plastic arm flows in compression until its particles meet:
 * the rounded length (PS_ARM_LENGTH_ROUNDING) keeps forces finite and the
 * tangent consistent there. Without it, |y_b - y_a| has a cone point, the
 * evaluation failed at coincident particles and Newton stalled next to
 * them (doc/model.md). Checked: coincident particles evaluate (PS_OK,
 * finite, that arm's force T dl/dy vanishes: |dl/dy| <= 1e-6, where the
 * unrounded length has |dl/dy| = 1 however close they are), and at a distance of 0.5 e r0 (inside
 * the rounding) the tangent equals central differences in the two
 * particles' dofs (rel. Frobenius 1e-6; step 1e-4 of the rounding radius:
 * truncation ~1e-8, round-off ~1e-9). */
static void crushed_arm(void) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  fixture F;
  setup(&F, ps_model_fibre, PS_YIELD_TOTAL, 2, PS_PLANE_STRAIN, 0.3, &ctx);
  ps_int nd = F.sys.n_dof, d = 2;
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f);
  double *fp = calloc((size_t)nd, sizeof *fp), *fm = calloc((size_t)nd, sizeof *fm);
  double *Kd = calloc((size_t)(nd * nd), sizeof *Kd);
  for (ps_int a = 0; a < F.P.n; a++) u[a * d] = 3.1e-3 * F.P.x[a * d];
  /* the shortest arm */
  ps_int i0 = 0;
  for (ps_int i = 1; i < F.net.n_arm; i++)
    if (F.net.r0[i] < F.net.r0[i0]) i0 = i;
  ps_int a = F.net.a[i0], b = F.net.b[i0];
  double r0 = F.net.r0[i0], E;
  for (double gap = 0.0; gap <= 0.5; gap += 0.5) {
    /* b onto a, then gap e r0 away along (0.6, 0.8) */
    double off[2] = {0.6 * gap * PS_ARM_LENGTH_ROUNDING * r0, 0.8 * gap * PS_ARM_LENGTH_ROUNDING * r0};
    for (int k = 0; k < d; k++)
      u[b * d + k] = F.P.x[a * d + k] + u[a * d + k] + off[k] - F.P.x[b * d + k];
    int status = ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, f, &E, PS_EVAL_TANGENT, &ctx);
    int finite = status == PS_OK && isfinite(E);
    for (ps_int j = 0; j < nd; j++) finite = finite && isfinite(f[j]);
    if (gap == 0.0) {
      double qn = hypot(F.sys.q[i0 * d], F.sys.q[i0 * d + 1]);
      /* (coincident to round-off of the positions, ~1e-19 m) */
      ps_check(finite && qn <= 1e-6 && isfinite(F.sys.T[i0]),
               "coincident particles %lld and %lld: evaluated (status %d), finite, the arm "
               "exerts no force (|dl/dy| = %g <= 1e-6, strain %.4f)",
               (long long)a, (long long)b, status, qn, F.sys.dl[i0] / r0);
      continue;
    }
    ps_check(finite, "particles %lld and %lld 0.5e-4 r0 apart: evaluated, finite", (long long)a,
             (long long)b);
    dense(&F.sys.A, nd, Kd);
    double h = 1e-4 * PS_ARM_LENGTH_ROUNDING * r0, num = 0, den = 0;
    ps_int cols[4] = {a * d, a * d + 1, b * d, b * d + 1};
    for (int c = 0; c < 4; c++) {
      ps_int j = cols[c];
      double u0 = u[j];
      u[j] = u0 + h;
      ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, fp, &E, 0, &ctx);
      u[j] = u0 - h;
      ps_system_eval(&F.sys, &F.model, &F.st, F.P.x, u, fm, &E, 0, &ctx);
      u[j] = u0;
      for (ps_int r = 0; r < nd; r++) {
        double kfd = (fp[r] - fm[r]) / (2 * h);
        num += (kfd - Kd[r * nd + j]) * (kfd - Kd[r * nd + j]);
        den += Kd[r * nd + j] * Kd[r * nd + j];
      }
    }
    ps_check_le(sqrt(num / den), 1e-6,
                "crushed arm (0.5 e r0 long): tangent vs central differences in its dofs");
  }
  free(u);
  free(f);
  free(fp);
  free(fm);
  free(Kd);
  teardown(&F);
}

/* the particle nearest the point c */
static ps_int nearest_particle(const ps_particles *P, const double *c) {
  ps_int a = 0;
  double best = INFINITY;
  for (ps_int p = 0; p < P->n; p++) {
    double r = 0;
    for (int k = 0; k < P->dim; k++) r += (P->x[p * P->dim + k] - c[k]) * (P->x[p * P->dim + k] - c[k]);
    if (r < best) {
      best = r;
      a = p;
    }
  }
  return a;
}


/* Kd[nf x nf] (the free tangent of S, dense) less the springs of S's
 * loose particles: the spring-free tangent */
static void remove_springs(const ps_system *S, double *Kd) {
  int d = S->dim;
  ps_int nf = S->n_free;
  for (ps_int p = 0; p < S->net->n_particle; p++) {
    if (!S->free_body[p]) continue;
    for (int be = 0; be < d; be++)
      for (int al = 0; al < d; al++) {
        ps_int r = S->free_of_dof[p * d + al], c = S->free_of_dof[p * d + be];
        if (r >= 0 && c >= 0) Kd[r * nf + c] -= S->spring * S->free_proj[d * d * p + be * d + al];
      }
  }
}

/* A particle held by one arm (or collinear arms: a crack face's sliver):
 * on the network at rest (no tensions), the particle nearest the centre
 * keeps only its shortest arm, of direction q. No arm resists its motion
 * across q, so without a spring the free tangent is singular (smallest
 * eigenvalue below 1e-13 of the largest: round-off); ps_system_eval marks
 * it loose in the d - 1 directions across q (projector I - q q^T to 1e-12,
 * no other particle loose), the spring makes the tangent positive definite (smallest
 * eigenvalue above 1e-9 of the largest: the lattice's own conditioning),
 * and the matrix-free product carries the same spring (1e-13). */
static void loose_particle(const ps_model_type *type, int dim, int plane, double nu,
                           const char *label) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  fixture F;
  setup(&F, type, PS_YIELD_TOTAL, dim, plane, nu, &ctx);
  int d = dim;
  const double c[3] = {3.5e-3, 3.0e-3, 2.5e-3};
  ps_int nd = F.sys.n_dof, a = nearest_particle(&F.P, c);
  /* its shortest arm is the one left (the network is jittered: no two
   * arms are collinear) */
  ps_int keep = F.net.fam_arm[F.net.fam_ptr[a]];
  for (ps_int k = F.net.fam_ptr[a]; k < F.net.fam_ptr[a + 1]; k++) {
    ps_int i = F.net.fam_arm[k];
    if (F.net.r0[i] < F.net.r0[keep]) keep = i;
  }
  for (ps_int k = F.net.fam_ptr[a]; k < F.net.fam_ptr[a + 1]; k++)
    F.st.broken[F.net.fam_arm[k]] = F.net.fam_arm[k] != keep;
  double q[3];
  for (int k = 0; k < d; k++)
    q[k] = (F.P.x[F.net.b[keep] * d + k] - F.P.x[F.net.a[keep] * d + k]) / F.net.r0[keep];
  ps_system S;
  clamp_left(&F, &S, &ctx);
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f), E;
  if (ps_system_eval(&S, &F.model, &F.st, F.P.x, u, f, &E, PS_EVAL_TANGENT, &ctx)) abort();
  /* the marks */
  int others = 0;
  for (ps_int p = 0; p < F.P.n; p++) others += p != a && S.free_body[p];
  double perr = 0;
  for (int be = 0; be < d; be++)
    for (int al = 0; al < d; al++)
      perr = fmax(perr, fabs(S.free_proj[d * d * a + be * d + al] - ((al == be) - q[al] * q[be])));
  ps_check(S.free_body[a] == d - 1 && others == 0 && perr <= 1e-12 && S.loose_max == 1 &&
               S.fragments_max == 0,
           "%s: particle %lld hanging on one arm: loose in %d direction(s) (want %d), "
           "projector I - q q^T to %.1e, %d other loose particles (counted %lld, fragments %lld)",
           label, (long long)a, S.free_body[a], d - 1, perr, others, (long long)S.loose_max,
           (long long)S.fragments_max);
  /* the free tangent with and without the spring */
  ps_int nf = S.n_free;
  double *Kd = calloc((size_t)(nf * nf), sizeof *Kd), lmin, lmax, l0min, l0max;
  dense(&S.A, nf, Kd);
  eig_range(nf, Kd, &lmin, &lmax);
  remove_springs(&S, Kd);
  eig_range(nf, Kd, &l0min, &l0max);
  ps_check(S.spring > 0 && lmin > 1e-9 * lmax && fabs(l0min) < 1e-13 * l0max,
           "%s: the tangent without the spring is singular (smallest eigenvalue %.2e of the "
           "largest), with it positive definite (%.2e)",
           label, l0min / l0max, lmin / lmax);
  /* the matrix-free product */
  double *x = calloc((size_t)nd, sizeof *x), *y = calloc((size_t)nd, sizeof *y);
  double *yref = calloc((size_t)nd, sizeof *yref);
  for (ps_int j = 0; j < nd; j++) x[j] = sin(1.0 + 7.0 * (double)j);
  ps_system_apply(&S, x, y);
  kfull_product(&S, x, yref);
  ps_check_le(rel_diff(nd, y, yref), 1e-13,
              "matrix-free K x with the loose particle's spring = Kfull x");
  free(x);
  free(y);
  free(yref);
  free(Kd);
  free(u);
  free(f);
  ps_system_free(&S);
  teardown(&F);
}

/* a loose group: three particles joined by their three arms, every other
 * arm of theirs broken (a fragment cut off by cracks), on the network at
 * rest, nothing of theirs prescribed. Each particle is held (2D: two
 * arms that span the plane), but the fragment's rigid motion costs
 * nothing: without springs the free tangent K0 is singular (smallest
 * eigenvalue below 1e-13 of the largest); ps_system_eval supports it
 * (its first particle in every direction, more across the line to the
 * second: d (d + 1) / 2 directions at least), no particle outside it is
 * marked, and K = K0 + springs is positive definite (above 1e-9). The
 * springs are a determinate support: for a self-equilibrated right-hand
 * side r = K0 z (z arbitrary), du = K^-1 r satisfies K0 du = r (to 1e-9
 * relative: the springs carry no force), so a Newton step inside a
 * fragment is K0's, less its rigid motion. */
static void loose_group(const ps_model_type *type, int dim, int plane, double nu,
                        const char *label) {
  ps_ctx ctx;
  ps_ctx_init(&ctx);
  fixture F;
  setup(&F, type, PS_YIELD_TOTAL, dim, plane, nu, &ctx);
  int d = dim;
  const double c[3] = {4.5e-3, 3.0e-3, 2.5e-3};
  ps_int nd = F.sys.n_dof, a = nearest_particle(&F.P, c), tri[3] = {-1, -1, -1};
  ps_int keep[3] = {-1, -1, -1};
  /* the shortest pair of a's arms a-b, a-c whose ends b, c share an arm */
  double best = INFINITY;
  for (ps_int k1 = F.net.fam_ptr[a]; k1 < F.net.fam_ptr[a + 1]; k1++)
    for (ps_int k2 = k1 + 1; k2 < F.net.fam_ptr[a + 1]; k2++) {
      ps_int i1 = F.net.fam_arm[k1], i2 = F.net.fam_arm[k2];
      ps_int b = F.net.a[i1] == a ? F.net.b[i1] : F.net.a[i1];
      ps_int cc = F.net.a[i2] == a ? F.net.b[i2] : F.net.a[i2];
      for (ps_int k3 = F.net.fam_ptr[b]; k3 < F.net.fam_ptr[b + 1]; k3++) {
        ps_int i3 = F.net.fam_arm[k3];
        if ((F.net.a[i3] == cc || F.net.b[i3] == cc) &&
            F.net.r0[i1] + F.net.r0[i2] + F.net.r0[i3] < best) {
          best = F.net.r0[i1] + F.net.r0[i2] + F.net.r0[i3];
          tri[0] = a, tri[1] = b, tri[2] = cc;
          keep[0] = i1, keep[1] = i2, keep[2] = i3;
        }
      }
    }
  if (tri[1] < 0) {
    ps_check(0, "%s: no triangle of arms at particle %lld", label, (long long)a);
    teardown(&F);
    return;
  }
  for (int t = 0; t < 3; t++)
    for (ps_int k = F.net.fam_ptr[tri[t]]; k < F.net.fam_ptr[tri[t] + 1]; k++) {
      ps_int i = F.net.fam_arm[k];
      F.st.broken[i] = i != keep[0] && i != keep[1] && i != keep[2];
    }
  ps_system S;
  clamp_left(&F, &S, &ctx);
  double *u = calloc((size_t)nd, sizeof *u), *f = calloc((size_t)nd, sizeof *f), E;
  if (ps_system_eval(&S, &F.model, &F.st, F.P.x, u, f, &E, PS_EVAL_TANGENT, &ctx)) abort();
  int others = 0, dirs = 0;
  for (ps_int p = 0; p < F.P.n; p++) {
    int in = p == tri[0] || p == tri[1] || p == tri[2];
    if (in) dirs += S.free_body[p];
    else others += S.free_body[p] != 0;
  }
  ps_check(dirs >= d * (d + 1) / 2 && others == 0 && S.fragments_max == 1,
           "%s: the fragment of particles %lld, %lld, %lld is supported in %d directions "
           "(at least %d), %d particles outside it marked, %lld fragment(s) counted",
           label, (long long)tri[0], (long long)tri[1], (long long)tri[2], dirs,
           d * (d + 1) / 2, others, (long long)S.fragments_max);
  ps_int nf = S.n_free;
  double *K = calloc((size_t)(nf * nf), sizeof *K), *K0 = calloc((size_t)(nf * nf), sizeof *K0);
  double lmin, lmax, l0min, l0max;
  dense(&S.A, nf, K);
  memcpy(K0, K, (size_t)(nf * nf) * sizeof *K);
  remove_springs(&S, K0);
  eig_range(nf, K, &lmin, &lmax);
  eig_range(nf, K0, &l0min, &l0max);
  ps_check(lmin > 1e-9 * lmax && fabs(l0min) < 1e-13 * l0max,
           "%s: the tangent without the springs is singular (smallest eigenvalue %.2e of the "
           "largest), with them positive definite (%.2e)",
           label, l0min / l0max, lmin / lmax);
  /* the springs carry no force under a self-equilibrated load */
  double *z = calloc((size_t)nf, sizeof *z), *r = calloc((size_t)nf, sizeof *r);
  double *du = calloc((size_t)nf, sizeof *du), num = 0, den = 0;
  for (ps_int k = 0; k < nf; k++) z[k] = cos(3.0 + 5.0 * (double)k);
  for (ps_int i = 0; i < nf; i++)
    for (ps_int k = 0; k < nf; k++) r[i] += K0[i * nf + k] * z[k];
  gsl_matrix_view Kv = gsl_matrix_view_array(K, (size_t)nf, (size_t)nf);
  gsl_vector_view rv = gsl_vector_view_array(r, (size_t)nf), xv = gsl_vector_view_array(du, (size_t)nf);
  gsl_linalg_cholesky_decomp1(&Kv.matrix);
  gsl_linalg_cholesky_solve(&Kv.matrix, &rv.vector, &xv.vector);
  for (ps_int i = 0; i < nf; i++) {
    double y = 0;
    for (ps_int k = 0; k < nf; k++) y += K0[i * nf + k] * du[k];
    num += (y - r[i]) * (y - r[i]);
    den += r[i] * r[i];
  }
  ps_check(sqrt(num / den) <= 1e-9,
           "%s: K^-1 of a self-equilibrated load solves K0 du = r (%.1e, want <= 1e-9)", label,
           sqrt(num / den));
  free(z);
  free(r);
  free(du);
  free(K);
  free(K0);
  free(u);
  free(f);
  ps_system_free(&S);
  teardown(&F);
}

int main(void) {
  const int T = PS_YIELD_TOTAL, D = PS_YIELD_DEVIATORIC;
  run_case(ps_model_fibre, T, 2, PS_PLANE_STRAIN, 0.3, "fibre, 2D plane strain nu=0.3");
  run_case(ps_model_fibre, T, 2, PS_PLANE_STRESS, 0.12,
           "fibre, 2D plane stress nu=0.12 (N K < G(N+2))");
  run_case(ps_model_fibre, T, 3, PS_SOLID_3D, 0.27, "fibre, 3D nu=0.27");
  /* the deviatoric reading: per half-arm yield, two rank-one family terms */
  run_case(ps_model_fibre, D, 2, PS_PLANE_STRAIN, 0.3, "fibre deviatoric, 2D plane strain");
  run_case(ps_model_fibre, D, 2, PS_PLANE_STRESS, 0.12, "fibre deviatoric, 2D plane stress");
  run_case(ps_model_fibre, D, 3, PS_SOLID_3D, 0.27, "fibre deviatoric, 3D");
  /* the lattice models on the same irregular network (elastic) */
  run_case(ps_model_bond, T, 2, PS_PLANE_STRESS, 1.0 / 3.0, "bond, 2D plane stress");
  run_case(ps_model_bond, T, 3, PS_SOLID_3D, 0.25, "bond, 3D");
  run_case(ps_model_state, T, 2, PS_PLANE_STRAIN, 0.3, "state, 2D plane strain nu=0.3");
  run_case(ps_model_state, T, 2, PS_PLANE_STRESS, 0.12, "state, 2D plane stress nu=0.12");
  run_case(ps_model_state, T, 3, PS_SOLID_3D, 0.27, "state, 3D nu=0.27");
  /* the horizon models on a point cloud (the horizon in m, cells from the
   * volumes, arms broken by the critical stretch) */
  run_case_cloud(ps_model_bond, T, 2, PS_PLANE_STRESS, 1.0 / 3.0, 1,
                 "bond on a cloud, 2D plane stress, fracture");
  run_case_cloud(ps_model_bond, T, 3, PS_SOLID_3D, 0.25, 1, "bond on a cloud, 3D, fracture");
  run_case_cloud(ps_model_state, T, 2, PS_PLANE_STRAIN, 0.25, 1,
                 "state on a cloud, 2D plane strain nu=0.25, fracture");
  run_case_cloud(ps_model_state, T, 3, PS_SOLID_3D, 0.27, 1, "state on a cloud, 3D, fracture");
  /* the threebody model (arm rotations): nu = 0.2 in both planes, kappa
   * = 0 (plane stress 1/3), and on a cloud with the micropotential
   * criterion; the lattice cases with the surface correction */
  run_case(ps_model_threebody, T, 2, PS_PLANE_STRESS, 0.2, "threebody, plane stress nu=0.2");
  run_case(ps_model_threebody, T, 2, PS_PLANE_STRAIN, 0.2, "threebody, plane strain nu=0.2");
  run_case(ps_model_threebody, T, 2, PS_PLANE_STRESS, 1.0 / 3.0,
           "threebody, plane stress nu=1/3 (kappa = 0)");
  run_case_cloud(ps_model_threebody, T, 2, PS_PLANE_STRESS, 0.25, 1,
                 "threebody on a cloud, plane stress nu=0.25, fracture");
  crushed_arm();
  loose_particle(ps_model_bond, 2, PS_PLANE_STRESS, 1.0 / 3.0, "bond 2D");
  loose_particle(ps_model_fibre, 2, PS_PLANE_STRAIN, 0.3, "fibre 2D");
  loose_particle(ps_model_state, 3, PS_SOLID_3D, 0.27, "state 3D");
  loose_particle(ps_model_bond, 3, PS_SOLID_3D, 0.25, "bond 3D");
  loose_group(ps_model_bond, 2, PS_PLANE_STRESS, 1.0 / 3.0, "fragment, bond 2D");
  loose_group(ps_model_fibre, 2, PS_PLANE_STRAIN, 0.3, "fragment, fibre 2D");
  loose_group(ps_model_bond, 3, PS_SOLID_3D, 0.25, "fragment, bond 3D");
  return ps_check_summary();
}
