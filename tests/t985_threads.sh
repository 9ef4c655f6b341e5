#!/bin/sh
# t985_threads.sh: the numbers of a run depend on solver.parts (the parts
# every parallel loop is split into: per-arm loops, matrix-free products,
# the preconditioner's subtrees), never on the threads (-t) that run them.
# Two whole runs to fracture: a fibre disk of 512 particles (eq116, the
# majorant and CG with the single-precision preconditioner) and a bond
# notched plate of 30 x 30 (critical stretch, CG with the old factor).
# (a) parts: 4 with -t 1, -t 2 and -t 4 gives the same history.csv (every
#     column but wall_s) and particles.csv, byte for byte; summary.txt
#     says threads 1, 2, 4 and parts 4; parts 3 (an uneven split) on 1
#     and 3 threads likewise.
# (b) parts: 2 is the default: a case with `parts: 2` on 4 threads (of
#     which 2 are used: threads = min(-t, parts)) gives the numbers and
#     the fingerprint of the case without the key on 1 thread (and those
#     are the numbers from before parts was a setting: checked when it
#     became one, doc/performance.md).
# (c) parts: 4 enters the fingerprint (another order of the sums).
# (d) parts outside 1 .. 64 is bad input (exit 1).
# Four threads on two cores are fine here: a test of bit identity, not of
# speed.
srcdir=${srcdir:-.}
P=./peristatic
T=t985_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"

cat > "$T/disk.yaml" <<'EOF'
name: t985-disk
geometry:
  type: disk
  c: 0.041666666666666664
  n_eta: 4
  n_xi: 8
  per_zone: 4
  jitter: 0.1
  seed: 11
kernel:
  alpha: 5.1
material:
  E: 210.0e9
  nu: 0.3
  plane: strain
  yield_strain: 0.002
  delta_over_c: 0.001
loading:
  type: eq116
path:
  load_step: 0.05
  load_step_after_break: 0.01
  max_load: 3.0
output:
  vtk_every: 0
EOF
cat > "$T/bond.yaml" <<'EOF'
name: t985-bond
geometry:
  type: box
  dim: 2
  counts: [30, 30]
  spacing: 1.6666666666666666e-3
  cracks: [[[-0.002, 0.025], [0.0125, 0.025]]]
material:
  model: bond
  E: 72.0e9
  nu: 0.3333333333333333
  plane: stress
  horizon_factor: 3.015
  micromodulus: constant
  partial_volumes: false
  surface_correction: false
  fracture: {critical_stretch: 1.0e-3}
loading:
  type: boundary
  boundary:
    - select: {y_max: 0.005}
      fix: [x, y]
    - select: {y_min: 0.045}
      fix: [x]
      displace: {y: 1.5e-4}
      measure: true
path:
  load_step: 0.02
  max_load: 1.0
  stop_load_drop: 0.05
output:
  vtk_every: 0
EOF
# $T/CASE-pN.yaml: CASE with solver.parts N
for c in disk bond; do
  for n in 2 3 4; do
    { cat "$T/$c.yaml"; printf 'solver:\n  parts: %s\n' "$n"; } > "$T/$c-p$n.yaml"
  done
done

val() { sed -n "s/^$2: //p" "$1"; }
# history.csv without its wall_s column
hist() { drop_columns "$1" wall_s; }
# same A B: history.csv (but wall_s) and particles.csv of runs A and B
# byte for byte (the first difference in $why)
same() {
  why=""
  hist "$T/$1/history.csv" > "$T/$1.h"
  hist "$T/$2/history.csv" > "$T/$2.h"
  if ! cmp "$T/$1.h" "$T/$2.h" > "$T/cmp" 2>&1; then why="history.csv: $(cat "$T/cmp")"; return 1; fi
  if ! cmp "$T/$1/particles.csv" "$T/$2/particles.csv" > "$T/cmp" 2>&1; then
    why="particles.csv: $(cat "$T/cmp")"; return 1
  fi
  [ -s "$T/$1.h" ] && [ -s "$T/$1/particles.csv" ] || { why="empty outputs"; return 1; }
}
# run NAME THREADS CASE: peristatic run -t THREADS into $T/NAME
run() {
  if ! $P run -q -t "$2" -o "$T/$1" "$T/$3.yaml" 2>"$T/$1.err"; then
    ko "run -t $2 $3.yaml failed: $(head -3 "$T/$1.err")"
    return 1
  fi
}

for c in disk bond; do
  # (a) parts 4 on 1, 2, 4 threads; parts 3 on 1 and 3
  if run "$c-p4-t1" 1 "$c-p4" && run "$c-p4-t2" 2 "$c-p4" && run "$c-p4-t4" 4 "$c-p4"; then
    ok4=1
    for t in 2 4; do
      if same "$c-p4-t1" "$c-p4-t$t"; then :; else ok4=0; ko "$c, parts 4: -t 1 and -t $t differ: $why"; fi
    done
    th="$(val "$T/$c-p4-t1/summary.txt" threads) $(val "$T/$c-p4-t2/summary.txt" threads) $(val "$T/$c-p4-t4/summary.txt" threads)"
    pa=$(val "$T/$c-p4-t4/summary.txt" parts)
    if [ "$th" != "1 2 4" ] || [ "$pa" != 4 ]; then
      ok4=0; ko "$c, parts 4: summary.txt threads '$th' (want '1 2 4'), parts '$pa' (want 4)"
    fi
    [ "$(val "$T/$c-p4-t1/summary.txt" fractured)" = yes ] || { ok4=0; ko "$c: no fracture"; }
    [ $ok4 = 1 ] && ok "$c to fracture, parts 4: -t 1, 2 and 4 give the same history.csv (but wall_s) and particles.csv, byte for byte"
  fi
  if run "$c-p3-t1" 1 "$c-p3" && run "$c-p3-t3" 3 "$c-p3"; then
    if same "$c-p3-t1" "$c-p3-t3"; then ok "$c, parts 3: -t 1 and -t 3 the same, byte for byte"
    else ko "$c, parts 3: -t 1 and -t 3 differ: $why"; fi
  fi
  # (b) parts 2 (on min(4, 2) threads) is the default (on 1)
  if run "$c-def-t1" 1 "$c" && run "$c-p2-t4" 4 "$c-p2"; then
    fd=$(val "$T/$c-def-t1/summary.txt" case_fingerprint)
    if same "$c-def-t1" "$c-p2-t4" && [ "$(val "$T/$c-p2-t4/summary.txt" threads)" = 2 ] &&
       [ "$fd" = "$(val "$T/$c-p2-t4/summary.txt" case_fingerprint)" ] &&
       [ "$(val "$T/$c-def-t1/summary.txt" parts)" = 2 ]; then
      ok "$c: parts 2 on -t 4 (2 threads used) is the default on -t 1: the same outputs and fingerprint"
    else
      ko "$c: parts 2 -t 4 against the default -t 1: ${why:-threads $(val "$T/$c-p2-t4/summary.txt" threads) (want 2), or another fingerprint}"
    fi
    # (c) the fingerprint knows parts
    if [ -n "$fd" ] && [ "$fd" != "$(val "$T/$c-p4-t1/summary.txt" case_fingerprint)" ]; then
      ok "$c: parts 4 changes the case fingerprint"
    else
      ko "$c: parts 4 has the default's fingerprint $fd"
    fi
  fi
done
if ! cmp -s "$T/disk-def-t1/particles.csv" "$T/disk-p4-t1/particles.csv"; then
  ok "disk: parts 4 gives other round-off than parts 2 (the parts fix the order of the sums)"
else
  ko "disk: parts 4 and 2 give the same particles.csv: is solver.parts read?"
fi

# (d) bad input
for n in 0 65; do
  sed "s/parts: 4/parts: $n/" "$T/disk-p4.yaml" > "$T/bad$n.yaml"
  expect 1 "solver.parts" -- run -q -o "$T/bad" "$T/bad$n.yaml"
done

rm -rf "$T" "$T.partial"
summary
