#!/usr/bin/env bash
# `pip install ./python` into a fresh virtual environment, then the pytest suite against that
# installed package (not the build tree) and the panoproj command installed with it, with no
# environment variable pointing at either. A CI stage; needs the Debian packages of
# install-deps.sh. ~1.5 min.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/install-deps.sh"
venv=$(mktemp -d)/venv
trap 'rm -rf "$(dirname "$venv")"' EXIT
python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q -r "$root/python/requirements-test.txt"
"$venv/bin/python" -m pip install -q "$root/python"
cd "$(dirname "$venv")"  # away from the source tree: the installed module must be the one imported
"$venv/bin/python" -c "import panoproj, sys; assert panoproj.__file__.startswith('$venv'), panoproj.__file__"
"$venv/bin/panoproj" --version
env -u PANOPROJ_CLI "$venv/bin/python" -m pytest -q -p no:cacheprovider "$root/python/tests"
