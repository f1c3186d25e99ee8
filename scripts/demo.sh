#!/usr/bin/env bash
# The README's demo command: builds mgelastic and runs the default demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release >/dev/null
exec build/release/app/mgelastic demo "$@"
