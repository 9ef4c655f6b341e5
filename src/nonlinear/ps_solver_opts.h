/* ps_solver_opts.h: the settings of the nonlinear solver (the case's
 * solver.* keys but max_memory_gib), apart from ps_solver.h so that the
 * case reader (src/io) can hold and fill them without seeing the solver.
 * Depends on nothing but the C library. */
#ifndef PS_SOLVER_OPTS_H
#define PS_SOLVER_OPTS_H

/* Settings of the Newton solve, its linear solves and the direction
 * strategy. Names in brackets are the case file's keys. */
typedef struct ps_solver_opts {
  double tolerance;       /* [tolerance] relative residual (default 1e-8) */
  int max_iterations;     /* [max_iterations] per Newton solve (default 30) */
  int max_small_steps;    /* [max_small_steps] a Newton solve fails as
                             stagnated after this many line-search steps in
                             a row below PS_SMALL_STEP (ps_solver.h) that
                             cut the residual by less than 10% together
                             (0: never; default 5) */
  int line_search;        /* [line_search] 1: the energy line search
                             (linesearch.h; default); 0: the first finite
                             step of the halvings from the full step */
  char linear[32];        /* [linear] the backend by name, resolved by
                             ps_linsolve_type_find when the solver is
                             created: "cholmod" (default, supernodal),
                             "cholmod-simplicial", "umfpack", "petsc" (a
                             build configured --with-petsc); UMFPACK is
                             the fallback where K is not positive definite */
  char petsc_options[1024]; /* [petsc_options] PETSc options of the petsc
                             backend ("-ksp_type cg -pc_type gamg"), then
                             those of the command line (which win) */
  int reuse_factor;       /* [reuse_factor] 1 (default): solve each Newton
                             system by CG preconditioned with the last
                             factor, and refactor only when CG does not
                             converge within pcg_max_iterations
                             (doc/performance.md); 0: a fresh factor per
                             Newton iteration */
  double pcg_rtol;        /* [cg_tolerance] relative tolerance of that CG
                             (default 1e-6) */
  int cg_forcing_adaptive; /* [cg_forcing: adaptive] inexact Newton
                             (forcing.h), 1 (default): CG stops at
                             Eisenstat and Walker's choice-2 forcing term
                             eta_k = 0.9 (|r_k| / |r_k-1|)^2 (safeguarded;
                             cg_forcing_max at the first iteration of a
                             solve and at most): rough CG solves while
                             Newton converges slowly, tight ones once it
                             converges fast; a solve that reaches
                             max_iterations goes on with the fixed rule
                             (cg_forcing) for max_iterations more. 0: the
                             fixed rule */
  double cg_forcing_max;  /* [cg_forcing_max] its loosest CG tolerance
                             (default 0.5) */
  double cg_forcing;      /* [cg_forcing: a number] the fixed rule: CG
                             stops at the relative residual max(pcg_rtol,
                             min(PS_CG_FORCING_MAX, cg_forcing x the
                             relative Newton residual)); 0: always pcg_rtol
                             (exact Newton). Both rules (but cg_forcing 0)
                             stop CG no tighter than PS_CG_OVERSOLVE x
                             tolerance / the relative Newton residual
                             (default PS_CG_FORCING_FIXED = 100; with the
                             adaptive rule, used after a handover) */
  int pcg_max_iterations; /* [cg_max_iterations] default 25 */
  int pcg_skip_arms;      /* [cg_skip_arms] skip CG when at least this many
                             arms changed state (yield, break) since the
                             last factorisation; 0: never skip (default) */
  int matrix_free;        /* [matrix_free] 1: CG applies the tangent
                             matrix-free (ps_system_apply: arm and rank-one
                             family terms) and the two-horizon matrix is
                             assembled only to be factored (default 1;
                             doc/performance.md) */
  int cg_truncate;        /* [cg_truncate] 1: when CG meets a direction of
                             negative curvature (an indefinite tangent),
                             its last iterate is the Newton direction
                             (truncated CG, a descent direction) instead of
                             a fresh factorisation and UMFPACK (default 1,
                             doc/performance.md) */
  int cg_single_precision; /* [cg_single_precision] 1: CG's preconditioner
                             uses the factor's values rounded to single
                             precision (half the memory traffic of its
                             triangular solves; default 1) */
  int reanalyze;          /* [reanalyze] 1: symbolic analysis before every
                             factorisation (benchmark comparison; 0) */
  int majorant;           /* [majorant] 1: for models with family terms,
                             when CG with the old factor fails, factor the
                             one-horizon majorant of the tangent
                             (ps_system_assemble_majorant, fewer nonzeros)
                             and run CG with it before factoring the
                             two-horizon tangent itself (default 1,
                             doc/performance.md) */
  int parts;              /* [parts] the parts the per-arm loops, the CG
                             products and the preconditioner's solves are
                             split into (1 .. PS_PARTS_MAX, ps_util.h;
                             default PS_PARTS_DEFAULT = 2): the most
                             threads a run uses; the numbers depend on it
                             (the order of the sums), not on the threads */
  int layout;             /* [layout] how `mpiexec -n P peristatic run`
                             holds the model (enum ps_layout; one process
                             ignores it): auto (default) distributed where
                             the case allows it (ps_problem_distributable,
                             src/app), else replicated; distributed (the
                             case must allow it); replicated (every rank
                             holds the whole model, PETSc shares the
                             matrix and its solves: doc/parallel.md) */
  int threads;            /* not a case key (the command line's -t):
                             threads of the CG products and preconditioner
                             solves (ps_team); 0 (default) as many as the
                             CPUs this process may use; at most `parts` are
                             used; the numbers a run gives do not depend
                             on it */
} ps_solver_opts;

enum ps_layout { PS_LAYOUT_AUTO, PS_LAYOUT_DISTRIBUTED, PS_LAYOUT_REPLICATED };

/* The defaults above, the only place they are written down (the case
 * reader starts from them). Defined in solver.c. */
void ps_solver_opts_default(ps_solver_opts *o);

#endif
