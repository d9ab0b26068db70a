#!/usr/bin/env bash
# Time per step of the driver against examples/bar_wave on the same bar, in
# instructions (valgrind callgrind; immune to the load of a shared machine):
# each program runs 100 and 300 steps; (I(300) - I(100)) / 200 is the cost of
# one step without set-up. usage: callgrind.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../../build}"
tmp="$(mktemp -d)"
for n in 100 300; do
  t=$(python3 -c "print($n * 7.5e-4)")
  valgrind --tool=callgrind --callgrind-out-file="$tmp/drv_$n" "$build/apps/fdem/fdem" "$here/bar.yaml" -fdem_output none -fdem_progress 0 -ts_max_time "$t" >/dev/null 2>&1
  valgrind --tool=callgrind --callgrind-out-file="$tmp/ex_$n" "$build/examples/bar_wave/bar_wave" -n 400 -ny 2 -ts_max_steps "$n" >/dev/null 2>&1
done
ir() { grep -m1 '^summary' "$1" | awk '{print $2}'; }
python3 - "$(ir $tmp/drv_100)" "$(ir $tmp/drv_300)" "$(ir $tmp/ex_100)" "$(ir $tmp/ex_300)" <<'PY'
import sys
d1, d3, e1, e3 = map(int, sys.argv[1:])
d, e = (d3 - d1) / 200, (e3 - e1) / 200
print(f"instructions per step: driver {d:.0f}, example {e:.0f}, ratio {d / e:.4f} (target <= 1.02)")
print(f"whole 300-step runs (set-up included): ratio {d3 / e3:.4f}")
PY
rm -rf "$tmp"
