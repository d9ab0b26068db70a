#!/usr/bin/env bash
# Installs (Debian packages), builds and runs fdem's default scene: irregular
# rigid pebbles dropped onto a deformable slab inside a fixed box, with
# friction, on 2 MPI ranks (under 2 minutes on 2 cores). Output in ./out:
# balance.csv, balance.png and scene.xmf (open it in ParaView).
# The book's section 5.3 scheme study is examples/scheme_study/run_study.sh.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fdem="${FDEM_BUILD_DIR:-$here/build}/apps/fdem/fdem"
mpirun -n 2 "$fdem" "$@"
"$fdem" plot out || echo "(no chart: python3 with matplotlib is needed for fdem plot)"
