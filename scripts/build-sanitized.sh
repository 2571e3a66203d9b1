#!/usr/bin/env bash
# The sanitized build that scripts/sanitize.sh (the ctest suite) and scripts/fuzz.sh (the libFuzzer
# targets) share, in build-sanitized/: clang, ASan + UBSan, and libFuzzer's coverage
# instrumentation, which fuzz/coverage-ignorelist.txt keeps out of the compute kernels and the
# tests (there it only slowed the suite). Installs clang if missing.
# Usage: scripts/build-sanitized.sh [TARGET...]   (default: every target)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/install-deps.sh" clang libclang-rt-14-dev
build="$root/build-sanitized"
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
flags+=" -fsanitize-coverage-ignorelist=$root/fuzz/coverage-ignorelist.txt"
# One Highway target (SSE4, compiled in statically): the kernels' logic is the same on every
# target, the main test stage checks them all, and five instrumented copies would dominate the build.
flags+=" -msse4.2 -DHWY_COMPILE_ONLY_STATIC"
# -g1 (line tables: reports keep file:line) instead of -g: full variable tracking made the two
# Highway files take 2.2x as long to compile.
# (Configured on every call, so that a change of these flags reaches an existing build; unchanged,
# it rebuilds nothing.)
CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPANOPROJ_BUILD_FUZZ=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
# (A failed build fails the script: pipefail takes ninja's status; grep's own no-match is not one.)
ninja -C "$build" "$@" | { grep -v '^ninja: no work to do' || true; }
