#!/usr/bin/env bash
# Installs the Debian packages fdem needs (if missing), then configures and
# builds fdem in ./build (or $FDEM_BUILD_DIR). Safe to run again.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${FDEM_BUILD_DIR:-$here/build}"
bash "$here/scripts/install-deps.sh"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"
