# bench/box3d.sh: the benchmarks' 3D box, sourced by bench/run.sh and
# bench/petsc.sh. box3d NAME N [MATERIAL-LINES] writes $work/NAME.yaml: N^3
# particles 1 mm apart on a cubic lattice, held at x = 0 and pulled 1 um
# in x at the other end (one elastic increment), and prints its path.
# Default material: the fibre model, alpha 3.5, elastic.
box3d() {
  f="$work/$1.yaml"
  # the default in a variable: inside ${3:-...} the first '}' would end it
  default_material='kernel: {alpha: 3.5}
material: {E: 210.0e9, nu: 0.3, yield_strain: 0.002, plastic: false}'
  cat > "$f" <<EOC
name: $1
geometry: {type: box, dim: 3, counts: [$2, $2, $2], spacing: 1.0e-3, lattice: square}
${3:-$default_material}
loading:
  type: boundary
  boundary:
    - select: {x_max: 0.0015}
      fix: [x, y, z]
    - select: {x_min: $(awk -v n="$2" 'BEGIN {printf "%.4f", (n - 1.5) * 1e-3}')}
      displace: {x: 1.0e-6}
      measure: true
solver: {cg_forcing: adaptive}
path: {load_step: 1.0, max_load: 1.0}
output: {fields: false}
EOC
  echo "$f"
}
