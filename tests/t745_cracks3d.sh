#!/bin/sh
# t745_cracks3d.sh: geometry.cracks and geometry.holes in 3D through the
# command line (tests/t740_cracks3d checks the cuts themselves): planar
# crack polygons [[x, y, z], ...] and spheres [cx, cy, cz, R] on a box and
# a point cloud; each bad entry (not planar, 2 or 17 points, zero area,
# R <= 0, the other dimension's form, J in 3D) exits 1 naming the file,
# the line and the entry.
srcdir=${srcdir:-.}
P=./peristatic
T=t745_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"

# a 3D box of 6 x 6 x 6 particles of 1 mm; GEOM is replaced by the
# geometry keys under test (from line 7 on)
box3d() {
  {
    printf 'name: t745\ngeometry:\n  type: box\n  dim: 3\n  counts: [6, 6, 6]\n  spacing: 1.0e-3\n'
    printf '%s\n' "$2"
    printf 'material: {model: bond, E: 1.0e9, nu: 0.25, plastic: false}\n'
    printf 'loading:\n  type: boundary\n  boundary:\n'
    printf '    - select: {z_max: 0.001}\n      fix: [x, y, z]\n'
    printf '    - select: {z_min: 0.005}\n      displace: {z: 1.0e-6}\n      measure: true\n'
    printf 'path: {load_step: 1.0, max_load: 1.0}\noutput: {vtk_every: 0}\n'
  } > "$T/$1.yaml"
}
box2d() {
  {
    printf 'name: t745\ngeometry:\n  type: box\n  dim: 2\n  counts: [6, 6]\n  spacing: 1.0e-3\n'
    printf '%s\n' "$2"
    printf 'material: {model: bond, E: 1.0e9, nu: 0.25, plane: strain, plastic: false}\n'
    printf 'loading:\n  type: boundary\n  boundary:\n'
    printf '    - select: {y_max: 0.001}\n      fix: [x, y]\n'
    printf '    - select: {y_min: 0.005}\n      displace: {y: 1.0e-6}\n'
  } > "$T/$1.yaml"
}
SQ='[[0.001, 0.001, 0.003], [0.005, 0.001, 0.003], [0.005, 0.005, 0.003], [0.001, 0.005, 0.003]]'

# the good ones: a square crack between the layers z = 2.5 and 3.5 mm and
# a sphere; the crack cuts arms, the sphere particles and arms
box3d plain ''
box3d square "  cracks: [$SQ]"
box3d sphere '  holes: [[0.003, 0.003, 0.003, 1.2e-3]]'
box3d both "  cracks: [$SQ]
  holes:
    - [0.003, 0.003, 0.0001, 0.0009]"
arms() { $P info "$1" 2>/dev/null | sed -n 's/^arms: //p'; }
parts() { $P info "$1" 2>/dev/null | sed -n 's/^particles: //p'; }
a0=$(arms "$T/plain.yaml")
a1=$(arms "$T/square.yaml")
n2=$(parts "$T/sphere.yaml")
a2=$(arms "$T/sphere.yaml")
if [ -n "$a0" ] && [ -n "$a1" ] && [ "$a1" -lt "$a0" ]; then
  ok "3D box: a square crack polygon cuts arms ($a1 of $a0 left)"
else
  ko "3D box: a square crack polygon: arms $a1 (without it $a0)"
fi
# the sphere of radius 1.2 mm about (3, 3, 3) mm holds the 8 particles at
# (2.5 | 3.5, 2.5 | 3.5, 2.5 | 3.5) mm (0.87 mm away; the next, 1.66 mm)
if [ "$n2" = 208 ] && [ -n "$a2" ] && [ "$a2" -lt "$a0" ]; then
  ok "3D box: a sphere hole removes its 8 particles and cuts arms ($a2 arms)"
else
  ko "3D box: a sphere hole: $n2 particles (want 208), $a2 arms"
fi
if $P run -q -o "$T/both" "$T/both.yaml" > /dev/null 2>&1 && [ -f "$T/both/summary.txt" ]; then
  ok "3D box with a crack polygon and a sphere hole runs"
else
  ko "3D box with a crack polygon and a sphere hole did not run"
fi

# a 3D point cloud (the same lattice) with a sphere hole and the crack
awk 'BEGIN { for (k = 0; k < 6; k++) for (j = 0; j < 6; j++) for (i = 0; i < 6; i++)
  printf "%.4f %.4f %.4f 1e-9\n", (i + 0.5) * 1e-3, (j + 0.5) * 1e-3, (k + 0.5) * 1e-3 }' > "$T/cloud.txt"
sed -e 's/type: box/type: cloud/' -e 's/  counts: \[6, 6, 6\]/  file: cloud.txt/' -e '/spacing/d' \
  "$T/both.yaml" > "$T/cloud.yaml"
n3=$(parts "$T/cloud.yaml")
a3=$(arms "$T/cloud.yaml")
# the sphere about (3, 3, 0.1) mm of 0.9 mm holds the 4 particles at
# (2.5 | 3.5, 2.5 | 3.5, 0.5) mm (0.84 mm away)
if [ "$n3" = 212 ] && [ -n "$a3" ]; then
  ok "3D cloud with a sphere hole (4 particles removed) and a crack polygon"
else
  ko "3D cloud with a sphere hole: $n3 particles (want 212), $a3 arms"
fi
# holes on a 2D cloud (2D holes were box only)
awk 'BEGIN { for (j = 0; j < 6; j++) for (i = 0; i < 6; i++)
  printf "%.4f %.4f 1e-6\n", (i + 0.5) * 1e-3, (j + 0.5) * 1e-3 }' > "$T/cloud2.txt"
box2d cloud2 '  holes: [[0.003, 0.003, 0.0008]]'
sed -i -e 's/type: box/type: cloud/' -e 's/  counts: \[6, 6\]/  file: cloud2.txt/' -e '/spacing/d' "$T/cloud2.yaml"
n4=$(parts "$T/cloud2.yaml")
[ "$n4" = 32 ] && ok "2D cloud with a hole (4 particles removed)" ||
  ko "2D cloud with a hole: $n4 particles (want 32)"
# the example case reads and builds
a5=$(arms "$srcdir/data/cases/penny-crack-3d.yaml")
[ -n "$a5" ] && ok "data/cases/penny-crack-3d.yaml: info builds its $a5 arms" ||
  ko "data/cases/penny-crack-3d.yaml: info failed"

# bad entries: exit 1, FILE:LINE: geometry.cracks entry N: ...
box3d nonplanar '  cracks:
    - [[0.001, 0.001, 0.003], [0.005, 0.001, 0.003],
       [0.005, 0.005, 0.0031], [0.001, 0.005, 0.003], [0.0005, 0.003, 0.003]]'
expect 1 "nonplanar.yaml:9: geometry.cracks entry 1: not planar: point 3 (0.005, 0.005, 0.0031) is 0.0001 m off the plane of the others" -- info "$T/nonplanar.yaml"
box3d two_points '  cracks:
    - [[0.001, 0.001, 0.003], [0.005, 0.005, 0.003], [0.001, 0.005, 0.003]]
    - [[0.001, 0.001, 0.003], [0.005, 0.001, 0.003]]'
expect 1 "two_points.yaml:9: geometry.cracks entry 2: a 3D crack is a planar polygon of 3 to 16 points \[\[x, y, z\], ...\] (got 2 points)" -- info "$T/two_points.yaml"
box3d zero_area '  cracks: [[[0.001, 0.001, 0.003], [0.002, 0.002, 0.003], [0.004, 0.004, 0.003]]]'
expect 1 "zero_area.yaml:7: geometry.cracks entry 1: zero area" -- info "$T/zero_area.yaml"
box3d seventeen "  cracks: [[$(awk 'BEGIN { for (i = 0; i < 17; i++) printf "%s[%.6f, %.6f, 0.003]", i ? ", " : "", 0.003 + 0.002 * cos(6.2831853 * i / 17), 0.003 + 0.002 * sin(6.2831853 * i / 17) }')]]"
expect 1 "seventeen.yaml:7: geometry.cracks entry 1: a 3D crack is a planar polygon of 3 to 16 points .*(got 17 points)" -- info "$T/seventeen.yaml"
box3d mixed '  cracks: [[[0.001, 0.001, 0.003], [0.005, 0.001], [0.005, 0.005, 0.003]]]'
expect 1 "mixed.yaml:7: geometry.cracks entry 1: point 2 has 2 coordinates but point 1 has 3" -- info "$T/mixed.yaml"
box3d seg3d '  cracks: [[[0.001, 0.003], [0.005, 0.003]]]'
expect 1 "seg3d.yaml:7: geometry.cracks entry 1 is a 2D segment \[\[x0, y0\], \[x1, y1\]\] but geometry.dim is 3" -- info "$T/seg3d.yaml"
box2d poly2d "  cracks: [$SQ]"
expect 1 "poly2d.yaml:7: geometry.cracks entry 1 is a 3D polygon of \[x, y, z\] points but geometry.dim is 2" -- info "$T/poly2d.yaml"
box3d r_zero '  holes: [[0.003, 0.003, 0.003, 0]]'
expect 1 "r_zero.yaml:7: geometry.holes entry 1: the radius R must be > 0 (got 0)" -- info "$T/r_zero.yaml"
box3d r_neg '  holes:
    - [0.003, 0.003, 0.003, 1.0e-3]
    - [0.003, 0.003, 0.003, -1.0e-3]'
expect 1 "r_neg.yaml:9: geometry.holes entry 2: the radius R must be > 0 (got -1.0e-3)" -- info "$T/r_neg.yaml"
box3d circle3d '  holes: [[0.003, 0.003, 1.0e-3]]'
expect 1 "circle3d.yaml:7: geometry.holes entry 1 is a circle \[cx, cy, R\] but geometry.dim is 3: a 3D hole is a sphere \[cx, cy, cz, R\]" -- info "$T/circle3d.yaml"
box2d sphere2d '  holes: [[0.003, 0.003, 0.003, 1.0e-3]]'
expect 1 "sphere2d.yaml:7: geometry.holes entry 1 is a sphere \[cx, cy, cz, R\] but geometry.dim is 2" -- info "$T/sphere2d.yaml"
box3d all_gone '  holes: [[0.003, 0.003, 0.003, 1.0]]'
expect 1 "all_gone.yaml: the holes remove every particle" -- info "$T/all_gone.yaml"
# J stays 2D
box3d j3d "  cracks: [$SQ]"
printf 'output: {j_integral: {crack: 0, rings: [0.001]}}\n' >> "$T/j3d.yaml"
sed -i 's/^output: {vtk_every: 0}$//' "$T/j3d.yaml"
expect 1 "j3d.yaml:[0-9]*: output.j_integral is 2D only (geometry.dim is 3)" -- info "$T/j3d.yaml"

rm -rf "$T"
summary
