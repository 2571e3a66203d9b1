#!/usr/bin/env bash
# The ctest suite under AddressSanitizer + UndefinedBehaviorSanitizer (clang's), in the build it
# shares with the fuzz targets (scripts/build-sanitized.sh). A CI stage; ~5.5 min to build (the
# fuzz targets included) and ~4 min to run on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build-sanitized.sh"
# Full allocation stacks, so that the one suppression (a leak inside OpenImageIO) can match.
# allocator_may_return_null: an allocation past memory fails as in a plain build (bad_alloc), which
# read_image turns into its one-line error (Io.HeadersDeclaringMoreThanMemoryAreAClearError).
# intercept_tls_get_addr=0: clang 14's runtime misreads the dynamic TLS of the dlopen'd OpenImageIO
# plugin on Debian 12's glibc ("DTLS 5 at 0x1803-0x5000002905"), and LeakSanitizer's tracer then
# crashed at the exit of a test that had passed (tiff_header_only, every CI run).
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:fast_unwind_on_malloc=0:allocator_may_return_null=1:intercept_tls_get_addr=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS="suppressions=$root/.ci/lsan.supp:print_suppressions=0"
# Not the real-photo figures (RealCubemap, the dual fisheye's Jordan Pond): they run the same code
# as the synthetic tests, on 8-Mpx photos, and took 3 of the stage's 6 minutes; nor the seam's
# sweep of 1620 conversions (Seam.EveryWrappingCaseRow...: the seam's quick tests run here); nor
# the GoPro MAX's analytic scene (the synthetic tests' code on 8 float renders).
ctest --test-dir "$root/build-sanitized" -j 2 --timeout 900 --output-on-failure -E 'RealCubemap\.|DualFisheye\.JordanPond|Seam\.EveryWrappingCaseRow|GoProMax\.AnAnalyticScene'
