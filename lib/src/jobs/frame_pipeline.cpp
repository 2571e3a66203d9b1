#include "jobs/frame_pipeline.hpp"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace panoproj {

void run_frame_pipeline(size_t n, int readers, const FrameStages& stages) {
  readers = std::max(readers, 1);
  const size_t slots = static_cast<size_t>(readers) + 1;
  std::mutex mutex;
  std::condition_variable changed;
  size_t limit = n;  // no stage takes a frame from here on: the earliest failed frame
  std::exception_ptr error;
  std::vector<char> read(n, 0);
  size_t converted = 0, written = 0;  // frames done by each stage, from the first

  auto fail = [&](size_t frame) {
    std::lock_guard<std::mutex> lock(mutex);
    if (frame < limit) limit = frame, error = std::current_exception();
    changed.notify_all();
  };
  // Waits until ready() or frame is at or past the limit; false for the latter.
  auto wait_for = [&](std::unique_lock<std::mutex>& lock, size_t frame, auto ready) {
    changed.wait(lock, [&] { return frame >= limit || ready(); });
    return frame < limit;
  };

  auto reader = [&](size_t first) {
    for (size_t i = first; i < n; i += static_cast<size_t>(readers)) {
      {
        std::unique_lock<std::mutex> lock(mutex);
        if (!wait_for(lock, i, [&] { return converted + slots > i; })) return;
      }
      try {
        stages.read(i);
      } catch (...) {
        fail(i);
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      read[i] = 1;
      changed.notify_all();
    }
  };
  auto writer = [&] {
    for (size_t i = 0; i < n; ++i) {
      {
        std::unique_lock<std::mutex> lock(mutex);
        if (!wait_for(lock, i, [&] { return converted > i; })) return;
      }
      try {
        stages.write(i);
      } catch (...) {
        fail(i);
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      written = i + 1;
      changed.notify_all();
    }
  };

  std::vector<std::thread> threads;
  size_t reported = 0;
  // Reports the frames written so far, none at or past the limit: after a report has thrown, a
  // frame the writer had already finished is not reported (the lock held on entry and on return).
  auto report = [&](std::unique_lock<std::mutex>& lock) {
    while (reported < written && reported < limit) {
      const size_t i = reported++;
      lock.unlock();
      try {
        stages.written(i);
      } catch (...) {
        fail(i + 1);  // (the frame is written; none after it)
      }
      lock.lock();
    }
  };
  try {
    for (int r = 0; r < readers; ++r) threads.emplace_back(reader, static_cast<size_t>(r));
    threads.emplace_back(writer);
    for (size_t i = 0; i < n; ++i) {
      {
        std::unique_lock<std::mutex> lock(mutex);
        bool go = false;
        for (;;) {
          report(lock);
          // (written + 1 >= i: write(i - 2) has returned, so convert(i - 2)'s output is free)
          changed.wait(lock, [&] { return i >= limit || reported < written || (read[i] && written + 1 >= i); });
          if (i >= limit) break;
          if (reported == written) {
            go = true;
            break;
          }
        }
        if (!go) break;
      }
      try {
        stages.convert(i);
      } catch (...) {
        fail(i);
        break;
      }
      std::lock_guard<std::mutex> lock(mutex);
      converted = i + 1;
      changed.notify_all();
    }
  } catch (...) {  // a thread the system refused: nothing taken from here on
    fail(0);
  }
  for (std::thread& t : threads) t.join();  // (each stops at the limit, or at n)
  std::unique_lock<std::mutex> lock(mutex);
  report(lock);
  if (error) std::rethrow_exception(error);
}

}  // namespace panoproj
