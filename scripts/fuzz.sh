#!/usr/bin/env bash
# Fuzzes the spec parser, the image-reading path, the Photo Sphere XMP reader and whole conversions
# of small images with libFuzzer under ASan and UBSan (fuzz/):
# installs clang if missing, builds in build-fuzz/, runs each target SECONDS (default 30) from
# the seed corpora in fuzz/corpus/ (new inputs go to a scratch copy, the repository's stay as
# they are). A crash leaves its input in build-fuzz/ and fails. The seed is fixed (SEED, default
# 1) so that a CI run is repeatable; pass another to explore further.
# Usage: [SEED=N] [TARGETS="spec read xmp convert"] scripts/fuzz.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-30}
bash "$root/scripts/install-deps.sh" clang libclang-rt-14-dev
build="$root/build-fuzz"
# -g1: line tables only (full -g makes the Highway files compile far longer). One Highway target
# (SSE4, static), as in scripts/sanitize.sh: the kernels' logic is the same on every target, and
# five instrumented copies would dominate the build.
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -msse4.2"
flags+=" -DHWY_COMPILE_ONLY_STATIC"
[[ -f "$build/build.ninja" ]] ||
  CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPANOPROJ_BUILD_FUZZ=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DPANOPROJ_BUILD_TESTS=OFF >/dev/null
ninja -C "$build" spec_fuzz read_fuzz xmp_fuzz convert_fuzz panoproj_oiio | grep -v '^ninja: no work to do' || true
for t in ${TARGETS:-spec read xmp convert}; do
  work="$build/corpus-$t"
  rm -rf "$work" && mkdir -p "$work"
  cp "$root/fuzz/corpus/$t/"* "$work/"
  echo "fuzz: ${t}_fuzz for ${seconds} s"
  # A single allocation over 2 GB ends the run as out-of-memory (the targets read and convert under
  # a 64 MB panoproj memory limit). .ci/lsan.supp: OpenImageIO's own leak on damaged PNGs (see there).
  # The whole log is kept; on a failure its report (from the first ERROR line) is shown.
  log="$build/${t}_fuzz.log"
  if (cd "$build" && UBSAN_OPTIONS=halt_on_error=1 ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
    LSAN_OPTIONS=suppressions="$root/.ci/lsan.supp" \
    "./fuzz/${t}_fuzz" -seed="${SEED:-1}" -max_total_time="$seconds" -max_len=4096 -malloc_limit_mb=2048 -rss_limit_mb=4096 \
    -print_final_stats=1 "$work" >"$log" 2>&1); then
    tail -n 12 "$log"
  else
    sed -n '/ERROR/,$p' "$log" | head -n 80
    echo "fuzz: ${t}_fuzz failed; whole log: $log"
    exit 1
  fi
done
