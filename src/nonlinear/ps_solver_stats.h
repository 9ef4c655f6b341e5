/* ps_solver_stats.h: what a solver has done (ps_solver_get_stats), apart
 * from ps_solver.h so that the reports (src/io/report.c) can hold and
 * write it without seeing the solver. Depends only on src/util. */
#ifndef PS_SOLVER_STATS_H
#define PS_SOLVER_STATS_H

#include "../util/ps_util.h"

/* What a solver has done since its creation: counts and times. Filled by
 * ps_solver_get_stats in one call; the reports take it as it is. */
typedef struct ps_solver_stats {
  ps_int newton_iterations;   /* Newton iterations of all solves */
  ps_int factorisations;      /* of the tangent (chosen backend + UMFPACK) */
  ps_int n_fallback;          /* UMFPACK fallbacks */
  ps_int ldl_factorisations;  /* LDL^T factors of indefinite tangents (path
                                 control, doc/path-following.md) */
  ps_int solves;              /* direct solves */
  ps_int ksp_iterations;      /* iterations of the linear solver's own
                                 iterative solves (PETSc's KSP), beside
                                 peristatic's CG (pcg_iterations) */
  ps_int pcg_iterations, pcg_failures, pcg_skipped;
  ps_int majorant_factorisations, majorant_failures; /* opts.majorant */
  ps_int shifted_steps;       /* Newton directions from a shifted tangent */
  ps_int cg_truncated;        /* from CG truncated at negative curvature */
  ps_int gmres_iterations;    /* GMRES on an indefinite tangent (path
                                 control past a peak) */
  ps_int stagnated;           /* Newton solves ended as stagnated */
  ps_int handovers;           /* adaptive CG solves that went on with the
                                 fixed rule at max_iterations */
  ps_int line_search_cuts;    /* backtracking steps of the line search */
  ps_int loose_particles;     /* the most particles the tangent's spring
                                 held at once (arms all broken, arms that
                                 do not span, fragments' supports) */
  ps_int fragments;           /* the most fragments supported at once */
  ps_int n_free;              /* free dofs */
  int threads;                /* threads of the run's CG */
  int parts;                  /* the parts of its loops (solver.parts) */
  double serial_share;        /* share of a preconditioner solve on one
                                 thread alone (the majorant's factor, else
                                 the tangent's) */
  double nnz_tangent;         /* nonzeros of the free tangent (upper) */
  double nnz_factor, flops_factor; /* of the last factorisation */
  double nnz_majorant_factor;
  double t_assembly, t_analyze, t_factor, t_solve, t_majorant_factor;
  double t_cg;                /* wall seconds in CG (products and
                                 preconditioner solves) */
} ps_solver_stats;

#endif
