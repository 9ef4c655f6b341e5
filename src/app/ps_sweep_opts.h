/* ps_sweep_opts.h: the Griffith sweep's list of elongation limits (the
 * case's griffith.* keys), for `peristatic griffith` (src/app/griffith.c).
 * Depends on nothing but the C library. */
#ifndef PS_SWEEP_OPTS_H
#define PS_SWEEP_OPTS_H

/* the longest list of griffith.delta_over_c values */
#define PS_MAX_SWEEP 64

typedef struct ps_sweep_opts {
  int n;                              /* values in delta_over_c, 1..PS_MAX_SWEEP */
  double delta_over_c[PS_MAX_SWEEP];  /* delta / c of each run (> 0; from
                                         griffith.delta_over_c, or 1 / d for
                                         the denominators d of
                                         griffith.denominators) */
} ps_sweep_opts;

/* The default list, the only place it is written down: the paper's
 * delta/c = 1/500, 1/750, ..., 1/3250 (12 values). Defined in
 * griffith.c. */
void ps_sweep_opts_default(ps_sweep_opts *o);

#endif
