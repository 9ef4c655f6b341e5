#!/bin/sh
# bench/distributed-memory.sh: what the distributed layout saves each rank
# (doc/design-distributed.md, "Why it is needed"). `peristatic run` of a
# case on 1 rank, on 2 ranks distributed (solver.layout: distributed) and
# on 2 ranks replicated (solver.layout: replicated, every rank the whole
# model), one run at a time, -t 1; every rank's peak resident memory from
# GNU time, the run's wall time, Newton and KSP iterations from
# summary.txt, and the largest difference of the displacements from the
# one-rank run's over the largest (particles.csv). Writes
# bench/distributed-memory.csv (a row per case, layout and repeat) and
# prints it, then the medians. make bench-distributed-memory
# (a build configured --with-petsc); not part of make check.
#   DMEM_CASES   case files (default: data/cases/penny-crack-3d-250k.yaml,
#                253,500 particles, CG + ICC)
#   DMEM_REPEATS repeats (default 3)
#   DMEM_PC      PETSc options on several ranks (default: block-Jacobi ICC,
#                "-pc_type bjacobi -sub_pc_type icc"; ICC itself is serial)
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$top}
bin="$build/peristatic"
[ -x "$bin" ] || { echo "bench-distributed-memory: no $bin" >&2; exit 1; }
cases=${DMEM_CASES:-$top/data/cases/penny-crack-3d-250k.yaml}
pc=${DMEM_PC:--pc_type bjacobi -sub_pc_type icc}
MPIEXEC=${MPIEXEC:-mpiexec}
work=${DMEM_WORK:-/tmp/peristatic-distributed-memory}
export OPENBLAS_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$work"
csv="$top/bench/distributed-memory.csv"
key() { awk -F': ' -v k="$1" '$1 == k {print $2; exit}' "$2"; }
# the largest |u - u_ref| over the largest |u_ref| (particles.csv)
udiff() {
  awk -F, 'FNR == 1 { n = 0; for (i = 1; i <= NF; i++) if ($i ~ /^u[xyz]$/) c[++n] = i; next }
    FNR == NR { for (k = 1; k <= n; k++) a[FNR, k] = $c[k]; next }
    { for (k = 1; k <= n; k++) { d = $c[k] - a[FNR, k]; if (d < 0) d = -d; if (d > m) m = d;
        v = a[FNR, k] < 0 ? -a[FNR, k] : a[FNR, k]; if (v > u) u = v } }
    END { if (u == 0) print "nan"; else printf "%.2g\n", m / u }' "$1" "$2"
}
reps=${DMEM_REPEATS:-3}
echo "case,repeat,layout,ranks,particles,arms,rss_rank_MiB,rss_max_MiB,wall_s,newton,ksp_its,du_vs_one_rank" > "$csv.tmp"
for cs in $cases; do
 name=$(basename "$cs" .yaml)
 rep=1
 while [ "$rep" -le "$reps" ]; do
  for run in "one:1:replicated" "distributed:2:distributed" "replicated:2:replicated"; do
    label=${run%%:*} rest=${run#*:}
    np=${rest%%:*} layout=${rest#*:}
    f="$work/$name-$label.yaml"
    awk -v l="$layout" '/^solver:/ { print; print "  layout: " l; s = 1; next } { print }
      END { if (!s) { print "solver:"; print "  layout: " l } }' "$cs" > "$f"
    out="$work/out-$name-$label"
    rm -rf "$out" "$out.partial" "$work/$name-$label".rss.*
    opts=""
    [ "$np" -gt 1 ] && opts=$pc
    # shellcheck disable=SC2086
    "$MPIEXEC" -n "$np" sh -c 'exec /usr/bin/time -f "%M" -o "$0.${OMPI_COMM_WORLD_RANK:-0}" "$@"' \
      "$work/$name-$label.rss" "$bin" run -q -t 1 -o "$out" $opts "$f" < /dev/null \
      > "$work/$name-$label.log" 2>&1 || { echo "$name $label failed: see $work/$name-$label.log" >&2; exit 1; }
    s="$out/summary.txt"
    rss=$(cat "$work/$name-$label".rss.* | awk '/^[0-9]+$/ {printf "%s%.0f", sep, $1 / 1024; sep = "/"}')
    rmax=$(cat "$work/$name-$label".rss.* | awk '/^[0-9]+$/ && $1 > m {m = $1} END {printf "%.0f", m / 1024}')
    du=0
    [ "$label" != one ] && du=$(udiff "$work/out-$name-one/particles.csv" "$out/particles.csv")
    echo "$name,$rep,$(key distributed "$s" | sed 's/yes/distributed/;s/no/whole/'),$np,$(key particles "$s"),$(key arms "$s"),$rss,$rmax,$(key wall_s "$s"),$(key newton_iterations "$s"),$(key ksp_iterations "$s"),$du" >> "$csv.tmp"
    tail -1 "$csv.tmp"
  done
  rep=$((rep + 1))
 done
done
mv "$csv.tmp" "$csv"
# medians per case, layout and ranks: peak memory of the largest rank, wall
awk -F, 'NR > 1 { k = $1 " " $3 " on " $4; n[k]++; m[k, n[k]] = $8; w[k, n[k]] = $9 }
  function med(a, k, c,   i, j, t, v) { for (i = 1; i <= c; i++) v[i] = a[k, i];
    for (i = 1; i <= c; i++) for (j = i + 1; j <= c; j++) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
    return c % 2 ? v[(c + 1) / 2] : (v[c / 2] + v[c / 2 + 1]) / 2 }
  END { for (k in n) printf "%s: largest rank %.0f MiB, %.1f s (median of %d)\n", k, med(m, k, n[k]), med(w, k, n[k]), n[k] }' "$csv" | sort
