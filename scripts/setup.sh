#!/bin/sh
# setup.sh: the first command on a fresh Debian machine. Installs what is
# missing (scripts/install-deps.sh, apt-get), builds peristatic and runs
# the default case. Options: --no-run only installs and builds;
# --with-petsc also installs PETSc and MPI and configures the PETSc
# backend (configure --with-petsc; CI's configuration, .ci/run).
set -eu
cd "$(dirname "$0")/.."
run=1
petsc=""
for a in "$@"; do
  case "$a" in
    --no-run) run=0 ;;
    --with-petsc) petsc=--with-petsc ;;
    *) echo "setup: unknown option '$a' (options: --no-run, --with-petsc)" >&2; exit 1 ;;
  esac
done
./scripts/install-deps.sh $petsc
if [ ! -x configure ]; then autoreconf -fi; fi
# configure again when the PETSc choice differs from the last configure's
if [ -f config.status ] && [ -n "$petsc" ] && ! grep -q -e "--with-petsc" config.status; then
  rm -f Makefile
fi
if [ ! -f Makefile ]; then ./configure $petsc; fi
make -j"$(nproc 2>/dev/null || echo 2)"
if [ "$run" -eq 1 ]; then
  ./peristatic run data/cases/small-disk.yaml
fi
