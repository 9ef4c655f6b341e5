#!/bin/sh
# bench/distributed.sh: the distributed model (each rank its share of the
# particles and arms, ps_solver_create_share) against today's replicated
# one (every rank the whole model, the same PETSc solves) and the serial
# CHOLMOD run, on two load increments of a case (the second past yield):
# tests/solve_check with SOLVE_CHECK_REPLICATED=1, which also checks the
# displacements against the serial solution. make bench-distributed (a
# build configured --with-petsc); not part of make check; a quiet
# machine (it measures wall time). Writes bench/distributed-results.csv
# (one row per run and increment) and prints medians.
#   DIST_BENCH_REPEATS  repeats (default 3)
#   DIST_BENCH_RANKS    rank counts (default "1 2")
#   DIST_BENCH_CASES    case files under data/cases (default paper-table1:
#                       the paper's 20,000-particle disk)
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$top}
check="$build/tests/solve_check"
[ -x "$check" ] || { echo "bench-distributed: make tests/solve_check first" >&2; exit 1; }
reps=${DIST_BENCH_REPEATS:-3}
ranks=${DIST_BENCH_RANKS:-1 2}
cases=${DIST_BENCH_CASES:-paper-table1}
MPIEXEC=${MPIEXEC:-mpiexec}
export OPENBLAS_NUM_THREADS=1 SOLVE_CHECK_REPLICATED=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
csv="$top/bench/distributed-results.csv"
echo "case,ranks,repeat,load_factor,owned,ghosts,newton_iterations,distributed_s,replicated_s,serial_s,max_du" > "$csv.tmp"
for cs in $cases; do
  for np in $ranks; do
    r=1
    while [ "$r" -le "$reps" ]; do
      out=$("$MPIEXEC" -x SOLVE_CHECK_REPLICATED -n "$np" "$check" "$top/data/cases/$cs.yaml") || {
        echo "bench-distributed: $cs on $np ranks failed: $out" >&2
        exit 1
      }
      printf '%s\n' "$out" | sed -n "s/^solve_check: rank 0 of $np: load factor \([^:]*\): ok (\([0-9]*\) owned, \([0-9]*\) ghosts; displacements off by \([^ ]*\) (owned).*; \([0-9]*\) Newton iterations; \([0-9.]*\) s distributed, \([0-9.]*\) s replicated, \([0-9.]*\) s serial)$/$cs,$np,$r,\1,\2,\3,\5,\6,\7,\8,\4/p" >> "$csv.tmp"
      r=$((r + 1))
    done
  done
done
mv "$csv.tmp" "$csv"
# medians per case, ranks and increment
awk -F, 'NR > 1 { k = $1 " ranks " $2 " load factor " $4; n[k]++; d[k, n[k]] = $8; p[k, n[k]] = $9; s[k, n[k]] = $10; it[k] = $7 }
  function med(a, k, m,   i, j, t, v) { for (i = 1; i <= m; i++) v[i] = a[k, i];
    for (i = 1; i <= m; i++) for (j = i + 1; j <= m; j++) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
    return m % 2 ? v[(m + 1) / 2] : (v[m / 2] + v[m / 2 + 1]) / 2 }
  END { for (k in n) printf "%s: distributed %.2f s, replicated %.2f s, serial CHOLMOD %.2f s (%d Newton iterations, median of %d)\n",
    k, med(d, k, n[k]), med(p, k, n[k]), med(s, k, n[k]), it[k], n[k] }' "$csv" | sort
