#!/bin/sh
# Work-precision benchmark: build if needed, run with a chosen N, plot.
#   bench/work_precision/run.sh [N] [extra options for bench_work_precision]
# N defaults to 1000000 particles (state 2e6 entries; ~4-5 minutes on 2 cores).
# Environment: BUILD_DIR (default /tmp/build-bench), OUT_DIR (default doc/bench), PYTHON.
set -e
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD_DIR=${BUILD_DIR:-/tmp/build-bench}
OUT_DIR=${OUT_DIR:-$ROOT/doc/bench}
N=${1:-1000000}
[ $# -gt 0 ] && shift

if [ ! -x "$BUILD_DIR/bench/work_precision/bench_work_precision" ] || [ "$ROOT/bench/work_precision/bench_work_precision.cpp" -nt "$BUILD_DIR/bench/work_precision/bench_work_precision" ] ||
   [ "$ROOT/bench/work_precision/problem.hpp" -nt "$BUILD_DIR/bench/work_precision/bench_work_precision" ]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" >/dev/null
  cmake --build "$BUILD_DIR" -j2 --target bench_work_precision
fi

mkdir -p "$OUT_DIR"
"$BUILD_DIR/bench/work_precision/bench_work_precision" -N "$N" \
  -csv "$OUT_DIR/work_precision.csv" -summary "$OUT_DIR/work_precision_summary.txt" "$@"
# the interpreter that has matplotlib (Debian's python3-matplotlib lives under /usr/bin/python3)
PYTHON=${PYTHON:-python3}
"$PYTHON" -c "import matplotlib" 2>/dev/null || PYTHON=/usr/bin/python3
"$PYTHON" "$ROOT/bench/work_precision/plot_work_precision.py" "$OUT_DIR/work_precision.csv" "$OUT_DIR/work_precision"
