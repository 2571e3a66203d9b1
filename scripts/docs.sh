#!/usr/bin/env bash
# The documentation site (docs/, Sphinx + MyST) into OUT (default out/docs), with warnings as
# errors; then scripts/check_site.py checks every internal link, anchor and picture of the built
# pages and lists the external links (not fetched: CI is offline). Formulas render with npm's
# MathJax 3, copied into the site (no CDN). Needs the Python module built (autodoc imports it).
# Usage: scripts/docs.sh [BUILD_DIR (default build)] [OUT]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-"$root/out/docs"}
start=$SECONDS
mathjax="$root/.deps/mathjax"
if [[ ! -f "$mathjax/node_modules/mathjax/es5/tex-svg.js" ]]; then
  mkdir -p "$mathjax"
  npm install --silent --no-audit --no-fund --prefix "$mathjax" mathjax@3.2.2 >&2
fi
rm -rf "$out"
PYTHONPATH="$build/python" "$root/.venv/bin/python" -m sphinx -b html -W --keep-going -q -d "$out/.doctrees" \
  "$root/docs" "$out"
mkdir -p "$out/_static/mathjax"
cp "$mathjax/node_modules/mathjax/es5/tex-svg.js" "$out/_static/mathjax/"
cp "$mathjax/node_modules/mathjax/LICENSE" "$out/_static/mathjax/"
"$root/.venv/bin/python" "$root/scripts/check_site.py" "$out"
echo "docs: $out built and checked in $((SECONDS - start)) s"
