#!/usr/bin/env bash
# Per-frame cost of the Python module against `mgelastic run` (issue 21) on a 64^3 embedded
# sphere: dynamic, one V-cycle per step, float, no output files, one thread. Process CPU time of
# N1 and N2 frames for both paths; per frame = difference / (N2 - N1); then, in one Python
# process, step() wall time against the library's own solve_seconds.
# Usage: scripts/bench/python_overhead.sh [build dir] [repetitions]
set -euo pipefail
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
build="$(realpath "${1:-build/release}")"
reps="${2:-3}"
python=/usr/bin/python3
[ -x "$python" ] || python=python3
export PYTHONPATH="$build/python"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
for n in 2 12; do
  "$python" - "$n" <<'PY'
import json, sys
n = int(sys.argv[1])
json.dump({"engine": "grid", "geometry": {"sphere": {"center": [0, 0, 0], "radius": 0.5}},
           "grid": {"resolution": 64},
           "material": {"youngs_modulus": 2e5, "poisson_ratio": 0.45, "density": 1000},
           "constraints": [{"region": {"box": {"center": [0, -0.5, 0], "size": [0.4, 0.1, 0.4]}}}],
           "loads": {"gravity": [0, -9.81, 0]},
           "time": {"dt": 1 / 30, "frames": n, "quasistatic": False, "vcycles_per_step": 1},
           "solver": {"precision": "float"},
           "output": {"dir": "out", "formats": [], "checkpoint_every": 0}},
          open(f"sphere{n}.json", "w"))
PY
done
cpu() { { /usr/bin/time -f "%U %S" "$@" >/dev/null; } 2>&1 | tail -1 | awk '{print $1 + $2}'; }
echo "| rep | CLI CPU s 2 / 12 frames | Python CPU s 2 / 12 frames | CLI s/frame | Python s/frame |"
echo "|---|---|---|---|---|"
for rep in $(seq "$reps"); do
  c2=$(cpu "$build/app/mgelastic" run sphere2.json --threads 1 --output out_cli)
  c12=$(cpu "$build/app/mgelastic" run sphere12.json --threads 1 --output out_cli)
  run_py="import mgelastic, sys; mgelastic.Simulation(mgelastic.Scene.load(sys.argv[1]), threads=1).run()"
  p2=$(cpu "$python" -c "$run_py" sphere2.json)
  p12=$(cpu "$python" -c "$run_py" sphere12.json)
  awk -v r="$rep" -v c2="$c2" -v c12="$c12" -v p2="$p2" -v p12="$p12" 'BEGIN {
    printf "| %d | %.2f / %.2f | %.2f / %.2f | %.3f | %.3f |\n", r, c2, c12, p2, p12,
      (c12 - c2) / 10, (p12 - p2) / 10 }'
done
"$python" - <<'PY'
import time
import mgelastic
sim = mgelastic.Simulation(mgelastic.Scene.load("sphere12.json"), threads=1)
sim.step()
wall = time.perf_counter()
solve = sum(sim.step().solve_seconds for _ in range(10))
wall = (time.perf_counter() - wall) / 10
print(f"python step(): {wall * 1e3:.1f} ms/frame wall, library solve_seconds "
      f"{solve / 10 * 1e3:.1f} ms/frame ({(wall - solve / 10) / wall * 100:.1f} % outside the solve)")
PY
"$build/app/mgelastic" run sphere12.json --threads 1 --output out_cli | grep '^time:'
