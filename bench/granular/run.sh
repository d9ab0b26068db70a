#!/bin/sh
# Dense-bed race, serial: fdem's sphere pair loop (bench_granular, the kernel
# level: no DMSwarm/TS yet) against LAMMPS gran/hooke/history on the same
# packing, in interleaved rounds. Prints particle-steps/s of each and the ratio
# fdem/LAMMPS per round, and both codes' final coordination numbers and
# translational kinetic energy per sphere (the same physics).
# Usage: run.sh BUILD_DIR [cells=20] [steps=1000] [rounds=3]
set -e
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?build directory}; cells=${2:-20}; steps=${3:-1000}; rounds=${4:-3}
command -v lmp >/dev/null || { echo "lmp not found (apt-get install lammps)"; exit 1; }
r=1
while [ $r -le "$rounds" ]; do
  f=$("$build/bench/granular/bench_granular" "$cells" "$steps")
  l=$(lmp -in "$here/in.bed" -var cells "$cells" -var steps "$steps" -log none 2>&1 | \
      awk '/^ *Step/{getline; getline; n=$2; ke=$3; cm=$4} /^Loop time/{t=$4} END{printf "%.6g %d %.4f %.6g", ke, n, cm, t}')
  echo "$f" "$l" | awk -v steps="$steps" -v r="$r" '{
    fps=$9; lke=$(NF-3); n=$(NF-2); cm=$(NF-1); t=$NF; lps=n*steps/t;
    printf "round %d: fdem %.3g particle-steps/s (coordination %s, kinetic energy/sphere %s), LAMMPS %.3g particle-steps/s (%d spheres, coordination %.3f, kinetic energy/sphere %s), fdem/LAMMPS %.3f\n", r, fps, $11, $13, lps, n, cm, lke, fps/lps }'
  r=$((r + 1))
done
