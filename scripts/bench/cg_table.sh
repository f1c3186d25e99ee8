#!/usr/bin/env bash
# Baselines side by side in one run, all to a relative residual of 1e-6 on the 3D mixed box:
# unpreconditioned CG (the paper's Fig. 11), hypre BoomerAMG-PCG on the same non-augmented
# matrix, and mgelastic's V(1,1) multigrid.
# Usage: scripts/bench/cg_table.sh [path/to/mgelastic] [sizes...]
set -euo pipefail
# Threads sleep at barriers instead of spinning: on a machine shared with other work spinning
# threads that get descheduled cost 10-100x.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
bin="${1:-build/release/app/mgelastic}"
shift || true
sizes=("${@:-32 64}")
# Seconds are wall / process CPU seconds (CPU: all threads; less sensitive to others' load).
printf '| N | nu | unknowns | CG it | CG s wall/CPU | hypre it | hypre s (setup+solve) wall/CPU | V-cycles | mgelastic s wall/CPU |\n'
printf '|---|---|---|---|---|---|---|---|---|\n'
for n in ${sizes[@]}; do
  for nu in 0.3 0.49; do
    # Unpreconditioned CG needs ~20 min at 128^3 (nu = 0.49): left out from 128 up.
    skip=(); if [ "$n" -ge 128 ]; then skip=(--skip-cg); fi
    "$bin" bench cg --dim 3 --n "$n" --poisson "$nu" "${skip[@]}" --json | python3 -c '
import json, sys
d = json.load(sys.stdin)
cg = ("-", "skipped") if d.get("cg_skipped") else ("%d" % d["iterations"], "%.2f / %.2f" % (d["seconds"], d["cpu_seconds"]))
hy = ("%d" % d["hypre_iterations"], "%.2f / %.2f" % (d["hypre_setup_seconds"] + d["hypre_solve_seconds"], d["hypre_cpu_seconds"])) if d["hypre_available"] else ("n/a", "n/a")
print("| %d | %.2f | %d | %s | %s | %s | %s | %d | %.2f / %.2f |" % (d["n"], d["poisson"], d["unknowns"], cg[0], cg[1], hy[0], hy[1], d["multigrid_cycles"], d["multigrid_seconds"], d["multigrid_cpu_seconds"]))'
  done
done
