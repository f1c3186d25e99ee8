#!/usr/bin/env bash
# Builds the tests that exercise memory and parsing under AddressSanitizer +
# UndefinedBehaviorSanitizer (preset asan: gcc, -O1 -g1, every finding fatal) and runs them:
# the modules core, geometry (mesh readers, robustness catalogue, voxelization, winding numbers,
# marching cubes) and io (atomic files, checkpoints, VTK writers and their spec-based reader).
# The numerical suite (grid, tet, scene solves, CLI) runs in the release build only: under the
# sanitizers its build alone would take CI's whole 30-minute budget. The scene loader is fuzzed
# under the same sanitizers by scripts/fuzz.sh (fuzz_scene).
#
#   scripts/sanitize.sh [extra ctest arguments]     e.g. scripts/sanitize.sh -R Reader
#   MGELASTIC_SANITIZE_MODULES="core geometry io grid" scripts/sanitize.sh   (more modules)
set -euo pipefail
cd "$(dirname "$0")/.."
read -r -a modules <<<"${MGELASTIC_SANITIZE_MODULES:-core geometry io}"
targets=()
for m in "${modules[@]}"; do targets+=("test_$m"); done
scripts/build.sh asan "${targets[@]}"
# halt_on_error: a UBSan report fails the test (the preset also compiles with
# -fno-sanitize-recover); detect_leaks: leaks fail it too.
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export ASAN_OPTIONS=detect_leaks=1
labels="^($(IFS='|'; echo "${modules[*]}"))\$"
ctest --preset asan -j "$(nproc)" -L "$labels" --timeout 1200 "$@"
