/* t975_api.c: the public interface's contracts, through peristatic.h only
 * (linked against libperistatic like any client): statuses and messages of
 * calls in the wrong order and of bad input, the getters' results against
 * what the problem must hold (sizes, volumes, the prescribed displacement),
 * and a handle reused for a second case. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "peristatic.h"

/* a 6 x 4 plate of the bond model, pulled at the right by 1 um */
static const char *CASE =
    "geometry: {type: cloud, dim: 2}\n"
    "material: {model: bond, E: 1.0e9, nu: 0.3333333333333333, plane: stress,\n"
    "           plastic: false}\n"
    "loading:\n"
    "  type: boundary\n"
    "  boundary:\n"
    "    - select: {x_max: 0.001}\n"
    "      fix: [x, y]\n"
    "    - select: {x_min: 0.005}\n"
    "      displace: {x: 1.0e-6}\n"
    "path: {load_step: 1.0, max_load: 1.0}\n";

static int has(const char *msg, const char *part) { return strstr(msg, part) != NULL; }

int main(void) {
  enum { NX = 6, NY = 4, N = NX * NY };
  double x[2 * N], v[N], u[2 * N], out[2 * N];
  for (int a = 0; a < N; a++) {
    x[2 * a] = (a % NX + 0.5) * 1e-3;
    x[2 * a + 1] = (a / NX + 0.5) * 1e-3;
    v[a] = 1e-6;
  }
  peristatic_init_process();
  peristatic *ps = peristatic_new();
  ps_check(ps != NULL, "peristatic_new gives a handle");
  ps_check(!strcmp(peristatic_case_name(ps), ""), "no case name before loading");

  /* order of calls */
  int s = peristatic_run(ps, NULL);
  ps_check(s == PERISTATIC_ERR_USAGE && has(peristatic_error(ps), "no case loaded"),
           "run before loading: PERISTATIC_ERR_USAGE, 'no case loaded' (%d, %s)", s,
           peristatic_error(ps));
  s = peristatic_get_displacements(ps, u);
  ps_check(s == PERISTATIC_ERR_USAGE, "displacements before a run: usage error (%d)", s);
  /* MPI: none started, so rank 0 of 1; PETSc options are checked */
  ps_check(peristatic_parallel_rank() == 0 && peristatic_parallel_size() == 1,
           "rank 0 of 1 before (and without) peristatic_parallel_init");
  s = peristatic_set_petsc_options(ps, "ksp_type cg");
  ps_check(s == PERISTATIC_ERR_INPUT && has(peristatic_error(ps), "must start with '-'"),
           "PETSc options without a dash refused (%d, %s)", s, peristatic_error(ps));
  s = peristatic_set_petsc_options(ps, NULL);
  ps_check(s == PERISTATIC_OK, "no PETSc options accepted (%d)", s);
  ps_check(peristatic_exit_status(PERISTATIC_ERR_USAGE) == 1 &&
               peristatic_exit_status(PERISTATIC_ERR_IO) == 3 &&
               peristatic_exit_status(PERISTATIC_ERR_SOLVER) == 2,
           "exit statuses as the program's (1 usage, 3 I/O, 2 solver)");

  /* bad particles: named */
  v[7] = -1;
  s = peristatic_set_particles(ps, 2, N, x, v, NULL);
  ps_check(s == PERISTATIC_ERR_INPUT && has(peristatic_error(ps), "particle 7 has volume -1"),
           "a negative volume is refused naming particle 7 (%s)", peristatic_error(ps));
  v[7] = 1e-6;
  s = peristatic_set_particles(ps, 4, N, x, v, NULL);
  ps_check(s == PERISTATIC_ERR_INPUT, "dim 4 refused (%d)", s);

  /* bad case text: named by the name given and the line */
  s = peristatic_load_text(ps, "material: {E: -1}\n", "mycase");
  ps_check(s == PERISTATIC_ERR_INPUT && has(peristatic_error(ps), "mycase:1:") &&
               has(peristatic_error(ps), "material.E"),
           "a negative modulus in text: 'mycase:1: ... material.E' (%s)", peristatic_error(ps));
  s = peristatic_load_text(ps, "geometry: {type: box, dim: 2, counts: [4, 4], spacing: 1}\n"
                               "colour: red\n", "mycase");
  ps_check(s == PERISTATIC_ERR_INPUT && has(peristatic_error(ps), "mycase:2:"),
           "an unknown key on line 2 named (%s)", peristatic_error(ps));

  /* the plate from arrays */
  s = peristatic_set_particles(ps, 2, N, x, v, NULL);
  ps_check(s == PERISTATIC_OK, "particles accepted (%s)", peristatic_error(ps));
  s = peristatic_load_text(ps, CASE, "plate");
  ps_check(s == PERISTATIC_OK, "case text loaded (%s)", peristatic_error(ps));
  s = peristatic_set_particles(ps, 2, N, x, v, NULL);
  ps_check(s == PERISTATIC_ERR_USAGE, "particles after the case: usage error (%d)", s);
  ps_check(!strcmp(peristatic_case_name(ps), "plate"), "the case is named after its text's "
           "name (%s)", peristatic_case_name(ps));
  char dir[64];
  s = peristatic_output_dir(ps, NULL, dir, sizeof dir);
  ps_check(s == PERISTATIC_OK && !strcmp(dir, "out/plate"), "default output folder out/plate "
           "(%s)", dir);
  s = peristatic_output_dir(ps, "..", dir, sizeof dir);
  ps_check(s == PERISTATIC_ERR_INPUT, "'..' is refused as an output folder (%d)", s);
  peristatic_set_verbosity(ps, 0);
  peristatic_set_threads(ps, 1);
  s = peristatic_run(ps, NULL);
  ps_check(s == PERISTATIC_OK, "the run ends (%d: %s)", s, peristatic_error(ps));
  ps_check(peristatic_particle_count(ps) == N && peristatic_dim(ps) == 2,
           "sizes: %ld particles in %dD", peristatic_particle_count(ps), peristatic_dim(ps));
  peristatic_get_positions(ps, out);
  ps_check(!memcmp(out, x, sizeof x), "positions read back bit for bit");
  peristatic_get_volumes(ps, out);
  ps_check(!memcmp(out, v, sizeof v), "volumes read back bit for bit");
  peristatic_get_displacements(ps, u);
  double umax = 0;
  int pulled_ok = 1;
  for (int a = 0; a < N; a++) {
    umax = fmax(umax, fabs(u[2 * a]));
    if (x[2 * a] >= 0.005) pulled_ok &= u[2 * a] == 1e-6; /* prescribed, lambda 1 */
    if (x[2 * a] <= 0.001) pulled_ok &= u[2 * a] == 0 && u[2 * a + 1] == 0;
  }
  ps_check(pulled_ok, "prescribed displacements exact at lambda = 1 (pulled 1e-6, held 0)");
  ps_check(umax == 1e-6, "no displacement beyond the pulled edge's (max %g)", umax);
  double d[N], inc = 0, nope = 0;
  ps_check(peristatic_get_damage(ps, d) == PERISTATIC_OK && d[0] == 0,
           "damage read (0: nothing breaks)");
  ps_check(peristatic_get_result(ps, "increments", &inc) == PERISTATIC_OK && inc == 1,
           "one increment (load_step 1, max_load 1): %g", inc);
  s = peristatic_get_result(ps, "sigma_nope", &nope);
  ps_check(s == PERISTATIC_ERR_INPUT && has(peristatic_error(ps), "names: sigma_failure"),
           "an unknown result name lists the names (%s)", peristatic_error(ps));
  ps_check(strlen(peristatic_stop_reason(ps)) > 0, "a stop reason: %s",
           peristatic_stop_reason(ps));

  /* particles given, but a case with another geometry */
  peristatic *q = peristatic_new();
  peristatic_set_particles(q, 2, N, x, v, NULL);
  char boxcase[2048];
  snprintf(boxcase, sizeof boxcase, "%s%s",
           "geometry: {type: box, dim: 2, counts: [6, 4], spacing: 1.0e-3}\n",
           strchr(CASE, '\n') + 1);
  s = peristatic_load_text(q, boxcase, "boxcase");
  ps_check(s == PERISTATIC_ERR_INPUT && has(peristatic_error(q), "particles were given"),
           "given particles with a box geometry refused (%s)", peristatic_error(q));
  peristatic_free(q);
  peristatic_free(ps);
  peristatic_free(NULL);
  return ps_check_summary();
}
