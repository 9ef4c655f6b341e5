#!/bin/sh
# t735_mesh_run.sh: geometry.type mesh through the command line.
# (d) The bond-model plate of tests/data/mesh/plate-box.yaml (a box of
#     20 x 10 spacings, held at its left column, pulled at its right one)
#     read instead from the Gmsh mesh of 20 x 10 structured quadrangles
#     (plate-mesh.yaml: plate.msh, held and pulled through its physical
#     curves "left" and "right") gives the same history.csv: every column
#     but wall_s to 1e-9 relative (the centroids are the box's lattice to
#     about 1e-12 of a spacing: Gmsh's transfinite nodes).
# (f) Bad input exits 1 with the file and line: an unknown set name (the
#     mesh's sets listed), select.set without a mesh, an extension that
#     names no format, geometry.format on another type or unknown, a set
#     name that two groups of the mesh share (dup_names.msh), the
#     mesh's dimension against geometry.dim; a missing mesh file exits 3
#     (input/output, as a missing cloud); a build without a reader refuses its format with
#     "this peristatic was built without Gmsh support: install
#     libgmsh-dev and re-run configure" (checked when configure left
#     Gmsh out).
# Without the Gmsh reader the run comparison FAILs unless configure was
# run --without-gmsh (PS_GMSH_STATE "disabled", set by make check).
srcdir=${srcdir:-.}
D="$srcdir/tests/data/mesh"
P=./peristatic
T=t735_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T" "$T.partial"
mkdir -p "$T"
cp "$D/plate.msh" "$T/"

# the same case with one line changed (sed script $1) into $T/$2
variant() {
  sed "$1" "$D/plate-mesh.yaml" > "$T/$2"
}

if [ "${PS_GMSH_STATE:-yes}" = yes ]; then
  if $P run -q -o "$T/box" "$D/plate-box.yaml" 2>"$T/box.err" &&
     $P run -q -o "$T/mesh" "$D/plate-mesh.yaml" 2>"$T/mesh.err"; then
    if awk -F, 'NR == FNR { for (i = 1; i <= NF; i++) a[FNR, i] = $i; n = FNR; next }
      FNR == 1 { for (i = 1; i <= NF; i++) if ($i == "wall_s") w = i }
      { for (i = 1; i <= NF; i++) {
          if (i == w || FNR == 1 && $i == a[FNR, i]) continue
          x = $i + 0; y = a[FNR, i] + 0; d = x - y; if (d < 0) d = -d
          s = y < 0 ? -y : y
          if (d > 1e-9 * s + 1e-300 || (FNR == 1 && $i != a[FNR, i])) bad++ } }
      END { exit !(bad == 0 && n == FNR && n > 1) }' "$T/box/history.csv" "$T/mesh/history.csv"
    then
      ok "plate.msh gives plate-box.yaml's history.csv (all columns but wall_s to 1e-9)"
    else
      ko "plate.msh and the box differ: $(paste -d'|' "$T/box/history.csv" "$T/mesh/history.csv")"
    fi
    grep -q "^# plate-mesh: 200 particles, 2278 arms" "$T/mesh.err" 2>/dev/null ||
      $P run -o "$T/mesh2" "$D/plate-mesh.yaml" 2>&1 | grep -q "200 particles, 2278 arms" &&
      ok "plate.msh: 200 particles, the box's 2278 arms" || ko "plate.msh particle and arm counts"
  else
    ko "the plate runs: $(cat "$T/box.err" "$T/mesh.err")"
  fi
  variant 's/set: left}/set: lefty}/' unknown_set.yaml
  expect 1 "unknown_set.yaml:11: loading.boundary entry 1: no set 'lefty' in .*plate.msh (its sets: bottom, right, top, left, plate)" -- info "$T/unknown_set.yaml"
  cp "$D/dup_names.msh" "$T/"
  variant 's/plate.msh/dup_names.msh/; s/set: left}/set: top}/' dup.yaml
  expect 1 "dup.yaml:11: loading.boundary entry 1: 'top' names two sets of .*dup_names.msh (a physical curve and a physical surface): rename one in the mesh" -- info "$T/dup.yaml"
  variant 's/plate.msh/nothere.msh/' missing.yaml
  expect 3 "nothere.msh: cannot open" -- info "$T/missing.yaml"
  variant 's/dim: 2/dim: 3/; s/nu: 0.3333333333333333/nu: 0.25/' dim3.yaml
  expect 1 "plate.msh: the mesh's elements are 2D but geometry.dim is 3" -- info "$T/dim3.yaml"
  $P info "$srcdir/data/cases/plate-gmsh.yaml" > "$T/example.out" 2>&1 &&
    ok "the shipped data/cases/plate-gmsh.yaml reads (info)" ||
    ko "data/cases/plate-gmsh.yaml: $(cat "$T/example.out")"
  variant 's/select: {set: left}/select: {set: left, y_max: 0.004}/' set_box.yaml
  $P info "$T/set_box.yaml" > "$T/set_box.out" 2>&1 &&
    ok "select: {set: left, y_max: ...} combines a set and a box" ||
    ko "set and box: $(cat "$T/set_box.out")"
elif [ "$PS_GMSH_STATE" = disabled ]; then
  echo "SKIP: the Gmsh plate run (configure --without-gmsh)"
else
  ko "the Gmsh reader was not built (configure found no libgmsh-dev): install it (scripts/install-deps.sh) or configure --without-gmsh"
fi
if [ "${PS_GMSH_STATE:-yes}" != yes ]; then
  expect 1 "plate-mesh.yaml:6: this peristatic was built without Gmsh support: install libgmsh-dev and re-run configure" -- info "$D/plate-mesh.yaml"
fi
if [ "${PS_EXODUS_STATE:-yes}" != yes ]; then
  variant 's/file: plate.msh/file: plate.exo/' exo.yaml
  expect 1 "exo.yaml:6: this peristatic was built without Exodus II support: install libexodusii-dev and re-run configure" -- info "$T/exo.yaml"
fi

# checks of the case file, whatever was built
variant 's/file: plate.msh/file: plate.dat/' ext.yaml
expect 1 "ext.yaml:6: geometry.file .*plate.dat: the extension names no mesh format (.msh: Gmsh; .exo, .e, .g, .gen: Exodus II): give geometry.format gmsh or exodus" -- info "$T/ext.yaml"
sed 's/{x_min: 0.019}/{x_min: 0.019, set: right}/' "$D/plate-box.yaml" > "$T/box_set.yaml"
expect 1 "box_set.yaml:11: loading.boundary entry 2: select.set names a set of a mesh: it needs geometry.type mesh" -- info "$T/box_set.yaml"
sed 's/spacing: 1.0e-3}/spacing: 1.0e-3, format: gmsh}/' "$D/plate-box.yaml" > "$T/box_format.yaml"
expect 1 "box_format.yaml:5: geometry.format does not apply to geometry.type box (it is for type mesh)" -- info "$T/box_format.yaml"
variant 's/dim: 2, file/dim: 2, format: abaqus, file/' format.yaml
expect 1 "format.yaml:6: geometry.format must be one of: gmsh, exodus (got abaqus)" -- info "$T/format.yaml"

rm -rf "$T" "$T.partial"
summary
