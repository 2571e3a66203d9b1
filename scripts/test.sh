#!/usr/bin/env bash
# Every test: installs what is missing, builds, runs ctest, then pytest when python/ has tests.
# Usage: scripts/test.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
bash "$root/scripts/build.sh" "$build"
ctest --test-dir "$build" --output-on-failure -j 2
if compgen -G "$root/python/tests/test_*.py" >/dev/null; then
  bash "$root/scripts/python-env.sh"
  "$root/.venv/bin/python" -m pytest -q "$root/python/tests"
else
  echo "pytest: skipped, python/ has no tests yet (the Python module is issue 4)"
fi
