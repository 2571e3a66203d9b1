#include "base/parallel.hpp"

#include <string>

#include "panoproj/error.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace panoproj {
namespace {

// The first exception any worker throws, rethrown on the calling thread once all have joined
// (an exception leaving a std::thread would end the process).
class FirstError {
 public:
  template <class F>
  void run(F&& f) noexcept {
    try {
      f();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      failed_ = true;
    }
  }
  bool failed() const { return failed_.load(std::memory_order_relaxed); }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
};

}  // namespace

void check_threads(int64_t threads) {
  if (threads < 0 || threads > kMaxThreads)
    throw Error("threads: " + std::to_string(threads) + " (expected 0 for all cores, or 1 to " +
                std::to_string(kMaxThreads) + ")");
}

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
  FirstError error;
  std::vector<std::thread> workers;
  workers.reserve(static_cast<size_t>(n - 1));
  for (int64_t i = 1; i < n; ++i)
    workers.emplace_back([&, i] { error.run([&] { band(rows * i / n, rows * (i + 1) / n); }); });
  error.run([&] { band(0, rows / n); });
  for (auto& t : workers) t.join();
  error.rethrow();
}

int workers_for(int64_t n, int threads) {
  return static_cast<int>(std::clamp<int64_t>(n, 1, resolve_threads(threads)));
}

void parallel_tasks(int64_t n, int threads, const std::function<void(int64_t, int)>& fn) {
  std::atomic<int64_t> next{0};
  FirstError error;
  // After a failure no new task starts; the ones running finish.
  auto worker = [&](int w) {
    error.run([&] {
      for (int64_t t; !error.failed() && (t = next.fetch_add(1)) < n;) fn(t, w);
    });
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers_for(n, threads); ++w) pool.emplace_back(worker, w);
  worker(0);
  for (auto& t : pool) t.join();
  error.rethrow();
}

}  // namespace panoproj
