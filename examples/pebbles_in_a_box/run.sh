#!/bin/bash
# Pebbles in a box, the long run: builds the example if needed, runs it under
# mpiexec -n 2 (NP) with HDF5 + XDMF output, verifies the files and draws the
# chart of heights and energies against time.
#   examples/pebbles_in_a_box/run.sh [OUT_DIR]     (default ./pebbles_output)
# Environment: BUILD_DIR (default /tmp/build-fdem), NP (2), ARGS (more options,
# e.g. ARGS="-fdem_bodies 100 -ts_max_time 4").
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT=$(mkdir -p "${1:-pebbles_output}" && cd "${1:-pebbles_output}" && pwd)
BUILD_DIR=${BUILD_DIR:-/tmp/build-fdem}
NP=${NP:-2}
EXE=$BUILD_DIR/examples/pebbles_in_a_box/pebbles_in_a_box
if [ ! -x "$EXE" ] || [ "$ROOT/examples/pebbles_in_a_box/pebbles_in_a_box.cpp" -nt "$EXE" ]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" >/dev/null
  cmake --build "$BUILD_DIR" -j2 --target pebbles_in_a_box
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rm -f "$OUT/pebbles.h5" "$OUT/pebbles.xmf" "$OUT/energy.csv" "$OUT/final_state.csv"
# 60 pebbles in a 1.5 x 0.7 box, 3 s (7500 steps of 4e-4), written every 100 steps
# shellcheck disable=SC2086
mpiexec --oversubscribe -n "$NP" "$EXE" -fdem_bodies 60 -ts_max_time 3 -fdem_output_every 100 -fdem_output "$OUT" \
  ${ARGS:-} | tee "$OUT/pebbles.log"
/usr/bin/python3 "$ROOT/examples/pebbles_in_a_box/plot_pebbles.py" "$OUT/energy.csv" "$OUT/pebbles_in_a_box.png" \
  "pebbles in a box: 60 pebbles, mpiexec -n $NP"
nsteps=$(grep -c "<Grid Name=\"step" "$OUT/pebbles.xmf" || true)
nbodies=$(grep -m1 -o "^[0-9]* pebbles" "$OUT/pebbles.log" | cut -d' ' -f1)
/usr/bin/python3 "$ROOT/examples/tumbling/check_output.py" "$OUT/pebbles" "$nsteps" "$((nbodies + 5))" || true
echo
echo "ParaView: open $OUT/pebbles.xmf (XDMF reader), colour by body_id, press play."
echo "Chart: $OUT/pebbles_in_a_box.png"
