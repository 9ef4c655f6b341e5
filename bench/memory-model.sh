#!/bin/sh
# bench/memory-model.sh: the measurements of doc/performance.md's "Memory
# model and the 10^6-point bar (issue 22)". One elastic increment of the
# 3D box (bench/box3d.sh) per model and size, PETSc's CG with incomplete
# Cholesky (-mat_type sbaij -pc_type icc) on 1 rank and block-Jacobi ICC on
# 2 ranks, -t 1, one run at a time. Writes $MEM_WORK/memory-model.csv: the
# counts and times of summary.txt, every rank's peak resident memory
# (/usr/bin/time), the KSP iterations (-ksp_converged_reason) and
# -log_view's KSPSolve / MatMult / PCApply / PCSetUp times, and the
# estimate of `peristatic info` (ps_estimate: estimate_memory_MiB).
#
#   sh bench/memory-model.sh [BUILD_DIR]   (a build configured --with-petsc;
#                                          MPIEXEC, GNU time as /usr/bin/time)
#
# MEM_WORK (default /tmp/peristatic-memory-model), MEM_CASES (default all
# below: "tag|material lines (\\n between)|sizes", `;` between),
# MEM_RUNS (default "icc:1:;bjicc:2:-pc_type bjacobi -sub_pc_type icc":
# "label:ranks:PETSc options" after the case's -mat_type sbaij -ksp_type cg
# -pc_type icc, `;` between; e.g. "bj10:1:-pc_type bjacobi
# -pc_bjacobi_blocks 10 -sub_pc_type icc" for 10 blocks on one rank; a
# label ending in -rep runs the case with solver.layout: replicated, every
# rank holding the whole model, where the default on several ranks is
# the distributed model: "bjicc-rep:2:-pc_type bjacobi -sub_pc_type icc"
# against "bjicc:2:..." measures what distribution saves a rank).
set -u
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-.}
bin="$build/peristatic"
[ -x "$bin" ] || { echo "no $bin (give the build directory)" >&2; exit 1; }
work=${MEM_WORK:-/tmp/peristatic-memory-model}
runs=${MEM_RUNS:-"icc:1:;bjicc:2:-pc_type bjacobi -sub_pc_type icc"}
mkdir -p "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
  OMPI_MCA_rmaps_base_oversubscribe=1
. "$here/box3d.sh"

cases=${MEM_CASES:-"b2|material: {model: bond, E: 210.0e9, nu: 0.25, horizon_factor: 2.015}|15 20 25 30 35;\
b3|material: {model: bond, E: 210.0e9, nu: 0.25, horizon_factor: 3.015}|15 20 25 30;\
b35|material: {model: bond, E: 210.0e9, nu: 0.25, horizon_factor: 3.5}|15 20 25 30;\
f35|kernel: {alpha: 3.5}\\nmaterial: {E: 210.0e9, nu: 0.3, yield_strain: 0.002, plastic: false}|15 20 25 30"}

csv="$work/memory-model.csv"
echo "case,run,ranks,distributed,particles,arms,free_dofs,nnz_upper,peak_MiB,rss_max_MiB,rss_all_MiB,wall_s,newton,cg_its,ksp_its,assembly_s,factor_s,solve_s,cg_s,ksp_solve_s,matmult_n,matmult_s,matsolve_n,matsolve_s,pcapply_n,pcapply_s,pcsetup_s,est_arms,est_nnz,est_MiB" > "$csv"
key() { awk -F': ' -v k="$1" '$1 == k {print $2; exit}' "$2"; }
ev() { awk -v e="$1" -v f="$2" '$1 == e {print $f; exit}' "$3"; }

printf '%s\n' "$cases" | tr ';' '\n' | while IFS='|' read -r tag mat sizes; do
  [ -n "$tag" ] || continue
  mat=$(printf '%b' "$mat") # \n: a new line
  for n in $sizes; do
    name="$tag-$n"
    f=$(box3d "$name" "$n" "$mat")
    # a box3d.sh whose default (the fibre lines) leaks after a given
    # material: drop it (a correct box3d.sh never writes it)
    sed -i '/^material: {E: 210.0e9, nu: 0.3, yield_strain: 0.002, plastic: false}}$/d' "$f"
    sed -i 's/^solver: {/solver: {linear: petsc, petsc_options: "-mat_type sbaij -ksp_type cg -pc_type icc", /' "$f"
    "$bin" info "$f" > "$work/$name.info" 2>&1
    printf '%s\n' "$runs" | tr ';' '\n' | while IFS=':' read -r label p opts; do
      [ -n "$label" ] || continue
      out="$work/out-$name-$label"
      rm -rf "$out" "$out.partial" "$work/$name-$label".rss.*
      fr=$f
      case $label in *-rep)
        fr="$work/$name-rep.yaml"
        sed 's/^solver: {/solver: {layout: replicated, /' "$f" > "$fr" ;;
      esac
      # shellcheck disable=SC2086
      ${MPIEXEC:-mpiexec} -n "$p" sh -c 'exec /usr/bin/time -f "%M" -o "$0.${OMPI_COMM_WORLD_RANK:-0}" "$@"' \
        "$work/$name-$label.rss" "$bin" run -q -t 1 -o "$out" $opts -ksp_converged_reason \
        -log_view "$fr" < /dev/null > "$work/$name-$label.log" 2>&1
      s="$out/summary.txt"
      [ -f "$s" ] || { echo "$name $label: no summary (see $work/$name-$label.log)" >&2; continue; }
      rss=$(cat "$work/$name-$label".rss.* | awk '/^[0-9]+$/ {printf "%s%.1f", sep, $1 / 1024; sep = "/"}')
      rmax=$(cat "$work/$name-$label".rss.* | awk '/^[0-9]+$/ && $1 > m {m = $1} END {printf "%.1f", m / 1024}')
      ksp=$(awk '/Linear solve converged/ {s += $NF} END {print s + 0}' "$work/$name-$label.log")
      L="$work/$name-$label.log"
      echo "$name,$label,$p,$(key distributed "$s"),$(key particles "$s"),$(key arms "$s"),$(key free_dofs "$s"),$(key nnz_tangent_upper "$s"),$(key peak_memory_MiB "$s"),$rmax,$rss,$(key wall_s "$s"),$(key newton_iterations "$s"),$(key cg_iterations "$s"),$ksp,$(key assembly_s "$s"),$(key factor_s "$s"),$(key solve_s "$s"),$(key cg_s "$s"),$(ev KSPSolve 4 "$L"),$(ev MatMult 2 "$L"),$(ev MatMult 4 "$L"),$(ev MatSolve 2 "$L"),$(ev MatSolve 4 "$L"),$(ev PCApply 2 "$L"),$(ev PCApply 4 "$L"),$(ev PCSetUp 4 "$L"),$(key estimate_arms "$work/$name.info"),$(key estimate_tangent_nnz "$work/$name.info"),$(key estimate_memory_MiB "$work/$name.info")" >> "$csv"
      tail -1 "$csv"
    done
  done
done
