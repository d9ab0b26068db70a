#!/usr/bin/env bash
# Reruns the fracture validation scenes (doc/fracture_validation.md) with the driver of build/ and
# rewrites their charts in doc/fracture_validation/: the Brazilian disc and the uniaxial compression,
# each on one rank (about 30-40 s each), keeping their output in out_brazilian_disc/ and
# out_uniaxial_prism/ (mesh.xmf: the per-cell damage, for ParaView; fracture.csv: the joints in the
# order they broke).
# With --convergence, runs instead the Brazilian disc's mesh convergence study on 2 ranks (the test's
# mesh, a coarser one, 0.0125, and two finer ones, 0.0072 and 0.006; about a minute on an idle machine; brazilian.py stops
# a run after 1500 s), prints its table and rewrites
# doc/fracture_validation/brazilian_convergence.{csv,png}; each run's output is in
# out_brazilian_<resolution>/.
# usage: bash scripts/fracture-validation.sh [--convergence] [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
convergence=0
if [ "${1:-}" = --convergence ]; then
  convergence=1
  shift
fi
build=${1:-build}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
if [ $convergence = 1 ]; then
  python3 scripts/brazilian_convergence.py "$build/apps/fdem/fdem" 2 0.0125,0.01,0.0072,0.006 doc/fracture_validation
  exit
fi
python3 tests/driver/brazilian.py mpiexec 1 "$build/apps/fdem/fdem" tests/driver/brazilian_disc.yaml --out out_brazilian_disc --plot doc/fracture_validation
python3 tests/driver/uniaxial.py mpiexec 1 "$build/apps/fdem/fdem" tests/driver/uniaxial_prism.yaml --out out_uniaxial_prism --plot doc/fracture_validation
