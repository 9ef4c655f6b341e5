#!/bin/sh
# t990_petsc.sh: the PETSc backend (solver.linear: petsc) against the
# serial CHOLMOD result, on 1, 2 and 3 MPI ranks (3 oversubscribes the
# 2-core machine: fine, this is a test of numbers, not of speed).
#
# In a build without PETSc (configure without --with-petsc): a case asking
# for it and a PETSc option on the command line are refused with exit 1 and
# a message that says how to get it; the MPI checks below are not in this
# build's list (they run in CI's configuration, .ci/run --with-petsc).
#
# With PETSc (default KSP: preonly + MUMPS Cholesky, a direct solve):
# (a) small-disk (the paper's fibre disk, 1,800 particles, to fracture;
#     a fresh factor for every Newton system, reuse_factor: false; on 2
#     and 3 ranks the distributed model, solver.layout auto, see (h)):
#     sigma_f / sigma_y and the broken arms identical to CHOLMOD's (as
#     printed, 8 digits), every history.csv column but wall_s and the
#     Newton residual identical as printed, and the final displacements
#     within 1e-8 of the largest (normwise relative), on -n 1, 2, 3;
#     (a2) the default (reused factors, the majorant's) on -n 2: sigma_f and the
#     broken arms as printed, displacements within 1e-6;
# (b) edge-crack-bond (bond model, 20,300 particles, J and K by the
#     interaction integral): every j_/k_ value of summary.txt within 1e-8
#     relative of CHOLMOD's, on -n 3 (the distributed model: J summed over
#     each rank's own particles and arms);
# (c) tension-block-3d (fibre model in 3D, to fracture, majorant: false): the broken arms
#     and the peak stress as printed, displacements within 1e-8, on -n 2;
# (d) two particles on 3 ranks (a rank with no particle and no row):
#     the CHOLMOD displacements within 1e-8;
# (e) iterative solves on the edge crack, 2 ranks, options on the command
#     line: CG + GAMG with the rigid-body near-null space, and CG + block
#     Jacobi ICC on the symmetric (sbaij) storage: J within 1e-6 (Newton's
#     tolerance 1e-8 and CG's bound the difference, not round-off);
# (g) ps_comm on 1, 2 and 3 ranks (tests/comm_check: sums, maxima, minima,
#     counts and agreed flags against their closed forms on every rank);
#     and a distributed model's evaluation (tests/share_check: each rank's
#     share with its ghosts filled by the halo, the energy, dissipation and
#     counts summed over the ranks by the solver's reductions, against the
#     whole model, at a state past yield and again after committing it
#     and loading further: the small disk (fibre, two horizons of
#     ghosts; total and deviatoric yield rules) and the notched
#     three-body plate (three)); and Newton on the distributed
#     model (tests/solve_check: each rank's share solved through PETSc's
#     MUMPS with the rows of its owned dofs, two load increments, the
#     second past yield: owned and ghost displacements within 1e-8 of the
#     largest of the serial CHOLMOD solution, yielding arms as serial;
#     then an arc-length and a dissipation-controlled step: load factor
#     and displacements within 1e-8; the small disk, the 3D tension block
#     and the three-body plate);
# (f) an unknown -pc_type is a clear error (exit 2, PETSc's words) and
#     leaves no output folder; solver.petsc_options that are not options
#     are refused naming the file and line (exit 1).
# The tolerances: MUMPS's LDL^T and CHOLMOD's LL^T of the same matrices
# differ by round-off (1e-12 relative here); 1e-8 is the issue's bound.
srcdir=${srcdir:-.}
P=./peristatic
T=t990_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"
C="$srcdir/data/cases"

with_solver() { # $1 = case file, $2 = output case file, $3 = extra solver lines (awk -v
  # reads \n in them as a line break)
  awk -v extra="$3" '/^solver:/ { s = 1; print; print extra; next }
    { print } END { if (!s) { print "solver:"; print extra } }' "$1" > "$2"
}
with_petsc() { # $1 = case file, $2 = output case file, $3 = extra solver lines
  with_solver "$1" "$2" "  linear: petsc${3:+\n$3}"
}

if [ "${PS_PETSC_STATE:-disabled}" != yes ]; then
  with_petsc "$C/small-disk.yaml" "$T/disk.yaml" ""
  line=$(grep -n "linear: petsc" "$T/disk.yaml" | cut -d: -f1)
  expect 1 "disk.yaml:$line: solver.linear: petsc needs a peristatic configured --with-petsc" \
    -- run -q -o "$T/x" "$T/disk.yaml"
  expect 1 "built without PETSc: configure --with-petsc" -- run -q -o "$T/x" -ksp_type cg \
    "$C/small-disk.yaml"
  if [ -d "$T/x" ]; then ko "a refused run wrote $T/x"; else ok "a refused run wrote nothing"; fi
  summary
  exit $?
fi

MPIEXEC=${MPIEXEC:-mpiexec}
# Open MPI refuses root and more ranks than cores unless told
OMPI_ALLOW_RUN_AS_ROOT=1
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM OMPI_MCA_rmaps_base_oversubscribe

val() { sed -n "s/^$2: //p" "$1"; }
# run NAME NP CASE [ARGS]: peristatic run on NP ranks (0: no mpiexec)
run() {
  name=$1 np=$2 cs=$3
  shift 3
  if [ "$np" -eq 0 ]; then set -- $P run -q -t 1 -o "$T/$name" "$@" "$cs"
  else set -- "$MPIEXEC" -n "$np" $P run -q -t 1 -o "$T/$name" "$@" "$cs"; fi
  if ! "$@" > "$T/$name.out" 2> "$T/$name.err"; then
    ko "$name: $* failed: $(head -5 "$T/$name.err")"
    return 1
  fi
}
# history.csv without wall_s and relative_residual (the residual Newton
# stopped at is round-off of the solver, not a result)
hist() { drop_columns "$1" wall_s relative_residual; }
# udiff A B: max |u_A - u_B| / max |u| over the displacement columns of
# particles.csv (ux, uy[, uz])
udiff() {
  awk -F, 'FNR == 1 { n = 0; for (i = 1; i <= NF; i++) if ($i ~ /^u[xyz]$/) c[++n] = i; next }
    FNR == NR { for (k = 1; k <= n; k++) a[FNR, k] = $c[k]; next }
    { for (k = 1; k <= n; k++) { d = $c[k] - a[FNR, k]; if (d < 0) d = -d; if (d > m) m = d;
        v = $c[k] < 0 ? -$c[k] : $c[k]; if (v > u) u = v } }
    END { if (u == 0) print "nan"; else printf "%.3g\n", m / u }' "$T/$1/particles.csv" "$T/$2/particles.csv"
}
u_ok() { # NAME REF TOL
  d=$(udiff "$2" "$1")
  if awk -v d="$d" -v t="$3" 'BEGIN { exit !(d != "nan" && d + 0 <= t + 0) }'; then
    ok "$1: displacements within $3 of $2's (max difference / max |u| = $d)"
  else ko "$1: displacements differ from $2's by $d of the largest (want <= $3)"; fi
}
same_val() { # NAME REF KEY
  a=$(val "$T/$1/summary.txt" "$3")
  b=$(val "$T/$2/summary.txt" "$3")
  if [ -n "$a" ] && [ "$a" = "$b" ]; then ok "$1: $3 = $a as $2's"
  else ko "$1: $3 = '$a', $2's '$b'"; fi
}
# every j_ and k_ value of summary.txt within TOL relative of REF's
j_ok() { # NAME REF TOL
  grep -E '^[jk]_' "$T/$2/summary.txt" > "$T/$2.jk"
  grep -E '^[jk]_' "$T/$1/summary.txt" > "$T/$1.jk"
  r=$(awk -v t="$3" 'FNR == NR { a[$1] = $2; n++; next }
    ($1 in a) { m++; d = $2 - a[$1]; s = $2 < 0 ? -$2 : $2; s2 = a[$1] < 0 ? -a[$1] : a[$1];
      if (s2 > s) s = s2; if (d < 0) d = -d; if (d > t * s) { bad = bad " " $1 } }
    END { if (n == 0 || m != n) print "missing"; else if (bad != "") print bad; else print "ok" }' \
    "$T/$2.jk" "$T/$1.jk")
  if [ "$r" = ok ]; then ok "$1: $(wc -l < "$T/$1.jk") J and K values within $3 of $2's"
  else ko "$1: J/K values beyond $3 of $2's: $r"; fi
}

# (a) the small disk to fracture, every Newton system solved by a fresh
# factor of its tangent (reuse_factor: false): the backends' runs then
# differ by the round-off of two direct solves. With factors reused as
# CG's preconditioners (the default; (a2)) CG stops at its tolerance with
# iterates that depend on the factor (CHOLMOD's single-precision copy,
# MUMPS's double, a factor of another tangent): 2e-8 of the
# displacements, measured with reuse on and the majorant on or off (the
# result of inexact Newton, not of the backend).
with_solver "$C/small-disk.yaml" "$T/disk-exact.yaml" "  reuse_factor: false"
with_petsc "$C/small-disk.yaml" "$T/disk.yaml" "  reuse_factor: false"
if run disk-chol 0 "$T/disk-exact.yaml"; then
  hist "$T/disk-chol/history.csv" > "$T/disk-chol.h"
  for np in 1 2 3; do
    run "disk-n$np" "$np" "$T/disk.yaml" || continue
    same_val "disk-n$np" disk-chol sigma_failure_over_sigma_y
    same_val "disk-n$np" disk-chol arms_broken
    hist "$T/disk-n$np/history.csv" > "$T/disk-n$np.h"
    if cmp -s "$T/disk-chol.h" "$T/disk-n$np.h" && [ -s "$T/disk-chol.h" ]; then
      ok "disk-n$np: history.csv (but wall_s, relative_residual) as CHOLMOD's"
    else ko "disk-n$np: history.csv differs: $(diff "$T/disk-chol.h" "$T/disk-n$np.h" | head -3)"; fi
    u_ok "disk-n$np" disk-chol 1e-8
  done
  # only rank 0 wrote: one summary, one set of field files, no stray folders
  n=$(ls -d "$T"/disk-n3* 2>/dev/null | grep -c -v '\.\(out\|err\|h\)$')
  if [ "$n" -eq 1 ] && [ ! -d "$T/disk-n3.partial" ]; then ok "3 ranks wrote one output folder"
  else ko "3 ranks left $n folders: $(ls -d "$T"/disk-n3*)"; fi
  if [ "$(grep -c '^# results in' "$T/disk-n1.err")" -eq 0 ] && [ ! -s "$T/disk-n3.out" ]; then
    ok "-q runs on 3 ranks print nothing on stdout"
  else ko "unexpected output of the MPI runs: $(head -3 "$T/disk-n3.out")"; fi
fi

# (b) the edge crack: J and K
with_petsc "$C/edge-crack-bond.yaml" "$T/edge.yaml" ""
if run edge-chol 0 "$C/edge-crack-bond.yaml"; then
  if run edge-n3 3 "$T/edge.yaml"; then
    j_ok edge-n3 edge-chol 1e-8
    # on the distributed model (solver.layout auto): each rank sums J over
    # its own particles and arms, with two horizons of ghosts
    if [ "$(val "$T/edge-n3/summary.txt" distributed)" = yes ]; then
      ok "edge-n3: J and K from the distributed model"
    else ko "edge-n3: not distributed"; fi
  fi
  # (e) iterative: CG + GAMG, options from the command line
  if run edge-gamg 2 "$T/edge.yaml" -ksp_type cg -pc_type gamg; then
    j_ok edge-gamg edge-chol 1e-6
  fi
  # the symmetric storage (upper triangle) with block-Jacobi incomplete
  # Cholesky
  if run edge-sbaij 2 "$T/edge.yaml" -mat_type sbaij -ksp_type cg -pc_type bjacobi \
    -sub_pc_type icc; then
    j_ok edge-sbaij edge-chol 1e-6
  fi
fi

# (a2) the small disk with the majorant's factor (the default) on 2
# ranks: the same fracture load and broken arms as CHOLMOD's default
# run, displacements within 1e-6 (CG's and Newton's tolerances)
with_petsc "$C/small-disk.yaml" "$T/disk-maj.yaml" ""
if run disk-maj-chol 0 "$C/small-disk.yaml" && run disk-maj-n2 2 "$T/disk-maj.yaml"; then
  same_val disk-maj-n2 disk-maj-chol sigma_failure_over_sigma_y
  same_val disk-maj-n2 disk-maj-chol arms_broken
  u_ok disk-maj-n2 disk-maj-chol 1e-6
fi

# (c) the 3D block to fracture, CG on the tangent's own factors in both
# backends (majorant: false), every rank holding the whole model
# (layout: replicated; the distributed layout is (h)): they agree to
# 3e-12 here
with_solver "$C/tension-block-3d.yaml" "$T/block-exact.yaml" "  majorant: false"
with_petsc "$C/tension-block-3d.yaml" "$T/block.yaml" "  majorant: false\n  layout: replicated"
if run block-chol 0 "$T/block-exact.yaml" && run block-n2 2 "$T/block.yaml"; then
  same_val block-n2 block-chol arms_broken
  same_val block-n2 block-chol sigma_failure_Pa
  u_ok block-n2 block-chol 1e-8
  # the rows along the space-filling curve (the default on several ranks)
  # and in the dofs' own order give the same run
  if run block-n3 3 "$T/block.yaml" && run block-n3-natural 3 "$T/block.yaml" -peristatic_rows natural; then
    same_val block-n3 block-chol arms_broken
    same_val block-n3-natural block-chol arms_broken
    u_ok block-n3 block-chol 1e-8
    u_ok block-n3-natural block-chol 1e-8
  fi
fi

# (d) a rank with no row: two particles (a 2 x 1 bond strip, the left one
# held, the right one held in y and pulled by a traction in x: 1 free dof,
# its x) make a system of 4 dofs in blocks of 2, one particle each for
# ranks 0 and 1, none for rank 2
cat > "$T/tiny.yaml" <<'EOF'
name: t990-tiny
geometry:
  type: box
  dim: 2
  counts: [2, 1]
  spacing: 1.0e-3
material:
  model: bond
  E: 72.0e9
  nu: 0.3333333333333333
  plane: stress
  horizon_factor: 1.5
loading:
  type: boundary
  boundary:
    - select: {x_max: 0.0005}
      fix: [x, y]
    - select: {x_min: 0.0005}
      fix: [y]
      traction: {x: 1.0e6}
path:
  load_step: 0.5
  max_load: 1.0
output:
  vtk_every: 0
EOF
with_petsc "$T/tiny.yaml" "$T/tiny-petsc.yaml" ""
if run tiny-chol 0 "$T/tiny.yaml" && run tiny-n3 3 "$T/tiny-petsc.yaml"; then
  nf=$(val "$T/tiny-n3/summary.txt" free_dofs)
  if [ "$nf" = 1 ]; then ok "tiny: 1 free dof, 2 particles on 3 ranks"; else ko "tiny: free_dofs $nf, want 1"; fi
  u_ok tiny-n3 tiny-chol 1e-8
fi

# (g) the reductions of a distributed run (ps_comm over MPI)
for np in 1 2 3; do
  out=$("$MPIEXEC" -n "$np" ./tests/comm_check 2>&1)
  rc=$?
  n=$(printf '%s\n' "$out" | grep -c "^comm_check: rank [0-9]* of $np: ok$")
  if [ "$rc" -eq 0 ] && [ "$n" -eq "$np" ]; then
    ok "ps_comm on $np ranks: every rank's sums, maxima, minima, counts and flags exact"
  else ko "ps_comm on $np ranks: exit $rc, $n of $np ranks ok: $(printf '%s' "$out" | head -3)"; fi
  sed 's/^material:/material:\n  yield_rule: deviatoric/' "$C/small-disk.yaml" \
    > "$T/small-disk-deviatoric.yaml"
  for cs in "$C/small-disk" "$T/small-disk-deviatoric" "$C/notched-plate-threebody"; do
    out=$("$MPIEXEC" -n "$np" ./tests/share_check "$cs.yaml" 2>&1)
    rc=$?
    n=$(printf '%s\n' "$out" | grep -c "^share_check: rank [0-9]* of $np: ok ")
    if [ "$rc" -eq 0 ] && [ "$n" -eq "$np" ]; then
      ok "${cs##*/} on $np ranks: each share's ghosts from the halo, forces at owned dofs, the energy, dissipation and counts over the ranks as the whole model's, before and after a commit"
    else ko "${cs##*/} on $np ranks: exit $rc, $n of $np ranks ok: $(printf '%s' "$out" | head -4)"; fi
  done
  for cs in small-disk tension-block-3d notched-plate-threebody; do
    out=$("$MPIEXEC" -n "$np" ./tests/solve_check "$C/$cs.yaml" 2>&1)
    rc=$?
    n=$(printf '%s\n' "$out" | grep -c "^solve_check: rank [0-9]* of $np: load factor [0-9.]*: ok ")
    m=$(printf '%s\n' "$out" | grep -c "^solve_check: rank [0-9]* of $np: [a-z-]* step: ok ")
    if [ "$rc" -eq 0 ] && [ "$n" -eq $((2 * np)) ] && [ "$m" -eq $((2 * np)) ]; then
      ok "$cs on $np ranks: Newton, an arc-length and a dissipation step on the distributed model, displacements and load factors as the serial solution's ($(printf '%s\n' "$out" | grep 'rank 0 of.*1.1:' | sed 's/.*displacements off by \([^ ]*\) (owned).*/\1/') of the largest)"
    else ko "$cs on $np ranks: exit $rc, $n and $m of $((2 * np)) ok: $(printf '%s' "$out" | grep -v ': ok ' | grep -v '^ *$' | head -4)"; fi
  done
done

# (h) the distributed layout of `peristatic run` (solver.layout: auto): a
# case whose arms cannot break runs on each process's share (ghosts out
# to the model's reach; with reuse_factor: false MUMPS's factor of each
# Newton system). Against
# the serial CHOLMOD run with a fresh factor per Newton system: history.csv
# (but wall_s and relative_residual) identical as printed and the
# displacements within 1e-8 of the largest (the issue's bound; the two
# direct solvers differ by round-off), on the plastic 3D block (no
# delta: it yields, never breaks; 2 and 3 ranks) and the elastic fibre
# plate with a hole under tractions (3 ranks). Each rank writes its own
# VTK pieces, rank 0 the .pvtu that joins them: the pieces hold every
# particle and every arm once.
sed -e '/delta: 2.0e-6/d' -e 's/max_load: 3.0/max_load: 1.5/' -e 's/load_step: 0.05/load_step: 0.25/' \
  -e 's/vtk_every: 0/vtk_every: 3/' "$C/tension-block-3d.yaml" > "$T/plastic.yaml"
with_solver "$T/plastic.yaml" "$T/plastic-exact.yaml" "  reuse_factor: false"
with_petsc "$T/plastic.yaml" "$T/plastic-petsc.yaml" "  reuse_factor: false"
with_petsc "$T/plastic.yaml" "$T/plastic-lagged.yaml" ""
with_solver "$C/plate-hole-fibre.yaml" "$T/hole-exact.yaml" "  reuse_factor: false"
with_petsc "$C/plate-hole-fibre.yaml" "$T/hole-petsc.yaml" "  reuse_factor: false"
# pieces NAME KIND STEP: the sum over the .pvtu's pieces of NumberOfPoints
# (particles) or NumberOfCells (arms)
pieces() {
  what=NumberOfPoints
  [ "$2" = arms ] && what=NumberOfCells
  for f in $(sed -n 's/.*Source="\([^"]*\)".*/\1/p' "$T/$1/$2_$3.pvtu"); do
    grep -a -o "$what=\"[0-9]*\"" "$T/$1/$f" | tr -dc '0-9'; echo
  done | awk '{ s += $1 } END { print s + 0 }'
}
dist_ok() { # NAME REF NP STEP
  if [ "$(val "$T/$1/summary.txt" distributed)" = yes ] &&
     [ "$(val "$T/$1/summary.txt" processes)" = "$3" ]; then
    ok "$1: distributed over $3 processes (summary.txt)"
  else ko "$1: not distributed on $3: $(grep -E '^(distributed|processes):' "$T/$1/summary.txt")"; fi
  hist "$T/$2/history.csv" > "$T/$2.h"
  hist "$T/$1/history.csv" > "$T/$1.h"
  if cmp -s "$T/$2.h" "$T/$1.h" && [ -s "$T/$2.h" ]; then
    ok "$1: history.csv (but wall_s, relative_residual) as the serial run's"
  else ko "$1: history.csv differs: $(diff "$T/$2.h" "$T/$1.h" | head -3)"; fi
  u_ok "$1" "$2" 1e-8
  # the whole tangent's size, counted over the shares' owned rows
  same_val "$1" "$2" nnz_tangent_upper
  n=$(ls "$T/$1" | grep -c "^particles_$4_p[0-9]*\.vtu$")
  np=$(pieces "$1" particles "$4") na=$(pieces "$1" arms "$4")
  want_n=$(val "$T/$2/summary.txt" particles) want_a=$(val "$T/$2/summary.txt" arms)
  if [ "$n" -eq "$3" ] && [ "$np" = "$want_n" ] && [ "$na" = "$want_a" ] &&
     grep -q "particles_$4.pvtu" "$T/$1/particles.pvd"; then
    ok "$1: $n VTK pieces of step $4 hold the $np particles and $na arms once"
  else ko "$1: $n pieces, $np particles (want $want_n), $na arms (want $want_a)"; fi
}
if run plastic-chol 0 "$T/plastic-exact.yaml"; then
  for np in 2 3; do
    run "plastic-n$np" "$np" "$T/plastic-petsc.yaml" && dist_ok "plastic-n$np" plastic-chol "$np" 0003
  done
  # a distributed run's folder (its pieces and .pvtu files) is one of
  # ours: a second run replaces it
  if run plastic-n2 2 "$T/plastic-petsc.yaml"; then
    ok "plastic-n2: a second run replaced the first one's folder of pieces"
  fi
fi
# and the default, CG with the old MUMPS factor (reuse_factor), its dot
# products over each rank's own dofs: within CG's and Newton's tolerances
if run plastic-lag-n3 3 "$T/plastic-lagged.yaml"; then
  u_ok plastic-lag-n3 plastic-chol 1e-6
  its=$(val "$T/plastic-lag-n3/summary.txt" cg_iterations)
  if [ "${its:-0}" -gt 0 ] && [ "$(val "$T/plastic-lag-n3/summary.txt" distributed)" = yes ]; then
    ok "plastic-lag-n3: distributed, $its CG iterations with lagged factors"
  else ko "plastic-lag-n3: cg_iterations '$its' (want > 0, distributed)"; fi
fi
if run hole-chol 0 "$T/hole-exact.yaml" && run hole-n3 3 "$T/hole-petsc.yaml"; then
  dist_ok hole-n3 hole-chol 3 0001
fi
# breaking on the distributed model (each rank breaks its copies of the
# arms past the criterion, the counts and the worst arms chosen over the
# ranks): the small disk to fracture is (a) above (solver.layout: auto
# makes it distributed); here the 3D block to fracture on 3 ranks, and
# the small disk with at most 40 arms a round (path.max_arms_per_round:
# every round breaks the worst 40 over the ranks, ties by the arms' ends)
# on 2: sigma_f and the broken arms as CHOLMOD's, history.csv identical
# (but wall_s, relative_residual), displacements within 1e-8
with_solver "$C/tension-block-3d.yaml" "$T/block-x.yaml" "  reuse_factor: false"
with_petsc "$C/tension-block-3d.yaml" "$T/block-d.yaml" "  reuse_factor: false"
sed 's/^path:/path:\n  max_arms_per_round: 40/' "$T/disk-exact.yaml" > "$T/worst-exact.yaml"
sed 's/^path:/path:\n  max_arms_per_round: 40/' "$T/disk.yaml" > "$T/worst.yaml"
# same_fracture NAME REF NP TOL [history]: NAME ran distributed over NP
# ranks, its sigma_f (sigma_failure_over_sigma_y, 8 digits) and broken
# arms are REF's as printed, its displacements within TOL of REF's and,
# with `history` (fresh factors in both: round-off apart), its
# history.csv (but wall_s, relative_residual) and sigma_failure_Pa (10
# digits) are REF's
same_fracture() {
  if [ "$(val "$T/$1/summary.txt" distributed)" = yes ] &&
     [ "$(val "$T/$1/summary.txt" processes)" = "$3" ]; then ok "$1: distributed over $3"
  else ko "$1: not distributed over $3"; fi
  same_val "$1" "$2" sigma_failure_over_sigma_y
  [ "$5" = history ] && same_val "$1" "$2" sigma_failure_Pa
  same_val "$1" "$2" arms_broken
  if [ "$5" = history ]; then
    hist "$T/$2/history.csv" > "$T/$2.h"
    hist "$T/$1/history.csv" > "$T/$1.h"
    if cmp -s "$T/$2.h" "$T/$1.h"; then ok "$1: history.csv (but wall_s, relative_residual) as $2's"
    else ko "$1: history.csv differs: $(diff "$T/$2.h" "$T/$1.h" | head -3)"; fi
  fi
  u_ok "$1" "$2" "$4"
}
for pair in "block-x block-d 3 block-x.yaml block-d.yaml" "worst-x worst-d 2 worst-exact.yaml worst.yaml"; do
  set -- $pair
  run "$1" 0 "$T/$4" && run "$2" "$3" "$T/$5" && same_fracture "$2" "$1" "$3" 1e-8 history
done
# path following on the distributed model: 25 increments of the
# perforated plate under arc-length control (fibre, past yield) on 3
# ranks and of the notched plate with softening arms under dissipation
# control (bond) on 2, fresh factors in both backends: history.csv (but
# wall_s, relative_residual) identical as printed, displacements within
# 1e-8
for pair in "arc 3 perforated-plate-arclength" "soft 2 notched-plate-softening"; do
  set -- $pair
  sed 's/^  max_increments: .*/  max_increments: 25/' "$C/$3.yaml" > "$T/$1.yaml"
  with_solver "$T/$1.yaml" "$T/$1-x.yaml" "  reuse_factor: false"
  with_petsc "$T/$1.yaml" "$T/$1-d.yaml" "  reuse_factor: false"
  if run "$1-x" 0 "$T/$1-x.yaml" && run "$1-d" "$2" "$T/$1-d.yaml"; then
    hist "$T/$1-x/history.csv" > "$T/$1-x.h"
    hist "$T/$1-d/history.csv" > "$T/$1-d.h"
    if [ "$(val "$T/$1-d/summary.txt" distributed)" = yes ] &&
       [ "$(val "$T/$1-d/summary.txt" increments)" = 25 ] && cmp -s "$T/$1-x.h" "$T/$1-d.h"; then
      ok "$1-d: $3 on $2 distributed ranks, 25 increments, history.csv as serial CHOLMOD's"
    else ko "$1-d: $(grep -E '^(distributed|increments):' "$T/$1-d/summary.txt" | tr '\n' ' ') $(diff "$T/$1-x.h" "$T/$1-d.h" | head -3)"; fi
    u_ok "$1-d" "$1-x" 1e-8
  fi
done
# breaking judged by the arms' owners only (the three-body model: the
# criterion reads the family's rotation), the other copies taking their
# flags through the arms' halo: the notched three-body plate at 30 x 30
# to fracture on 2 ranks, sigma_f, broken arms and increments as serial
# CHOLMOD's, displacements within 1e-8
sed -e 's/counts: \[60, 60\]/counts: [30, 30]/' \
  -e 's/spacing: 8.333333333333333e-4/spacing: 1.6666666666666666e-3/' \
  "$C/notched-plate-threebody.yaml" > "$T/tb.yaml"
with_solver "$T/tb.yaml" "$T/tb-x.yaml" "  reuse_factor: false"
with_petsc "$T/tb.yaml" "$T/tb-d.yaml" "  reuse_factor: false"
if run tb-x 0 "$T/tb-x.yaml" && run tb-d 2 "$T/tb-d.yaml"; then
  if [ "$(val "$T/tb-d/summary.txt" distributed)" = yes ]; then ok "tb-d: distributed over 2"
  else ko "tb-d: not distributed"; fi
  same_val tb-d tb-x sigma_failure_over_sigma_y
  same_val tb-d tb-x arms_broken
  same_val tb-d tb-x increments
  u_ok tb-d tb-x 1e-8
fi
# the deviatoric yield rule (its half-arms' plastic strains read their
# families' mean strains: a ghost arm at the share's edge takes its
# owner's broken flag through the arms' halo) on 2 ranks with the default
# lagged factors: sigma_f and the broken arms as serial CHOLMOD's default
# run, displacements within 1e-6 as (a2) (CG's and Newton's tolerances)
sed 's/^material:/material:\n  yield_rule: deviatoric/' "$C/small-disk.yaml" > "$T/dev-x.yaml"
with_petsc "$T/dev-x.yaml" "$T/dev-d.yaml" ""
run dev-x 0 "$T/dev-x.yaml" && run dev-d 2 "$T/dev-d.yaml" && same_fracture dev-d dev-x 2 1e-6
# the fibre model's moduli correction (weights balanced over the whole
# cloud: each rank builds the whole network once, takes its share's arms'
# weights from the whole model and frees it) on 2 ranks, fresh factors:
# sigma_f, the broken arms and history.csv (but wall_s,
# relative_residual) as serial CHOLMOD's, displacements within 1e-8
sed 's/^material:/material:\n  surface_correction: true/' "$T/disk-exact.yaml" > "$T/corr-x.yaml"
sed 's/^material:/material:\n  surface_correction: true/' "$T/disk.yaml" > "$T/corr-d.yaml"
run corr-x 0 "$T/corr-x.yaml" && run corr-d 2 "$T/corr-d.yaml" &&
  same_fracture corr-d corr-x 2 1e-8 history
# a case that asks for the distributed layout and cannot have it (the
# serial CHOLMOD backend) is refused before anything is written
with_solver "$C/small-disk.yaml" "$T/disk-dist.yaml" "  layout: distributed"
out=$("$MPIEXEC" -n 2 $P run -q -t 1 -o "$T/dist-refused" "$T/disk-dist.yaml" 2>&1 >/dev/null)
rc=$?
if [ "$rc" -eq 1 ] && printf '%s' "$out" | grep -q "solver.layout: distributed, but solver.linear is not petsc" \
   && [ ! -d "$T/dist-refused" ]; then
  ok "solver.layout: distributed with CHOLMOD: exit 1, says why, no output folder"
else ko "solver.layout: distributed with CHOLMOD: exit $rc, message: $out"; fi

# checkpoints of the distributed model: each rank writes its share's
# state (checkpoint_pR.bin, its kept factor matrix among it); the
# restart-disk of t915 (yielding and breaking arms) on 2 ranks, stopped
# at 13 increments and restarted in place, then stopped again and
# restarted into another folder, gives the uninterrupted 2-rank run's
# history.csv (but wall_s), particles.csv, summary.txt's counts and VTK
# files (pieces, .pvtu, .pvd) to the byte; a restart on 3 ranks is
# refused (exit 1, nothing written), as is one process's restart of it
R="$srcdir/tests/data/restart"
{ cat "$R/disk.yaml"; echo 'solver: {linear: petsc}'; } > "$T/rd.yaml"
sed 's/max_load: 3.0}/max_load: 3.0, max_increments: 13}/' "$T/rd.yaml" > "$T/rd-cut.yaml"
same_run() { # A B WHAT: B's outputs are A's (but the wall times)
  bad=""
  drop_columns "$T/$1/history.csv" wall_s > "$T/$1.hw"
  drop_columns "$T/$2/history.csv" wall_s > "$T/$2.hw"
  cmp -s "$T/$1.hw" "$T/$2.hw" || bad="$bad history.csv"
  cmp -s "$T/$1/particles.csv" "$T/$2/particles.csv" || bad="$bad particles.csv"
  grep -v '_s:\|_MiB:' "$T/$1/summary.txt" > "$T/$1.sw"
  grep -v '_s:\|_MiB:' "$T/$2/summary.txt" > "$T/$2.sw"
  cmp -s "$T/$1.sw" "$T/$2.sw" || bad="$bad summary.txt"
  nf=0
  for f in "$T/$1"/*.vtu "$T/$1"/*.pvtu "$T/$1"/*.pvd; do
    nf=$((nf + 1))
    cmp -s "$f" "$T/$2/${f##*/}" || bad="$bad ${f##*/}"
  done
  if [ -z "$bad" ] && [ "$nf" -gt 6 ] && [ -f "$T/$2/checkpoint_p1.bin" ]; then
    ok "$3: history.csv (but wall_s), particles.csv, summary.txt's counts and $nf VTK files as the uninterrupted run's"
  else ko "$3: differs from the uninterrupted run in$bad ($nf VTK files)"; fi
}
if run rd-full 2 "$T/rd.yaml" && run rd-cut 2 "$T/rd-cut.yaml"; then
  if [ "$(($(wc -l < "$T/rd-cut/history.csv") - 1))" -eq 13 ] &&
     [ -f "$T/rd-cut/checkpoint_p0.bin" ] && [ -f "$T/rd-cut/checkpoint_p1.bin" ] &&
     [ ! -e "$T/rd-cut/checkpoint.bin" ]; then
    ok "rd-cut: 13 increments, a checkpoint per rank"
  else ko "rd-cut: $(ls "$T/rd-cut" | grep checkpoint | tr '\n' ' ')"; fi
  out=$("$MPIEXEC" -n 3 $P run -q -t 1 --restart "$T/rd-cut" -o "$T/rd-3" "$T/rd.yaml" 2>&1 >/dev/null)
  rc=$?
  if [ "$rc" -eq 1 ] && printf '%s' "$out" | grep -q "checkpoint_p0.bin is the checkpoint of process 0 of a distributed run on 2" \
     && [ ! -d "$T/rd-3" ]; then
    ok "a restart of a 2-rank checkpoint on 3 ranks: exit 1, says why, nothing written"
  else ko "a restart on 3 ranks: exit $rc, message: $out"; fi
  expect 1 "has no checkpoint.bin but checkpoint_p0.bin" -- run -q -t 1 --restart "$T/rd-cut" \
    -o "$T/rd-1" "$T/rd.yaml"
  if run rd-cut 2 "$T/rd.yaml" --restart "$T/rd-cut"; then
    same_run rd-full rd-cut "2 ranks stopped at 13 increments, restarted in place"
  fi
  # the cut run again over the restarted one's folder (its checkpoint
  # pieces are ours), then restarted into another folder
  if run rd-cut 2 "$T/rd-cut.yaml" && run rd-other 2 "$T/rd.yaml" --restart "$T/rd-cut"; then
    same_run rd-full rd-other "2 ranks stopped at 13, restarted into another folder"
  fi
fi

# (f) bad PETSc options
out=$("$MPIEXEC" -n 2 $P run -q -t 1 -o "$T/badrows" -peristatic_rows diagonal "$T/edge.yaml" 2>&1 >/dev/null)
rc=$?
if [ "$rc" -ne 0 ] && printf '%s' "$out" | grep -q -- "-peristatic_rows must be curve or natural" \
   && [ ! -d "$T/badrows" ]; then
  ok "-peristatic_rows diagonal: exit $rc, named, no output folder"
else ko "-peristatic_rows diagonal: exit $rc, message: $out"; fi
out=$("$MPIEXEC" -n 2 $P run -q -t 1 -o "$T/bad" -pc_type nonsense "$T/edge.yaml" 2>&1 >/dev/null)
rc=$?
if [ "$rc" -eq 2 ] && printf '%s' "$out" | grep -q "PETSc's KSPSetFromOptions (check the PETSc options) failed" \
   && printf '%s' "$out" | grep -q nonsense && [ ! -d "$T/bad" ]; then
  ok "-pc_type nonsense: exit 2, PETSc names it, no output folder"
else ko "-pc_type nonsense: exit $rc, message: $out"; fi
with_petsc "$C/small-disk.yaml" "$T/badopt.yaml" "  petsc_options: ksp_type cg"
line=$(grep -n "petsc_options" "$T/badopt.yaml" | cut -d: -f1)
expect 1 "badopt.yaml:$line: solver.petsc_options must be PETSc options" -- \
  run -q -o "$T/bad" "$T/badopt.yaml"
summary
