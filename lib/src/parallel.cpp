#include "panoproj/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace panoproj {

int resolve_threads(int threads) {
  if (threads > 0) return threads;
  return std::max(1u, std::thread::hardware_concurrency());
}

void parallel_rows(int64_t rows, int threads, const std::function<void(int64_t, int64_t)>& band) {
  const int64_t n = std::min<int64_t>(resolve_threads(threads), std::max<int64_t>(rows, 1));
  if (n <= 1) {
    band(0, rows);
    return;
  }
  std::vector<std::thread> workers;
  workers.reserve(static_cast<size_t>(n - 1));
  for (int64_t i = 1; i < n; ++i)
    workers.emplace_back([&, i] { band(rows * i / n, rows * (i + 1) / n); });
  band(0, rows / n);
  for (auto& t : workers) t.join();
}

int workers_for(int64_t n, int threads) {
  return static_cast<int>(std::clamp<int64_t>(n, 1, resolve_threads(threads)));
}

void parallel_tasks(int64_t n, int threads, const std::function<void(int64_t, int)>& fn) {
  std::atomic<int64_t> next{0};
  auto worker = [&](int w) {
    for (int64_t t; (t = next.fetch_add(1)) < n;) fn(t, w);
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers_for(n, threads); ++w) pool.emplace_back(worker, w);
  worker(0);
  for (auto& t : pool) t.join();
}

}  // namespace panoproj
