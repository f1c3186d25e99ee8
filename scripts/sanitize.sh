#!/usr/bin/env bash
# Builds the asan preset (gcc, AddressSanitizer + UndefinedBehaviorSanitizer, every finding
# fatal) and runs the test suite on it: readers, scene loader, kernels, engines and the CLI.
# Left out are only the long solves on real scans and the largest 3-D rate studies, which run
# minutes each under the sanitizers and exercise the same kernels as the smaller tests.
#
#   scripts/sanitize.sh [extra ctest arguments]     e.g. scripts/sanitize.sh -R Reader
set -euo pipefail
cd "$(dirname "$0")/.."
long_tests='^RealScans\.|ThreeDimensionalN64|QuasistaticTwistConvergesAtEveryStage'
long_tests+='|FiveHundredStepTwist|WCycleRateIsResolutionIndependentIn3D'
long_tests+='|MixedBoxRateIsDepthIndependentIn2D|RecedingCoarseClampSlowsDeepHierarchies|MixedBoxRateIsResolutionIndependentIn3D'
long_tests+='|RateOnTetGenMeshesOfSeveralSizes|CorotatedLoadStepping\.|CorotatedDistributiveSmoother\.RatesPerVCycle'
long_tests+='|NewtonKrylovStepBeatsThePicardCycleAt30Fps|RecycledDirectionsImproveTheOneCycleStep'
long_tests+='|AdaptivePatchesSpeedUpTheCycleAndDoNotDependOnTheThreadCount'
scripts/build.sh asan
# halt_on_error: a UBSan report fails the test (the preset also compiles with
# -fno-sanitize-recover); detect_leaks: leaks fail it too.
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export ASAN_OPTIONS=detect_leaks=1
ctest --preset asan -j "$(nproc)" -E "$long_tests" --timeout 1200 "$@"
