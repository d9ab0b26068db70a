#!/bin/sh
# Runs bench_deformable on 1 and 2 ranks (~10^6 tetrahedra by default) and
# prints the speed-up of the internal forces and of a whole step, from the
# wall clock and from the CPU time of the busiest rank (the figure to quote on
# a loaded machine: run it with OMPI_MCA_mpi_yield_when_idle=1 so that a rank
# waiting for the other does not count spinning as work), and each run's
# fraction of the STREAM bound. See doc/performance.md, "The deformable step".
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
awk '/^RESULT/ { for (i = 2; i <= NF; ++i) { split($i, kv, "="); v[kv[1]] = kv[2] }
                 r = v["ranks"]; F[r] = v["force_s"]; S[r] = v["step_s"]; FC[r] = v["force_cpu_s"]; SC[r] = v["step_cpu_s"]; Q[r] = v["fraction"]; QC[r] = v["fraction_cpu"] }
     END { printf "speed-up 1 -> 2 ranks: internal forces %.2fx (CPU %.2fx), whole step %.2fx (CPU %.2fx)\n", F[1]/F[2], FC[1]/FC[2], S[1]/S[2], SC[1]/SC[2];
           printf "fraction of the STREAM bound: 1 rank %.1f%% (CPU %.1f%%), 2 ranks %.1f%% (CPU %.1f%%)\n", 100*Q[1], 100*QC[1], 100*Q[2], 100*QC[2] }' "$OUT"
rm -f "$OUT"
