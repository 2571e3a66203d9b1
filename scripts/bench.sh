#!/usr/bin/env bash
# Benchmarks panoproj against OpenCV's cv::remap and memcpy (bench/bench_remap.cpp);
# with "big" first, the 40000x20000 demonstration instead (bench/bench_big.cpp, ~4.5 GB); with
# "python" first, the Python module and panoproj.compat against py360convert (bench/bench_python.py;
# --only compat: compat's first and repeat calls alone); with "plot"
# first, bench_remap then its chart in docs/bench_remap.png (bench/plot_remap.py, matplotlib); with
# "io" first, the file boundary's figures: start-up, JPEG and PPM whole processes against the codec
# floor and FFmpeg's v360, a 32768x16384 JPEG's views (bench/bench_io.py; hyperfine, ffmpeg); with
# "cv" first, cv2.remap of pip's OpenCV 4.14 and 5.0 in one process with panoproj's convert and
# Plan.run (bench/bench_cv_lines.py); with "profile" first, where bilinear's time goes by engine
# phase (bench/profile_phases.py, perf); with "video" first, videos against FFmpeg's v360: decode
# and convert alone, transcodes against the encoder's floor, peak RSS (bench/bench_video.py); with
# "video-quality" first, a video's luma PSNR and chroma error against an analytic truth, panoproj
# against v360 (bench/video_quality.py); with "gopro-max" first, GoPro MAX 5.6K pairs and a .360
# to a 5376x2688 equirect, against max2sphere given its binary (bench/bench_gopro_max.py); with
# "stitch" first, a Hugin project's layers against nona -m TIFF_m (bench/bench_stitch.py); with
# "photometry" first, convert with a lens's photometric keys against without (bench/bench_photometry.py); with
# "undistort" first, a COLMAP model's undistortion against pycolmap and COLMAP 3.8 (bench/bench_undistort.py).
# Installs what is missing, builds in build-bench/, runs.
# Usage: scripts/bench.sh [--threads N] [--runs N]  |  scripts/bench.sh big [--threads N]
#        scripts/bench.sh python [--runs N] [--only keep|compat]  |  scripts/bench.sh plot [--runs N]
#        scripts/bench.sh io [--rounds N] [--runs N] [--batch-runs N] [--only startup,jpeg,ppm,batch,big]
#        scripts/bench.sh cv [--runs N] [--rounds N]  |  scripts/bench.sh profile [--runs N]
#        scripts/bench.sh video [--runs N] [--frames N] [--only filter,transcode,rss]  |  scripts/bench.sh video-quality
#        scripts/bench.sh gopro-max [--runs N] [--frames N] [--max2sphere PATH] [--only pairs,convert,video]
#        scripts/bench.sh stitch [--runs N] [--only none,deflate,float,photometry,photometry-float]
#        scripts/bench.sh photometry [--runs N]  |  scripts/bench.sh undistort [--runs N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ ${1:-} == io ]]; then
  shift
  bash "$root/scripts/install-deps.sh" hyperfine ffmpeg
  read -ra py_args < <(bash "$root/scripts/python-env.sh" --cmake-args)
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF "${py_args[@]}"
  exec "$root/.venv/bin/python" "$root/bench/bench_io.py" "$@"
fi
if [[ ${1:-} == video-quality ]]; then
  bash "$root/scripts/install-deps.sh" ffmpeg
  bash "$root/scripts/python-env.sh"
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
  exec "$root/.venv/bin/python" "$root/bench/video_quality.py"
fi
if [[ ${1:-} == gopro-max ]]; then
  shift
  bash "$root/scripts/install-deps.sh" ffmpeg
  read -ra py_args < <(bash "$root/scripts/python-env.sh" --cmake-args)
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF "${py_args[@]}"
  exec "$root/.venv/bin/python" "$root/bench/bench_gopro_max.py" "$@"
fi
if [[ ${1:-} == stitch ]]; then
  shift
  bash "$root/scripts/install-deps.sh" hugin-tools
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
  exec python3 "$root/bench/bench_stitch.py" "$@"
fi
if [[ ${1:-} == undistort ]]; then
  shift
  bash "$root/scripts/install-deps.sh" colmap
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
  bash "$root/scripts/python-env.sh"
  exec python3 "$root/bench/bench_undistort.py" "$@"
fi
if [[ ${1:-} == photometry ]]; then
  shift
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
  exec python3 "$root/bench/bench_photometry.py" "$@"
fi
if [[ ${1:-} == video ]]; then
  shift
  bash "$root/scripts/install-deps.sh" ffmpeg
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
  exec python3 "$root/bench/bench_video.py" "$@"
fi
if [[ ${1:-} == cv ]]; then
  # One environment per OpenCV line (pip's wheels; two cv2 cannot share a process), panoproj's
  # module the same build in both; then the faster line per pair and kernel.
  shift
  bash "$root/scripts/install-deps.sh"
  read -ra py_args < <(bash "$root/scripts/python-env.sh" --cmake-args)
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF "${py_args[@]}"
  out="$root/build-bench/cv"
  mkdir -p "$out"
  for line in 4.14.0.94 5.0.0.93; do
    venv="$root/.venv-cv${line%%.*}"
    [[ -x $venv/bin/python ]] || "$root/.venv/bin/python" -m venv "$venv"
    "$venv/bin/python" -c "import cv2, sys; sys.exit(cv2.__version__ != '${line%.*}')" 2>/dev/null ||
      "$venv/bin/python" -m pip install -q "numpy>=1.22" "opencv-python-headless==$line"
    echo "== cv2 $line"
    PYTHONPATH="$root/build-bench/python" "$venv/bin/python" "$root/bench/bench_cv_lines.py" --json "$out/$line.json" "$@"
  done
  exec "$root/.venv/bin/python" "$root/bench/bench_cv_lines.py" --combine "$out"/*.json
fi
if [[ ${1:-} == profile ]]; then
  shift
  bash "$root/scripts/install-deps.sh" linux-perf
  bash "$root/scripts/build.sh" "$root/build-bench" -DPANOPROJ_BUILD_BENCH=ON -DPANOPROJ_BUILD_TESTS=OFF
  exec python3 "$root/bench/profile_phases.py" "$@"
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
