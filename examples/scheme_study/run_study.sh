#!/bin/sh
# Runs the full scheme study (Munjiza section 5.3; doc/schemes.md) and plots it.
#   examples/scheme_study/run_study.sh [BUILD_DIR] [OUTDIR] [extra scheme_study options]
# BUILD_DIR defaults to build (the program is BUILD_DIR/examples/scheme_study/scheme_study),
# OUTDIR to doc/study. Takes about half a minute of CPU (-timing_runs N: the cost
# figure is the best of N untimed repeats, default 3; 0 skips them). The printed tables are
# kept in OUTDIR/summary.txt (the library's messages about the deliberately
# unstable runs are dropped).
set -e
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
out=${2:-$root/doc/study}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] && shift
exe=$build/examples/scheme_study/scheme_study
if [ ! -x "$exe" ]; then
  echo "no $exe: cmake -S $root -B $build && cmake --build $build --target scheme_study" >&2
  exit 1
fi
mkdir -p "$out"
log=$(mktemp)
"$exe" -fdem_output "$out" "$@" > "$log" 2>&1 || { tail -20 "$log" >&2; echo "(full log: $log)" >&2; exit 1; }
grep -v -e 'diverges' -e 'Inf or NaN' "$log" | tee "$out/summary.txt"
rm -f "$log"
# a python with matplotlib (the distribution's, if the default python lacks it)
py=
for p in python3 /usr/bin/python3; do
  if command -v "$p" > /dev/null 2>&1 && "$p" -c 'import matplotlib' > /dev/null 2>&1; then py=$p; break; fi
done
if [ -z "$py" ]; then echo "no python3 with matplotlib: CSVs written to $out, no plots" >&2; exit 1; fi
"$py" "$here/plot_study.py" "$out"
