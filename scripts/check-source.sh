#!/usr/bin/env bash
# The source tree's habits as checks (part of scripts/test.sh): C++ lines changed since the commit
# .ci/format-base names are as the pinned clang-format (python/requirements-test.txt) formats
# them; includes follow the library's layers; format names and extensions live in the format
# table; the engine, samplers and tap rules never switch on a projection's type
# (scripts/check_source.py says each rule); no function of the front ends and jobs is over 100
# lines (lizard, pinned beside clang-format; lambdas count in their function). Exits 1 listing
# what breaks them.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
status=0
base=$(cat .ci/format-base)
if ! git cat-file -e "$base^{commit}" 2>/dev/null; then
  echo "check-source: the format base $base (.ci/format-base) is not in this clone (fetch its history)" >&2
  exit 1
fi
diff=$(git diff -U0 --no-color "$base" -- '*.cpp' '*.hpp' | .venv/bin/clang-format-diff.py -p1 -binary .venv/bin/clang-format || true)
if [[ -n $diff ]]; then
  echo "$diff"
  echo "check-source: lines changed since $base are not as clang-format $(.venv/bin/clang-format --version | grep -o '[0-9.]*$') lays them out (run: git clang-format --binary .venv/bin/clang-format $base)" >&2
  status=1
fi
python3 scripts/check_source.py || status=1
if ! long=$(.venv/bin/lizard -L 100 -C 1000 -w tools python/src lib/src/jobs); then
  echo "$long"
  echo "check-source: functions over 100 lines in the front ends or jobs (split them)" >&2
  status=1
fi
exit $status
