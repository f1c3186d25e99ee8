#!/usr/bin/env bash
# The README's test command: installs dependencies, builds, runs the whole test suite.
# MGELASTIC_DATA_DIR (e.g. ../shared/meshes) enables the tests on real meshes.
set -euo pipefail
# The tests run in the build tree: a relative data path is resolved here, against the caller's
# directory (a missing folder stays as given, so the tests report it).
if [ -n "${MGELASTIC_DATA_DIR:-}" ] && [ -d "$MGELASTIC_DATA_DIR" ]; then
  MGELASTIC_DATA_DIR="$(cd "$MGELASTIC_DATA_DIR" && pwd)"
  export MGELASTIC_DATA_DIR
fi
cd "$(dirname "$0")/.."
preset="${1:-release}"
scripts/build.sh "$preset"
ctest --preset "$preset" -j "$(nproc)"
