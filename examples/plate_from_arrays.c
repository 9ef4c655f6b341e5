/* plate_from_arrays.c: libperistatic from a program of one's own. The
 * particles of a rectangular plate (a square lattice, nx x ny particles of
 * spacing d) are made here as arrays; the rest of the case (material,
 * supports, load path) is YAML text; the plate is pulled to yield and the
 * program prints what it reads back through the interface.
 *
 * Build against an installed library:
 *     cc plate_from_arrays.c $(pkg-config --cflags --libs peristatic)
 * Run: ./a.out [CLOUD.txt]   (with a file name, the particles are also
 * written there as a point cloud "x y volume", so that `peristatic run`
 * can solve the same plate from a case file: make check compares the two.)
 */
#include <peristatic.h>
#include <stdio.h>
#include <stdlib.h>

enum { NX = 24, NY = 8 };
static const double D = 1.0e-3; /* lattice spacing, m */

/* Everything but the particles: the fibre model in plane strain, the left
 * edge held, the right edge pulled by 0.05 mm (twice the yield strain of
 * 0.002 over the 23 mm between the edges' particles). */
static const char *CASE_TEXT =
    "name: plate-from-arrays\n"
    "geometry: {type: cloud, dim: 2}\n"
    "material: {E: 210.0e9, nu: 0.3, plane: strain, yield_strain: 0.002}\n"
    "loading:\n"
    "  type: boundary\n"
    "  boundary:\n"
    "    - select: {x_max: 0.001}\n"
    "      fix: [x]\n"
    "    - select: {x_max: 0.001, y_max: 0.001}\n"
    "      fix: [y]\n"
    "    - select: {x_min: 0.023}\n"
    "      displace: {x: 5.0e-5}\n"
    "      measure: true\n"
    "path: {load_step: 0.25, max_load: 1.0}\n";

int main(int argc, char **argv) {
  static double x[NX * NY * 2], volume[NX * NY], u[NX * NY * 2];
  for (int j = 0, a = 0; j < NY; j++)
    for (int i = 0; i < NX; i++, a++) {
      x[2 * a] = (i + 0.5) * D;
      x[2 * a + 1] = (j + 0.5) * D;
      volume[a] = D * D;
    }
  if (argc > 1) { /* the same particles as a point cloud file */
    FILE *f = fopen(argv[1], "w");
    if (!f) return perror(argv[1]), 1;
    for (int a = 0; a < NX * NY; a++)
      fprintf(f, "%.17g %.17g %.17g\n", x[2 * a], x[2 * a + 1], volume[a]);
    if (fclose(f)) return perror(argv[1]), 1;
  }

  peristatic *ps = peristatic_new();
  if (!ps) return fputs("out of memory\n", stderr), 2;
  int status = peristatic_set_particles(ps, 2, NX * NY, x, volume, NULL);
  if (status == PERISTATIC_OK) status = peristatic_load_text(ps, CASE_TEXT, "plate-from-arrays");
  if (status == PERISTATIC_OK) status = peristatic_set_verbosity(ps, 0);
  if (status == PERISTATIC_OK) status = peristatic_set_threads(ps, 1);
  if (status == PERISTATIC_OK) status = peristatic_run(ps, NULL); /* no files */
  if (status != PERISTATIC_OK) {
    fprintf(stderr, "plate_from_arrays: %s\n", peristatic_error(ps));
    int code = peristatic_exit_status(status);
    peristatic_free(ps);
    return code;
  }
  double arms, iterations, sigma, lambda;
  peristatic_get_result(ps, "arms", &arms);
  peristatic_get_result(ps, "newton_iterations", &iterations);
  peristatic_get_result(ps, "sigma_failure", &sigma);
  peristatic_get_result(ps, "lambda_peak", &lambda);
  peristatic_get_displacements(ps, u);
  printf("library %s\nparticles %ld\narms %.0f\nnewton_iterations %.0f\n",
         peristatic_version(), peristatic_particle_count(ps), arms, iterations);
  printf("peak_boundary_stress_Pa %.10g\nload_factor_at_peak %.10g\n", sigma, lambda);
  /* the particle at the top right corner and the middle of the top row */
  int corner = NX * NY - 1, middle = NX * (NY - 1) + NX / 2;
  printf("particle %d ux %.10g uy %.10g\n", corner, u[2 * corner], u[2 * corner + 1]);
  printf("particle %d ux %.10g uy %.10g\n", middle, u[2 * middle], u[2 * middle + 1]);
  peristatic_free(ps);
  return 0;
}
