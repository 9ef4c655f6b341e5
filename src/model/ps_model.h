/* ps_model.h: material models in arm-length space. A model maps the current
 * arm lengths l to arm tensions T (N, per unit thickness in 2D), the stored
 * energy, and the tangent dT/dl as a diagonal plus one rank-one term per
 * particle family:
 *   dT_i/dl_j = D_i delta_ij + sum_a c_a w_{a,i} w_{a,j},
 * with w_a supported on a's family (the arms incident to a). Assembly owns
 * the geometry (directions q, geometric stiffness, dof map). A new model is
 * one file with one ps_model_type table. Models receive the elongations
 * dl = l - r0 (computed without cancellation, so strains of 1e-9 keep
 * full precision). */
#ifndef PS_MODEL_H
#define PS_MODEL_H

#include "../network/ps_network.h"

enum ps_plane { PS_PLANE_STRAIN = 0, PS_PLANE_STRESS = 1, PS_SOLID_3D = 2 };
/* The breaking criterion of the bond and state models (the fibre model
 * breaks by plastic elongation, material.delta, Eq. 118). */
enum ps_fracture {
  PS_FRACTURE_NONE = 0,    /* arms never break */
  PS_FRACTURE_STRETCH = 1, /* s = dl / xi > s0 (Silling & Askari 2005) */
  PS_FRACTURE_ENERGY = 2   /* the arm's micropotential w > w_c, in tension
                              (the energy criterion of MODEL-NOTES) */
};
/* The bond model's micromodulus c(xi). */
enum ps_micromodulus {
  PS_MICRO_CONICAL = 0, /* c0 (1 - xi/delta), Fallah et al. 2020 Eq. 7 */
  PS_MICRO_CONSTANT = 1 /* c, Silling & Askari's PMB, as Peridigm's "Elastic
                           Bond Based" */
};
enum ps_yield_rule {
  PS_YIELD_TOTAL = 0,      /* Eq. 111 as printed: |eps - eps_p| > eps_y */
  PS_YIELD_DEVIATORIC = 1  /* |eps - epsbar_a - eps_p,a| > eps_y per half-arm
                              (MODEL-NOTES; fibre.c) */
};

/* How the fibre model's Eq. 118 measures an arm against delta. */
enum ps_break_rule {
  PS_BREAK_ELONGATION = 0, /* eps_p r0 > delta: Eq. 118 as printed, the
                              arm's own plastic elongation (the default) */
  PS_BREAK_STRAIN = 1,     /* eps_p > delta / L, L = break_length fixed
                              for every arm: a critical plastic strain */
  PS_BREAK_TOUGHNESS = 2   /* eps_p r0 > delta sqrt(r0 / L): the limit
                              elongation grows as sqrt(r0), the scaling
                              of the crack-face opening an arm of length
                              r0 spans at the tip (K sqrt(r0)) */
};

/* Material parameters (SI). */
typedef struct ps_material {
  double E;            /* Young's modulus, Pa (> 0) */
  double nu;           /* Poisson's ratio, in (-1, 0.5) (< 0.5) */
  int plane;           /* enum ps_plane; 3D needs PS_SOLID_3D */
  double yield_strain; /* eps_y (> 0); ignored when plastic == 0 */
  int plastic;         /* 0: elastic arms, 1: return mapping Eq. 111 */
  double delta;        /* plastic elongation limit, m (Eq. 118); <= 0 or
                          inf: arms never break */
  double rho;          /* density, kg/m^3; uniform, so it drops out of the
                          forces; gives the masses in particles.csv */
  int yield_rule;      /* enum ps_yield_rule */
  int break_rule;      /* enum ps_break_rule (fibre) */
  double break_length; /* L, m (> 0) for PS_BREAK_STRAIN and
                          PS_BREAK_TOUGHNESS; 0 otherwise */
  /* the horizon models (bond, state, threebody; type->lattice): */
  double horizon;      /* delta, m: arms r <= horizon carry force (Eq. 7).
                          In a case: material.horizon when given (> 0),
                          else 0 and the set-up makes it
                          material.horizon_factor spacings */
  double spacing;      /* the cell size Delta x of every particle in the
                          partial volumes (Li & Hao Eq. A.2), m: the
                          lattice constant of a box lattice; 0 on a point
                          cloud (or the disk): each particle b's own cell
                          size V_b^(1/N) (ps_cell_size) */
  int surface_correction; /* < 0: unset, the model's default (bond,
                             threebody: on; fibre, state: off); 0: off;
                             1: on. Bond, threebody: the energy-based
                             surface correction of Li & Hao (2023, Eq.
                             A.3-A.6); fibre, state: the moduli
                             correction (ps_moduli.h, doc/moduli.md) */
  int micromodulus;    /* enum ps_micromodulus (bond) */
  int full_volumes;    /* 1: every neighbour within the horizon counts in
                          full (Peridigm's default); 0: the partial volumes
                          of Li & Hao Eq. A.2 (bond, state, threebody) */
  /* bond, state and threebody models: breaking (enum ps_fracture;
   * threebody: the energy criterion only). The criterion is
   * given as s0, as w_c or as a fracture energy G_c that the model's
   * prepare converts (ps_fracture_from_energy). */
  int fracture;
  double critical_stretch;        /* s0 (> 0) */
  double critical_micropotential; /* w_c, J/m^6 in 3D, J/m^5 in 2D (per unit
                                     thickness, areas as volumes) */
  double fracture_energy;         /* G_c, J/m^2 (> 0), or 0: s0 or w_c given */
  double softening_ratio;         /* bond, stretch criterion: r = s1/s0 > 1,
                                     the arm softens linearly from s0 to
                                     zero force at s1 = r s0, unloads
                                     towards the origin (damage) and breaks
                                     at s1; with fracture_energy, s0 is the
                                     brittle s0 over sqrt(r), so that each
                                     arm dissipates the same energy. 0:
                                     brittle, the arm breaks at s0 */
  /* derived by ps_material_finish: */
  double G;            /* shear modulus, Eq. 78 */
  double K;            /* bulk modulus: Eq. 79 (3D), 80 (plane stress),
                          81 (plane strain) */
  double kappa;        /* Kolosov constant for Eq. 116 */
  double sigma_y;      /* nominal yield stress E eps_y */
} ps_material;

/* The accepted range of Young's modulus, Pa: far beyond any material's
 * (rubber 1e6, steel 2.1e11, diamond 1.2e12) and any unit system's
 * rescaling, and far inside what the solver's sums of squares of forces
 * hold without overflow (E up to about 1e150). */
#define PS_E_MIN 1e-20
#define PS_E_MAX 1e20
/* The accepted range of the yield strain eps_y (a strain; steel: 0.002). */
#define PS_YIELD_STRAIN_MIN 1e-9
#define PS_YIELD_STRAIN_MAX 1.0

/* The accepted range of a critical stretch s0. */
#define PS_STRETCH_MIN 1e-9
#define PS_STRETCH_MAX 10.0

/* Check the parameters (E in [PS_E_MIN, PS_E_MAX], nu in (-1, 0.5), with
 * plasticity eps_y in [PS_YIELD_STRAIN_MIN, PS_YIELD_STRAIN_MAX], rho >
 * 0) and fill the derived ones, which must come out finite and positive
 * (G, K, sigma_y; kappa finite). Returns PS_OK or PS_ERR_INPUT with a
 * message naming the parameter ("material.E must be ..."), without the
 * file: the caller adds it. */
int ps_material_finish(ps_material *m, int dim, ps_ctx *ctx);

/* Per-arm state shared by all models. */
typedef struct ps_arm_state {
  ps_int n_arm;
  double *eps_p;          /* [2 n_arm] committed plastic strain (of the last
                             converged state): [i] the arm's (total reading)
                             or its a-side's, [n_arm + i] its b-side's
                             (deviatoric reading); bond with softening:
                             [i] the largest elongation reached, m (its
                             damage history) */
  double *eps_p_trial;    /* [2 n_arm] from the last evaluate (return
                             mapping from eps_p) */
  unsigned char *broken;  /* 1: arm broken (Eq. 118 or the model's
                             criterion), carries nothing */
  double *stretch;        /* [n_arm] dl / r0 of the last evaluate, written
                             by the models whose criterion reads it (bond,
                             state; threebody: in tension the stretch s_eq
                             whose 1/2 c R xi s_eq^2 is the arm's
                             micropotential, stretch and shear) */
  double broken_energy;   /* the stored energy of the arms when they broke,
                             summed, J (per unit thickness in 2D); NAN when
                             the model's energy does not split into arms
                             (type->arm_energy NULL) */
  unsigned char *yielding;/* 1: on the yield surface in the last evaluate */
} ps_arm_state;

/* The plastic strain of arm i for output and breaking: eps_p[i] (total
 * reading) or the mean of its two sides (deviatoric reading). */
double ps_arm_plastic_strain(const ps_arm_state *st, ps_int i, int yield_rule);

int ps_arm_state_alloc(ps_arm_state *st, ps_int n_arm, ps_ctx *ctx);
void ps_arm_state_free(ps_arm_state *st);
/* Copy st into dst (both allocated for the same n_arm). */
void ps_arm_state_copy(ps_arm_state *dst, const ps_arm_state *st);

/* The items of st for a checkpoint (ps_state_list, ps_util.h), named
 * prefix + field: every array and broken_energy. Returns PS_OK or
 * ps_state_add's status. */
int ps_arm_state_list(ps_arm_state *st, const char *prefix, ps_state_list *l, ps_ctx *ctx);

/* Tangent in arm-length space (see top of file). */
typedef struct ps_arm_tangent {
  double *D;  /* [n_arm] N/m */
  double *c;  /* [n_particle] family coefficient */
  double *w;  /* [2 n_arm] aligned with net->fam_arm */
  double *c2; /* [n_particle] a second rank-one family term c2 w2 w2^T
                 (deviatoric reading), 0 when unused */
  double *w2; /* [2 n_arm] */
  /* models with arm rotations (ps_model_type.rotations; threebody):
   * Dr[i] = d^2 Psi / d theta_i^2 of the arm terms (N m per radian^2,
   * per unit thickness), allocated by the assembly on first use (NULL
   * for the other models); rot[term] = 1: family term `term` acts on the
   * arm rotations theta (its w are weights of dtheta/dy), 0: on the arm
   * lengths */
  double *Dr;
  unsigned char rot[2];
} ps_arm_tangent;

int ps_arm_tangent_alloc(ps_arm_tangent *t, const ps_network *net, ps_ctx *ctx);
void ps_arm_tangent_free(ps_arm_tangent *t);

typedef struct ps_model ps_model;

/* The operations every model provides. */
typedef struct ps_model_type {
  const char *name;
  /* T[i], *energy (J, per unit thickness in 2D) and, when tan != NULL, the
   * tangent, at arm elongations dl[i] = l_i - r0_i (m); writes
   * st->eps_p_trial and st->yielding. Broken arms get T = 0 and no
   * stiffness. Returns PS_OK. */
  int (*evaluate)(const ps_model *m, const double *dl, ps_arm_state *st,
                  double *T, double *energy, ps_arm_tangent *tan, ps_ctx *ctx);
  /* How far arm i of the last evaluate is past the model's breaking
   * criterion, relative to the criterion's limit: the arm's measure over
   * its limit, less one (fibre: eps_p r0 / delta - 1, Eq. 118; bond,
   * state: s / s0 - 1), so > 0 breaks it, the larger the further, and
   * path.control event finds the load at which the largest is 0. Read
   * only when ps_material_breaks; -1 for a broken arm. */
  double (*break_excess)(const ps_model *m, const ps_arm_state *st, ps_int i);
  /* 1: break_excess reads arm i's own state only (its stretch, its
   * plastic strain under the total yield rule), so that a process holding
   * a copy of the arm (a ghost's) judges it as its owner does (breaking
   * on a distributed model, ps_model_breaks_alike) */
  int break_local;
  /* Optional (NULL: the energy does not split into arms): the stored
   * energy of intact arm i at the last evaluate, J (per unit thickness in
   * 2D), summed into st->broken_energy when it breaks (bond: 1/2 k dl^2,
   * the micropotential times V_a V_b v). */
  double (*arm_energy)(const ps_model *m, const ps_arm_state *st, ps_int i);
  /* Optional (NULL: the model dissipates nothing it can measure): the
   * energy arm i dissipates from the committed state `c` to the state of
   * the last evaluate `st` at elongation dl (m), J (per unit thickness in
   * 2D), and in *dD its derivative with respect to dl there, N (the rate
   * of further loading; an arm at its committed damage that would load
   * on counts as loading). Bond with softening: 1/2 dl0 (k kappa -
   * T_env(kappa)) at the largest elongation kappa, minus its committed
   * value. */
  double (*arm_dissipation)(const ps_model *m, const ps_arm_state *c, const ps_arm_state *st,
                            ps_int i, double dl, double *dD);
  /* Optional (NULL: whenever arm_dissipation is there): 0 when this
   * instance's arm_dissipation is 0 for every arm and state (bond without
   * softening, elastic fibre), so that its sum over the arms is skipped:
   * the same 0. */
  int (*dissipates)(const ps_model *m);
  /* Optional (NULL: nothing to do): check the parameters against the
   * network, precompute per-arm data into m->arm_k and allocate m->work.
   * Returns PS_OK, PS_ERR_INPUT (message names the parameter),
   * PS_ERR_NOMEM. */
  int (*prepare)(ps_model *m, const ps_particles *P, ps_ctx *ctx);
  /* The reach of the tangent's coupling: 1 when it has rank-one family
   * terms (c != 0; fibre, state), which couple every two particles of a
   * family, so the assembly needs the two-horizon pattern; 0: arms only,
   * the one-horizon pattern (bond). */
  int family_coupling;
  /* 1: a horizon model (bond, state; the name is historical: they were
   * defined on box lattices only): arms carry force within a horizon
   * delta, a length (material.horizon) or material.horizon_factor
   * spacings, and every particle has the same size h, so that the
   * network's rule r < alpha max(h_a, h_b) is r < alpha h, the model's
   * reach. On a box lattice h is the lattice spacing and alpha
   * ps_model_lattice_reach spacings; on a point cloud or the disk h is
   * the mean spacing (ps_mean_spacing) and alpha ps_model_cloud_reach /
   * h (app/setup.c). 0: sizes from Eq. 115 or Eq. 44 and the case's
   * alpha (fibre). */
  int lattice;
  /* Horizon models: how far past the horizon arms reach, in cells
   * (spacings): 1/2 when the partial volumes of Li & Hao (2023) Eq. A.2
   * carry arms up to the horizon plus half a cell (state), 0 when an arm
   * ends at the horizon (bond: c(xi) = 0 there for the conical
   * micromodulus; the constant one is cut there as Peridigm does). */
  double reach_extra_spacings;
  /* Optional (NULL: nu is free): the Poisson's ratio the model fixes in
   * dim dimensions (plane: enum ps_plane), for the check that refuses
   * another one when the case is read (bond: 1/3 in plane stress, 1/4 in
   * plane strain and 3D, Fallah et al. 2020 section 5). */
  double (*fixed_poisson)(int dim, int plane);
  /* 1: the energy depends on the arm rotations theta_i as well as on the
   * lengths (threebody, 2D): the assembly calls evaluate_rot instead of
   * evaluate, with theta_i = atan2(n x y, n . y) (n the reference
   * direction, y the current arm vector, unrounded), and the arm forces
   * are not central: T q + M r on b, r = dtheta/dy_b = (z x y)/|y|^2. 0:
   * evaluate, central forces (fibre, bond, state). */
  int rotations;
  /* the evaluation of a model with rotations: as evaluate, plus the arm
   * rotations th[n_arm] (rad) in and the arm moments M[i] = dPsi/dtheta_i
   * (N m per unit thickness) out; the tangent gains tan->Dr and the
   * family terms may act on rotations (tan->rot). NULL when !rotations. */
  int (*evaluate_rot)(const ps_model *m, const double *dl, const double *th,
                      ps_arm_state *st, double *T, double *M, double *energy,
                      ps_arm_tangent *tan, ps_ctx *ctx);
} ps_model_type;

struct ps_model {
  const ps_model_type *type;
  const ps_network *net;
  ps_material mat;
  double *R;       /* [n_particle] workspace: sum_b A_ab r0_ab */
  double *epsbar;  /* [n_particle] mean strain of the last evaluate */
  double *arm_k;   /* [n_arm] per-arm constants of models that prepare
                      them (bond: stiffness dT/dl, N/m; state: w v V_a
                      V_b), else NULL; read-only after prepare */
  double *arm_s0;  /* [n_arm] critical stretch per arm (bond, state with
                      material.fracture), else NULL */
  double *arm_side;/* [2 n_arm] state model on a cloud with partial
                      volumes: arm i's weight w v V_a V_b in the
                      dilatation of its end a ([i], v the share of b's
                      cell in a's horizon) and of its end b ([n_arm + i]);
                      NULL when both are arm_k[i] (every lattice, full
                      volumes, no moduli correction); fibre with the
                      moduli correction: the corrected half-arm weights
                      A_ab phi ([i]) and A_ba phi ([n_arm + i]), else
                      NULL; read-only after prepare */
  double *work;    /* scratch of evaluate for models that need it
                      (deviatoric fibre rule: [4 n_arm + 2 n_particle],
                      psi' and psi'' per half-arm, their family means),
                      else NULL; like R and epsbar, written by evaluate
                      through the const model */
  ps_team *team;   /* threads of evaluate for a model that splits its
                      loops (fibre), not owned; NULL: the calling thread */
  int parts;       /* the parts of those loops (ps_model_set_team; 0 or
                      1: one): the numbers depend on the parts, never on
                      the team */
  /* A share of a distributed model (doc/design-distributed.md): the
   * network is a process's owned particles and their ghosts, and only
   * the arms and particles this process owns count in the energy, the
   * dissipation and the counts of arms (each arm and particle of the
   * whole model is owned by one process); forces and tangent rows at
   * owned particles are complete without masks. NULL: every arm
   * (particle) is owned, one process. Not owned by the model. */
  const unsigned char *own_arm;      /* [n_arm] 1: owned */
  const unsigned char *own_particle; /* [n_particle] 1: owned */
  const ps_int *global;              /* [n_particle] each particle's number
                                        in the whole model (the worst arms
                                        over the processes are named by
                                        their ends' numbers); NULL: its
                                        own (one process) */
  struct ps_arm_halo *arm_halo;      /* a share's arms' broken flags from
                                        their owners (criteria not judged
                                        alike, ps_model_breaks_alike);
                                        NULL: none. Not owned by the model */
  const struct ps_model_given *given;/* constants prepare takes instead of
                                        computing them (ps_model_create_given);
                                        NULL: computed */
};

/* Per-arm constants a model takes from outside instead of computing them
 * in its prepare: on a share of a distributed model, the whole model's
 * where they read the whole cloud (ps_model_whole_constants), mapped to
 * the share's arms by ps_model_share_constants. Arrays over the share's
 * arms, borrowed (they must outlive the model's prepare only: it copies
 * them). */
typedef struct ps_model_given {
  const double *arm_k;    /* [n_arm] the state model's arm_k, else NULL */
  const double *arm_side; /* [2 n_arm] the fibre and state models' arm_side */
} ps_model_given;

/* The arms of a share as the items of a halo (ps_halo): its own arms
 * first, then the others, each named by its ends' numbers in the whole
 * model (ga < gb: ga n_global + gb) and asked of the process owning its
 * lower end, which owns the arm (ps_share). Breaking sends the owners'
 * broken flags to the other copies through it. */
typedef struct ps_arm_halo {
  ps_halo h;
  ps_int *order; /* [n_arm] the local arm at each position */
  ps_int n_own;
  double *x;     /* [n_arm] the flags exchanged, by position */
} ps_arm_halo;

/* The arm halo of model m (own_arm and global set) on the processes of
 * comm: owner[n_particle] the process of each local particle, n_global
 * the whole model's particles. Collective. PS_OK, PS_ERR_INPUT (the
 * halo's, or more than 3e9 particles), PS_ERR_NOMEM (*ah then empty). */
int ps_arm_halo_create(ps_arm_halo *ah, const ps_model *m, const int *owner, ps_int n_global,
                       const ps_comm *comm, ps_ctx *ctx);
void ps_arm_halo_free(ps_arm_halo *ah);

/* 1 when arm i (particle a) is this process's: its energy and counts are
 * the process's share (ps_model.own_arm, own_particle) */
static inline int ps_model_owns_arm(const ps_model *m, ps_int i) {
  return !m->own_arm || m->own_arm[i];
}
static inline int ps_model_owns_particle(const ps_model *m, ps_int a) {
  return !m->own_particle || m->own_particle[a];
}

/* Split the loops of m's evaluate into `parts` parts run on `team` (a
 * model that does not split its loops ignores both): the energy's sums
 * are then formed part by part in the parts' order, other round-off than
 * one part's. */
void ps_model_set_team(ps_model *m, ps_team *team, int parts);

/* The virtual-fibre model: Eq. 110 force flux density with the
 * energy-consistent mean strain epsbar_a = sum_b A_ab r0 eps_ab / sum_b A_ab
 * r0, return mapping Eq. 111, breaking Eq. 118. */
extern const ps_model_type *const ps_model_fibre;

/* Bond-based peridynamics (Fallah et al. 2020): pairwise force c s V_a V_b
 * with the conical micromodulus of Eq. 7, c(xi) = c0 (1 - xi/delta),
 * c0 = 48 K / (pi delta^3) in 2D (= 24 E / (pi delta^3 (1 - nu)) in plane
 * stress, per unit thickness) and 90 K / (pi delta^4) in 3D, or the
 * constant one of the PMB model, c = 12 K / (pi delta^3) in 2D and
 * 18 K / (pi delta^4) in 3D; partial volumes at the horizon (Li & Hao Eq.
 * A.2) or full ones, and, optionally, the energy-based surface correction
 * (Eq. A.3-A.6). Arms break by critical stretch or micropotential
 * (material.fracture). nu is fixed: 1/3 in plane stress, 1/4 in plane
 * strain and 3D. */
extern const ps_model_type *const ps_model_bond;

/* 1 when the material has a breaking criterion: a finite delta > 0
 * (fibre, Eq. 118) or material.fracture (bond, state). */
int ps_material_breaks(const ps_material *mat);

/* The intact arms of st past the model's criterion (break_excess > 0),
 * of those m owns (own_arm); 0 when !ps_material_breaks. */
ps_int ps_model_count_past(const ps_model *m, const ps_arm_state *st);

/* After a converged, committed state: mark the arms past the model's
 * criterion (type->break_excess > 0) as broken and set *n_broken to how
 * many broke now; nothing when !ps_material_breaks. With max_count > 0,
 * only the max_count arms past it by the most, ties by the arm's number
 * in the whole model (a gentler step when re-equilibration after
 * breaking them all fails); adds their energy (of the arms m owns) to
 * st->broken_energy. On several processes (ctx->comm) every count and
 * choice is the run's and each process marks its copies, own and ghost
 * (collective; m->global names the arms; where !ps_model_breaks_alike
 * each process judges its own arms and m->arm_halo brings the owners'
 * flags to the other copies). One mechanism for every model
 * (model/breaking.c). Returns PS_OK, PS_ERR_INPUT (several processes,
 * !ps_model_breaks_alike and no arm halo) or PS_ERR_NOMEM (then no arm
 * is marked and *n_broken = 0). */
int ps_model_break_arms(const ps_model *m, ps_arm_state *st, ps_int max_count,
                        ps_int *n_broken, ps_ctx *ctx);

/* 1 when every process holding an arm judges it alike: the type's
 * criterion reads the arm's own state (ps_model_type.break_local) and
 * the yield rule is total (the deviatoric rule's plastic strains read
 * the family's mean strain, which a ghost's truncated family gets
 * wrong). Otherwise a distributed model's arms are judged by their
 * owners only, and the other copies take the owners' flags
 * (ps_model.arm_halo). */
int ps_model_breaks_alike(const ps_model_type *type, const ps_material *mat);

/* The largest break_excess over the intact arms of st that m owns (-1
 * when there is none, or when !ps_material_breaks): 0 at the load where
 * the next arm reaches its criterion. */
double ps_model_max_excess(const ps_model *m, const ps_arm_state *st);

/* break_excess of the stretch-type criteria (bond, state): st->stretch[i]
 * / m->arm_s0[i] - 1 (tension only; -1 for a broken arm). */
double ps_model_stretch_excess(const ps_model *m, const ps_arm_state *st, ps_int i);

/* The bond and state models' critical stretch per arm, m->arm_s0 (NULL
 * allocated here when mat.fracture is set): s0 for the stretch criterion;
 * for the energy criterion, the stretch at which the arm's micropotential
 * w = 1/2 cxi s^2 xi reaches w_c, with cxi[i] the arm's micromodulus (c(xi)
 * R, corrected; a zero cxi never breaks; cxi may be NULL for the stretch
 * criterion). An arm whose m->arm_k is 0 (it carries nothing: beyond the
 * horizon) never breaks. When mat.fracture_energy G_c is
 * set, s0 or w_c are first computed from it by the closed forms of
 * doc/fracture.md (model "bond" with the micromodulus of mat, or
 * "state"). Returns PS_OK, PS_ERR_INPUT (a combination without a closed
 * form), PS_ERR_NOMEM. */
int ps_model_fracture_prepare(ps_model *m, const double *cxi, ps_ctx *ctx);

/* Ordinary state-based linear elastic PD with the dilatation / deviatoric
 * split (pd-elastoplastic-animation-supplement, Eq. 26-47; Madenci &
 * Oterkus): W_a = a theta_a^2 + b sum_b w (e_ab)^2 V_b, theta_a = d sum_b
 * w e_ab V_b, influence w = delta / xi, e the arm elongation; 3D: a =
 * (K - 5G/3)/2, b = 15G/(2 pi delta^5), d = 9/(4 pi delta^4); 2D (per unit
 * thickness): a = (K - 2G)/2, b = 6G/(pi delta^4), d = 2/(pi delta^3), K
 * the 2D bulk modulus (Eq. 80/81). Partial volumes (Li & Hao A.2) or full
 * ones, no surface correction, any nu; arms break by critical stretch
 * (material.fracture) and then leave the dilatation sums. Tangent:
 * diagonal plus one rank-one term per family (the dilatation), like the
 * fibre model's epsbar. */
extern const ps_model_type *const ps_model_state;

/* The three-body model (bond stretch plus bond shear, Li & Hao 2023, in
 * the form of doc/design-threebody.md), 2D: Psi = sum_i [1/2 c k_i s_i^2
 * + 1/4 kappa (k_ai g_ai^2 + k_bi g_bi^2)], s the arm stretch, g_ai the
 * arm's rotation relative to the k-weighted mean rotation of a's family,
 * finite rotations; c = 12 K beta / (pi delta^3), kappa = 12 (G - lambda)
 * beta / (pi delta^3) (derived; >= 0 needs nu <= 1/3 in plane stress, <=
 * 1/4 in plane strain), beta the lattice factor; partial volumes (Eq.
 * A.2), surface correction (Eq. A.3-A.6, bulk-lattice W_inf), breaking
 * by the arm micropotential (criterion energy). See threebody.c. */
extern const ps_model_type *const ps_model_threebody;

/* The largest Poisson's ratio of the three-body model in a 2D plane
 * (kappa >= 0): 1/3 in plane stress, 1/4 in plane strain; the check
 * allows 1e-3 more (kappa then taken as 0). */
double ps_threebody_max_poisson(int plane);

/* The three-body model's own checks, shared by its prepare and the case
 * reader (which adds the file and line): nu within
 * ps_threebody_max_poisson (+1e-3), and breaking by the micropotential,
 * not a critical stretch (fracture != PS_FRACTURE_STRETCH). PS_OK or
 * PS_ERR_INPUT with "material.nu = ..." / "material.fracture: ..." in
 * ctx. */
int ps_threebody_poisson_check(double nu, int plane, ps_ctx *ctx);
int ps_threebody_fracture_check(int fracture, ps_ctx *ctx);

/* Li & Hao (2023) Eq. A.2: the share of a lattice cell of size dx at
 * distance xi inside a horizon delta (1 inside, 0 beyond, linear across
 * the horizon's edge). */
double ps_partial_volume(double xi, double delta, double dx);

/* The cell size of particle a in the partial volumes: mat->spacing on a
 * box lattice (> 0), else (a point cloud, the disk: mat->spacing = 0)
 * V_a^(1/N), the side of the square (cube) of the particle's volume. */
double ps_cell_size(const ps_material *mat, const ps_particles *P, ps_int a);

/* The partial volumes (Eq. A.2) of arm i (ends a, b) of a horizon model
 * in the horizon mat->horizon: *va the share of b's cell in a's horizon
 * (the weight of b in a's sums), *vb that of a's cell in b's horizon. On
 * a lattice (one cell size) *va == *vb. (Full volumes are the models'
 * own rule.) */
void ps_arm_partial_volumes(const ps_material *mat, const ps_particles *P,
                            const ps_network *net, ps_int i, double *va, double *vb);

/* The mean spacing of a cloud, m: (sum_a V_a / n)^(1/N), the side of the
 * square (cube) of the mean particle volume; on a box lattice of spacing
 * d it is d (to round-off). material.horizon_factor counts the horizon in
 * these on a point cloud or the disk. */
double ps_mean_spacing(const ps_particles *P);

/* The check of a model that fixes Poisson's ratio (type->fixed_poisson):
 * PS_OK when nu is free or within 1e-3 of the fixed value, else
 * PS_ERR_INPUT with "material.nu = 0.3: bond-based peridynamics has nu =
 * 1/3 in plane stress (Fallah et al. 2020, section 5)" in ctx. */
int ps_model_poisson_check(const ps_model_type *type, double nu, int dim, int plane,
                           ps_ctx *ctx);

/* Checks shared by the horizon models (bond, state): positions given, a
 * finite horizon > 0, a spacing >= 0 (0: cell sizes from the volumes),
 * elastic. Returns PS_OK or PS_ERR_INPUT naming the parameter. */
int ps_lattice_model_check(const ps_material *mat, int dim, const ps_particles *P,
                           const char *model, ps_ctx *ctx);

/* Look a model type up by name ("fibre", "bond", "state", "threebody");
 * NULL if unknown. */
const ps_model_type *ps_model_type_find(const char *name);

/* How far, in horizons (alpha max h), a share of a distributed model
 * (ps_share) must hold ghosts for its owned particles' forces and tangent
 * rows to be the whole model's: 1 for the arms of an owned particle, one
 * more for the family terms of its neighbours (family_coupling or
 * rotations), one more where an arm's constants read the families of its
 * ends (the bond and three-body surface correction). The constants of
 * ps_model_whole_constants are given to a share, not computed there.
 * tests/t755_share checks each value and that one horizon less is not
 * enough. */
int ps_model_share_horizons(const ps_model_type *type, const ps_material *mat);

/* 1 when the model's per-arm constants read the whole cloud, so that no
 * number of horizons of ghosts gives a share the whole model's: the fibre
 * and state moduli correction balances its weights over it
 * (ps_moduli_balance); a share takes them from the whole model
 * (ps_model_share_constants, ps_model_create_given). Else 0. */
int ps_model_whole_constants(const ps_model_type *type, const ps_material *mat);

/* The constants of the whole model `whole` (prepared on the whole
 * network) for the arms of a share's network `net`, whose particle k is
 * particle global[k] of the whole: *arm_k[net->n_arm] (NULL when whole
 * has none) and *arm_side[2 net->n_arm] (NULL likewise), an arm's sides
 * in the share's orientation; allocated here, the caller frees them.
 * Returns PS_OK, PS_ERR_INTERNAL (a share arm the whole network lacks),
 * PS_ERR_NOMEM. */
int ps_model_share_constants(const ps_model *whole, const ps_network *net,
                             const ps_int *global, double **arm_k, double **arm_side,
                             ps_ctx *ctx);

/* The reach of a lattice model's arms, in spacings, for a horizon of
 * horizon_factor spacings: m + e with m = horizon_factor, e =
 * reach_extra_spacings; for e > 0 just short of it, m + e (1 - 1e-9) (an
 * arm of exactly that length carries nothing: its partial volume is 0),
 * for e = 0 just beyond it, m (1 + 1e-9) (an arm of exactly the
 * horizon's length is in), so that lattice round-off does not decide. */
double ps_model_lattice_reach(const ps_model_type *type, double horizon_factor);

/* The reach of a horizon model's arms on a point cloud or the disk, m,
 * for the horizon mat->horizon and the largest cell size dx_max (the
 * largest ps_cell_size): with partial volumes and e =
 * reach_extra_spacings > 0, delta + e dx_max (1 - 1e-9) (the partial
 * volume of a neighbour b is > 0 up to delta + dx_b / 2, so the largest
 * cell sets the reach; arms beyond a smaller cell's end carry nothing);
 * with full volumes or e = 0, delta (1 + 1e-9) (an arm of exactly the
 * horizon's length is in). */
double ps_model_cloud_reach(const ps_model_type *type, const ps_material *mat,
                            double dx_max);

/* Create a model on a network of the particles P (and run the type's
 * prepare). Returns PS_OK, PS_ERR_INPUT (from prepare), PS_ERR_NOMEM. */
int ps_model_create(ps_model *m, const ps_model_type *type,
                    const ps_particles *P, const ps_network *net,
                    const ps_material *mat, ps_ctx *ctx);
/* For a type's prepare: the constants of m->given into the model, arm_k
 * over m->arm_k (allocated by prepare) when given has them, arm_side into
 * m->arm_side (allocated here when NULL). Returns PS_OK or PS_ERR_NOMEM. */
int ps_model_take_given(ps_model *m, ps_ctx *ctx);
/* ps_model_create with the constants of `given` taken instead of
 * computed (NULL: ps_model_create), where the model computes them
 * (ps_model_whole_constants). Same returns. */
int ps_model_create_given(ps_model *m, const ps_model_type *type, const ps_particles *P,
                          const ps_network *net, const ps_material *mat,
                          const ps_model_given *given, ps_ctx *ctx);
void ps_model_free(ps_model *m);

#endif
