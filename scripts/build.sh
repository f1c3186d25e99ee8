#!/usr/bin/env bash
# Configures and builds one CMake preset (default: release), optionally only some targets.
#
#   scripts/build.sh [preset] [target ...]      e.g. scripts/build.sh release mgelastic_cli
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
shift || true
targets=()
for t in "$@"; do targets+=(--target "$t"); done
scripts/install-deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$(nproc)" "${targets[@]}"
