#!/usr/bin/env bash
# Heavy oracles of `panoproj tiles`, run before resolving (not in CI; tests/tiles_oracle.py):
#   1. Pannellum's own generate.py (npm pannellum 2.5.7, Pillow 9.5.0, nona from hugin-tools)
#      on the Jordan Pond sample: config, file names, face letters and turns, PSNR per level;
#   2. the pyramids of both viewers in chromium-headless-shell (npm pannellum, marzipano and
#      playwright-core), served on 127.0.0.1, against panoproj's own renders of the same views;
#   3. with `big`: a 32768x16384 source to a full pyramid, time and peak memory against
#      generate.py + nona.
# Usage: scripts/tiles-oracle.sh [big] [WORK (default out/tiles-oracle)]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/scripts/browser-tools.sh"
big=0
if [[ ${1:-} == big ]]; then big=1; shift; fi
work=$(mkdir -p "${1:-$root/out/tiles-oracle}" && cd "${1:-$root/out/tiles-oracle}" && pwd)
bash "$root/scripts/install-deps.sh" chromium-headless-shell hugin-tools
bash "$root/scripts/build.sh" >/dev/null
bash "$root/scripts/python-env.sh" >/dev/null
npm_tools "$work" pannellum@2.5.7 marzipano@0.10.2 playwright-core@1.65.1
# generate.py's own environment: Pillow 9.5.0 (its Image.ANTIALIAS is gone from Pillow 10).
[ -x "$work/venv-pillow/bin/python" ] || python3 -m venv "$work/venv-pillow"
"$work/venv-pillow/bin/pip" install -q pillow==9.5.0
gen="$work/node_modules/pannellum/utils/multires/generate.py"
export PYTHONPATH="$root/build/python" PANOPROJ_CLI="$root/build/tools/panoproj"
py="$root/.venv/bin/python"
status=0
"$py" "$root/tests/tiles_oracle.py" generate-py "$work" "$gen" "$work/venv-pillow/bin/python" || status=1
serve "$work"
"$py" "$root/tests/tiles_oracle.py" browser "$work" "http://127.0.0.1:$port" || status=1
if ((big)); then
  "$py" "$root/tests/tiles_oracle.py" big "$work" "$gen" "$work/venv-pillow/bin/python" || status=1
fi
exit $status
