#!/usr/bin/env bash
# Reruns the fracture validation scenes (doc/fracture_validation.md) with the driver of build/ and
# rewrites their charts in doc/fracture_validation/: the Brazilian disc and the uniaxial compression,
# each on one rank (about 30-40 s each), keeping their output in out_brazilian_disc/ and
# out_uniaxial_prism/ (mesh.xmf: the per-cell damage, for ParaView).
# usage: bash scripts/fracture-validation.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
python3 tests/driver/brazilian.py mpiexec 1 "$build/apps/fdem/fdem" tests/driver/brazilian_disc.yaml --out out_brazilian_disc --plot doc/fracture_validation
python3 tests/driver/uniaxial.py mpiexec 1 "$build/apps/fdem/fdem" tests/driver/uniaxial_prism.yaml --out out_uniaxial_prism --plot doc/fracture_validation
