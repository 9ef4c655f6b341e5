#!/bin/sh
# setup.sh: the first command on a fresh Debian machine. Installs what is
# missing (scripts/install-deps.sh, apt-get), builds peristatic and runs
# the default case. With --no-run it only installs and builds.
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
if [ ! -x configure ]; then autoreconf -fi; fi
if [ ! -f Makefile ]; then ./configure; fi
make -j"$(nproc 2>/dev/null || echo 2)"
if [ "${1:-}" != "--no-run" ]; then
  ./peristatic run data/cases/small-disk.yaml
fi
