/* problem_pd.h: the peridynamic problem behind ps_nl_problem
 * (ps_nl_problem.h): the model, the assembled system (and the majorant's),
 * the arm states with their committed copy, the external forces and the
 * load factor. The solver's lifecycle and path steps (solver.c) create,
 * commit, restore and break it through these functions; Newton and the
 * direction strategy see only its ps_nl_problem. The one file of
 * src/nonlinear that calls the model and the assembly (problem_pd.c). */
#ifndef PS_PROBLEM_PD_H
#define PS_PROBLEM_PD_H

#include "../assembly/ps_assembly.h"
#include "ps_nl_problem.h"

typedef struct ps_pd {
  const ps_particles *P;
  const ps_network *net;
  ps_model model;
  ps_system sys;
  ps_arm_state st, st_saved;  /* trial and committed arm states */
  int have_majorant;          /* sys_pre exists (ps_nl_problem.has_majorant) */
  ps_system sys_pre;          /* one-horizon majorant of sys's tangent */
  unsigned char *arm_state_at_factor; /* [n_arm + 1] yielding | 2 broken at
                                 the last mark */
  int matrix_free;            /* 1: the tangent is kept as data and applied
                                 matrix-free, assembled only for a factor */
  double lambda;              /* the load factor of the residual */
  const double *fext;         /* [n_dof] external forces at load factor 1,
                                 zero on prescribed dofs, or NULL; not owned */
  double t_assembly;          /* wall seconds in evaluation and assembly */
  double dissipation_step;    /* ps_pd_dissipation at the last evaluation,
                                 when dissipation_valid (else not yet
                                 computed: ps_pd_step_dissipation) */
  int dissipation_valid;
  const ps_comm *comm;        /* the run's processes (ctx->comm at create;
                                 NULL: one): the energy, the dissipation
                                 and the counts below are summed over them */
  unsigned char *owned_free;  /* [n_free] owned_dof of each free dof */
  unsigned char *owned_dof;   /* [n_dof] a share's owned dofs
                                 (ps_pd_set_share; NULL: all) */
  double nnz_whole;           /* a share's: the whole free tangent's upper
                                 triangle's nonzeros (ps_pd_set_share) */
  ps_arm_halo arm_halo;       /* a share's, where its arms are judged by
                                 their owners (model.arm_halo points here) */
} ps_pd;

/* Create the problem: the model of `type` on the network, the system's
 * dof map and pattern for the prescribed-dof mask fixed[n_dof], the arm
 * states, and, with majorant = 1 and a model with family terms, the
 * majorant's system. matrix_free: see ps_pd. Returns PS_OK or fatal (*out
 * NULL). */
int ps_pd_create(ps_pd **out, const ps_particles *P, const ps_network *net,
                 const ps_model_type *type, const ps_material *mat,
                 const unsigned char *fixed, int majorant, int matrix_free, ps_ctx *ctx);
/* ps_pd_create with the model's constants given (ps_model_create_given;
 * NULL: ps_pd_create). */
int ps_pd_create_given(ps_pd **out, const ps_particles *P, const ps_network *net,
                       const ps_model_type *type, const ps_material *mat,
                       const ps_model_given *given, const unsigned char *fixed, int majorant,
                       int matrix_free, ps_ctx *ctx);
void ps_pd_free(ps_pd *pd);

/* Make pd a share of a distributed problem (ps_share): only the arms and
 * particles own_arm and own_particle mark (both borrowed) count in its
 * energy and counts (ps_model), and only the owned particles' dofs in the
 * solver's norms (ps_nl_problem.owned); global (borrowed, NULL on one
 * process) gives each particle's number in the whole model, which names
 * the arms breaking chooses over the processes; owner (borrowed) the
 * process of each particle and n_global the whole model's particles,
 * for the arms' halo of a material whose arms only their owners judge
 * (ps_model_breaks_alike; collective then). PS_OK, PS_ERR_INPUT or
 * PS_ERR_NOMEM. */
int ps_pd_set_share(ps_pd *pd, const unsigned char *own_arm, const unsigned char *own_particle,
                    const ps_int *global, const int *owner, ps_int n_global, ps_ctx *ctx);

/* The problem's ps_nl_problem (data = pd). */
ps_nl_problem ps_pd_problem(ps_pd *pd);

/* threads for the evaluations and the matrix-free product (not owned;
 * NULL: one) and the parts they split their loops into
 * (ps_system_set_parts: PS_OK, PS_ERR_INPUT, PS_ERR_NOMEM) */
int ps_pd_set_team(ps_pd *pd, ps_team *team, int parts, ps_ctx *ctx);

/* the trial arm states become the committed ones (plastic strains
 * included) / back to the committed ones */
void ps_pd_commit(ps_pd *pd);
void ps_pd_restore(ps_pd *pd);

/* The energy the arms dissipate from the committed states to those of the
 * last evaluation (ps_model_type.arm_dissipation; 0 for a model without
 * it), J (per unit thickness in 2D); with g != NULL also its gradient with
 * respect to the displacements there, g[n_dof] = sum_i dD_i/ddl_i
 * ddl_i/du (loading arms only). */
double ps_pd_dissipation(const ps_pd *pd, double *g);

/* ps_pd_dissipation(pd, NULL) at the last evaluation (0 before the
 * first, and after ps_pd_step_committed), computed at the first request
 * after each evaluation and kept: an evaluation only marks it stale, so
 * the line search's trial evaluations do not pay for a sum over every
 * arm. Nothing may change the arm states or the arm elongations between
 * an evaluation and the request but another evaluation (a break or a
 * restore is always followed by one before the value is read). */
double ps_pd_step_dissipation(ps_pd *pd);

/* the committed state dissipates nothing from itself: the step's
 * dissipation becomes 0 (ps_solver_commit) */
void ps_pd_step_committed(ps_pd *pd);

/* one round of the model's breaking rule (Eq. 118) on the trial states:
 * at most max_count arms, *n_broken of them. Returns the model's status. */
int ps_pd_break_arms(ps_pd *pd, ps_int max_count, ps_int *n_broken, ps_ctx *ctx);

/* out[n_free] = K_fp du_p (ps_system_coupling) */
void ps_pd_coupling(ps_pd *pd, const double *du, double *out);

/* arms yielding and not broken (over every process) */
ps_int ps_pd_count_yielding(const ps_pd *pd);

/* nonzeros of the free tangent's upper triangle (0 before the first
 * assembly); a share's: the whole model's (its pattern's, counted over
 * the processes when the share was made) */
double ps_pd_nnz_tangent(const ps_pd *pd);

#endif
