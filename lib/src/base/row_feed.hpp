#pragma once
// An image's rows coming in from the top on one thread (a decoder), waited for on others (the
// tiles that read them). Internal.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace panoproj {

class RowFeed {
 public:
  // Rows [0, k) are in.
  void arrived(int64_t k);
  // No more rows come (the reader is done, or failed): every wait returns.
  void close();
  // Whether rows [0, k) are in, without waiting.
  bool has(int64_t k) const { return rows_.load(std::memory_order_acquire) >= k; }
  // Waits until rows [0, k) are in (true) or the feed closes short of them (false).
  bool wait(int64_t k);

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::atomic<int64_t> rows_{0};
  bool closed_ = false;
};

}  // namespace panoproj
