#!/bin/sh
# install-deps.sh: install what peristatic needs to build, test and plot on
# Debian (12 or later). Installs only the packages that are missing; needs
# root (or sudo). Safe to run again.
set -eu
# time: the tests measure a refused run's peak memory with /usr/bin/time;
# gcc's libasan8/libubsan1 (with build-essential) serve make check-sanitize
PKGS="build-essential autoconf automake libtool pkg-config \
libsuitesparse-dev libgsl-dev libyaml-dev libopenblas-dev gnuplot-nox time"
# Optional: the mesh readers of geometry.type mesh (configure builds each
# reader when it finds its package, and works without them: then
# configure --without-gmsh --without-exodus, or make check fails the mesh
# tests). libgmsh-dev: Gmsh's C API (gmshc.h, -lgmsh); gmsh: its command
# line, to remake the test meshes (tests/data/mesh/*.geo); libexodusii-dev:
# Exodus II (exodusII.h, -lexoIIv2c). Together about 230 MB installed
# (OpenCASCADE, HDF5, NetCDF, MPI come with them).
PKGS="$PKGS libgmsh-dev gmsh libexodusii-dev"
# --with-petsc: also the PETSc backend (configure --with-petsc;
# solver.linear: petsc): Debian's PETSc 3.18 with MPI (Open MPI), MUMPS,
# hypre and ML, and mpiexec for the tests (openmpi-bin).
if [ "${1:-}" = "--with-petsc" ]; then
  PKGS="$PKGS petsc-dev openmpi-bin"
elif [ -n "${1:-}" ]; then
  echo "install-deps: unknown option '$1' (the only one: --with-petsc)" >&2
  exit 1
fi
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" \
    || missing="$missing $p"
done
if [ -z "$missing" ]; then
  echo "install-deps: all dependencies present"
  exit 0
fi
echo "install-deps: installing:$missing"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends $missing
