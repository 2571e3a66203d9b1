#!/usr/bin/env bash
# A virtual environment for the Python side (.venv): Debian's own python3 refuses pip installs
# outside one. Works with this machine's python3 and with Debian's. Idempotent.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv="$root/.venv"
if [[ ! -x "$venv/bin/python" ]]; then
  python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import pytest" 2>/dev/null; then
  "$venv/bin/python" -m pip install -q pytest
fi
