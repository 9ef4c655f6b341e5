#!/bin/sh
# bench/run.sh: fixed, seeded benchmark cases of peristatic. Writes every
# run to bench/results.csv and medians plus the growth exponent of the
# solve time with size to bench/summary.txt. Not part of `make check`.
#   BENCH_REPEATS  repeats per case (default 3; medians are reported)
#   BENCH_LARGE=1  also 40k and 80k particles (elastic), a 3D box of 50,653
#                  particles (elastic, 6.7 GB), and runs to fracture
#                  of the paper's disk at its 20k particles, delta = c/3250
#                  (repeated) and c/1000 (once), and that disk at 10k and
#                  20k under dissipation control through the peak (once),
#                  from the start and after a load phase (load_until_unstable)
#   BENCH_HUGE=1   with BENCH_LARGE: also the paper's disk at 40k and 80k
#                  particles run to fracture at c/1000 with the sweep's
#                  settings (once each; ~9 and ~40 minutes)
#   BENCH_QUICK=1  tiny cases only: a smoke test of this script (seconds)
#   BENCH_THREADS  peristatic -t for every run (default: its own, the CPUs,
#                  at most 2); with BENCH_LARGE the paper-size runs to
#                  fracture are also run once with -t 1 (rows "...-t1")
# Run it on a quiet machine: it measures wall time.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
bin="$top/peristatic"
out="$top/bench"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
reps=${BENCH_REPEATS:-3}
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
[ -x "$bin" ] || { echo "bench: build peristatic first (make)" >&2; exit 1; }

csv="$out/results.csv.tmp"
echo "case,kind,particles,arms,free_dofs,linear,reuse_factor,repeat,network_s,assembly_s,analyze_s,factor_s,solve_s,increments,newton_iterations,factorisations,cg_iterations,nnz_tangent_upper,nnz_factor,flops_factor,sigma_failure_over_sigma_y,wall_s,peak_memory_MiB,cg_s,threads,arms_broken" > "$csv"

# disk CASE-FILE: n_eta n_xi kind(elastic|fracture) linear reuse
# (SOLVER_EXTRA: more solver keys, e.g. "cg_forcing: 0")
make_case() {
  f="$work/$1.yaml"
  if [ "$4" = elastic ]; then
    plastic=false; maxload=0.05; step=0.05
  else
    plastic=true; maxload=3.0; step=0.05
  fi
  cat > "$f" <<EOC
name: $1
geometry: {type: disk, n_eta: $2, n_xi: $3, per_zone: 5, jitter: 0.1, seed: 11}
material: {E: 210.0e9, nu: 0.3, plane: strain, yield_strain: 0.002, plastic: $plastic, delta_over_c: 0.001}
loading: {type: eq116}
solver: {linear: $5, reuse_factor: $6, reanalyze: ${REANALYZE:-false}${SOLVER_EXTRA:+, $SOLVER_EXTRA}}
path: {load_step: $step, load_step_after_break: 0.01, max_load: $maxload}
output: {vtk_every: 0}
EOC
  echo "$f"
}

val() { awk -F': ' -v k="$2" '$1 == k {print $2}' "$1"; }

# run CASE-FILE NAME KIND LINEAR REUSE REPEATS: run and append one row each
run_file() {
  r=1
  while [ "$r" -le "$6" ]; do
    th=${RUN_THREADS:-${BENCH_THREADS:-}}
    "$bin" run -q ${th:+-t "$th"} -o "$work/out" "$1" >/dev/null
    s="$work/out/summary.txt"
    printf '%s,%s,%s,%s,%s,%s,%s,%s' "$2" "$3" "$(val "$s" particles)" "$(val "$s" arms)" \
      "$(val "$s" free_dofs)" "$4" "$5" "$r" >> "$csv"
    for k in network_s assembly_s analyze_s factor_s solve_s increments newton_iterations \
             factorisations cg_iterations nnz_tangent_upper nnz_factor flops_factor \
             sigma_failure_over_sigma_y wall_s peak_memory_MiB cg_s threads arms_broken; do
      printf ',%s' "$(val "$s" $k)" >> "$csv"
    done
    printf '\n' >> "$csv"
    echo "bench: $2 ($3, $4, reuse $5) repeat $r: $(val "$s" wall_s) s" >&2
    r=$((r + 1))
  done
}

run_case() { # name n_eta n_xi kind linear reuse repeats
  run_file "$(make_case "$1" "$2" "$3" "$4" "$5" "$6")" "$1" "$4" "$5" "$6" "$7"
}

# elastic solves (one increment) at growing size: network, assembly,
# analysis, factorisation, solve
sizes="10 20 5k|14 28 10k|20 40 20k"
mid="14 28"
small_fracture="6 12"
box3d_sizes="12 20"
if [ "${BENCH_QUICK:-0}" = 1 ]; then
  sizes="2 4 0.2k|4 8 0.8k"; mid="4 8"; small_fracture="2 4"; box3d_sizes="6"; reps=1
fi
IFS='|'
set -f
for sz in $sizes; do
  IFS=' '
  set -- $sz
  run_case "disk-$3-elastic" "$1" "$2" elastic cholmod true "$reps"
done
IFS=' '
set +f
if [ "${BENCH_LARGE:-0}" = 1 ]; then
  run_case disk-40k-elastic 28 56 elastic cholmod true "$reps"
  run_case disk-80k-elastic 40 80 elastic cholmod true 1
fi
# linear solvers compared on the same elastic solve (10k particles),
# fresh factorisation each Newton iteration (reuse off)
set -- $mid
for lin in cholmod cholmod-simplicial umfpack; do
  run_case disk-mid-elastic-$lin "$1" "$2" elastic "$lin" false 1
done
# fresh symbolic analysis before every factorisation, for comparison
REANALYZE=true run_case disk-mid-elastic-reanalyze "$1" "$2" elastic cholmod false 1
# a 3D box (elastic solve, uniaxial grips): the two-horizon stencil in 3D
# is ~8x denser than in 2D, so alpha = 3.5 and 20^3 particles here
. "$top/bench/box3d.sh"
for n3 in $box3d_sizes; do
  run_file "$(box3d "box3d-$n3" "$n3")" "box3d-$n3" elastic cholmod true "$reps"
done
# the issue's 3D box of 50k particles (37^3 = 50,653; ~70 s, 6.7 GB)
[ "${BENCH_LARGE:-0}" = 1 ] && run_file "$(box3d box3d-37 37)" box3d-37 elastic cholmod true 1

# the plate with a hole with the bond model: its one-horizon pattern
[ "${BENCH_QUICK:-0}" = 1 ] || run_file "$top/data/cases/plate-hole-bond.yaml" plate-hole-bond elastic cholmod true "$reps"

# full runs to fracture (delta = c/1000): factor reuse on and off
set -- $small_fracture
run_case disk-small-fracture "$1" "$2" fracture cholmod true "$reps"
run_case disk-small-fracture "$1" "$2" fracture cholmod false 1
if [ "${BENCH_QUICK:-0}" != 1 ]; then
  run_case disk-5k-fracture 10 20 fracture cholmod true "$reps"
  # what sessions 4-5 save in the linear solves: the same run with an
  # exact CG tolerance, the assembled tangent, a double-precision
  # preconditioner and no truncation of CG at negative curvature
  SOLVER_EXTRA="cg_forcing: 0, matrix_free: false, cg_single_precision: false, cg_truncate: false" \
    run_case disk-5k-fracture-cg-exact 10 20 fracture cholmod true 1
fi
# the notched plate of PEERS.md (data/cases/notched-plate-*.yaml) to
# complete fracture, N x N particles: the issue's targets are 5 s (3,600),
# 20 s (10,000) and 2 minutes (40,000) for the bond and fibre models
notched() { # model N: the case with N x N particles, grips 3 rows
  f="$work/notched-$1-$2.yaml"
  sed -e "s/counts: \[60, 60\]/counts: [$2, $2]/" \
    -e "s/spacing: 8.333333333333333e-4/spacing: $(awk -v n="$2" 'BEGIN {printf "%.16g", 0.05 / n}')/" \
    -e "s/y_max: 0.0025/y_max: $(awk -v n="$2" 'BEGIN {printf "%.16g", 0.15 / n}')/" \
    -e "s/y_min: 0.0475/y_min: $(awk -v n="$2" 'BEGIN {printf "%.16g", 0.05 - 0.15 / n}')/" \
    -e "s/vtk_every: 5/vtk_every: 0/" "$top/data/cases/notched-plate-$1.yaml" > "$f"
  grep -q "counts: \[$2, $2\]" "$f" || { echo "bench: cannot size the notched plate" >&2; exit 1; }
  echo "$f"
}
if [ "${BENCH_QUICK:-0}" != 1 ]; then
  for model in pmb state fibre; do
    [ -f "$top/data/cases/notched-plate-$model.yaml" ] || continue
    run_file "$(notched $model 60)" notched-$model-3600 fracture cholmod true "$reps"
    [ "${BENCH_LARGE:-0}" = 1 ] && run_file "$(notched $model 100)" notched-$model-10k fracture cholmod true 1
    [ "${BENCH_LARGE:-0}" = 1 ] && run_file "$(notched $model 200)" notched-$model-40k fracture cholmod true 1
  done
fi
# path following past the peak (doc/path-following.md): the softening
# notched plate under dissipation control, through its snap-back to 10% of
# the peak reaction (increments, Newton iterations, factorisations)
[ "${BENCH_QUICK:-0}" = 1 ] ||
  run_file "$top/data/cases/notched-plate-softening.yaml" notched-softening-dissipation fracture cholmod true 1
# and the PMB notched plate (60 x 60) under event control, each arm
# breaking at its critical stretch (path.control: event; the load-control
# row notched-pmb-3600 above is the same plate)
if [ "${BENCH_QUICK:-0}" != 1 ]; then
  fe="$work/notched-pmb-event.yaml"
  sed -e 's/^path:$/path:\n  control: event/' "$(notched pmb 60)" > "$fe"
  grep -q '^  control: event$' "$fe" || { echo "bench: cannot set event control" >&2; exit 1; }
  run_file "$fe" notched-pmb-event-3600 fracture cholmod true 1
fi
if [ "${BENCH_LARGE:-0}" = 1 ]; then
  # the paper's disk at its size (20k particles, data/cases/paper-griffith.yaml)
  # run to fracture at delta = c/3250, the sweep's first run
  f="$work/paper-c3250.yaml"
  sed 's/^  delta_over_c: 0.001$/  delta_over_c: 0.0003076923077/' \
    "$top/data/cases/paper-griffith.yaml" > "$f"
  grep -q '^  delta_over_c: 0.0003076923077$' "$f" || { echo "bench: cannot set delta" >&2; exit 1; }
  run_file "$f" paper-griffith-c3250 fracture cholmod true "$reps"
  # and at the issue's (and Table 1's) delta = c/1000, which fractures since
  # algorithm version 7 (arm lengths rounded at zero); ~5 min, so once
  run_file "$top/data/cases/paper-griffith.yaml" paper-griffith-c1000 fracture cholmod true 1
  # issue 20's target: the paper's disk at c/1000 under dissipation control
  # through the peak to a boundary stress below half of it (10k, then the
  # 20k of the issue; at most 400 increments; doc/path-following.md)
  for sz in "14 28 10k" "20 40 20k"; do
    set -- $sz
    fd="$work/disk-dissipation-$3.yaml"
    sed -e "s/^  n_eta: 20\$/  n_eta: $1/" -e "s/^  n_xi: 40\$/  n_xi: $2/" \
      -e 's/^path:$/path:\n  control: dissipation\n  max_increments: 400/' \
      -e 's/^  stop_load_drop: 0.8$/  stop_load_drop: 0.5/' \
      -e '/^  stop_tip_advance:/d' -e '/^  stop_crack_tip:/d' -e '/^griffith:/,$d' \
      "$top/data/cases/paper-griffith.yaml" > "$fd"
    grep -q '^  control: dissipation$' "$fd" || { echo "bench: cannot set the control" >&2; exit 1; }
    run_file "$fd" "disk-dissipation-$3-c1000" fracture cholmod true 1
    # the same with load control's increments until the crack runs at one
    # load (path.load_until_unstable)
    fh="$work/disk-load-dissipation-$3.yaml"
    sed 's/^  control: dissipation$/  control: dissipation\n  load_until_unstable: true/' \
      "$fd" > "$fh"
    grep -q '^  load_until_unstable: true$' "$fh" || { echo "bench: cannot set the phase" >&2; exit 1; }
    run_file "$fh" "disk-load-dissipation-$3-c1000" fracture cholmod true 1
  done
  # the same on one thread (a sweep's job with -j 2 on 2 cores)
  RUN_THREADS=1 run_file "$f" paper-griffith-c3250-t1 fracture cholmod true 1
  RUN_THREADS=1 run_file "$top/data/cases/paper-griffith.yaml" paper-griffith-c1000-t1 fracture cholmod true 1
  if [ "${BENCH_HUGE:-0}" = 1 ]; then
    for sz in "28 56 40k" "40 80 80k"; do
      set -- $sz
      f="$work/paper-$3.yaml"
      sed -e "s/^  n_eta: 20\$/  n_eta: $1/" -e "s/^  n_xi: 40\$/  n_xi: $2/" \
        "$top/data/cases/paper-griffith.yaml" > "$f"
      grep -q "^  n_xi: $2\$" "$f" || { echo "bench: cannot set the disk size" >&2; exit 1; }
      run_file "$f" "paper-griffith-$3-c1000" fracture cholmod true 1
    done
  fi
fi
mv "$csv" "$out/results.csv"

# medians per (case, linear, reuse) and the growth exponent of the elastic
# solve (wall and factorisation time against free dofs)
awk -F, 'NR > 1 {
    key = $1 "," $6 "," $7; if (!(key in n)) keys[++nk] = key
    n[key]++; w[key, n[key]] = $22; fa[key, n[key]] = $12; cgs[key, n[key]] = $24
    size[key] = $5; its[key] = $15; fac[key] = $16; cg[key] = $17; nnz[key] = $18
    nl[key] = $19; fl[key] = $20; mem[key] = $23; sf[key] = $21; kind[key] = $2; thr[key] = $25
  }
  function median(a, key, m,   i, j, t, v) {
    for (i = 1; i <= m; i++) v[i] = a[key, i]
    for (i = 1; i <= m; i++) for (j = i + 1; j <= m; j++) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
    return (m % 2) ? v[(m + 1) / 2] : (v[m / 2] + v[m / 2 + 1]) / 2
  }
  END {
    printf "%-32s %-18s %5s %7s %9s %9s %10s %9s %9s %6s %6s %6s %8s %8s %9s %7s\n", "case", "linear", "reuse",
      "runs", "free_dofs", "nnz(A)", "nnz(L)", "flops", "wall_s", "newton", "factor", "cg", "factor_s",
      "cg_s", "peak_MiB", "threads"
    for (ik = 1; ik <= nk; ik++) {
      k = keys[ik]
      split(k, p, ",")
      mw = median(w, k, n[k]); mf = median(fa, k, n[k]); mc = median(cgs, k, n[k])
      printf "%-32s %-18s %5s %7d %9d %9.3g %10.3g %9.3g %9.3f %6d %6d %6d %8.3f %8.3f %9.1f %7s\n", p[1], p[2], p[3],
        n[k], size[k], nnz[k], nl[k], fl[k], mw, its[k], fac[k], cg[k], mf, mc, mem[k], thr[k]
      if (kind[k] == "elastic" && p[1] ~ /^disk-[0-9.]+k-elastic$/ && p[2] == "cholmod" && p[3] == "true") {
        m++; lx[m] = log(size[k]); ly[m] = log(mw); lf[m] = log(mf / (fac[k] > 0 ? fac[k] : 1))
      }
    }
    if (m >= 2) {
      sx = sy = sxx = sxy = sf2 = sxf = 0
      for (i = 1; i <= m; i++) { sx += lx[i]; sy += ly[i]; sxx += lx[i]^2; sxy += lx[i] * ly[i]; sxf += lx[i] * lf[i]; sf2 += lf[i] }
      b = (m * sxy - sx * sy) / (m * sxx - sx^2)
      bf = (m * sxf - sx * sf2) / (m * sxx - sx^2)
      printf "\ngrowth with size (elastic solves, %d sizes): wall time ~ dofs^%.2f, one factorisation ~ dofs^%.2f\n", m, b, bf
    }
  }' "$out/results.csv" > "$out/summary.txt.tmp"
{
  echo "# peristatic benchmark, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, OPENBLAS_NUM_THREADS=$OPENBLAS_NUM_THREADS"
  echo "# medians over repeats; all runs in bench/results.csv"
  cat "$out/summary.txt.tmp"
} > "$out/summary.txt"
rm -f "$out/summary.txt.tmp"
cat "$out/summary.txt"
