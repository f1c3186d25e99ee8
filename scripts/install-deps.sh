#!/usr/bin/env bash
# Installs the Debian 12 packages mgelastic needs to build, test and benchmark.
# Idempotent: packages already present are skipped, so repeated runs are quick.
# Extra package names given as arguments are installed too (scripts/install-fuzz-deps.sh).
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libsuitesparse-dev libhypre-dev
  libopenblas0-openmp  # the BLAS under CHOLMOD/UMFPACK (Debian's alternatives pick it over the reference BLAS)
  python3 python3-dev ccache zlib1g-dev libdeflate-dev
  pybind11-dev python3-numpy python3-pytest python3-matplotlib  # Python module, its tests, plots
  tetgen  # executable only (AGPL, never linked): TetMultigrid.RateOnTetGenMeshesOfSeveralSizes
  "$@"
)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "installing: ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
