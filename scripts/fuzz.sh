#!/usr/bin/env bash
# Mutation fuzzing of fdem's input readers for MINUTES minutes (default 10):
# builds the fuzz driver (tests/fuzz/fdem_fuzz) with AddressSanitizer +
# UndefinedBehaviorSanitizer in ./build-asan (as scripts/sanitize.sh does) and
# runs tests/fuzz/fuzz.py on the seed files of tests/fuzz/corpus and
# tests/bad_input, 1 and 2 ranks in turn. Prints the count of each outcome
# (accepted, rejected with file:line, rejected without, crash, sanitizer
# report, leak, hang) and keeps the inputs worth a look in build-asan/fuzz/.
# Exit 1 if any input crashed, hung, leaked, made a sanitizer report or was
# rejected without file:line. Extra arguments go to fuzz.py (e.g. --seed 7).
# FDEM_FUZZ_BUILD_DIR=<dir of a configured build> skips the sanitizer build.
#
# scripts/fuzz.sh MINUTES --scenes [fuzz.py options]: the scene files instead
# (fuzz.py --scenes): builds the fdem driver (target fdem_driver) in
# FDEM_FUZZ_BUILD_DIR (default ./build, configured in Release if it is not)
# and runs it on mutations of examples/scenes, tests/driver and
# tests/driver/bad; inputs worth a look are kept in BUILD/fuzz-scenes/.
# E.g. scripts/fuzz.sh 25 --scenes --seed 2026 --taskset 0 (every run on CPU 0).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
minutes="${1:-10}"
shift || true
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
if [ "${1:-}" = "--scenes" ]; then
  shift
  build="${FDEM_FUZZ_BUILD_DIR:-$here/build}"
  [ -f "$build/CMakeCache.txt" ] || cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" -j "$(nproc)" --target fdem_driver
  exec python3 "$here/tests/fuzz/fuzz.py" --scenes --driver "$build/apps/fdem/fdem" --minutes "$minutes" \
    --seeds "$here/examples/scenes" "$here/tests/driver" "$here/tests/driver/bad" --out "$build/fuzz-scenes" "$@"
fi
if [ -n "${FDEM_FUZZ_BUILD_DIR:-}" ]; then
  build="$FDEM_FUZZ_BUILD_DIR"
  cmake --build "$build" -j "$(nproc)" --target fdem_fuzz
else
  build="${FDEM_ASAN_BUILD_DIR:-$here/build-asan}"
  bash "$here/scripts/sanitize.sh" --build-only fdem_fuzz
fi
python3 "$here/tests/fuzz/fuzz.py" --driver "$build/tests/fuzz/fdem_fuzz" --minutes "$minutes" \
  --seeds "$here/tests/fuzz/corpus" "$here/tests/bad_input" --out "$build/fuzz" "$@"
