#!/bin/sh
# Rigid-body benchmarks (doc/rigid.md): cost per body-step and orientation
# error against cost; CSVs and the chart into doc/rigid.
#   bench/rigid/run.sh [BUILD_DIR]   (default /tmp/build-bench; OUT_DIR default doc/rigid)
set -e
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD_DIR=${1:-${BUILD_DIR:-/tmp/build-bench}}
OUT_DIR=${OUT_DIR:-$ROOT/doc/rigid}
EXE=$BUILD_DIR/bench/rigid/bench_rigid
if [ ! -x "$EXE" ] || [ "$ROOT/bench/rigid/bench_rigid.cpp" -nt "$EXE" ]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" >/dev/null
  cmake --build "$BUILD_DIR" -j2 --target bench_rigid
fi
mkdir -p "$OUT_DIR"
"$EXE" -mode cost -n 10000 -steps 10 -repeat 2 -csv "$OUT_DIR/cost_per_body_step.csv" | tee "$OUT_DIR/cost_per_body_step.txt"
"$EXE" -mode error -n 100 -nh 6 -csv "$OUT_DIR/orientation_error_vs_cost.csv" | tee "$OUT_DIR/orientation_error_vs_cost.txt"
/usr/bin/python3 "$ROOT/bench/rigid/plot_rigid.py" "$OUT_DIR/orientation_error_vs_cost.csv" "$OUT_DIR/orientation_error_vs_cost.png"
