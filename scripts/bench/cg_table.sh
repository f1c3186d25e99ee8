#!/usr/bin/env bash
# CG on the non-augmented system (the paper's Fig. 11 baseline) next to multigrid, both to a
# relative residual of 1e-6 in the same run, on the 3D mixed box.
# Usage: scripts/bench/cg_table.sh [path/to/mgelastic]
set -euo pipefail
bin="${1:-build/release/app/mgelastic}"
printf '| N | nu | unknowns | CG iterations | CG s | V-cycles | multigrid s |\n|---|---|---|---|---|---|---|\n'
for n in 32 64; do
  for nu in 0.3 0.49; do
    "$bin" bench cg --dim 3 --n "$n" --poisson "$nu" --json | python3 -c '
import json, sys
d = json.load(sys.stdin)
print("| %d | %.2f | %d | %d | %.2f | %d | %.2f |" % (d["n"], d["poisson"], d["unknowns"], d["iterations"], d["seconds"], d["multigrid_cycles"], d["multigrid_seconds"]))'
  done
done
