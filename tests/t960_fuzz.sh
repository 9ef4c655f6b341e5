#!/bin/sh
# t960_fuzz.sh: mutated case files, point clouds and Gmsh meshes (text
# .msh files, read by Gmsh's library; tests/fuzz/ps_fuzz.c)
# over every seed in data/cases and tests/data: each must end with exit
# status 0..3, no signal, no sanitizer report, and `info` within its time
# limit. PS_FUZZ_N inputs (default 300; `make fuzz` runs thousands),
# PS_FUZZ_SEED picks the mutations (default 1: the same inputs each time).
srcdir=${srcdir:-.}
n=${PS_FUZZ_N:-300}
seed=${PS_FUZZ_SEED:-1}
dir=t960_tmp
rm -rf "$dir"
mkdir -p "$dir"
# the seeds: every shipped case and every test input
set -- "$srcdir"/data/cases/*.yaml "$srcdir"/tests/data/*/*.yaml \
  "$srcdir"/tests/data/*/*.yml "$srcdir"/tests/data/*/*.txt \
  "$srcdir"/data/cases/*.msh "$srcdir"/tests/data/*/*.msh
out=$(./tests/fuzz/ps_fuzz -n "$n" -s "$seed" -r -d "$dir" ./peristatic "$@")
rc=$?
printf '%s\n' "$out"
if [ "$rc" -eq 0 ]; then
  echo "1 passed, 0 failed"
  rm -rf "$dir"
  exit 0
fi
nf=$(printf '%s\n' "$out" | grep -c '^FAIL: input')
echo "failing inputs are kept in $dir/ (fail-N.yaml, fail-N.stderr)"
echo "0 passed, ${nf} failed"
exit 1
