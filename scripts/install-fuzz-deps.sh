#!/usr/bin/env bash
# Installs what the fuzz preset needs on top of scripts/install-deps.sh: clang, libFuzzer and the
# sanitizer runtimes (libclang-rt-14-dev), and LLVM's OpenMP runtime for clang (libomp-dev).
# Kept apart so the normal build does not pay for a second compiler. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/install-deps.sh clang libclang-rt-14-dev libomp-dev
