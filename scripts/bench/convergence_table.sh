#!/usr/bin/env bash
# Prints the grid engine's convergence table (issue 2): rate per cycle (geometric mean of the last
# five of 12), relative residual after 12 cycles, seconds per cycle and levels, for the mixed box.
# Usage: scripts/bench/convergence_table.sh [path/to/mgelastic] [V|W]
set -euo pipefail
bin="${1:-build/release/app/mgelastic}"
cycle="${2:-V}"
printf '| nu | 3D 32^3 | 3D 64^3 | 2D 32^2 | 2D 64^2 |\n|---|---|---|---|---|\n'
for nu in 0.2 0.3 0.45 0.49 0.495; do
  row="| $nu"
  for cfg in "--dim 3 --n 32" "--dim 3 --n 64" "--dim 2 --n 32" "--dim 2 --n 64"; do
    # shellcheck disable=SC2086
    cell=$("$bin" bench convergence $cfg --poisson "$nu" --cycle "$cycle" --json | python3 -c '
import json, sys
d = json.load(sys.stdin)
print("%.3f (%.0e, %.3f s, %d lv)" % (d["rate"], d["relative_residual"], d["vcycle_seconds"], d["levels"]))')
    row="$row | $cell"
  done
  echo "$row |"
done
