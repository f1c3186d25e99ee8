#!/usr/bin/env bash
# Same-run comparison of two mgelastic binaries on the V(1,1) profile of the mixed box: the runs
# alternate (old, new, old, new, ...) so both see the same machine load, and each phase's
# minimum over the repetitions is printed (the least disturbed run).
# Usage: scripts/bench/vcycle_ab.sh OLD_BINARY NEW_BINARY [size] [threads] [repetitions] [cycles]
#          [more bench vcycle options]
#   e.g. an embedded shape: scripts/bench/vcycle_ab.sh OLD NEW 0 2 3 6 --mesh armadillo.obj \
#          --resolution 128
set -euo pipefail
old="$1" new="$2" size="${3:-64}" threads="${4:-1}" reps="${5:-3}" cycles="${6:-6}"
shift $(($# < 6 ? $# : 6))
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
for i in $(seq "$reps"); do
  for which in old new; do
    bin="$old"
    [ "$which" = new ] && bin="$new"
    "$bin" bench vcycle --sizes "$size" --threads "$threads" --cycles "$cycles" --json "$@" \
      >"$dir/${which}_$i.json"
  done
done
python3 - "$dir" "$reps" <<'PY'
import json, sys
folder, reps = sys.argv[1], int(sys.argv[2])
phases = ["boundary_smoothing", "interior_smoothing", "residual", "restriction",
          "prolongation", "coarse_solve", "refinement", "cycle_residual", "solve_setup",
          "other"]  # "other": binaries before the roofline split it
table = {}
for which in ["old", "new"]:
    runs = [json.load(open(f"{folder}/{which}_{i}.json"))["runs"][0] for i in range(1, reps + 1)]
    cycles = len(runs[0]["residuals"]) - 1
    row = {p: min(r["phase_seconds"].get(p, 0.0) for r in runs) / cycles for p in phases}
    row["total per V-cycle"] = min(r["vcycle_seconds"] for r in runs)
    row["rate"] = runs[0]["rate"]
    row["working set (MB)"] = runs[0]["working_set_bytes"] / 1e6
    table[which] = row
print("%-20s | %9s | %9s" % ("subroutine", "old", "new"))
for key in table["old"]:
    print("%-20s | %9.4f | %9.4f" % (key, table["old"][key], table["new"][key]))
PY
