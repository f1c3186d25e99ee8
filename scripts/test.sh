#!/usr/bin/env bash
# The README's test command: installs dependencies, builds, runs the whole test suite.
# MGELASTIC_DATA_DIR (e.g. ../shared/meshes) enables the tests on real meshes.
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
scripts/build.sh "$preset"
ctest --preset "$preset" -j "$(nproc)"
