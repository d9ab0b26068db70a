#!/bin/sh
# The chute race: a granular chute flow (in.chute: periodic along x and y, a frozen rough base,
# gravity tilted by 26 degrees, gran/hooke/history; set up like LAMMPS's own bench/in.chute)
# settled by LAMMPS once, then run from that state by fdem (the scene of make_chute.py: spheres
# in the rigid model's DMSwarm with periodic boundaries, the TS, the contact engine) and by
# LAMMPS, on 1 and 2 ranks, in interleaved rounds. Prints particle-steps per second per core
# of each (wall clock of the time stepping: fdem's "stepping" time, LAMMPS's "Loop time"),
# fdem/LAMMPS, and the mean flow velocity <vx> of the moving spheres at the end of each run:
# both start from the same state, so they should agree to the chaos of the flow. LIGGGHTS
# (in.chute.liggghts) runs in the same rounds when it is installed; it starts from the same
# positions and velocities but without the spins (its set command has no omega).
# Usage: chute.sh FDEM_BUILD_DIR [lx=40] [ly=20] [layers=39] [steps=1000] [rounds=3] [settle=20000]
#        (40 x 20 x 39 + the base: 32 000 spheres, as LAMMPS's chute benchmark)
set -e
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?build directory}; lx=${2:-40}; ly=${3:-20}; layers=${4:-39}; steps=${5:-1000}; rounds=${6:-3}; settle=${7:-20000}
command -v lmp >/dev/null || { echo "lmp not found (apt-get install lammps)"; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
tmp=$(mktemp -d)
lmp -in "$here/in.chute" -var mode settle -var lx "$lx" -var ly "$ly" -var layers "$layers" -var settle "$settle" -var datafile "$tmp/start.data" -var dumpfile "$tmp/start.dump" -log none > /dev/null 2>&1
python3 "$here/make_chute.py" "$tmp/start.dump" "$steps" > "$tmp/chute.yaml"
lig=$(command -v liggghts || true)
[ -n "$lig" ] && python3 "$here/make_chute.py" "$tmp/start.dump" "$steps" --liggghts "$tmp"
n=$(( (layers + 1) * lx * ly ))
OBS_NAME="mean flow velocity <vx>"
fdem_run() {
  f=$(mpiexec -n $1 "$build/apps/fdem/fdem" "$tmp/chute.yaml" -fdem_output "$tmp/out" -fdem_progress 0 2>&1)
  echo "$f" | sed -n 's/.*stepping \([0-9.e+-]*\) s:.*/\1/p'
  awk -F, 'NR > 1 && $2 ~ /^s/ {s += $6; c++} END {printf "%.6f\n", s / c}' "$tmp/out/bodies.csv"
}
lmp_run() { mpiexec -n $1 lmp -in "$here/in.chute" -var mode race -var datafile "$tmp/start.data" -var steps "$steps" -log none; }
lig_run() { mpiexec -n $1 "$lig" -in "$here/in.chute.liggghts" -var dir "$tmp" -var steps "$steps" -log none; }
. "$here/rounds.sh"
run_rounds
rm -rf "$tmp"
