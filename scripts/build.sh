#!/usr/bin/env bash
# Installs what is missing (scripts/install-deps.sh) and builds panoproj with CMake + Ninja.
# Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]   (default BUILD_DIR: build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
shift || true
bash "$root/scripts/install-deps.sh"
# Configure on the first build, and again when the extra arguments change.
stamp="$build/.panoproj-cmake-args"
if [[ ! -f "$build/build.ninja" || "$(cat "$stamp" 2>/dev/null)" != "$*" ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  echo "$*" >"$stamp"
fi
# ccache (when installed) keys on paths relative to the tree: another clone or the wheel's
# build (scripts/wheel.sh) reuses what this one compiled.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root}
# Two cores here; Ninja's default (cores + 2) is right.
ninja -C "$build" | grep -v '^ninja: no work to do' || true
test -x "$build/tools/panoproj"
