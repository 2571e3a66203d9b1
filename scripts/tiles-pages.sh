#!/usr/bin/env bash
# A heavy oracle, run before resolving (not in CI): a tiles page in headless Chromium with no
# network (tests/browser/tiles_page_states.mjs): from disk, served with the CDN unreachable, and
# served with local viewer files (--script-url). npm's pannellum and playwright-core in a scratch
# folder (test tools only; nothing of them enters the repository). Screenshots into OUT.
# Usage: scripts/tiles-pages.sh [OUT (default out/tiles-pages)]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/scripts/browser-tools.sh"
work=$(mkdir -p "${1:-$root/out/tiles-pages}" && cd "${1:-$root/out/tiles-pages}" && pwd)
bash "$root/scripts/install-deps.sh" chromium-headless-shell
bash "$root/scripts/build.sh" >/dev/null
npm_tools "$work" pannellum@2.5.7 playwright-core@1.65.1
pp="$root/build/tools/panoproj"
pano="$root/samples/images/jordan_pond_4096x2048.jpg"
rm -rf "$work/cdn" "$work/local"
"$pp" tiles "$pano" "$work/cdn" --tile 256 -q
"$pp" tiles "$pano" "$work/local" --tile 256 -q --script-url viewer/
cp -r "$work/node_modules/pannellum/build" "$work/local/viewer"
serve "$work"
cp "$root/tests/browser/tiles_page_states.mjs" "$work/"
(cd "$work" && node tiles_page_states.mjs "file://$work/cdn/index.html" "http://127.0.0.1:$port/cdn/index.html" \
  "http://127.0.0.1:$port/local/index.html" "$work/tiles_page_")
ls -l "$work"/tiles_page_*.jpg
