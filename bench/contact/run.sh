#!/bin/bash
# Contact pipeline benchmarks (doc/contact_model.md):
#  (a) bench_contact: time per body and per candidate tetrahedron pair of the
#      search, the force evaluation and the halo, N = 1e2..1e4 pebbles, dense
#      and sparse packing, 1 rank (CSV + table);
#  (b) the same on 2 ranks with -log_view: the FDEMContact* event lines;
#  (c) bench_contact_kernels: the narrow-phase kernel alone (pairs/s).
#   bench/contact/run.sh [BUILD_DIR]   (default /tmp/build-bench; OUT_DIR default doc/contact)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD_DIR=${1:-${BUILD_DIR:-/tmp/build-bench}}
OUT_DIR=${OUT_DIR:-$ROOT/doc/contact}
NLIST=${NLIST:-100,316,1000,3162,10000}
cmake -S "$ROOT" -B "$BUILD_DIR" >/dev/null
cmake --build "$BUILD_DIR" -j2 --target bench_contact bench_contact_kernels >/dev/null
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$OUT_DIR"
B=$BUILD_DIR/bench/contact/bench_contact
echo "== (a) contact pipeline, 1 rank"
"$B" -n_list "$NLIST" -steps 20 -fdem_rigid_rotation munjiza -csv "$OUT_DIR/bench_contact_np1.csv" | tee "$OUT_DIR/bench_contact_np1.txt"
echo "== (b) 2 ranks, -log_view events (N = 1000 and 10000, dense and sparse)"
mpiexec --oversubscribe -n 2 "$B" -n_list 1000,10000 -steps 20 -fdem_rigid_rotation munjiza -csv "$OUT_DIR/bench_contact_np2.csv" -log_view > "$OUT_DIR/bench_contact_np2_log_view.txt"
grep -E "^ +N \||^ +[0-9]+ \||contact pipeline" "$OUT_DIR/bench_contact_np2_log_view.txt"
echo "Event                Count      Time (sec)     Flop                              --- Global ---  --- Stage ----  Total"
grep -E "^FDEMContact(Detect|Force|Halo)" "$OUT_DIR/bench_contact_np2_log_view.txt"
echo "== (c) narrow-phase kernel alone"
"$BUILD_DIR/bench/contact_kernels/bench_contact_kernels" 10000 | grep -A4 "Narrow phase" | tee "$OUT_DIR/bench_contact_kernels_narrow.txt"
