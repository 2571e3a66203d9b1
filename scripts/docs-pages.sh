#!/usr/bin/env bash
# Not in CI (it installs Chromium and playwright-core): the built documentation site served
# locally and opened in headless Chromium with no network (tests/browser/docs_pages.mjs):
# screenshots of the front page, the Python API page, the projections page's formulas and the C++
# reference into OUT, and a failure if a page asks for anything off the machine or its formulas
# do not render; then the four at half size in one picture, OUT/docs_site.jpg (the README's).
# Usage: scripts/docs-pages.sh [OUT (default out/docs-pages)]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/scripts/browser-tools.sh"
work=$(mkdir -p "${1:-$root/out/docs-pages}" && cd "${1:-$root/out/docs-pages}" && pwd)
bash "$root/scripts/install-deps.sh" chromium-headless-shell
bash "$root/scripts/docs.sh" "$root/build" "$work/site"
npm_tools "$work" playwright-core@1.65.1
serve "$work/site"
cp "$root/tests/browser/docs_pages.mjs" "$work/"
(cd "$work" && node docs_pages.mjs "http://127.0.0.1:$port" "$work/docs_page_")
PYTHONPATH="$root/build/python" "$root/.venv/bin/python" - "$work" <<'PY'
import sys
import numpy as np
import panoproj as pp
work = sys.argv[1]
half = [pp.read(f"{work}/docs_page_{n}.png")[:, :, :3].reshape(450, 2, 640, 2, 3).mean(axis=(1, 3))
        for n in ("front", "python", "projection", "cpp")]
grid = np.vstack([np.hstack(half[:2]), np.hstack(half[2:])]).round().astype(np.uint8)
pp.write(f"{work}/docs_site.jpg", grid, quality=80, overwrite=True)
PY
ls -l "$work"/docs_page_*.png "$work/docs_site.jpg"
