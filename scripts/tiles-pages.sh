#!/usr/bin/env bash
# A heavy oracle, run before resolving (not in CI): a tiles page in headless Chromium with no
# network (tests/browser/tiles_page_states.mjs): from disk, served with the CDN unreachable, and
# served with local viewer files (--script-url). npm's pannellum and playwright-core in a scratch
# folder (test tools only; nothing of them enters the repository). Screenshots into OUT.
# Usage: scripts/tiles-pages.sh [OUT (default out/tiles-pages)]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mkdir -p "${1:-$root/out/tiles-pages}" && cd "${1:-$root/out/tiles-pages}" && pwd)
bash "$root/scripts/install-deps.sh" chromium-headless-shell
bash "$root/scripts/build.sh" >/dev/null
(cd "$work" && { [ -f package.json ] || npm init -y >/dev/null; } &&
  npm install --silent --no-audit --no-fund pannellum@2.5.7 playwright-core@1.65.1)
pp="$root/build/tools/panoproj"
pano="$root/samples/images/jordan_pond_4096x2048.jpg"
rm -rf "$work/cdn" "$work/local"
"$pp" tiles "$pano" "$work/cdn" --tile 256 -q
"$pp" tiles "$pano" "$work/local" --tile 256 -q --script-url viewer/
cp -r "$work/node_modules/pannellum/build" "$work/local/viewer"
port=$((20000 + RANDOM % 20000))
(cd "$work" && exec python3 -m http.server "$port" --bind 127.0.0.1 >/dev/null 2>&1) &
server=$!
trap 'kill $server 2>/dev/null' EXIT
sleep 1
cp "$root/tests/browser/tiles_page_states.mjs" "$work/"
(cd "$work" && node tiles_page_states.mjs "file://$work/cdn/index.html" "http://127.0.0.1:$port/cdn/index.html" \
  "http://127.0.0.1:$port/local/index.html" "$work/tiles_page_")
ls -l "$work"/tiles_page_*.jpg
