/* main.c: the peristatic command line: `peristatic run CASE.yaml`,
 * `peristatic griffith CASE.yaml`, `peristatic info CASE.yaml`, --help. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "api/peristatic.h"
#include "config.h"

static const char *HELP_MAIN =
    "peristatic " PACKAGE_VERSION " - implicit static peridynamics (virtual-fibre arm network)\n"
    "\n"
    "Usage: peristatic COMMAND [OPTIONS] CASE.yaml\n"
    "\n"
    "Commands:\n"
    "  run       solve the case along its load path to fracture (or max load)\n"
    "  griffith  sweep the elongation limit delta over griffith.* values on one\n"
    "            particle cloud; fit sigma_failure/sigma_y against sqrt(delta/c)\n"
    "  info      build the particles and the arm network, print their sizes, exit\n"
    "  help CMD  explain one command\n"
    "\n"
    "Options:\n"
    "  -o, --out DIR   output directory (default: output.dir, else out/<case name>)\n"
    "  -q, --quiet     no progress lines\n"
    "  -v, --verbose   Newton iterations too (twice: source locations in errors)\n"
    "      --resume    griffith: continue a sweep in DIR, reusing finished runs\n"
    "      --restart DIR  run: continue the run whose output folder is DIR from its\n"
    "                  checkpoint (DIR.partial's after an interruption, else DIR's)\n"
    "  -j, --jobs N    griffith: N runs at a time, one process each (N cores)\n"
    "  -t, --threads N threads per run (default: the CPUs, shared among -j jobs;\n"
    "                  at most solver.parts are used, default 2; results depend\n"
    "                  on solver.parts, not on N)\n"
    "      --max-memory GIB  refuse a case whose estimated memory exceeds GIB\n"
    "                  (default solver.max_memory_gib, else 80% of the RAM)\n"
    "  -h, --help      this text\n"
    "\n"
    "Each load increment prints one progress line:\n"
    "  step  lambda  sig/sig_y  newton  residual  yielding  broken  tip/c\n"
    "lambda is the load factor (disk: remote stress S / sigma_y of Eq. 116;\n"
    "boundary cases: multiplier of loading.boundary displacements and tractions),\n"
    "sig/sig_y the boundary stress over E eps_y (0 without a measure: true entry),\n"
    "residual the final |r_free|/|reactions|,\n"
    "yielding/broken the arm counts, tip/c the crack tip distance over c.\n"
    "\n"
    "Outputs (written to DIR.partial, renamed to DIR when the run completes, so a\n"
    "failed run leaves earlier results intact): history.csv, summary.txt,\n"
    "particles.csv, particles_NNNN.vtu and arms_NNNN.vtu with their time series\n"
    "particles.pvd and arms.pvd (open a .pvd in ParaView; warp by 'displacement')\n"
    "and path.png (the load-displacement curve). griffith adds griffith.csv,\n"
    "griffith_fit.txt, griffith.png.\n"
    "\n"
    "Threads: CG and the per-arm loops of a run are split into solver.parts parts\n"
    "(default 2, up to 64) run on min(-t N, parts) threads (-t default: the\n"
    "CPUs, shared among -j jobs). The parts fix the order of every sum: the\n"
    "numbers depend on solver.parts, never on -t (solver.parts: 4 to use 4\n"
    "cores; -t 1 when the other cores are busy). CHOLMOD and OpenBLAS get one\n"
    "thread each (OMP_THREAD_LIMIT=1, peristatic restarts itself with it)\n"
    "unless the environment sets OPENBLAS_NUM_THREADS or OMP_THREAD_LIMIT; use\n"
    "-j for a sweep's cores (doc/peristatic.md ENVIRONMENT).\n"
    "\n"
    "Example:\n"
    "  peristatic run data/cases/small-disk.yaml\n"
    "  peristatic griffith -o out/sweep data/cases/small-disk.yaml\n"
    "  peristatic run data/cases/plate-hole-bond.yaml   (bond-based PD, tractions)\n"
    "  peristatic run data/cases/edge-crack-bond.yaml   (J-integral in summary.txt)\n"
    "  peristatic run data/cases/notched-plate-pmb.yaml (Peridigm's PMB plate,\n"
    "                                                    to complete fracture)\n"
    "\n"
    "Models (material.model): fibre (Olsson et al. 2021, the default; yield_rule\n"
    "total or deviatoric; breaks by material.delta, Eq. 118), bond (bond-based\n"
    "PD, Fallah et al. 2020; micromodulus conical or constant as Peridigm's\n"
    "PMB), state (ordinary state-based PD), threebody (Li & Hao 2023, 2D);\n"
    "bond, state and threebody take a box, a point cloud, a mesh or the disk\n"
    "(material.horizon in m, or horizon_factor spacings) and break arms by\n"
    "material.fracture (critical stretch, G_c or micropotential; doc/fracture.md).\n"
    "Path (path.control): load (the default); arc_length, which passes limit\n"
    "points where load control stalls; dissipation, which fixes the energy the\n"
    "arms dissipate per increment and follows softening and snap-back (softening\n"
    "bond arms, material.fracture.softening_ratio, or plastic fibre arms;\n"
    "path.load_until_unstable: load increments first, until the crack runs);\n"
    "event, which ends each increment where the next arm reaches its breaking\n"
    "criterion, so arms break at it and not past it and the load may fall while\n"
    "the crack grows (any model that breaks; doc/path-following.md).\n"
    "\n"
    "Before it builds the network, peristatic estimates the case's particles, arms,\n"
    "tangent and factor nonzeros and memory; run and griffith refuse (exit 1) a\n"
    "case whose estimate exceeds the memory limit (--max-memory), saying what it\n"
    "needs; info prints the estimate and refuses only what it cannot build.\n"
    "\n"
    "peristatic is also a library: libperistatic with peristatic.h and\n"
    "peristatic.pc, for programs that build particles and run cases themselves\n"
    "(doc/library.md, examples/plate_from_arrays.c).\n"
    "\n"
    "The case file format and every default: doc/peristatic.md. Exit status: 0 on\n"
    "success, 1 on bad input (or a case above the memory limit), 2 on a solver\n"
    "failure or out of memory, 3 on an I/O error (or an output folder that is not\n"
    "peristatic's, or that another run is writing), 130/143 when SIGINT/SIGTERM\n"
    "ended the run (its partial output is in DIR.partial).\n";

static const char *HELP_RUN =
    "peristatic run [-o DIR] [-q|-v] [-t N] [--max-memory GIB] [--restart DIR]\n"
    "               [PETSc options] CASE.yaml\n"
    "\n"
    "Solves the case to equilibrium at each increment of the load factor with\n"
    "Newton's method (consistent tangent, CHOLMOD, energy line search), commits\n"
    "the plastic arm strains (Eq. 111), breaks arms whose plastic elongation\n"
    "exceeds delta (Eq. 118) and re-equilibrates at the same load until no arm\n"
    "breaks. A Newton failure halves the increment (path.min_step is the limit).\n"
    "Stops when the crack tip passes path.stop_crack_tip * c (disk), when the\n"
    "boundary stress falls below path.stop_load_drop of its peak, or at\n"
    "path.max_load. Reports sigma_failure = the peak boundary stress.\n"
    "A run in which nothing breaks ends with 'no fracture': not an error.\n"
    "Each Newton system is solved by conjugate gradients in solver.parts parts\n"
    "(default 2) on up to as many threads (-t N; the same numbers on one),\n"
    "preconditioned by an earlier factor.\n"
    "Refuses (exit 1), before building the network, a case whose estimated\n"
    "memory (peristatic info: estimate_memory_MiB) exceeds the limit: --max-memory\n"
    "GIB, else solver.max_memory_gib, else 80% of the RAM.\n"
    "\n"
    "Checkpoints (output.checkpoint: false turns them off): every\n"
    "output.checkpoint_every increments (default 10) and when\n"
    "the run ends or is interrupted between increments, run writes\n"
    "checkpoint.bin (the whole state) into its output folder (DIR.partial while\n"
    "it runs; distributed over P processes, checkpoint_pR.bin per rank R, to\n"
    "restart on P again). --restart DIR continues the run of DIR from its\n"
    "checkpoint (DIR.partial's when there is one, else DIR's) with the same case\n"
    "file (path.max_increments may be raised): history.csv keeps the rows up to the\n"
    "checkpoint, and the results are those of an uninterrupted run to the last\n"
    "bit. A checkpoint of another case, another version or a damaged one is\n"
    "refused (exit 1), the folder left as it is.\n"
    "\n"
    "PETSc (a build configured --with-petsc): with solver.linear: petsc the\n"
    "Newton systems go to a PETSc KSP and PC chosen by PETSc options, from\n"
    "solver.petsc_options and the command line (-ksp_type cg -pc_type gamg;\n"
    "default MUMPS Cholesky); mpiexec -n P peristatic run CASE.yaml runs on P\n"
    "ranks: each holds its share of the particles and arms where the case\n"
    "allows it (solver.layout: auto, the default, or distributed), else the\n"
    "whole model with the matrix and its solve shared; rank 0 writes the\n"
    "results, every rank its VTK pieces and checkpoint (doc/parallel.md).\n";

static const char *HELP_GRIFFITH =
    "peristatic griffith [-o DIR] [-q|-v] [--resume] [-j N] [-t N] [--max-memory GIB]\n"
    "                    CASE.yaml\n"
    "\n"
    "Runs the case once per value of griffith.delta_over_c (default the paper's\n"
    "c/500 .. c/3250 in steps of 250 in the denominator) on one particle cloud.\n"
    "Writes griffith.csv (delta/c, sqrt(delta/c), sigma_failure/sigma_y,\n"
    "fractured, increments, Newton iterations, arms broken, wall time), the\n"
    "least-squares line over the runs that fractured (griffith_fit.txt: slope,\n"
    "intercept, R^2, and the nominal Griffith slope sqrt(2/(pi eps_y)) beside it),\n"
    "and griffith.png (gnuplot). Griffith's law predicts a straight line through\n"
    "the origin; see doc/griffith.md for how to read the plot.\n"
    "\n"
    "A fresh sweep replaces DIR when it completes. With --resume it works in DIR\n"
    "itself and reuses every run folder (delta_cNNNN) whose summary.txt matches\n"
    "the particle cloud and delta: a long sweep can be stopped and continued.\n"
    "With -j N the runs are shared among N worker processes, each taking the\n"
    "next run not yet taken, largest delta (longest run) first, and logging to\n"
    "DIR/job-K.log: on N cores the sweep takes about 1/N of the time and N times\n"
    "the memory of one run (refused when the N runs' estimate exceeds the memory\n"
    "limit, see run); each job gets CPUs/N threads (-t to set them).\n"
    "\n"
    "A run whose solve fails before the crack runs (Newton increment below\n"
    "path.min_step, or a re-equilibration that fails without the load falling\n"
    "below its peak) is a row marked 'stalled' (no fracture, left out of the\n"
    "fit), not an error: at large delta the whole plate yields first.\n";

static const char *HELP_INFO =
    "peristatic info [--max-memory GIB] CASE.yaml\n"
    "\n"
    "Reads the case and builds the particle cloud; prints the size estimate\n"
    "(estimate_* lines: particles, arms, tangent and factor nonzeros, memory of\n"
    "the network, of info and of a run; memory_limit_MiB) before it builds\n"
    "anything large; then builds the arm network and the tangent's sparsity\n"
    "pattern and prints particles, arms, arms per particle, size ratio, free\n"
    "dofs, nonzeros of the tangent (upper triangle, per row), coupled particle\n"
    "pairs, the assembly's memory and the times: a quick look at the size of a\n"
    "case before running it. Refuses (exit 1) only a case whose network and\n"
    "pattern exceed the memory limit; estimate_memory_MiB above the limit\n"
    "means run would refuse it.\n";

/* the help text of a command (the general one when NULL or unknown) */
static const char *help_for(const char *cmd) {
  if (cmd && !strcmp(cmd, "run")) return HELP_RUN;
  if (cmd && !strcmp(cmd, "griffith")) return HELP_GRIFFITH;
  if (cmd && !strcmp(cmd, "info")) return HELP_INFO;
  return HELP_MAIN;
}

/* CHOLMOD as Debian builds it (SuiteSparse 5.12) zeroes and scatters in
 * its supernodal factorisation with 4 OpenMP threads, asked for by a
 * num_threads clause that OMP_NUM_THREADS does not override: on a small
 * machine waking them for each supernode slows every factorisation down
 * and, in `griffith -j N`, competes with the other runs
 * (doc/performance.md). Only OMP_THREAD_LIMIT caps the clause, and libgomp reads
 * it once, when it is loaded, before main: so peristatic runs itself again
 * with OMP_THREAD_LIMIT=1, unless the environment sets OMP_THREAD_LIMIT
 * (which is then kept as it is). Returns only when not re-executed. */
static void limit_openmp_threads(char **argv) {
  if (getenv("OMP_THREAD_LIMIT") || setenv("OMP_THREAD_LIMIT", "1", 1) != 0) return;
  execv("/proc/self/exe", argv); /* no /proc: carry on as we are */
}

/* the number from 1 to 64 after option argv[*i] (*i moves to it), or -1
 * after a message naming the option and `what` it counts */
static int count_arg(int argc, char **argv, int *i, const char *what) {
  const char *opt = argv[*i];
  char *end = NULL;
  long v = ++*i < argc ? strtol(argv[*i], &end, 10) : 0;
  if (*i >= argc || !end || *end || v < 1 || v > 64) {
    fprintf(stderr, "peristatic: %s needs a number of %s from 1 to 64\n", opt, what);
    return -1;
  }
  return (int)v;
}

/* Is s a plain decimal number (digits, a point, a sign, an exponent; no
 * hex, inf or nan) that strtod reads whole? */
static int plain_decimal(const char *s) {
  char *end = NULL;
  if (!s[0] || strspn(s, "0123456789.eE+-") != strlen(s)) return 0;
  strtod(s, &end);
  return end && !*end;
}

/* the number of GiB after option argv[*i] (*i moves to it): a plain
 * decimal number in (0, PERISTATIC_MAX_MEMORY_GIB], the range of
 * solver.max_memory_gib; or -1 after a message */
static double memory_arg(int argc, char **argv, int *i) {
  double v = ++*i < argc && plain_decimal(argv[*i]) ? strtod(argv[*i], NULL) : 0;
  if (*i >= argc || !(v > 0) || !(v <= PERISTATIC_MAX_MEMORY_GIB)) {
    fprintf(stderr, "peristatic: --max-memory needs a number of GiB > 0 (at most %g)\n",
            PERISTATIC_MAX_MEMORY_GIB);
    return -1;
  }
  return v;
}

/* What the command line asked for. */
typedef struct cli {
  const char *cmd, *file, *out; /* command, case file, -o DIR (NULL: none) */
  int verbosity;                /* -q/-v; -1: the case's output.verbosity */
  int resume, jobs, threads;    /* --resume, -j N, -t N (0: the CPUs) */
  const char *restart;          /* run --restart DIR (NULL: none) */
  double max_memory;            /* --max-memory GIB; 0: the case's */
  char petsc[1024];             /* PETSc options (-ksp_type cg ...), "" */
} cli;

/* 1 when a is a PETSc option: one dash, a lower-case letter, and an
 * underscore in the name (-ksp_type, -pc_gamg_threshold, -log_view) */
static int petsc_option(const char *a) {
  return a[0] == '-' && a[1] >= 'a' && a[1] <= 'z' && strchr(a, '_') != NULL;
}

/* 1 when argument v can be a PETSc option's value: not an option, not
 * the case file (.yaml/.yml) */
static int petsc_value(const char *v) {
  size_t n = strlen(v);
  if (v[0] == '-' && !(v[1] >= '0' && v[1] <= '9') && v[1] != '.') return 0;
  return !(n >= 5 && !strcmp(v + n - 5, ".yaml")) && !(n >= 4 && !strcmp(v + n - 4, ".yml"));
}

/* append PETSc option argv[*i] (and its value) to c->petsc. 0 or 1 (a
 * message: too long) */
static int add_petsc_option(int argc, char **argv, int *i, cli *c) {
  size_t n = strlen(c->petsc);
  int w = snprintf(c->petsc + n, sizeof c->petsc - n, "%s%s", n ? " " : "", argv[*i]);
  if (*i + 1 < argc && petsc_value(argv[*i + 1])) {
    ++*i;
    if (w >= 0 && (size_t)w < sizeof c->petsc - n) {
      n += (size_t)w;
      w = snprintf(c->petsc + n, sizeof c->petsc - n, " %s", argv[*i]);
    }
  }
  if (w < 0 || (size_t)w >= sizeof c->petsc - n) {
    fprintf(stderr, "peristatic: the PETSc options are too long (at most %zu characters)\n",
            sizeof c->petsc - 1);
    return 1;
  }
  return 0;
}

/* Read the options and arguments into *c. Returns -1 to go on, else the
 * exit status (after --help or --version, or a message on stderr). */
static int parse_options(int argc, char **argv, cli *c) {
  *c = (cli){.verbosity = -1, .jobs = 1};
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      fputs(help_for(c->cmd), stdout);
      return 0;
    } else if (!strcmp(a, "-o") || !strcmp(a, "--out")) {
      if (++i >= argc) {
        fprintf(stderr, "peristatic: %s needs a directory\n", a);
        return 1;
      }
      c->out = argv[i];
    } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
      c->verbosity = 0;
    } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
      c->verbosity = c->verbosity < 2 ? 2 : c->verbosity + 1;
    } else if (!strcmp(a, "--resume")) {
      c->resume = 1;
    } else if (!strcmp(a, "--restart")) {
      if (++i >= argc || !argv[i][0]) {
        fprintf(stderr, "peristatic: --restart needs the output folder of an earlier run\n");
        return 1;
      }
      c->restart = argv[i];
    } else if (!strcmp(a, "-j") || !strcmp(a, "--jobs")) {
      if ((c->jobs = count_arg(argc, argv, &i, "jobs")) < 0) return 1;
    } else if (!strcmp(a, "-t") || !strcmp(a, "--threads")) {
      if ((c->threads = count_arg(argc, argv, &i, "threads")) < 0) return 1;
    } else if (!strcmp(a, "--max-memory")) {
      if ((c->max_memory = memory_arg(argc, argv, &i)) < 0) return 1;
    } else if (!strcmp(a, "--version")) {
      puts("peristatic " PACKAGE_VERSION);
      return 0;
    } else if (petsc_option(a)) {
      if (add_petsc_option(argc, argv, &i, c)) return 1;
    } else if (a[0] == '-') {
      fprintf(stderr, "peristatic: unknown option '%s' (see peristatic --help)\n", a);
      return 1;
    } else if (!c->cmd) {
      c->cmd = a;
    } else if (!c->file) {
      c->file = a;
    } else {
      fprintf(stderr, "peristatic: unexpected argument '%s'\n", a);
      return 1;
    }
  }
  return -1;
}

/* The command: help, or run/griffith/info with a case file. Returns -1 to
 * go on, else the exit status (after the help text or a message). */
static int check_command(const cli *c) {
  if (!c->cmd) {
    fputs(HELP_MAIN, stdout);
    return 1;
  }
  if (!strcmp(c->cmd, "help")) {
    fputs(help_for(c->file), stdout);
    return 0;
  }
  if (strcmp(c->cmd, "run") && strcmp(c->cmd, "griffith") && strcmp(c->cmd, "info")) {
    fprintf(stderr, "peristatic: unknown command '%s' (commands: run, griffith, info)\n",
            c->cmd);
    return 1;
  }
  if (!c->file) {
    fprintf(stderr, "peristatic %s: no case file given (see peristatic help %s)\n", c->cmd,
            c->cmd);
    return 1;
  }
  if (c->restart && strcmp(c->cmd, "run")) {
    fprintf(stderr, "peristatic %s: --restart is an option of run (griffith: --resume)\n",
            c->cmd);
    return 1;
  }
  return -1;
}

/* the message of a fatal status on stderr; its exit status */
static int fail(int status, const peristatic *ps) {
  /* every rank of an MPI run meets the same error: rank 0 says it */
  if (peristatic_parallel_rank() == 0) fprintf(stderr, "peristatic: %s\n", peristatic_error(ps));
  return peristatic_exit_status(status);
}

/* The command on the case: set-up, then run, griffith or info. Returns
 * PERISTATIC_OK or an error status (the message in ps). */
static int command(peristatic *ps, const cli *c) {
  int status = peristatic_load_file(ps, c->file);
  if (status == PERISTATIC_OK && c->verbosity >= 0)
    status = peristatic_set_verbosity(ps, c->verbosity);
  if (status == PERISTATIC_OK && c->max_memory > 0)
    status = peristatic_set_max_memory(ps, c->max_memory, "--max-memory");
  if (status == PERISTATIC_OK) status = peristatic_set_threads(ps, c->threads);
  if (status == PERISTATIC_OK && c->restart) status = peristatic_set_restart(ps, c->restart);
  char outdir[1100];
  if (status == PERISTATIC_OK) status = peristatic_output_dir(ps, c->out, outdir, sizeof outdir);
  if (status != PERISTATIC_OK) return status;
  if (!strcmp(c->cmd, "info")) return peristatic_info(ps, stdout);
  if (!strcmp(c->cmd, "griffith")) return peristatic_griffith(ps, outdir, c->resume, c->jobs);
  /* a stalled solve is an error for `run` (exit 2); its outputs stay in
   * the partial folder */
  status = peristatic_run(ps, outdir);
  return status == PERISTATIC_STALLED ? peristatic_stalled_error(ps, outdir) : status;
}

int main(int argc, char **argv) {
  limit_openmp_threads(argv);
  peristatic_init_process();
  cli c;
  int code = parse_options(argc, argv, &c);
  if (code < 0) code = check_command(&c);
  if (code >= 0) return code;
  /* only run and griffith look at the flag; info ends at once */
  if (strcmp(c.cmd, "info")) peristatic_install_signal_handlers();
  peristatic *ps = peristatic_new();
  if (!ps) {
    fputs("peristatic: out of memory\n", stderr);
    return 2;
  }
  /* under mpiexec, or with PETSc options, MPI starts now (a serial run
   * with solver.linear: petsc starts it when it creates the solver) */
  int status = peristatic_set_petsc_options(ps, c.petsc);
  if (status == PERISTATIC_OK && (peristatic_parallel_launched() || c.petsc[0]))
    status = peristatic_parallel_init(ps);
  if (status == PERISTATIC_OK) status = command(ps, &c);
  code = status < 0 ? fail(status, ps) : 0;
  peristatic_free(ps);
  peristatic_parallel_finalize();
  return code;
}
