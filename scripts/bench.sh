#!/usr/bin/env bash
# Benchmarks panoproj against OpenCV's cv::remap and memcpy (bench/bench_remap.cpp);
# with "big" first, the 40000x20000 demonstration instead (bench/bench_big.cpp, ~4.5 GB); with
# "python" first, the Python module against py360convert (bench/bench_python.py); with "plot"
# first, bench_remap then its chart in docs/bench_remap.png (bench/plot_remap.py, matplotlib); with
# "io" first, the file boundary's figures: start-up, JPEG and PPM whole processes against the codec
# floor and FFmpeg's v360, a 32768x16384 JPEG's views (bench/bench_io.py; hyperfine, ffmpeg).
# Installs what is missing, builds in build-bench/, runs.
# Usage: scripts/bench.sh [--threads N] [--runs N]  |  scripts/bench.sh big [--threads N]
#        scripts/bench.sh python [--runs N]  |  scripts/bench.sh plot [--runs N]
#        scripts/bench.sh io [--rounds N] [--runs N] [--only startup,jpeg,ppm,big]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ ${1:-} == io ]]; then
  shift
  bash "$root/scripts/install-deps.sh" hyperfine ffmpeg
  read -ra py_args < <(bash "$root/scripts/python-env.sh" --cmake-args)
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF "${py_args[@]}"
  exec "$root/.venv/bin/python" "$root/bench/bench_io.py" "$@"
fi
if [[ ${1:-} == python ]]; then
  shift
  bash "$root/scripts/install-deps.sh"
  read -ra py_args < <(bash "$root/scripts/python-env.sh" --cmake-args)
  "$root/.venv/bin/python" -c "import py360convert" 2>/dev/null || "$root/.venv/bin/python" -m pip install -q py360convert
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF "${py_args[@]}"
  PYTHONPATH="$root/build-bench/python" exec "$root/.venv/bin/python" "$root/bench/bench_python.py" "$@"
fi
bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
if [[ ${1:-} == plot ]]; then
  shift
  bash "$root/scripts/python-env.sh"
  "$root/.venv/bin/python" -c "import matplotlib" 2>/dev/null || "$root/.venv/bin/python" -m pip install -q matplotlib
  "$root/build-bench/bench/bench_remap" "$@" | tee /dev/stderr | "$root/.venv/bin/python" "$root/bench/plot_remap.py" "$root/docs/bench_remap.png"
  exit
fi
if [[ ${1:-} == big ]]; then
  shift
  "$root/build-bench/bench/bench_big" "$@"
else
  "$root/build-bench/bench/bench_remap" "$@"
fi
