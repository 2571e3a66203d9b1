#!/usr/bin/env bash
# A virtual environment for the Python side (.venv) with python/requirements-test.txt: Debian's
# own python3 refuses pip installs outside one. Works with this machine's python3 and with
# Debian's. Idempotent: a second run only checks (about a second). Also .venv-omnidir, OpenCV's
# contrib build for one oracle, and .venv-cv4, OpenCV 4.x for another.
# Usage: scripts/python-env.sh [--cmake-args]   (prints the CMake arguments that build the
# module against this environment)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv="$root/.venv"
if [[ ! -x "$venv/bin/python" ]]; then
  python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import pybind11, numpy, pytest, xdist, cv2, dask.distributed, scikit_build_core, OpenImageIO, mypy, pyright, py360convert, pyproj, pycolmap, av, sphinx, myst_parser" 2>/dev/null \
  || [[ ! -x "$venv/bin/clang-format" || ! -x "$venv/bin/lizard" ]]; then
  "$venv/bin/python" -m pip install -q -r "$root/python/requirements-test.txt" >&2
fi
# cv2.omnidir (opencv-contrib) cannot share a venv with opencv-python: its own, for
# python/tests/test_lens_models.py's omni-radtan oracle.
omnidir="$root/.venv-omnidir"
if ! "$omnidir/bin/python" -c "import cv2; cv2.omnidir" 2>/dev/null; then
  python3 -m venv "$omnidir"
  "$omnidir/bin/python" -m pip install -q "opencv-contrib-python-headless==5.0.0.93" numpy >&2
fi
# pip's OpenCV 4.x beside .venv's 5.x: `maps m.npy` is tested against both lines (the same
# environment scripts/bench.sh cv uses).
cv4="$root/.venv-cv4"
if ! "$cv4/bin/python" -c "import cv2, sys; sys.exit(cv2.__version__ != '4.14.0')" 2>/dev/null; then
  python3 -m venv "$cv4"
  "$cv4/bin/python" -m pip install -q "numpy>=1.22" "opencv-python-headless==4.14.0.94" >&2
fi
if [[ ${1:-} == --cmake-args ]]; then
  echo "-DPANOPROJ_BUILD_PYTHON=ON" \
    "-DPython_EXECUTABLE=$("$venv/bin/python" -c 'import sys; print(sys.executable)')" \
    "-Dpybind11_DIR=$("$venv/bin/python" -m pybind11 --cmakedir)"
fi
