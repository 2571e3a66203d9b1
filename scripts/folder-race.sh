#!/usr/bin/env bash
# The folder race by hand (as root): how many of RUNS runs of `tiles` and `views` let an
# unprivileged swapper redirect their writes into a root-only folder. The suite runs 25 of each
# (test_a_swapped_temporary_folder_never_redirects_a_write); this runs any build, e.g. an older one.
# Usage: scripts/folder-race.sh [CLI] [RUNS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cli=${1:-"$root/build/tools/panoproj"}
runs=${2:-50}
image=$(mktemp --suffix=.png)
trap 'rm -f "$image"' EXIT
cp "$root/samples/images/mars_spirit_1024x512_rgba.png" "$image"
for command in tiles views; do
  "$root/.venv/bin/python" "$root/python/tests/folder_race.py" "$cli" "$image" "$command" "$runs"
done
