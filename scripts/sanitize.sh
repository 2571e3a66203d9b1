#!/usr/bin/env bash
# The ctest suite under AddressSanitizer + UndefinedBehaviorSanitizer (gcc's; nothing extra to
# install), in build-asan/. A CI stage; ~9 min to build and ~4 min to run on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/install-deps.sh"
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
# One Highway target (SSE4, compiled in statically): the kernels' logic is the same on every
# target, the main test stage checks them all, and instrumenting five copies took 8 of CI's 16 min.
flags+=" -msse4.2 -DHWY_COMPILE_ONLY_STATIC"
# No use-after-scope poisoning (gcc's instruments every inlined scope of the Highway kernels: the
# two SIMD files took 190 and 230 s to compile with it, 39 and 48 s without); clang's fuzz build
# (scripts/fuzz.sh) keeps it.
flags+=" -fno-sanitize-address-use-after-scope"
# -g1 (line tables: reports keep file:line) instead of -g: full variable tracking made the two
# Highway files take 2.2x as long to compile (simd_geometry.cpp: 164 s -> 76 s at -O2).
cmake -S "$root" -B "$root/build-asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
ninja -C "$root/build-asan" | grep -v '^ninja: no work to do' || true
# Full allocation stacks, so that the one suppression (a leak inside OpenImageIO) can match.
# allocator_may_return_null: an allocation past memory fails as in a plain build (bad_alloc), which
# read_image turns into its one-line error (Io.HeadersDeclaringMoreThanMemoryAreAClearError).
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:fast_unwind_on_malloc=0:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS="suppressions=$root/.ci/lsan.supp:print_suppressions=0"
# Not the real-photo figures (RealCubemap, the dual fisheye's Jordan Pond): they run the same code
# as the synthetic tests, on 8-Mpx photos, and took 3 of the stage's 6 minutes.
ctest --test-dir "$root/build-asan" -j 2 --timeout 900 --output-on-failure -E 'RealCubemap\.|DualFisheye\.JordanPond'
