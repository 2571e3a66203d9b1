#!/usr/bin/env bash
# A heavy oracle, run before resolving (not in CI): preset=threejs checked in three.js itself.
# Installs Debian's Chromium and, in a scratch folder, three and playwright-core from npm (test
# tools only); converts the Jordan Pond sample to an equirect and to cube files with
# preset=threejs and (the deliberate mistake) preset=unity; renders both as three.js backgrounds
# from eight views in headless Chromium (SwiftShader WebGL) and compares (threejs_presets.mjs).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/scripts/browser-tools.sh"
work=${1:-"$root/out/browser-oracle"}
bash "$root/scripts/install-deps.sh" chromium
bash "$root/scripts/build.sh" >/dev/null
pp="$root/build/tools/panoproj"
mkdir -p "$work/threejs" "$work/unity"
cp "$root/tests/browser/threejs_presets.html" "$root/tests/browser/threejs_presets.mjs" "$work/"
npm_tools "$work" three@0.187.0 playwright-core@1.65.1
"$pp" convert "$root/samples/images/jordan_pond_4096x2048.jpg" "$work/e.png" --to equirect --size 2048x1024 --overwrite -q
for preset in threejs unity; do
  "$pp" convert "$work/e.png" "$work/$preset/{axis}.png" --to "cubemap:layout=files,preset=$preset" --size 512x512 --overwrite -q
done
serve "$work"
(cd "$work" && node threejs_presets.mjs "http://127.0.0.1:$port/threejs_presets.html")
