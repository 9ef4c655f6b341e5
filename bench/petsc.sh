#!/bin/sh
# bench/petsc.sh: the PETSc backend's preconditioners on peristatic's own
# tangents (make bench-petsc; a build configured --with-petsc). Writes one
# row per run to bench/petsc-results.csv and a table of medians to
# bench/petsc-summary.txt. Not part of make check; run it on a quiet
# machine (it measures wall time).
#   PETSC_BENCH_REPEATS  repeats per row (default 1; medians reported)
#   PETSC_BENCH_LARGE=1  also the 3D boxes of 50,653 (fibre) and 250,047
#                        (bond) particles (minutes each, up to ~6 GB)
#   PETSC_BENCH_RANKS    the rank counts (default "1 2")
#   PETSC_BENCH_CASES    the 2D cases (default "intact yielded cracked")
# Cases (each with the serial CHOLMOD run beside it):
#   disk-intact   the paper's disk, 20,000 particles, one elastic step
#   disk-yielded  the same disk loaded to 0.9 sigma_y with plastic arms
#                 (the tangent of yielded arms: about half yield)
#   disk-cracked  the small disk (1,800 particles) to fracture: tangents
#                 of a running crack, many breaking rounds
#   box3d-37      fibre model, 37^3 particles, alpha 3.5 (elastic)
#   box3d-63-bond bond model, 63^3 = 250,047 particles (elastic)
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
bin=${PERISTATIC:-$top/peristatic}
out="$top/bench"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
reps=${PETSC_BENCH_REPEATS:-1}
ranks=${PETSC_BENCH_RANKS:-1 2}
MPIEXEC=${MPIEXEC:-mpiexec}
export OPENBLAS_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
[ -x "$bin" ] || { echo "bench-petsc: build peristatic first (make)" >&2; exit 1; }
"$bin" run -q -o "$work/probe" -ksp_type cg "$top/data/cases/tension-bar.yaml" 2>"$work/probe.err" || {
  echo "bench-petsc: this peristatic has no PETSc backend (configure --with-petsc)" >&2
  exit 1
}

csv="$out/petsc-results.csv.tmp"
echo "case,solver,ranks,repeat,particles,free_dofs,wall_s,setup_s,solve_s,cg_s,newton_iterations,factorisations,cg_iterations,peak_memory_MiB,sigma_failure_over_sigma_y,arms_broken" > "$csv"
val() { awk -F': ' -v k="$2" '$1 == k {print $2}' "$1"; }

# the solvers compared: name and PETSc options ("cholmod": the serial
# default, no PETSc)
solvers() {
  cat <<'EOS'
cholmod|
mumps|
gamg|-ksp_type cg -pc_type gamg
hypre|-ksp_type cg -pc_type hypre
bjacobi-icc|-mat_type sbaij -ksp_type cg -pc_type bjacobi -sub_pc_type icc
EOS
}

# run_one CASE-FILE NAME SOLVER OPTIONS RANKS
run_one() {
  r=1
  while [ "$r" -le "$reps" ]; do
    rm -rf "$work/out"
    if [ "$3" = cholmod ]; then
      set -- "$1" "$2" "$3" "$4" "$5"
      "$bin" run -q -t 1 -o "$work/out" "$1" < /dev/null > /dev/null 2> "$work/err" || true
    else
      sed 's/^solver: {/solver: {linear: petsc, /' "$1" > "$work/petsc.yaml"
      # shellcheck disable=SC2086
      "$MPIEXEC" -n "$5" "$bin" run -q -t 1 -o "$work/out" $4 "$work/petsc.yaml" < /dev/null > /dev/null 2> "$work/err" || true
    fi
    s="$work/out/summary.txt"
    if [ ! -f "$s" ]; then
      echo "$2,$3,$5,$r,failed: $(head -1 "$work/err" | tr ',' ';')" >> "$csv"
      echo "bench-petsc: $2 $3 on $5 rank(s) failed: $(head -1 "$work/err")" >&2
      r=$((r + 1))
      continue
    fi
    setup=$(awk -F': ' '$1 == "analyze_s" || $1 == "factor_s" || $1 == "majorant_factor_s" {t += $2} END {printf "%.3f", t}' "$s")
    echo "$2,$3,$5,$r,$(val "$s" particles),$(val "$s" free_dofs),$(val "$s" wall_s),$setup,$(val "$s" solve_s),$(val "$s" cg_s),$(val "$s" newton_iterations),$(val "$s" factorisations),$(val "$s" cg_iterations),$(val "$s" peak_memory_MiB),$(val "$s" sigma_failure_over_sigma_y),$(val "$s" arms_broken)" >> "$csv"
    r=$((r + 1))
  done
}

bench_case() { # CASE-FILE NAME [RANKS]
  solvers | while IFS='|' read -r name opts; do
    if [ "$name" = cholmod ]; then run_one "$1" "$2" cholmod "" 1; continue; fi
    for np in ${3:-$ranks}; do run_one "$1" "$2" "$name" "$opts" "$np"; done
  done
}

disk() { # NAME n_eta n_xi plastic max_load delta_over_c
  cat > "$work/$1.yaml" <<EOC
name: $1
geometry: {type: disk, n_eta: $2, n_xi: $3, per_zone: 5, jitter: 0.1, seed: 11}
material: {E: 210.0e9, nu: 0.3, plane: strain, yield_strain: 0.002, plastic: $4, delta_over_c: $6}
loading: {type: eq116}
solver: {cg_forcing: adaptive}
path: {load_step: 0.05, load_step_after_break: 0.01, max_load: $5}
output: {vtk_every: 0}
EOC
  echo "$work/$1.yaml"
}
. "$top/bench/box3d.sh"

cases=${PETSC_BENCH_CASES:-intact yielded cracked}
for c in $cases; do
  case $c in
  intact) bench_case "$(disk disk-intact 20 40 false 0.05 0.001)" disk-intact ;;
  yielded) bench_case "$(disk disk-yielded 20 40 true 0.9 0.001)" disk-yielded ;;
  cracked) bench_case "$(disk disk-cracked 6 12 true 3.0 0.001)" disk-cracked ;;
  *) echo "bench-petsc: unknown case '$c' in PETSC_BENCH_CASES (intact, yielded, cracked)" >&2; exit 1 ;;
  esac
done
if [ "${PETSC_BENCH_LARGE:-0}" = 1 ]; then
  bench_case "$(box3d box3d-37 37)" box3d-37
  bench_case "$(box3d box3d-63-bond 63 'material: {model: bond, E: 210.0e9, nu: 0.25, horizon_factor: 2.015}')" \
    box3d-63-bond 1
fi
mv "$csv" "$out/petsc-results.csv"

# medians per case, solver and ranks
awk -F, 'NR > 1 && $5 !~ /failed/ { k = $1 "," $2 "," $3; n[k]++; w[k, n[k]] = $7; st[k, n[k]] = $8;
    so[k, n[k]] = $9; m[k, n[k]] = $14; it[k] = $11 "/" $13; nf[k] = $12; sf[k] = $15; ab[k] = $16;
    if (!(k in seen)) { seen[k] = 1; order[++no] = k } }
  function med(a, k, c,   i, j, t, v) { for (i = 1; i <= c; i++) v[i] = a[k, i] + 0
    for (i = 1; i <= c; i++) for (j = i + 1; j <= c; j++) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
    return c % 2 ? v[(c + 1) / 2] : (v[c / 2] + v[c / 2 + 1]) / 2 }
  END { printf "%-14s %-12s %5s %8s %8s %8s %14s %6s %8s %12s %6s\n", "case", "solver", "ranks",
          "wall_s", "setup_s", "solve_s", "newton/cg_its", "setups", "peak_MiB", "sigma_f/sy", "broken"
    for (i = 1; i <= no; i++) { k = order[i]; split(k, f, ",")
      printf "%-14s %-12s %5s %8.2f %8.2f %8.2f %14s %6s %8.0f %12s %6s\n", f[1], f[2], f[3],
        med(w, k, n[k]), med(st, k, n[k]), med(so, k, n[k]), it[k], nf[k], med(m, k, n[k]), sf[k], ab[k] } }' \
  "$out/petsc-results.csv" > "$out/petsc-summary.txt"
cat "$out/petsc-summary.txt"
