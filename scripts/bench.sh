#!/usr/bin/env bash
# Benchmarks panoproj against OpenCV's cv::remap and memcpy (bench/bench_remap.cpp).
# Installs what is missing, builds in build-bench/, runs.
# Usage: scripts/bench.sh [--threads N] [--runs N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
"$root/build-bench/bench/bench_remap" "$@"
