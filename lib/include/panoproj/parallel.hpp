#pragma once
// Splits rows [0, rows) into contiguous bands, one per worker (threads = 0: all cores).
#include <cstdint>
#include <functional>

namespace panoproj {

int resolve_threads(int threads);
void parallel_rows(int64_t rows, int threads, const std::function<void(int64_t, int64_t)>& band);

}  // namespace panoproj
