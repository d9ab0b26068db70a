#!/usr/bin/env bash
# Installs, builds and runs fdem's main example: the book's section 5.3 study
# of the 13 explicit schemes (Table 5.2, Figs 5.18-5.21 as CSV and PNG in doc/study).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
bash "$here/examples/scheme_study/run_study.sh" "${FDEM_BUILD_DIR:-$here/build}" "$here/doc/study"
