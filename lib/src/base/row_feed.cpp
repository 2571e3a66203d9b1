#include "base/row_feed.hpp"

namespace panoproj {

void RowFeed::arrived(int64_t k) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (k > rows_.load(std::memory_order_relaxed)) rows_.store(k, std::memory_order_release);
  }
  changed_.notify_all();
}

void RowFeed::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

bool RowFeed::wait(int64_t k) {
  if (has(k)) return true;
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return closed_ || has(k); });
  return has(k);
}

}  // namespace panoproj
