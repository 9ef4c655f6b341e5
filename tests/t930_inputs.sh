#!/bin/sh
# t930_inputs.sh: the regression inputs of issue 23 (input parsing). Each
# bad input makes `peristatic info` (and `run` where it ran before) exit 1
# with a message naming the file, the line and the key; inputs that hung
# libyaml or read gigabytes are refused at once. Large or deep inputs are
# generated here, not committed.
srcdir=${srcdir:-.}
D="$srcdir/tests/data/inputs"
P=./peristatic
T=t930_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"

# nesting and size, before libyaml: 50,000 levels took 15 s in Debian's
# libyaml 0.2.5 (quadratic), so the 200,000 here would take minutes
awk 'BEGIN { printf "geometry:\n  dim: "; for (i = 0; i < 200000; i++) printf "["; print "" }' > "$T/deep.yaml"
no_hang 30 1 "deep.yaml:2: nesting deeper than 32 levels" -- info "$T/deep.yaml"
awk 'BEGIN { for (i = 0; i < 200; i++) printf "%*sa:\n", i, "" }' > "$T/deep_block.yaml"
no_hang 30 1 "deep_block.yaml:33: nesting deeper than 32 levels" -- info "$T/deep_block.yaml"
awk 'BEGIN { for (i = 0; i < 20000; i++) print "# a comment line of a case file that is far too large" }' > "$T/big.yaml"
no_hang 30 1 "big.yaml: larger than 1 MiB (1080000 bytes); case files are small YAML texts" -- info "$T/big.yaml"
expect 1 "big.yaml: larger than 1 MiB" -- run -o "$T/x" "$T/big.yaml"

# encoding errors name the line
expect 1 "utf8.yaml:4: YAML read error: .*UTF-8" -- info "$D/utf8.yaml"

# numbers: decimal only, finite, in range
expect 1 "hex_number.yaml:4: material.E must be a decimal number (got '0x10')" -- info "$D/hex_number.yaml"
expect 1 "blank_number.yaml:4: material.E must be a decimal number (got ' 2.1e11')" -- info "$D/blank_number.yaml"
expect 1 "counts_range.yaml:3: geometry.counts must be an integer in 1..2147483647 (got 2147483648)" -- info "$D/counts_range.yaml"

# keys of another geometry
expect 1 "file_on_disk.yaml:8: geometry.file does not apply to geometry.type disk (it is for type cloud)" -- info "$D/file_on_disk.yaml"

# values that broke a computation downstream
expect 1 "alpha_big.yaml:3: kernel.alpha must be in \[0.001, 1000\] (got 1.0e155)" -- info "$D/alpha_big.yaml"
expect 1 "k_big.yaml:3: kernel.k must be an integer in 1..16 (got 2147483647)" -- info "$D/k_big.yaml"
expect 1 "huge_E.yaml:3: material.E must be in \[1e-20, 1e+20\] (got 1.0e300)" -- info "$D/huge_E.yaml"
expect 1 "huge_E.yaml:3: material.E must be in" -- run -q -o "$T/x" "$D/huge_E.yaml"
if [ ! -e "$T/x" ] && [ ! -e "$T/x.partial" ]; then
  ok "material.E = 1e300: refused before the run (no output folder)"
else
  ko "material.E = 1e300: the run left output"
fi

# info runs the model's checks that run runs
expect 1 "bond_nu.yaml: material.nu = 0.3: bond-based peridynamics has nu = 1/3" -- info "$srcdir/tests/data/cli/bond_nu.yaml"

# point clouds: overflowing coordinates, a file without line breaks
expect 1 "cloud_overflow.txt:11: y (field 2 of 'x y volume \[block\]') is not a finite decimal number (got '1e400')" -- info "$D/cloud_overflow.yaml"
awk 'BEGIN { for (i = 0; i < 1000000; i++) printf "0 0 1e-6 "; }' > "$T/noline.txt"
printf 'geometry: {type: cloud, dim: 2, file: noline.txt, sizes: eq44}\nloading:\n  type: boundary\n  boundary:\n    - {select: {x_max: 0}, fix: [x, y]}\n' > "$T/noline.yaml"
no_hang 30 1 "noline.txt:1: line longer than 4096 characters" -- info "$T/noline.yaml"

# solver.max_memory_gib is a key (and 0 is not a limit)
if $P info "$D/max_memory.yaml" > "$T/info.txt" 2>&1; then
  ok "solver.max_memory_gib: 4 is accepted"
else
  ko "solver.max_memory_gib: 4 refused: $(cat "$T/info.txt")"
fi
sed 's/max_memory_gib: 4/max_memory_gib: 0/' "$D/max_memory.yaml" > "$T/memory0.yaml"
expect 1 "memory0.yaml:3: solver.max_memory_gib must be in (0, " -- info "$T/memory0.yaml"

rm -rf "$T" "$T.partial"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
