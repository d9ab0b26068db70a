#!/usr/bin/env bash
# Installs, builds and runs the whole fdem test suite (CTest: kernel unit
# tests, PETSc tests under mpiexec -n 1 and -n 2, examples that check
# themselves). Extra arguments go to ctest (e.g. -L ts, -R order).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${FDEM_BUILD_DIR:-$here/build}"
bash "$here/scripts/build.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
cd "$build"
ctest --output-on-failure -j "$(nproc)" --timeout 900 "$@"
