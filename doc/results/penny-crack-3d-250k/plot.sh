#!/bin/sh
# plot.sh OUT_DIR: the picture of data/cases/penny-crack-3d-250k.yaml's
# run: the opening displacement u_z on the plane y = 0 (a cut through the
# crack's centre), from OUT_DIR/particles.csv, into penny-crack.png here,
# and the crack's opening profile (the gap between the layers z = +-0.5 mm
# on y = 0) into profile.csv, drawn beside Sneddon's opening of a penny
# crack in an infinite body, 8 (1 - nu^2) sigma sqrt(a^2 - x^2) / (pi E),
# with sigma the boundary stress of OUT_DIR/history.csv, E = 1 GPa and
# nu = 1/4 of the case, a = 0.98717 x 15 mm (the circle of the 16-gon's
# area), plus the far field's gap (the profile's value at its ends).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
csv="$1/particles.csv"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["y"] > -1e-4 && $c["y"] < 1e-4 { print $c["x"] * 1e3, $c["z"] * 1e3, $c["uz"] * 1e6 }' \
  "$csv" > "$here/slice.dat"
# the gap u_z(z = +0.5) - u_z(z = -0.5) along x on y = 0
awk '$2 > 0.4 && $2 < 0.6 { up[$1] = $3 } $2 < -0.4 && $2 > -0.6 { lo[$1] = $3 }
  END { print "x_mm,opening_um"; for (x in up) if (x in lo) printf "%s,%.6g\n", x, up[x] - lo[x] }' \
  "$here/slice.dat" | sort -t, -k1,1g > "$here/profile.csv"
sigma=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "boundary_stress_Pa") c = i; next }
  { s = $c } END { print s }' "$1/history.csv")
far=$(awk -F, 'NR == 2 { print $2 }' "$here/profile.csv")
gnuplot <<EOG
set terminal pngcairo size 1000,820 noenhanced
set output '$here/penny-crack.png'
set multiplot layout 2,1 title 'penny crack, 253,500 particles (bond PD, PETSc CG + ICC): cut y = 0'
set size ratio -1
set xlabel 'x (mm)'
set ylabel 'z (mm)'
set cblabel 'u_z (micrometres)'
set palette defined (0 'blue', 1 'white', 2 'red')
set title 'opening displacement u_z (the crack: z = 0, |x| < 15 mm)'
plot '$here/slice.dat' using 1:2:3 with points pt 5 ps 0.35 palette notitle
set size noratio
set title 'gap across the crack plane, y = 0'
set xlabel 'x (mm)'
set ylabel 'u_z(+0.5) - u_z(-0.5) (micrometres)'
set datafile separator ','
a = 0.98717 * 15.0
w0 = 8 * (1 - 0.25**2) * $sigma * 1e-3 / (pi * 1.0e9) * 1e6
sneddon(x) = $far + (abs(x) < a ? w0 * sqrt(a**2 - x**2) : 0)
set samples 400
plot '$here/profile.csv' using 1:2 skip 1 with linespoints pt 7 ps 0.5 title 'peristatic', \\
     sneddon(x) with lines lw 2 dt 2 title 'Sneddon (infinite body) + far-field gap'
unset multiplot
EOG
rm -f "$here/slice.dat"
