#!/bin/bash
# The book's Fig 5.7-5.9: runs the spinning top with h = 0.0005, 0.001, 0.005
# (cd + the book's munjiza rotation, and nosquish/exact for comparison), writes
# the CSVs and plots omega_x, omega_y against -sin 100t, cos 100t.
#   examples/spinning_top/run.sh [BUILD_DIR] [OUT_DIR]   (defaults: build, doc/rigid)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
out=${2:-$root/doc/rigid}
exe=$build/examples/spinning_top/spinning_top
[ -x "$exe" ] || cmake --build "$build" --target spinning_top
mkdir -p "$out"
for rot in munjiza nosquish exact; do
  for h in 0.0005 0.001 0.005; do
    "$exe" -ts_dt $h -fdem_rigid_rotation $rot -fdem_output "$out"
  done
done
/usr/bin/python3 "$here/plot.py" "$out"
