#!/usr/bin/env bash
# The driver against the C++ example it replaces: the same bar (9600
# tetrahedra), the same scheme, time step and number of steps (1027), on N
# ranks; whole runs (set-up included) timed in turn by farm-bench, the ratio
# driver / example taken pair by pair. usage: run.sh [BUILD_DIR] [N]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../../build}"
n="${2:-1}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
farm-bench -n 5 --timeout 900 --vs "mpiexec -n $n $build/examples/bar_wave/bar_wave -n 400 -ny 2" \
  -- mpiexec -n "$n" "$build/apps/fdem/fdem" "$here/bar.yaml" -fdem_output none -fdem_progress 0
