#!/bin/sh
# t386_event_energy.sh: the energy check of every G_c-calibrated fracture
# criterion, on a strip pulled apart across a straight pre-notched
# ligament to complete separation, under event control (path.control:
# event: every increment ends where the next arm reaches its criterion;
# doc/path-following.md).
#
# The specimen: a square of 40 x 40 particles, dx = 1 mm, plane stress,
# E = 72 GPa, horizon 3.015 dx (square lattice), G_c = 10 J/m^2; two edge
# notches along y = 20 mm (x < 10 mm and x > 30 mm) leave a ligament of
# L = 20 mm = 20 dx; the top and bottom rows are pulled apart (+/- y,
# held in x). Under load control such a strip breaks at its peak load in
# one burst of breaking rounds (1.4-1.5 G_c L of broken arms' energy, the
# arms far past the criterion when their round comes); event control
# follows it through its snap-backs (the grip displacement falls back in
# about a third of the increments) and every arm breaks at its criterion.
#
# The criteria (each calibrated from G_c by the closed forms of
# doc/fracture.md):
#   bond, stretch: PMB (constant micromodulus, full volumes), nu = 1/3;
#   bond, energy: the same with the micropotential criterion;
#   state, stretch: nu = 1/4 (the dilatation term is not zero: the arm's
#     energy includes its share of it), partial volumes;
#   threebody, energy: nu = 1/4 (its shear constant is positive up to 1/4
#     in plane strain, 1/3 in plane stress), partial volumes.
#
# What is checked, per criterion:
# 1. the run ends by the load-drop rule, every increment converged, and
#    the reaction has fallen below 5% of its peak (the issue's "load
#    falls below 5%");
# 2. energy balance: in every increment that breaks arms, the energy
#    released at the fixed grip displacement where they broke (the stored
#    energy before, less that of the damaged strip at the same grip: its
#    secant, reaction/displacement of the increment, times u^2/2) is at
#    least the broken arms' energy (1e-6 of the stored energy); summed,
#    D = W - E_final >= B (W by the same secants: the strip is linear
#    between breakings, Clapeyron);
# 3. the issue's check: B / (G_c L), the broken arms' energy per unit
#    ligament, within 10% of 1. Where the 10% goes: the lattice's own
#    share R of G_c in the arms that cross a unit length of the plane
#    (1.006 for the PMB here; t385), the event tolerance (each arm breaks
#    at most (1 + 1e-3)^2 past its energy at the criterion), arms broken
#    off the plane next to the crack (the state model at nu = 1/3 breaks
#    16% more arms than cross the ligament and reaches B = 1.12 G_c L at
#    this resolution, 1.02 at horizon 4 dx: doc/fracture.md), and the
#    arms still intact when the load falls below 5%.
#    D / (G_c L) is printed, not asserted: each broken arm also lets the
#    network around it relax at the fixed grip (D/B = 1.14-1.21 here, the
#    lattice's snap per arm; doc/fracture.md).
srcdir=${srcdir:-.}
P=./peristatic
T=t386_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T"
mkdir -p "$T"

GC=10.0
L=0.020

# case TAG MODEL NU FRACTURE EXTRA: writes $T/TAG.yaml
strip_case() {
  cat > "$T/$1.yaml" <<EOF
name: t386-$1
geometry:
  type: box
  dim: 2
  counts: [40, 40]
  spacing: 1.0e-3
  cracks: [[[-0.001, 0.020], [0.010, 0.020]], [[0.030, 0.020], [0.041, 0.020]]]
material:
  model: $2
  E: 72.0e9
  nu: $3
  plane: stress
  horizon_factor: 3.015
$5
  fracture: $4
loading:
  type: boundary
  boundary:
    - select: {y_min: 0.039}
      displace: {y: 1.0e-4}
      measure: true
    - select: {y_min: 0.039}
      fix: [x]
    - select: {y_max: 0.001}
      displace: {y: -1.0e-4}
      measure: true
    - select: {y_max: 0.001}
      fix: [x]
path:
  control: event
  load_step: 0.05
  max_load: 5
  stop_load_drop: 0.05
output:
  vtk_every: 0
EOF
}

PMB="  micromodulus: constant
  partial_volumes: false
  surface_correction: false"
strip_case bond-stretch bond 0.3333333333333333 "{fracture_energy: $GC, criterion: stretch}" "$PMB"
strip_case bond-energy bond 0.3333333333333333 "{fracture_energy: $GC, criterion: energy}" "$PMB"
strip_case state-stretch state 0.25 "{fracture_energy: $GC, criterion: stretch}" ""
strip_case threebody-energy threebody 0.25 "{fracture_energy: $GC, criterion: energy}" ""

for tag in bond-stretch bond-energy state-stretch threebody-energy; do
  out="$T/$tag"
  if ! $P run -q -o "$out" "$T/$tag.yaml" >/dev/null 2>"$T/$tag.err"; then
    ko "$tag: exit non-zero: $(cat "$T/$tag.err")"
    continue
  fi
  reason=$(awk -F': ' '$1 == "stop_reason" { print $2 }' "$out/summary.txt")
  # the analysis of history.csv (see the header): name value lines
  awk -F, -v G="$GC" -v L="$L" '
  NR == 1 { for (i = 1; i <= NF; i++) h[$i] = i; next }
  { F = $h["reaction"]; u = $h["displacement_m"]; E = $h["stored_energy"]
    B = $h["broken_energy"]; n = $h["arms_broken"]; rows++
    if ($h["converged"] != 1) unconv++
    if (u > 0) { s = F / u; W += 0.5 * s * (u * u - u0 * u0) } else nou++
    if (n > n0) {
      rel = E0 - 0.5 * s * u0 * u0; dB = B - B0; events++
      if (rel < dB - 1e-6 * E0) bad++
      if (dB > 0 && (minr == "" || rel / dB < minr)) minr = rel / dB }
    if (u < u0) back++
    if (F > Fmax) Fmax = F
    u0 = u; E0 = E; B0 = B; n0 = n; Fend = F }
  END {
    printf "rows %d\nunconverged %d\nno_displacement %d\nevents %d\nbad %d\nmin_ratio %.4f\n", rows, unconv, nou, events, bad + 0, minr
    printf "back %d\narms %d\nW %.6g\nE %.6g\nD %.6g\nB %.6g\n", back, n0, W, E0, W - E0, B0
    printf "rB %.4f\nrD %.4f\nfall %.4f\n", B0 / (G * L), (W - E0) / (G * L), Fend / Fmax }' \
    "$out/history.csv" > "$T/$tag.an"
  v() { awk -v k="$1" '$1 == k { print $2 }' "$T/$tag.an"; }
  holds() { awk "BEGIN { exit !($1) }" 2>/dev/null; }
  if [ "$(v unconverged)" = 0 ] && [ "$(v no_displacement)" = 0 ] &&
     printf '%s' "$reason" | grep -q "fell below 0.05 of its peak" && holds "$(v fall) < 0.05"; then
    ok "$tag: $(v rows) increments converged, $(v arms) arms broken in $(v events) events (the grip displacement fell back in $(v back)); the reaction fell to $(v fall) of its peak ($reason)"
  else
    ko "$tag: $(v unconverged) increments unconverged, $(v no_displacement) rows without a grip displacement, reaction at $(v fall) of its peak, end: $reason"
  fi
  if [ "$(v bad)" = 0 ] && holds "$(v D) >= $(v B)"; then
    ok "$tag: every event releases at least its broken arms' energy at the fixed grip (worst ratio $(v min_ratio)); D = W - E = $(v D) >= B = $(v B) J/m"
  else
    ko "$tag: $(v bad) events release less than their broken arms' energy (worst ratio $(v min_ratio)); D $(v D), B $(v B) J/m"
  fi
  if holds "$(v rB) >= 0.9 && $(v rB) <= 1.1"; then
    ok "$tag: broken arms' energy per unit ligament B/(G_c L) = $(v rB) within 10% of 1 (dissipated D/(G_c L) = $(v rD))"
  else
    ko "$tag: B/(G_c L) = $(v rB), not within 10% of 1 (D/(G_c L) = $(v rD))"
  fi
done
summary
