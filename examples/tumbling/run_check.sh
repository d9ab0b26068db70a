#!/bin/bash
# Runs the tumbling example with HDF5 + XDMF output and verifies the files with
# check_output.py (h5py + XML parsing).
#   run_check.sh NP EXE OUTDIR [MPIEXEC [MPIEXEC FLAGS...]]
# Example: examples/tumbling/run_check.sh 2 build/examples/tumbling/tumbling /tmp/tumbling mpiexec --oversubscribe
set -euo pipefail
np=$1 exe=$2 out=$3
shift 3
[ $# -gt 0 ] || set -- mpiexec --oversubscribe
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
rm -f "$out/tumbling.h5" "$out/tumbling.xmf"
nbodies=${NBODIES:-30}
# NBODIES mesh bodies + 3 without a mesh (octahedra); 100 steps of 0.005, written every 10 steps: 11 outputs
"$@" -n "$np" "$exe" -fdem_bodies "$nbodies" -fdem_plain_bodies 3 -ts_max_time 0.5 -ts_dt 0.005 -fdem_output_every 10 -fdem_output "$out" -fdem_rigid_rotation exact
/usr/bin/python3 "$here/check_output.py" "$out/tumbling" 11 $((nbodies + 3))
echo "open $out/tumbling.xmf in ParaView"
