#!/bin/sh
# t920_limits.sh: sizes refused up front and inputs that cannot make a
# network (issue 23). Cases that would need more memory than the limit are
# refused before anything large is allocated, in seconds, with the figures
# and how to raise the limit; info prints the estimate; coincident
# particles, a huge origin and an empty network get their own messages
# naming the case (and the cloud file and line).
srcdir=${srcdir:-.}
D="$srcdir/tests/data/limits"
P=./peristatic
T=t920_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"

# a horizon over the whole 100 x 100 lattice (~5e7 arms): run refuses it
# at once (it built for minutes before) with the figures and the way out
no_hang 30 1 "huge_horizon.yaml: a run needs about [0-9.]* GiB (estimate: 1e+04 particles, 5e+07 arms, .*factor .* nonzeros) but the limit is 8.0 GiB (--max-memory); set solver.max_memory_gib or --max-memory GIB to raise it" \
  -- run --max-memory 8 -o "$T/x" "$D/huge_horizon.yaml"
[ ! -e "$T/x" ] && [ ! -e "$T/x.partial" ] && ok "a refused run writes nothing" ||
  ko "a refused run left an output folder"
# the same through kernel.alpha (fibre model): info refuses what it cannot
# build (its tangent pattern), after printing the estimate
expect 1 "huge_alpha.yaml: info (particles, arms and the tangent's pattern) needs about [0-9]* GiB" \
  -- info --max-memory 4 "$D/huge_alpha.yaml"
out=$($P info --max-memory 4 "$D/huge_alpha.yaml" 2>/dev/null)
printf '%s\n' "$out" | grep -q "^estimate_arms: 6.4[0-9]*e+06" &&
  printf '%s\n' "$out" | grep -q "^memory_limit_MiB: 4096 (--max-memory)" &&
  ! printf '%s\n' "$out" | grep -q "^arms:" &&
  ok "info prints the estimate of the case it refuses, and nothing it did not build" ||
  ko "info of the refused case: $out"
# 10^8 particles: refused from the counts, before any allocation
no_hang 30 1 "many_particles.yaml: building its particles and arms needs about [0-9]* GiB (estimate: 1e+08 particles, 1.2e+09 arms" \
  -- info --max-memory 8 "$D/many_particles.yaml"
# (10^8 particles would take gigabytes: 64 MiB leaves room for a
# sanitizer's own memory; /usr/bin/time is Debian's package time)
kb=$(/usr/bin/time -f "%M" $P run --max-memory 8 -o "$T/x" "$D/many_particles.yaml" 2>&1 >/dev/null | tail -1)
[ "${kb:-999999}" -lt 65536 ] && ok "... with a peak of $kb KiB (nothing allocated)" ||
  ko "10^8 particles: peak ${kb:-unknown} KiB (want < 64 MiB; /usr/bin/time from package time)"
# a disk asking for 2.9e10 particles (n_xi * per_zone beyond 2^31)
expect 1 "many_disk.yaml: building its particles and arms needs about [0-9]* GiB (estimate: 2.88e+10 particles" \
  -- run -o "$T/x" "$D/many_disk.yaml"
# --max-memory: a tiny limit refuses a small case and names it; bad values
expect 1 "small_box.yaml: a run needs about [0-9]* MiB (estimate: 72 particles.*) but the limit is 2 MiB (--max-memory); set solver.max_memory_gib or --max-memory GIB" \
  -- run --max-memory 0.001 -o "$T/x" "$D/small_box.yaml"
expect 1 "max-memory needs a number of GiB > 0" -- run --max-memory 0 "$D/small_box.yaml"
expect 1 "max-memory needs a number of GiB > 0" -- run --max-memory 2x "$D/small_box.yaml"
expect 1 "max-memory needs a number of GiB > 0" -- run --max-memory
expect 1 "max-memory needs a number of GiB > 0 (at most 1e+06)" -- run --max-memory 0x10 "$D/small_box.yaml"
expect 1 "max-memory needs a number of GiB > 0 (at most 1e+06)" -- run --max-memory 1e7 "$D/small_box.yaml"
# the limit from the case names its key
{ cat "$D/small_box.yaml"; echo "solver: {max_memory_gib: 0.001}"; } > "$T/small_box_limit.yaml"
expect 1 "small_box_limit.yaml: a run needs about [0-9]* MiB .* but the limit is 2 MiB (solver.max_memory_gib)" \
  -- run -o "$T/x" "$T/small_box_limit.yaml"
$P --help | grep -q -- "--max-memory GIB" && ok "--help names --max-memory" || ko "--help: --max-memory"
# info prints the estimate before its own measured lines; the estimate is
# close to them on a small case
out=$($P info "$D/small_box.yaml")
for k in estimate_particles estimate_arms estimate_tangent_nnz estimate_factor_nnz \
         estimate_memory_MiB memory_limit_MiB arms tangent_nnz_upper; do
  printf '%s\n' "$out" | grep -q "^$k: [0-9]" || ko "info prints $k"
done
if printf '%s\n' "$out" | awk -F': ' '$1 == "estimate_arms" { e = $2 } $1 == "arms" { a = $2; ea = NR }
     $1 == "memory_limit_MiB" { l = NR } END { exit !(e > 0.9 * a && e < 1.1 * a && l < ea) }'; then
  ok "info: the estimate lines come first, estimated arms within 10% of the network's"
else
  ko "info's estimate: $out"
fi
$P run -q --max-memory 1 -o "$T/ok" "$D/small_box.yaml" && [ -f "$T/ok/summary.txt" ] &&
  ok "--max-memory 1 runs the small case" || ko "--max-memory 1 refused the small case"

# one outlying particle the sample misses: a stray point far away (its
# Eq. 115 size makes its horizon cover the 60 x 60 lattice) makes the
# fibre model's tangent pattern grow as n^2 (~600 MiB for info); every
# particle's own horizon is counted, so the estimate sees it
awk 'BEGIN { for (j = 0; j < 60; j++) for (i = 0; i < 60; i++) printf "%.6f %.6f 1e-6\n", i * 1e-3, j * 1e-3;
  print "1000.0 0.0 1e-6" }' > "$T/out60.txt"
printf 'geometry: {type: cloud, dim: 2, file: out60.txt, sizes: eq115}\nloading:\n  type: boundary\n  boundary:\n    - {select: {x_max: 0.0005}, fix: [x, y]}\n    - {select: {x_min: 0.0585}, displace: {x: 1.0e-6}}\n' > "$T/out60.yaml"
no_hang 30 1 "out60.yaml: info (particles, arms and the tangent's pattern) needs about [0-9]* MiB" \
  -- info --max-memory 0.1 "$T/out60.yaml"
# 150 particles of a 200 x 200 Eq. 44 cloud with volumes 3e4 too large:
# the estimate listed whole bodies for each sample (24 s); now it counts
awk 'BEGIN { for (j = 0; j < 200; j++) for (i = 0; i < 200; i++)
  printf "%.4f %.4f %s\n", i * 1e-3, j * 1e-3, (200 * j + i) % 267 == 103 ? "0.0314" : "1e-6" }' > "$T/bigvol.txt"
printf 'geometry: {type: cloud, dim: 2, file: bigvol.txt, sizes: eq44}\nloading:\n  type: boundary\n  boundary:\n    - {select: {x_max: 0.0005}, fix: [x, y]}\n    - {select: {x_min: 0.1985}, displace: {x: 1.0e-6}}\n' > "$T/bigvol.yaml"
no_hang 30 1 "bigvol.yaml: info (particles, arms and the tangent's pattern) needs about [0-9]* GiB" \
  -- info --max-memory 4 "$T/bigvol.yaml"

# coincident particles with Eq. 44 sizes (and Eq. 115): the right pair,
# with the cloud file and lines (coincide.txt lines 4 and 5)
expect 1 "coincide_eq44.yaml: .*coincide.txt:5: particles 1 and 2 coincide (at (0.001, 0)), the first at line 4" \
  -- run -o "$T/x" "$D/coincide_eq44.yaml"
expect 1 "coincide_eq44.yaml: .*coincide.txt:5: particles 1 and 2 coincide" \
  -- info "$D/coincide_eq44.yaml"
expect 1 "coincide_eq115.yaml: .*coincide.txt:5: particles 1 and 2 coincide" \
  -- run -o "$T/x" "$D/coincide_eq115.yaml"
# a box whose origin is huge against its spacing collapses onto one point
expect 1 "huge_origin.yaml: particles 0 and [0-9]* coincide (at (1e+20, .*coordinates too large for their spacing" \
  -- run -o "$T/x" "$D/huge_origin.yaml"
# a cloud coordinate that overflows (the cloud reader names it)
expect 1 "nan_cloud.txt:4: .*not a finite" -- run -o "$T/x" "$D/nan_cloud.yaml"
# no arms at all
expect 1 "no_arms.yaml: no arms: the horizon holds no neighbours; alpha too small or particles too far apart" \
  -- run -o "$T/x" "$D/no_arms.yaml"
# setup errors name the case file: too few particles for Eq. 115
expect 1 "too_few.yaml: .*Eq. 115 with n = 5 needs at least 6 particles (have 3)" \
  -- info "$D/too_few.yaml"

rm -rf "$T" "$T.partial"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
