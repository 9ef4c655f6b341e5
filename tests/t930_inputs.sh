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
# the nesting is measured on libyaml's own events: no byte-order mark,
# line break (CR, NEL, LS, PS) after a comment, quote in a continued
# plain scalar or UTF-16 text hides the brackets from it
awk 'BEGIN { for (i = 0; i < 60000; i++) printf "["; print "" }' > "$T/brackets"
printf '\357\273\277' | cat - "$T/brackets" > "$T/bom.yaml"
no_hang 30 1 "bom.yaml:1: nesting deeper than 32 levels" -- info "$T/bom.yaml"
printf '# c\r' | cat - "$T/brackets" > "$T/cr.yaml"
no_hang 30 1 "cr.yaml:2: nesting deeper than 32 levels" -- info "$T/cr.yaml"
printf '# c\302\205' | cat - "$T/brackets" > "$T/nel.yaml"
no_hang 30 1 "nel.yaml:2: nesting deeper than 32 levels" -- info "$T/nel.yaml"
printf '# c\342\200\250' | cat - "$T/brackets" > "$T/ls.yaml"
no_hang 30 1 "ls.yaml:2: nesting deeper than 32 levels" -- info "$T/ls.yaml"
printf '# c\342\200\251' | cat - "$T/brackets" > "$T/ps.yaml"
no_hang 30 1 "ps.yaml:2: nesting deeper than 32 levels" -- info "$T/ps.yaml"
printf "x: a\n  'b\ny: " | cat - "$T/brackets" > "$T/quote.yaml"
no_hang 30 1 "quote.yaml:3: nesting deeper than 32 levels" -- info "$T/quote.yaml"
# UTF-16LE: a byte-order mark, then '[' and NUL 65,536 times
printf '[\000' > "$T/u16"
for i in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16; do cat "$T/u16" "$T/u16" > "$T/u16x"; mv "$T/u16x" "$T/u16"; done
printf '\377\376' | cat - "$T/u16" > "$T/utf16.yaml"
no_hang 30 1 "utf16.yaml:1: nesting deeper than 32 levels" -- info "$T/utf16.yaml"
# anchors and aliases: libyaml 0.2.5 registers anchors in quadratic time
# (200,000 took minutes); case files use neither
awk 'BEGIN { c = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"; printf "x: [";
  for (i = 0; i < 200000; i++)
    printf "&%s%s%s,", substr(c, int(i / 3844) + 1, 1), substr(c, int(i / 62) % 62 + 1, 1), substr(c, i % 62 + 1, 1)
  print "1]" }' > "$T/anchors.yaml"
no_hang 30 1 "anchors.yaml:1: case files use no YAML anchors (&) or aliases (\*)" -- info "$T/anchors.yaml"
printf 'kernel:\n  alpha: 5.1\n  k: *v\n' > "$T/alias.yaml"
expect 1 "alias.yaml:3: case files use no YAML anchors (&) or aliases (\*)" -- info "$T/alias.yaml"
printf 'kernel:\n  alpha: &v 5.1\n  k: *v\n' > "$T/anchor.yaml"
expect 1 "anchor.yaml:2: case files use no YAML anchors (&) or aliases (\*)" -- info "$T/anchor.yaml"
awk 'BEGIN { for (i = 0; i < 20000; i++) print "# a comment line of a case file that is far too large" }' > "$T/big.yaml"
no_hang 30 1 "big.yaml: larger than 1 MiB (1080000 bytes); case files are small YAML texts" -- info "$T/big.yaml"
expect 1 "big.yaml: larger than 1 MiB" -- run -o "$T/x" "$T/big.yaml"

# encoding errors name the line
expect 1 "utf8.yaml:4: YAML read error: .*UTF-8" -- info "$D/utf8.yaml"

# numbers: decimal only, finite, in range
expect 1 "hex_number.yaml:4: material.E must be a decimal number (got '0x10')" -- info "$D/hex_number.yaml"
expect 1 "blank_number.yaml:4: material.E must be a decimal number (got ' 2.1e11')" -- info "$D/blank_number.yaml"
expect 1 "counts_range.yaml:3: geometry.counts must be an integer in 1..2147483647 (got 2147483648)" -- info "$D/counts_range.yaml"

# a leading zero is octal to YAML 1.1: refused without a fraction or
# exponent (0, 0.5 and 0e3 are decimal)
sed 's/E: 0x10/E: 010/' "$D/hex_number.yaml" > "$T/octal.yaml"
expect 1 "octal.yaml:4: material.E must be a decimal number (got '010')" -- info "$T/octal.yaml"
sed 's/E: 0x10/E: 0e3/' "$D/hex_number.yaml" > "$T/zero_e.yaml"
expect 1 "zero_e.yaml:4: material.E must be > 0 (got 0e3)" -- info "$T/zero_e.yaml"
sed 's/E: 0x10/E: 02.1e11/' "$D/hex_number.yaml" > "$T/zero_frac.yaml"
$P info "$T/zero_frac.yaml" > /dev/null 2>&1 && ok "E: 02.1e11 (a fraction) is decimal" ||
  ko "E: 02.1e11 refused"

# coordinates beyond 1e150 m: a crack at 1e308 was ignored (NaN in the cut
# test), cloud points 2e200 apart "coincided" (their squares overflowed)
sed 's/spacing: 1.0e-3}/spacing: 1.0e-3, cracks: [[[0.002, -1.0e308], [0.002, 1.0e308]]]}/' "$D/hex_number.yaml" |
  sed 's/E: 0x10/E: 2.1e11/' > "$T/far_crack.yaml"
expect 1 "far_crack.yaml:5: coordinates beyond 1e150 m (geometry.cracks: got -1.0e308)" -- info "$T/far_crack.yaml"
sed 's/spacing: 1.0e-3}/spacing: 1.0e-3, origin: [0, 2.0e150], holes: [[1.0e151, 0, 1.0e-3]]}/' "$D/hex_number.yaml" |
  sed 's/E: 0x10/E: 2.1e11/' > "$T/far_origin.yaml"
expect 1 "far_origin.yaml:5: coordinates beyond 1e150 m (geometry.origin: got 2.0e150)" -- info "$T/far_origin.yaml"
sed 's/origin: \[0, 2.0e150\], //' "$T/far_origin.yaml" > "$T/far_hole.yaml"
expect 1 "far_hole.yaml:5: coordinates beyond 1e150 m (geometry.holes: got 1.0e151)" -- info "$T/far_hole.yaml"
printf '0 0 1e-6\n1e-3 0 1e-6\n0 1e-3 1e-6\n1e-3 1e-3 1e-6\n-1e200 0 1e-6\n' > "$T/far.txt"
printf 'geometry: {type: cloud, dim: 2, file: far.txt, sizes: eq44}\nloading:\n  type: boundary\n  boundary:\n    - {select: {x_max: 0}, fix: [x, y]}\n' > "$T/far_cloud.yaml"
expect 1 "far.txt:5: coordinates beyond 1e150 m (x, field 1 of 'x y volume \[block\]': got '-1e200')" -- info "$T/far_cloud.yaml"

# keys of another geometry
expect 1 "file_on_disk.yaml:8: geometry.file does not apply to geometry.type disk (it is for types cloud and mesh)" -- info "$D/file_on_disk.yaml"

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

# material.fracture and the bond/state keys (issue 18): each refused with
# the file, the line and the key; the PMB notched plate is the base case
N="$srcdir/data/cases/notched-plate-pmb.yaml"
sed 's/critical_stretch: 1.0e-3/critical_stretch: -1.0e-3/' "$N" > "$T/s0_negative.yaml"
expect 1 "s0_negative.yaml:30: material.fracture.critical_stretch must be > 0 (got -1.0e-3)" -- info "$T/s0_negative.yaml"
sed 's/critical_stretch: 1.0e-3/critical_stretch: 0/' "$N" > "$T/s0_zero.yaml"
expect 1 "s0_zero.yaml:30: material.fracture.critical_stretch must be > 0 (got 0)" -- info "$T/s0_zero.yaml"
sed 's/critical_stretch: 1.0e-3/critical_stretch: 20/' "$N" > "$T/s0_big.yaml"
expect 1 "s0_big.yaml:30: material.fracture.critical_stretch must be in \\[1e-09, 10\\]" -- info "$T/s0_big.yaml"
sed 's/{critical_stretch: 1.0e-3}/{critical_stretch: 1.0e-3, fracture_energy: 5}/' "$N" > "$T/two_criteria.yaml"
expect 1 "two_criteria.yaml:30: material.fracture needs exactly one of critical_stretch, fracture_energy and critical_micropotential (got 2)" -- info "$T/two_criteria.yaml"
sed 's/{critical_stretch: 1.0e-3}/{critical_stretch: 1.0e-3, criterion: energy}/' "$N" > "$T/criterion_s0.yaml"
expect 1 "criterion_s0.yaml:30: material.fracture.criterion goes with fracture_energy" -- info "$T/criterion_s0.yaml"
sed 's/{critical_stretch: 1.0e-3}/{fracture_energy: 5, criterion: brittle}/' "$N" > "$T/criterion_bad.yaml"
expect 1 "criterion_bad.yaml:30: material.fracture.criterion must be one of" -- info "$T/criterion_bad.yaml"
sed -e 's/  model: bond/  model: fibre/' -e '/^  micromodulus/d' -e '/^  partial_volumes/d' -e '/^  surface_correction/d' "$N" > "$T/fibre_fracture.yaml"
expect 1 "fibre_fracture.yaml:27: material.fracture is for the bond, state and threebody models: the fibre model breaks arms by plastic elongation, material.delta" -- info "$T/fibre_fracture.yaml"
sed -e 's/  model: bond/  model: state/' "$N" > "$T/state_micro.yaml"
expect 1 "state_micro.yaml:27: material.micromodulus is for the bond model (material.model is state (line 22))" -- info "$T/state_micro.yaml"
sed -e 's/  model: bond/  model: state/' -e '/^  micromodulus/d' -e 's/{critical_stretch: 1.0e-3}/{fracture_energy: 5, criterion: energy}/' "$N" > "$T/state_energy.yaml"
expect 1 "state_energy.yaml:29: material.fracture: the energy criterion is for the bond model" -- info "$T/state_energy.yaml"
sed 's/  fracture: {critical_stretch: 1.0e-3}/  delta: 1.0e-6/' "$N" > "$T/bond_delta.yaml"
expect 1 "bond_delta.yaml:30: material.delta is the fibre model's breaking limit (Eq. 118): the bond model breaks arms by material.fracture" -- info "$T/bond_delta.yaml"
sed 's/  micromodulus: constant/  micromodulus: flat/' "$N" > "$T/micro_bad.yaml"
expect 1 "micro_bad.yaml:27: material.micromodulus must be one of" -- info "$T/micro_bad.yaml"
# path.round_tolerance: a relative residual in (0, 1)
sed 's/^path:/path:\n  round_tolerance: 0/' "$N" > "$T/round_tol0.yaml"
expect 1 "round_tol0.yaml:46: path.round_tolerance must be in (0, 1) (got 0)" -- info "$T/round_tol0.yaml"
sed 's/^path:/path:\n  round_tolerance: 1/' "$N" > "$T/round_tol1.yaml"
expect 1 "round_tol1.yaml:46: path.round_tolerance must be in (0, 1) (got 1)" -- info "$T/round_tol1.yaml"
# material.break_rule and break_length (issue 19): the fibre model's only,
# break_length with (and only with) the strain rule; the fibre notched plate
F="$srcdir/data/cases/notched-plate-fibre.yaml"
sed 's/  fracture: {critical_stretch: 1.0e-3}/&\n  break_rule: strain/' "$N" > "$T/bond_break.yaml"
expect 1 "bond_break.yaml:31: material.break_rule and break_length are the fibre model's (how Eq. 118 measures an arm against delta): the bond model breaks arms by material.fracture" -- info "$T/bond_break.yaml"
sed 's/^  delta: .*/&\n  break_rule: strain/' "$F" > "$T/strain_no_length.yaml"
expect 1 "strain_no_length.yaml:36: material.break_rule strain needs material.break_length L (m)" -- info "$T/strain_no_length.yaml"
sed 's/^  delta: .*/&\n  break_length: 1e-3/' "$F" > "$T/length_alone.yaml"
expect 1 "length_alone.yaml:36: material.break_length goes with break_rule strain or toughness" -- info "$T/length_alone.yaml"
sed 's/^  delta: .*/&\n  break_rule: energy/' "$F" > "$T/break_bad.yaml"
expect 1 "break_bad.yaml:36: material.break_rule must be one of" -- info "$T/break_bad.yaml"
sed 's/^  delta: .*/&\n  break_rule: toughness/' "$F" > "$T/toughness_no_length.yaml"
expect 1 "toughness_no_length.yaml:36: material.break_rule toughness needs material.break_length L (m): an arm breaks at the plastic elongation delta sqrt(r0 / L)" -- info "$T/toughness_no_length.yaml"
sed 's/^  delta: .*/&\n  break_rule: strain\n  break_length: -1e-3/' "$F" > "$T/length_negative.yaml"
expect 1 "length_negative.yaml:37: material.break_length must be > 0" -- info "$T/length_negative.yaml"

# softening arms and dissipation control (issue 20)
sed 's/{critical_stretch: 1.0e-3}/{critical_stretch: 1.0e-3, softening_ratio: 1}/' "$N" > "$T/soft_one.yaml"
expect 1 "soft_one.yaml:30: material.fracture.softening_ratio must be in \\[1, " -- info "$T/soft_one.yaml"
sed 's/{critical_stretch: 1.0e-3}/{critical_micropotential: 1.0e3, softening_ratio: 3}/' "$N" > "$T/soft_energy.yaml"
expect 1 "soft_energy.yaml:30: material.fracture.softening_ratio goes with the stretch criterion" -- info "$T/soft_energy.yaml"
sed -e 's/  model: bond/  model: state/' -e '/^  micromodulus/d' -e 's/{critical_stretch: 1.0e-3}/{critical_stretch: 1.0e-3, softening_ratio: 3}/' "$N" > "$T/soft_state.yaml"
expect 1 "soft_state.yaml:29: material.fracture.softening_ratio is for the bond model" -- info "$T/soft_state.yaml"
sed 's/  stop_load_drop: 0.05/  stop_load_drop: 0.05\n  control: dissipation/' "$N" > "$T/diss_brittle.yaml"
expect 1 "diss_brittle.yaml:49: path.control dissipation needs arms that dissipate energy as they deform" -- info "$T/diss_brittle.yaml"
# event control needs arms that break: the tension bar's fibre arms never do
sed 's/^  load_step: 0.05/  control: event\n&/' "$srcdir/data/cases/tension-bar.yaml" > "$T/event_unbreakable.yaml"
expect 1 "event_unbreakable.yaml:27: path.control event ends each increment where the next arm reaches its breaking criterion, but no arm of this fibre model can break: give material.delta" -- info "$T/event_unbreakable.yaml"
sed 's/  stop_load_drop: 0.05/  stop_load_drop: 0.05\n  control: event\n  event_tolerance: 0/' "$N" > "$T/event_tol.yaml"
expect 1 "event_tol.yaml:50: path.event_tolerance must be" -- info "$T/event_tol.yaml"
# the load phase belongs to dissipation control; unstable_arms is a count
sed 's/  stop_load_drop: 0.05/  stop_load_drop: 0.05\n  load_until_unstable: true/' "$N" > "$T/phase_load.yaml"
expect 1 "phase_load.yaml:49: path.load_until_unstable starts dissipation control with load control; it needs path.control dissipation" -- info "$T/phase_load.yaml"
sed 's/  stop_load_drop: 0.05/  stop_load_drop: 0.05\n  unstable_arms: -3/' "$N" > "$T/phase_arms.yaml"
expect 1 "phase_arms.yaml:49: path.unstable_arms must be" -- info "$T/phase_arms.yaml"

# loading fields, names and path.steps (issue 21 item 5): the tension bar
# with its path or its last boundary entry replaced
B="$srcdir/data/cases/tension-bar.yaml"
head -25 "$B" > "$T/bar_head.yaml"
steps() { cat "$T/bar_head.yaml" - > "$T/$1.yaml"; }
printf 'path:\n  steps: [0.1, 0.5, 0.5, 1]\n' | steps steps_flat
expect 1 "steps_flat.yaml:27: path.steps must increase: entry 3 (0.5) is not above entry 2 (0.5)" -- info "$T/steps_flat.yaml"
printf 'path:\n  steps: [0.5, 0.25]\n' | steps steps_down
expect 1 "steps_down.yaml:27: path.steps must increase: entry 2 (0.25) is not above entry 1 (0.5)" -- info "$T/steps_down.yaml"
printf 'path:\n  steps:\n    - 0.5\n    - -1\n' | steps steps_negative
expect 1 "steps_negative.yaml:29: path.steps must be > 0 (got -1)" -- info "$T/steps_negative.yaml"
printf 'path:\n  steps: []\n' | steps steps_empty
expect 1 "steps_empty.yaml:27: path.steps must be a list of load factors" -- info "$T/steps_empty.yaml"
printf 'path:\n  steps: 1\n' | steps steps_scalar
expect 1 "steps_scalar.yaml:27: path.steps must be a list of load factors, e.g. \[0.25, 0.5, 1\] (got 1)" -- info "$T/steps_scalar.yaml"
printf 'path:\n  control: arc_length\n  steps: [0.5, 1]\n' | steps steps_arc
expect 1 "steps_arc.yaml:28: path.steps is a list of load factors for load control, but path.control is arc_length (line 27)" -- info "$T/steps_arc.yaml"
printf 'path:\n  steps: [0.5, 1]\n  max_load: 2\n' | steps steps_max
expect 1 "steps_max.yaml:28: path.max_load and path.steps (line 27) are both given" -- info "$T/steps_max.yaml"
printf 'path:\n  load_step: 0.1\n  steps: [0.5, 1]\n' | steps steps_dl
expect 1 "steps_dl.yaml:27: path.load_step and path.steps (line 28) are both given" -- info "$T/steps_dl.yaml"
head -22 "$B" > "$T/bar_bc.yaml"
entry() { cat "$T/bar_bc.yaml" - > "$T/$1.yaml"; }
printf '    - select: {x_min: 0.0745}\n      displace: {x: {value: 1e-3, gradient: [0, 1e-3, 0]}}\n' | entry grad3
expect 1 "grad3.yaml:24: loading.boundary entry 3: displace.x.gradient has 3 numbers but geometry.dim is 2" -- info "$T/grad3.yaml"
printf '    - select: {x_min: 0.0745}\n      displace:\n        x: {hessian: [[0, 1], [2, 0]]}\n' | entry hess_asym
expect 1 "hess_asym.yaml:25: loading.boundary.displace.x.hessian must be symmetric" -- info "$T/hess_asym.yaml"
printf '    - select: {x_min: 0.0745}\n      displace:\n        x: {hessian: [[0, 1], [1]]}\n' | entry hess_ragged
expect 1 "hess_ragged.yaml:25: loading.boundary.displace.x.hessian must be square: row 2 has 1 numbers" -- info "$T/hess_ragged.yaml"
printf '    - select: {x_min: 0.0745}\n      displace: {x: {}}\n' | entry field_empty
expect 1 "field_empty.yaml:24: loading.boundary.displace.x is empty" -- info "$T/field_empty.yaml"
printf '    - select: {x_min: 0.0745}\n      displace: {x: {slope: 1}}\n' | entry field_key
expect 1 "field_key.yaml:24: .*slope" -- info "$T/field_key.yaml"
printf '    - select: {x_min: 0.0745}\n      displace: {x: 1e-3}\n      about: [0, 0]\n' | entry about_alone
expect 1 "about_alone.yaml:25: loading.boundary entry 3: about is the point of a displacement field" -- info "$T/about_alone.yaml"
printf '    - select: {x_min: 0.0745}\n      displace: {x: {gradient: [1e-3, 0]}}\n      about: [0, 0, 0]\n' | entry about_3d
expect 1 "about_3d.yaml:25: loading.boundary entry 3: about has 3 coordinates but geometry.dim is 2" -- info "$T/about_3d.yaml"
printf '    - select: {x_min: 0.0745}\n      displace: {x: 1e-3}\n      name: right-grip\n' | entry name_chars
expect 1 "name_chars.yaml:25: loading.boundary.name may hold only letters, digits and _" -- info "$T/name_chars.yaml"
printf '    - select: {x_min: 0.0745}\n      displace: {x: 1e-3}\n      name: grip\n    - select: {x_min: 0.07}\n      fix: [y]\n      name: grip\n' | entry name_twice
expect 1 "name_twice.yaml:26: loading.boundary entry 4: name 'grip' is taken by entry 3 (line 23)" -- info "$T/name_twice.yaml"
printf '    - select: {x_min: 0.0745}\n      displace:\n        x: {hessian: [[1e300, 0], [0, 0]]}\n      about: [-1e150, 0]\n' | entry field_inf
expect 1 "field_inf.yaml:23: loading.boundary entry 3: the displacement field of component x is not finite at particle" -- info "$T/field_inf.yaml"
printf '    - select: {x_min: 0.0745}\n      traction: {x: 1e6}\n      name: pull\n' | entry name_traction
expect 1 "name_traction.yaml:23: loading.boundary entry 3: name 'pull' reports the reactions of supports" -- info "$T/name_traction.yaml"

rm -rf "$T" "$T.partial"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
