/* ps_output_opts.h: what a run writes and prints (the case's output.*
 * keys), for the run's outputs (src/app/run.c, src/io/report.c) and the
 * command line. Depends on nothing but the C library. */
#ifndef PS_OUTPUT_OPTS_H
#define PS_OUTPUT_OPTS_H

/* output.j_integral: at most this many rings */
#define PS_MAX_J_RINGS 8

/* output.j_integral.tips: which ends of the crack segment [p0, p1] are
 * tips (p0: "start", direction p0 - p1; p1: "end", direction p1 - p0) */
enum ps_j_tips { PS_J_TIPS_BOTH = 0, PS_J_TIPS_START = 1, PS_J_TIPS_END = 2 };

typedef struct ps_output_opts {
  char dir[1024];      /* [dir] "" (default): the command line uses
                          out/<case name> */
  int vtk_every;       /* [vtk_every] write the field files (.vtu) every n
                          increments, and the last state (0: the last
                          only; default 10) */
  int fields;          /* [fields] 0: no field files (.vtu, .pvd) and no
                          particles.csv, only history.csv and summary.txt
                          (default 1) */
  int n_j_rings;       /* [j_integral] J of the final state by Eq. 39 and
                          Eq. 36 (Fallah) and K_I, K_II (interaction
                          integral) for each tip and square ring, into
                          summary.txt (2D; contour between particle rows,
                          geometry.spacing apart); 0: none (default) */
  double j_tip[2];     /* [j_integral.tip] crack tip, m */
  double j_dir[2];     /* [j_integral.direction] unit vector from the
                          crack into the material ahead of the tip (with
                          tip; default [1, 0]: a crack running along +x
                          to the tip) */
  int j_crack;         /* [j_integral.crack] index (from 0) into
                          geometry.cracks: the tips are that segment's
                          ends, each with the direction of the segment
                          out of it; -1 (default): tip and direction */
  int j_tips;          /* [j_integral.tips] with crack: enum ps_j_tips */
  double j_rings[PS_MAX_J_RINGS]; /* [j_integral.rings] outer half-widths l
                          of the square rings, m (q = 1 inside l/2, 0
                          outside l) */
  int checkpoint;      /* [checkpoint] 0: `peristatic run` writes no
                          checkpoint.bin at all, nor keeps the factors'
                          copies it needs (default 1) */
  int checkpoint_every; /* [checkpoint_every] `peristatic run` writes
                          checkpoint.bin (doc/peristatic.md RESTART) every
                          n increments, and at the end of the run or at an
                          interruption between increments; 0: only then
                          (default 10) */
  int verbosity;       /* [verbosity] 0 quiet, 1 progress, 2 Newton detail,
                          3 source locations in errors (default 1; -q and
                          -v override it) */
} ps_output_opts;

/* The defaults above, the only place they are written down (the case
 * reader starts from them). Defined in report.c. */
void ps_output_opts_default(ps_output_opts *o);

#endif
