#!/bin/bash
# A short pebbles_in_a_box run with HDF5 + XDMF output, verified with
# examples/tumbling/check_output.py (XML structure, datasets, rigid skins).
#   run_check.sh NP EXE OUTDIR [MPIEXEC [MPIEXEC FLAGS...]]
set -euo pipefail
np=$1 exe=$2 out=$3
shift 3
[ $# -gt 0 ] || set -- mpiexec --oversubscribe
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
rm -f "$out/pebbles.h5" "$out/pebbles.xmf"
# 6 pebbles + 5 box parts; 250 steps of 4e-4 written every 50: 6 outputs. The run
# is too short to come to rest: the rest check is switched off (-fdem_expect_ke 1e30).
"$@" -n "$np" "$exe" -fdem_bodies 6 -ts_max_time 0.1 -fdem_box_x 0.7 -fdem_box_y 0.45 -fdem_output_every 50 -fdem_expect_ke 1e30 -fdem_output "$out"
/usr/bin/python3 "$here/../tumbling/check_output.py" "$out/pebbles" 6 11
echo "open $out/pebbles.xmf in ParaView"
