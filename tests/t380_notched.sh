#!/bin/sh
# t380_notched.sh: the notched plate of ../shared/PEERS.md
# (data/cases/notched-plate-*.yaml) with every model that breaks arms: by a
# critical stretch (pmb, state), by a plastic elongation (fibre, Eq. 118)
# or by the arm micropotential (threebody).
# 1. Elastic, bond for bond as Peridigm runs it (constant micromodulus,
#    full volumes, no surface correction): the top-grip reaction at load
#    factor 0.1 times the layer thickness dx equals Peridigm's, 868.485 N
#    (60 x 60, 48,000 bonds) and 506.46 N (100 x 100, where Peridigm's
#    round-off cuts the bonds through the notch tip: the notch is extended
#    by 1e-10 m to cut them too, 135,974 bonds). Tolerance 0.5% (the
#    issue's), both agree to 1e-6 today (doc/verification.md).
# 2. To complete fracture (critical stretch 1e-3; fibre: yield strain 1e-3,
#    delta = yield strain x dx; threebody: nu = 0.25, the micropotential
#    criterion with the G_c that s0 = 1e-3 stands for): exit 0 with every increment converged
#    (Newton never aborts), the reaction falls below 5% of its peak, and
#    the crack runs from the notch tip across the whole ligament within one
#    horizon of the notch plane: in every column of the ligament the most
#    damaged particle lies within delta of y = H/2 and has lost at least a
#    quarter of its arms (damage, Eq. 119 analogue).
# 3. path.round_tolerance (breaking rounds re-equilibrated to a relative
#    residual of 1e-2, the state they end in to solver.tolerance), bond and
#    fibre: the same physics as 2 with fewer Newton iterations: the same
#    peak reaction (1e-6 relative), the same number of broken arms (1%),
#    the reaction below 5% of its peak, the crack across the ligament.
srcdir=${srcdir:-.}
C="$srcdir/data/cases"
P=./peristatic
T=t380_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T"
mkdir -p "$T"

# the reaction (N/m) of the last history row, times dx: N for the layer
last_reaction_N() { awk -F, -v dx="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "reaction") c = i }
  NR > 1 { r = $c } END { printf "%.6f", r * dx }' "$1/history.csv"; }
# |got/want - 1| <= tol
close_to() { awk -v g="$1" -v w="$2" -v t="$3" 'BEGIN { d = g / w - 1; if (d < 0) d = -d; exit !(d <= t) }'; }

# 1. elastic reactions against Peridigm
sed -e '/fracture:/d' -e 's/load_step: 0.01/load_step: 0.1/' -e 's/max_load: 1.0/max_load: 0.1/' \
  "$C/notched-plate-pmb.yaml" > "$T/elastic60.yaml"
sed -e 's/counts: \[60, 60\]/counts: [100, 100]/' -e 's/spacing: 8.333333333333333e-4/spacing: 5.0e-4/' \
  -e 's/y_max: 0.0025/y_max: 0.0015/' -e 's/y_min: 0.0475/y_min: 0.0485/' \
  -e 's/\[0.0125, 0.025\]/[0.0125000001, 0.025]/' "$T/elastic60.yaml" > "$T/elastic100.yaml"
for n in 60 100; do
  if [ $n = 60 ]; then dx=8.333333333333333e-4; want=868.485; bonds=48000
  else dx=5.0e-4; want=506.46; bonds=135974; fi
  if $P run -q -o "$T/e$n" "$T/elastic$n.yaml" >/dev/null 2>&1; then
    got=$(last_reaction_N "$T/e$n" $dx)
    arms=$(awk '$1 == "arms:" { print $2 }' "$T/e$n/summary.txt")
    if [ "$arms" = "$bonds" ] && close_to "$got" "$want" 0.005; then
      ok "PMB plate $n x $n: $arms bonds, reaction $got N (Peridigm: $want N, 0.5%)"
    else
      ko "PMB plate $n x $n: $arms bonds (want $bonds), reaction $got N (Peridigm: $want N)"
    fi
  else
    ko "PMB plate $n x $n: the elastic run failed"
  fi
done

# every increment converged and the reaction fell below 5% of its peak
dropped() { awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "converged") c = i; if ($i == "reaction") r = i } }
       NR > 1 { n++; if ($c != 1) bad++; if ($r > pk) pk = $r; last = $r }
       END { exit !(n > 5 && bad == 0 && last < 0.05 * pk && pk > 0) }' "$1/history.csv"; }
# columns of the ligament: x from the notch tip (0.0125) to the right edge
crack_across() { awk -F, -v d=0.0025125 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "x") cx = i; if ($i == "y") cy = i; if ($i == "damage") cd = i } next }
       { k = sprintf("%.6f", $cx); if (!(k in best) || $cd > best[k]) { best[k] = $cd; yb[k] = $cy } }
       END { n = 0; bad = 0
             for (k in best) if (k + 0 > 0.0125) { n++; dy = yb[k] - 0.025; if (dy < 0) dy = -dy
               if (dy > d || best[k] < 0.25) bad++ }
             exit !(n >= 44 && bad == 0) }' "$1/particles.csv"; }
# the largest reaction of a run
peak_reaction() { awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "reaction") r = i }
  NR > 1 && $r > pk { pk = $r } END { printf "%.12g", pk }' "$1/history.csv"; }
summary_item() { awk -v k="$2:" '$1 == k { print $2 }' "$1/summary.txt"; }

# 2. to complete fracture, every model that breaks arms
for model in pmb state fibre threebody; do
  out="$T/$model"
  if $P run -q -o "$out" "$C/notched-plate-$model.yaml" >/dev/null 2>"$T/$model.err"; then
    ok "notched plate, $model: runs to its end (exit 0)"
  else
    ko "notched plate, $model: exit non-zero: $(cat "$T/$model.err")"
    continue
  fi
  if dropped "$out"; then
    ok "notched plate, $model: every increment converged, the reaction fell below 5% of its peak"
  else
    ko "notched plate, $model: an increment failed or the reaction stayed above 5% of its peak"
  fi
  if crack_across "$out"; then
    ok "notched plate, $model: the crack crosses the whole ligament within one horizon of the notch plane"
  else
    ko "notched plate, $model: the damage does not run along the notch plane across the ligament"
  fi
done

# 3. loose breaking rounds: the same physics as 2, fewer Newton iterations
for model in pmb fibre; do
  out="$T/$model-rt"
  sed 's/^path:/path:\n  round_tolerance: 1.0e-2/' "$C/notched-plate-$model.yaml" > "$T/$model-rt.yaml"
  if ! $P run -q -o "$out" "$T/$model-rt.yaml" >/dev/null 2>"$T/$model-rt.err"; then
    ko "notched plate, $model, round_tolerance 1e-2: exit non-zero: $(cat "$T/$model-rt.err")"
    continue
  fi
  [ -f "$T/$model/history.csv" ] || { ko "notched plate, $model: no default run to compare with"; continue; }
  pk=$(peak_reaction "$out") pk0=$(peak_reaction "$T/$model")
  nb=$(summary_item "$out" arms_broken) nb0=$(summary_item "$T/$model" arms_broken)
  it=$(summary_item "$out" newton_iterations) it0=$(summary_item "$T/$model" newton_iterations)
  if close_to "$pk" "$pk0" 1e-6 && close_to "$nb" "$nb0" 0.01 && dropped "$out" && crack_across "$out" &&
     [ "$it" -lt "$it0" ]; then
    ok "notched plate, $model, round_tolerance 1e-2: peak $pk (default $pk0), $nb arms broken ($nb0), the crack across the ligament, $it Newton iterations ($it0)"
  else
    ko "notched plate, $model, round_tolerance 1e-2: peak $pk (default $pk0), $nb arms broken ($nb0), $it Newton iterations ($it0), or the reaction/crack check failed"
  fi
done
[ "$fail" -eq 0 ] && rm -rf "$T"
summary
