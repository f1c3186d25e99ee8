#!/usr/bin/env bash
# The README's demo command: builds the mgelastic CLI (nothing else) with the `demo` preset and
# runs the default demo. The preset (build/demo: -O1, generic CPU, unity build, no tests) compiles
# in about half the CPU time of `release`; the optimized CLI is `scripts/build.sh release
# mgelastic_cli` (build/release/app/mgelastic).
set -euo pipefail
cd "$(dirname "$0")/.."
# Idle OpenMP threads sleep instead of spinning (on a busy machine spinning doubles the CPU).
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
scripts/build.sh demo mgelastic_cli >/dev/null
exec build/demo/app/mgelastic demo "$@"
