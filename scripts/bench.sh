#!/usr/bin/env bash
# Benchmarks panoproj against OpenCV's cv::remap and memcpy (bench/bench_remap.cpp);
# with "big" first, the 40000x20000 demonstration instead (bench/bench_big.cpp, ~4.5 GB).
# Installs what is missing, builds in build-bench/, runs.
# Usage: scripts/bench.sh [--threads N] [--runs N]  |  scripts/bench.sh big [--threads N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
if [[ ${1:-} == big ]]; then
  shift
  "$root/build-bench/bench/bench_big" "$@"
else
  "$root/build-bench/bench/bench_remap" "$@"
fi
