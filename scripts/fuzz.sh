#!/usr/bin/env bash
# Builds the libFuzzer targets (preset fuzz: clang, ASan + UBSan) and runs each for a bounded
# time on a working copy of its seed corpus, as many targets at once as there are cores; fails
# on any crash, hang, leak or sanitizer report.
#
#   scripts/fuzz.sh [seconds-per-target] [target ...]      (default: 30 s, all targets)
#   MGELASTIC_FUZZ_RUNS=1000000 scripts/fuzz.sh 3600 obj   (stop at a number of executions)
#
# Targets: obj stl ply off gmsh tetgen medit scene (fuzz/fuzz_<target>.cpp, seeds in
# fuzz/corpus/<target>/). The working corpus grows in build/fuzz/corpus/<target>/ across runs;
# a crashing input is saved as build/fuzz/artifacts/<target>/crash-* (reproduce it with
# `build/fuzz/fuzz/fuzz_<target> <file>`). Prints the executions per target.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(obj stl ply off gmsh tetgen medit scene); fi

scripts/install-fuzz-deps.sh
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"

runs_flag=()
if [ -n "${MGELASTIC_FUZZ_RUNS:-}" ]; then runs_flag=(-runs="$MGELASTIC_FUZZ_RUNS"); fi
# One target: fuzz it for the given time; writes its result line to build/fuzz/fuzz_<t>.result.
fuzz_target() {
  local t=$1 corpus=build/fuzz/corpus/$1 artifacts=build/fuzz/artifacts/$1/
  local log=build/fuzz/fuzz_$1.log start status=0
  mkdir -p "$corpus" "$artifacts"
  for seed in fuzz/corpus/"$t"/*; do
    [ -e "$corpus/${seed##*/}" ] || cp "$seed" "$corpus/"
  done
  start=$(date +%s)
  # -timeout: an input taking more than 10 s is a hang; -rss_limit_mb: a reader must not need
  # gigabytes for a small file (libFuzzer also fails a single malloc above this limit).
  build/fuzz/fuzz/fuzz_"$t" -max_total_time="$seconds" "${runs_flag[@]}" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts" "$corpus" \
    >"$log" 2>&1 || status=$?
  local elapsed=$(($(date +%s) - start)) executions rate result=ok
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  executions=${executions:-0}
  rate=$((executions / (elapsed > 0 ? elapsed : 1)))
  [ "$status" -eq 0 ] || result="FAILED (exit $status, log $log)"
  printf '%-8s %12s %8s %10s %s\n' "$t" "$executions" "$elapsed" "$rate" "$result" \
    >"build/fuzz/fuzz_$t.result"
}

# As many targets at once as there are cores (each fuzzer is single-threaded).
rm -f build/fuzz/fuzz_*.result
jobs=$(nproc)
running=0
for t in "${targets[@]}"; do
  fuzz_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait
failed=()
printf '%-8s %12s %8s %10s %s\n' target executions seconds exec/s result
for t in "${targets[@]}"; do
  cat "build/fuzz/fuzz_$t.result"
  grep -q ' ok$' "build/fuzz/fuzz_$t.result" || failed+=("$t")
done
if [ ${#failed[@]} -ne 0 ]; then
  for t in "${failed[@]}"; do
    echo "---- fuzz_$t: end of build/fuzz/fuzz_$t.log"
    grep -v '^#[0-9]' "build/fuzz/fuzz_$t.log" | tail -40
  done
  echo "fuzzing failed: ${failed[*]}" >&2
  exit 1
fi
