#!/bin/sh
# The dense-bed race at the level of the driver: the fdem scene of
# make_bed.py (spheres in the rigid model's DMSwarm, the TS, the contact
# engine) against LAMMPS's in.bed (the same packing, law, dt and skin), on 1
# and 2 ranks, in interleaved rounds. Prints particle-steps per second per core
# of each (wall clock of the time stepping: fdem's "stepping" time, LAMMPS's
# "Loop time"), fdem/LAMMPS, and the coordination number of each at the end
# (2 x touching pairs / spheres): both start from LAMMPS's initial state
# (written by in.bed with -var dumpv), so they should agree to the chaos of
# a dense packing.
# Usage: race.sh FDEM_BUILD_DIR [cells=10] [steps=1000] [rounds=3]
set -e
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?build directory}; cells=${2:-10}; steps=${3:-1000}; rounds=${4:-3}
command -v lmp >/dev/null || { echo "lmp not found (apt-get install lammps; liggghts too for its column)"; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
tmp=$(mktemp -d)
lmp -in "$here/in.bed" -var cells "$cells" -var steps 0 -var dumpv 1 -var dumpfile "$tmp/start.dump" -log none > /dev/null 2>&1
python3 "$here/make_bed.py" "$cells" "$steps" --from "$tmp/start.dump" > "$tmp/bed.yaml" # the same start as LAMMPS
lig=$(command -v liggghts || true)
[ -n "$lig" ] && python3 "$here/make_bed.py" "$cells" "$steps" --from "$tmp/start.dump" --liggghts "$tmp"
n=$((4 * cells * cells * cells))
OBS_NAME=coordination
fdem_run() {
  f=$(mpiexec -n $1 "$build/apps/fdem/fdem" "$tmp/bed.yaml" -fdem_output none -fdem_progress 0 2>&1)
  echo "$f" | sed -n 's/.*stepping \([0-9.e+-]*\) s:.*/\1/p'
  echo "$f" | sed -n 's/.*last evaluation \([0-9]*\) touching.*/\1/p' | awk -v n=$n '{printf "%.3f\n", 2 * $1 / n}'
}
lmp_run() { mpiexec -n $1 lmp -in "$here/in.bed" -var cells "$cells" -var steps "$steps" -log none; }
lig_run() { mpiexec -n $1 "$lig" -in "$here/in.bed.liggghts" -var dir "$tmp" -var steps "$steps" -log none; }
. "$here/rounds.sh"
run_rounds
rm -rf "$tmp"
