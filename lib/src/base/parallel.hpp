#pragma once
// Work over threads (threads = 0: all cores). Internal. An exception thrown by the work stops further
// tasks and is rethrown by the call once every thread has joined (the first one, if several).
#include <cstdint>
#include <functional>

#include "panoproj/limits.hpp"  // threads: check_threads, resolve_threads

namespace panoproj {

// Splits rows [0, rows) into contiguous bands, one per worker.
void parallel_rows(int64_t rows, int threads, const std::function<void(int64_t, int64_t)>& band);
// Rows [0, rows) in blocks of `block` rows handed out as parallel_tasks' (so the calling thread
// checks for an interrupt between them: long single passes over large images).
void parallel_row_blocks(int64_t rows, int threads,
                         const std::function<void(int64_t, int64_t)>& band, int64_t block = 64);
// Workers parallel_tasks uses for n tasks: min(threads, n), at least 1.
int workers_for(int64_t n, int threads);
// Hands tasks 0 .. n-1 out in order, one at a time, to workers_for(n, threads) threads; worker 0
// is the calling thread (per-worker state can be indexed by worker).
void parallel_tasks(int64_t n, int threads, const std::function<void(int64_t task, int worker)>& fn);

}  // namespace panoproj
