#!/bin/sh
# t900_cli.sh: the command line on good and bad input. Bad input must exit
# non-zero with a message naming the file and line (or the parameter or
# particle); a run that fails must leave earlier outputs intact.
srcdir=${srcdir:-.}
D="$srcdir/tests/data/cli"
P=./peristatic
T=t900_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"

$P --help | grep -q "Usage: peristatic COMMAND" && ok "--help teaches the usage" || ko "--help"
$P help run | grep -q "Newton" && ok "help run explains the command" || ko "help run"
expect 1 "unknown command 'frobnicate'" -- frobnicate x.yaml
expect 1 "threads needs a number of threads from 1 to 64" -- run --threads 0 x.yaml
expect 1 "\-t needs a number of threads from 1 to 64" -- run -t
expect 3 "nonexistent.yaml: cannot open" -- run nonexistent.yaml
expect 1 "malformed.yaml:[0-9]*: YAML syntax error" -- run "$D/malformed.yaml"
expect 1 "unknown_key.yaml:9: .*colour" -- run "$D/unknown_key.yaml"
expect 1 "negative_E.yaml:1[0-9]: material.E must be > 0 (got -3.0e9)" -- run "$D/negative_E.yaml"
expect 1 "alpha_zero.yaml:[0-9]*: kernel.alpha must be > 0" -- run "$D/alpha_zero.yaml"
expect 1 "cloud_bad.txt:4:" -- run "$D/cloud_bad.yaml"
expect 1 "no supports in direction y" -- run -o "$T/x" "$D/no_support_y.yaml"
expect 1 "particle 36 .* has no arms" -- run -o "$T/x" "$D/cloud_loose.yaml"
expect 1 "not properly supported: .*particle 4[0-4] at (0.50[0-2], 0.50[0-2]), dof [xy]" -- run -o "$T/x" "$D/cloud_island.yaml"
expect 1 "not properly supported: particle 36 at (0.5, 0.5), dof x is not held at rest" -- run -o "$T/x" "$D/cloud_island_free.yaml"
expect 1 "nothing loads the model" -- run -o "$T/x" "$D/no_load.yaml"
expect 1 "bond_nu.yaml: material.nu = 0.3: bond-based peridynamics has nu = 1/3" -- run -o "$T/x" "$D/bond_nu.yaml"

# the deviatoric yield reading runs past yield and its arms yield
if $P run -q -o "$T/dev" "$D/box_deviatoric.yaml" &&
   awk -F, 'NR > 1 { y = $8 } END { exit !(y > 0) }' "$T/dev/history.csv"; then
  ok "yield_rule: deviatoric runs past yield (arms yielding)"
else
  ko "yield_rule: deviatoric run"
fi

# material.break_rule toughness on the 1,800-particle disk of the
# resolution study (doc/griffith.md, doc/results/resolution/): the case of
# paper-griffith.yaml at 6 x 12 zones, L = 3.441 mm. The rule changes
# which arms break: sigma_f = 1.0398 sigma_y (Eq. 118 as printed: 1.1126)
sed -e 's/^  n_eta: .*/  n_eta: 6/' -e 's/^  n_xi: .*/  n_xi: 12/' -e '/^griffith:/,$d' \
  -e 's/^  delta_over_c: .*/&\n  break_rule: toughness\n  break_length: 3.441e-3/' \
  "$srcdir/data/cases/paper-griffith.yaml" > "$T/toughness.yaml"
if $P run -q -t 1 -o "$T/tough" "$T/toughness.yaml" &&
   awk -F': ' '$1 == "sigma_failure_over_sigma_y" { s = $2 } $1 == "fractured" { f = $2 }
               END { exit !(f == "yes" && s > 1.0397 && s < 1.0399) }' "$T/tough/summary.txt"; then
  ok "break_rule: toughness on the 1,800-particle disk fractures at 1.0398 sigma_y"
else
  ko "break_rule: toughness on the 1,800-particle disk: $(grep -E 'sigma_failure_over|fractured' "$T/tough/summary.txt" 2>/dev/null | tr '\n' ' ')"
fi

# a traction: the bond-based strip carries the applied stress (mean of
# the Eq. 24 stress over a column in the middle = p = 1 MPa, to 1e-4)
if $P run -q -o "$T/tr" "$D/traction_box.yaml" &&
   awk -F, 'NR > 1 && $2 > 0.008 && $2 < 0.009 { s += $11; n++ }
            END { m = s / n; exit !(n == 10 && m > 0.9999e6 && m < 1.0001e6) }' "$T/tr/particles.csv"; then
  ok "a traction on the last column gives the mean stress p across the strip"
else
  ko "traction: mean stress across the strip is not p"
fi

# a good run writes its outputs
if $P run -q -o "$T/good" "$D/box_base.yaml" && [ -f "$T/good/summary.txt" ] &&
   [ -f "$T/good/history.csv" ] && $V "$T/good/particles_0002.vtu" > "$T/good.dump" &&
   grep -q "^POINTS 128$" "$T/good.dump" && grep -q "^FIELD load_factor 1$" "$T/good.dump" &&
   $V "$T/good/arms_0001.vtu" | grep -q "^SCALARS broken double 1$" &&
   [ "$(wc -l < "$T/good/history.csv")" -eq 3 ] && ! grep -qi nan "$T/good/history.csv"; then
  ok "a good run writes summary.txt, history.csv (2 increments, no NaN) and VTU files"
else
  ko "a good run writes its outputs"
fi
# the time series: every increment (vtk_every 1), the final state last
if series_ok "$T/good" && [ "$(cut -d' ' -f1 "$T/series.particles" | tr '\n' ' ')" = "1 2 " ]; then
  ok "particles.pvd and arms.pvd list steps 1 and 2, files that exist; the last displacement is particles.csv's"
else
  ko "the time series of a good run: $why"
fi
# a 3D case runs to fracture through the whole pipeline
if $P run -q -o "$T/b3" "$srcdir/data/cases/tension-block-3d.yaml" &&
   grep -q "^fractured: yes" "$T/b3/summary.txt" && $V "$T/b3/particles_0012.vtu" | grep -q "^POINTS 432$" &&
   head -1 "$T/b3/particles.csv" | grep -q "uz,damage.*stress_xz_Pa" && series_ok "$T/b3" &&
   [ "$(cat "$T/series.arms")" = "12 arms_0012.vtu" ]; then
  ok "3D block: runs to fracture, writes 3D VTU (the final state only: vtk_every 0, in the .pvd files; displacement as in the CSV)"
else
  ko "3D block run: $why"
fi
# a diverging run names the load factor, exits 2, and leaves them intact
cp "$T/good/summary.txt" "$T/summary.before"
expect 2 "Newton diverged at load factor" -- run -q -o "$T/good" "$D/diverges.yaml"
if cmp -s "$T/summary.before" "$T/good/summary.txt"; then
  ok "the failed run left the earlier outputs intact"
else
  ko "the failed run changed the earlier outputs"
fi
# a run whose Newton solve stalls: an error for `run` (exit 2, the partial
# output has the summary), a "stalled" row (no fracture) in a sweep
expect 2 "Newton diverged at load factor" -- run -q -o "$T/stall" "$D/stall_sweep.yaml"
if [ ! -e "$T/stall" ] && grep -q "^stalled: yes" "$T/stall.partial/summary.txt"; then
  ok "a stalled run: no output folder, summary.txt in the partial one says stalled"
else
  ko "a stalled run's outputs"
fi
if $P griffith -q -o "$T/stallsweep" "$D/stall_sweep.yaml" &&
   [ "$(grep -c ',stalled,' "$T/stallsweep/griffith.csv")" -eq 2 ] &&
   grep -q "^fractured: 0" "$T/stallsweep/griffith_fit.txt" && ! grep -qi nan "$T/stallsweep/griffith.csv"; then
  ok "griffith: stalled runs are rows marked stalled, not errors, and not fitted"
else
  ko "griffith with stalled runs"
fi
# a re-equilibration that fails with the load still at its peak is no
# fracture: exit 2 for `run`, stalled rows in a sweep
expect 2 "not below its peak (the crack had not run" -- run -q -o "$T/refail" "$D/refail_sweep.yaml"
if $P griffith -q -o "$T/refailsweep" "$D/refail_sweep.yaml" &&
   [ "$(grep -c ',stalled,' "$T/refailsweep/griffith.csv")" -eq 2 ] &&
   grep -q "^stop_reason: .*load not below its peak" "$T/refailsweep/delta_c1000/summary.txt"; then
  ok "griffith: failed re-equilibration at a rising load is a stalled row, not a fracture"
else
  ko "griffith with failed re-equilibration at a rising load"
fi
# a Griffith sweep writes its table, fit and plot
if $P griffith -q -o "$T/sweep" "$D/tiny_sweep.yaml" && [ "$(wc -l < "$T/sweep/griffith.csv")" -eq 3 ] &&
   grep -q "^r2: " "$T/sweep/griffith_fit.txt" && ! grep -qi nan "$T/sweep/griffith.csv"; then
  ok "griffith writes griffith.csv (2 runs, no NaN) and griffith_fit.txt"
else
  ko "griffith writes its table and fit"
fi
# the same sweep with two worker processes gives the same table
if $P griffith -q -j 2 -o "$T/sweepj" "$D/tiny_sweep.yaml" &&
   [ -f "$T/sweepj/job-1.log" ] && [ -f "$T/sweepj/job-2.log" ] &&
   [ "$(cut -d, -f1-7 "$T/sweep/griffith.csv")" = "$(cut -d, -f1-7 "$T/sweepj/griffith.csv")" ]; then
  ok "griffith -j 2: two workers, the same table (all but wall time)"
else
  ko "griffith -j 2 differs from the serial sweep"
fi
if command -v gnuplot >/dev/null 2>&1; then
  if [ -s "$T/sweep/griffith.png" ] && head -c 4 "$T/sweep/griffith.png" | grep -q PNG; then
    ok "griffith.png is a PNG"
  else
    ko "griffith.png missing or empty (gnuplot present)"
  fi
fi
# the speed-ups of the Newton solve (inexact CG tolerance from the Newton
# residual, matrix-free tangent products, a single-precision
# preconditioner) change the path of the iterates, not the converged
# states: the 1,800-particle disk to fracture gives the same peak as with
# CG to 1e-6 on the assembled tangent, preconditioned in double (tolerance 1e-7 on
# sigma_f: both states are converged to relative residuals <= 1e-8)
cp "$srcdir/data/cases/small-disk.yaml" "$T/exact.yaml"
printf 'solver: {cg_forcing: 0, matrix_free: false, cg_single_precision: false}\n' >> "$T/exact.yaml"
val() { awk -F': ' -v k="$2" '$1 == k {print $2}' "$1"; }
# same_peak DIR1 DIR2: the two runs' sigma_f agree to 1e-7 (relative) and
# their peaks are at the same load factor
same_peak() {
  awk -v a="$(val "$1/summary.txt" sigma_failure_over_sigma_y)" \
      -v b="$(val "$2/summary.txt" sigma_failure_over_sigma_y)" \
      'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a > 0 && d <= 1e-7 * b) }' &&
  [ "$(val "$1/summary.txt" load_factor_at_peak)" = "$(val "$2/summary.txt" load_factor_at_peak)" ]
}
if $P run -q -o "$T/fast" "$srcdir/data/cases/small-disk.yaml" &&
   $P run -q -o "$T/exact" "$T/exact.yaml" && same_peak "$T/fast" "$T/exact"; then
  ok "default solver and exact CG on the assembled tangent: the same sigma_f ($(val "$T/fast/summary.txt" sigma_failure_over_sigma_y)) and peak load factor"
else
  ko "sigma_f differs between the default solver and exact CG on the assembled tangent"
fi
# the default adaptive CG tolerance (Eisenstat-Walker) against the fixed
# rule of versions 4-7 (cg_forcing: 100): the same converged states
cp "$srcdir/data/cases/small-disk.yaml" "$T/fixed.yaml"
printf 'solver: {cg_forcing: 100}\n' >> "$T/fixed.yaml"
if $P run -q -o "$T/fixed" "$T/fixed.yaml" && same_peak "$T/fast" "$T/fixed"; then
  ok "adaptive (default) and fixed CG forcing: the same sigma_f and peak load factor"
else
  ko "sigma_f differs between the adaptive and the fixed CG forcing"
fi
# a Newton solve that reaches max_iterations under the adaptive rule goes
# on with the fixed rule: with max_iterations 6 some solves do (32 in
# version 8), and the run still ends at the default's sigma_f
cp "$srcdir/data/cases/small-disk.yaml" "$T/handover.yaml"
printf 'solver: {max_iterations: 6}\n' >> "$T/handover.yaml"
if $P run -q -o "$T/handover" "$T/handover.yaml" &&
   [ "$(val "$T/handover/summary.txt" newton_handovers)" -gt 0 ] && same_peak "$T/fast" "$T/handover"; then
  ok "max_iterations 6: $(val "$T/handover/summary.txt" newton_handovers) solves handed over to the fixed CG rule, the same sigma_f"
else
  ko "the handover at max_iterations (adaptive CG rule) did not act or changed sigma_f"
fi
# threads: a CG iteration's sums are split in parts fixed by the data, so
# one thread and two give the same history to the last digit
if $P run -q -t 1 -o "$T/t1" "$srcdir/data/cases/small-disk.yaml" &&
   $P run -q -t 2 -o "$T/t2" "$srcdir/data/cases/small-disk.yaml" &&
   [ "$(val "$T/t1/summary.txt" threads)" = 1 ] && [ "$(val "$T/t2/summary.txt" threads)" = 2 ] &&
   cmp -s "$T/t1/particles.csv" "$T/t2/particles.csv" &&
   [ "$(cut -d, -f1-10 "$T/t1/history.csv")" = "$(cut -d, -f1-10 "$T/t2/history.csv")" ]; then
  ok "-t 1 and -t 2: the same history.csv (all but wall time) and particles.csv, byte for byte"
else
  ko "-t 1 and -t 2 give different results"
fi
rm -rf "$T" "$T.partial"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
