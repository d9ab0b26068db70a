#!/bin/sh
# Runs bench_deformable on 1 and 2 ranks (~10^6 tetrahedra by default) and
# prints the speed-up of the internal forces and of a whole step.
# Usage: bench/deformable/run.sh [build dir] [extra options, e.g. -n 55 -steps 20]
set -e
BUILD=${1:-build}
[ $# -gt 0 ] && shift
EXE="$BUILD/bench/deformable/bench_deformable"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
OUT=$(mktemp)
for np in 1 2; do
  echo "== mpiexec -n $np"
  mpiexec --oversubscribe -n $np "$EXE" "$@" | tee -a "$OUT"
done
awk '/^RESULT/ { split($2,a,"="); split($4,f,"="); split($5,s,"="); F[a[2]]=f[2]; S[a[2]]=s[2] }
     END { printf "speed-up 1 -> 2 ranks: internal forces %.2fx, whole step %.2fx\n", F[1]/F[2], S[1]/S[2] }' "$OUT"
rm -f "$OUT"
