#!/usr/bin/env bash
# Sanitizer stage (CI runs it after scripts/test.sh): builds fdem with
# AddressSanitizer + UndefinedBehaviorSanitizer (-DFDEM_SANITIZE=ON) in its
# own build directory (./build-asan, or $FDEM_ASAN_BUILD_DIR) and runs the
# test suite under it, except the long runs (label "example": the example
# programs, and the tests listed in $exclude below; doc/hardening.md).
# Any sanitizer report fails the stage: a report aborts the process (and so
# the test), and the full test log is searched for reports as well.
#   scripts/sanitize.sh                      build + the sanitizer subset
#   scripts/sanitize.sh --build-only [target...]   build only (scripts/fuzz.sh)
#   scripts/sanitize.sh -R bad_input         extra arguments go to ctest
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${FDEM_ASAN_BUILD_DIR:-$here/build-asan}"
bash "$here/scripts/install-deps.sh"
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFDEM_SANITIZE=ON \
  -DFDEM_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
if [ "${1:-}" = --build-only ]; then
  shift
  targets=()
  for t in "$@"; do targets+=(--target "$t"); done
  cmake --build "$build" -j "$(nproc)" "${targets[@]}"
  exit 0
fi
start=$(date +%s)
cmake --build "$build" -j "$(nproc)"
echo "sanitize: build took $(( $(date +%s) - start )) s"

# halt_on_error: the first report ends the process with an error.
# LeakSanitizer stays off in MPI programs: Open MPI keeps allocations to its
# exit that LSan reports (through libraries without frame pointers, so no
# suppression file can name them); PETSc's -malloc_dump covers fdem's PETSc
# objects in the error-path tests (tests/bad_input). The kernel unit tests
# (no MPI) run with LeakSanitizer on.
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=0:detect_leaks=0:strict_string_checks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Long under a sanitizer (each > 10 min on 2 cores); their code paths run in
# the smaller tests of the same label.
# The fracture validation runs (tension bar, Brazilian disc, compression, fragmentation:
# 40-175 s each in the normal build, 6-7x that under the sanitizers) likewise: the joints,
# broken-joint contact, fragments and checkpoints run in test_fracture_bar,
# test_fracture_contact, the fracture driver scenes and driver_fracture_fragments.
exclude='^(test_contact_rigid|test_contact_stack|test_deformable_wave|test_deformable_cantilever|driver_restart|driver_scene_pebbles_in_a_box|driver_scene_disc_platens|driver_scene_platen|driver_default_scene|test_fracture_tension|driver_fracture_uniaxial|driver_fracture_brazilian)_|^driver_scene_fragmentation$'
cd "$build"
status=0
start=$(date +%s)
ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=1" ctest -L kernels -j "$(nproc)" --output-on-failure "$@" || status=1
grep -E "ERROR: (Address|Leak)Sanitizer|runtime error:" Testing/Temporary/LastTest.log && status=1
ctest -LE 'kernels|example' -E "$exclude" -j "$(nproc)" --timeout 900 --output-on-failure "$@" || status=1
grep -E "ERROR: (Address|Leak)Sanitizer|runtime error:" Testing/Temporary/LastTest.log && status=1
echo "sanitize: tests took $(( $(date +%s) - start )) s"
exit $status
