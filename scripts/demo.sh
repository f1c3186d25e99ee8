#!/usr/bin/env bash
# The README's demo command: builds the mgelastic CLI (nothing else) and runs the default demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release mgelastic_cli >/dev/null
exec build/release/app/mgelastic demo "$@"
