#!/usr/bin/env bash
# Every test: installs what is missing, checks the source's habits (scripts/check-source.sh),
# builds (with the Python module), runs ctest and pytest, and builds the documentation site
# (scripts/docs.sh: warnings are errors, every internal link checked).
# Usage: scripts/test.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
# The Python module builds against the venv's pybind11 >= 2.12 and numpy (scripts/python-env.sh).
# exiftool: a second reader of the Photo Sphere XMP panoproj writes; strace: injects system-call
# faults for the robustness suite (python/tests/test_robustness.py), time (GNU) measures its
# commands' peak memory; ffmpeg: v360, the cube formats' oracle
# (python/tests/test_v360_oracle.py); hugin-tools and enblend: nona, the stitch job's oracle, and
# the blender its layers are for (python/tests/test_stitch.py). Test oracles only.
bash "$root/scripts/install-deps.sh" libimage-exiftool-perl strace time ffmpeg hugin-tools enblend
read -ra py_args < <(bash "$root/scripts/python-env.sh" --cmake-args)
bash "$root/scripts/check-source.sh"
bash "$root/scripts/build.sh" "$build" "${py_args[@]}"
ctest --test-dir "$build" --output-on-failure -j 2
PYTHONPATH="$build/python" PANOPROJ_CLI="$build/tools/panoproj" "$root/.venv/bin/python" -m pytest -q -n 2 "$root/python/tests"
bash "$root/scripts/docs.sh" "$build"
