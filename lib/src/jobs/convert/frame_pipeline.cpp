#include "jobs/convert/frame_pipeline.hpp"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace panoproj {
namespace {

// One run's shared state: the stages' progress, and the limit no stage takes a frame from (the
// earliest failed frame), guarded by one mutex.
class Pipeline {
 public:
  Pipeline(size_t n, int readers, const FrameStages& stages)
      : n_(n),
        readers_(std::max(readers, 1)),
        stages_(stages),
        limit_(n),
        read_(static_cast<size_t>(readers_), 0) {}

  void run() {
    std::vector<std::thread> threads;
    try {
      for (int r = 0; r < readers_; ++r)
        threads.emplace_back([this, r] { read_frames(static_cast<size_t>(r)); });
      threads.emplace_back([this] { write_frames(); });
      convert_frames();
    } catch (...) {  // a thread the system refused: nothing taken from here on
      fail(0);
    }
    for (std::thread& t : threads) t.join();  // (each stops at the limit, or at n)
    std::unique_lock<std::mutex> lock(mutex_);
    report(lock);
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void fail(size_t frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (frame < limit_) limit_ = frame, error_ = std::current_exception();
    changed_.notify_all();
  }

  // Waits until ready() or frame is at or past the limit; false for the latter.
  template <class Ready>
  bool wait_for(std::unique_lock<std::mutex>& lock, size_t frame, Ready ready) {
    changed_.wait(lock, [&] { return frame >= limit_ || ready(); });
    return frame < limit_;
  }

  // Runs stage(i) once the wait allows; false when the pipeline stops at i.
  template <class Ready, class Stage, class Done>
  bool step(size_t i, Ready ready, const Stage& stage, Done done) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (!wait_for(lock, i, ready)) return false;
    }
    try {
      stage(i);
    } catch (...) {
      fail(i);
      return false;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    done();
    changed_.notify_all();
    return true;
  }

  void read_frames(size_t first) {
    const size_t slots = static_cast<size_t>(readers_) + 1;
    bool more = true;
    const auto read = [&](size_t i) { more = stages_.read(i); };
    for (size_t i = first; i < n_; i += static_cast<size_t>(readers_)) {
      if (!step(
              i, [&] { return converted_ + slots > i; }, read,
              [&] {
                if (more)
                  read_[first] = i / static_cast<size_t>(readers_) + 1;
                else
                  limit_ = std::min(limit_, i);  // the end: no error
              }))
        return;
      if (!more) return;
    }
  }

  // Whether frame i has been read (reader i % readers has read its i / readers + 1 frames).
  bool is_read(size_t i) const {
    return read_[i % static_cast<size_t>(readers_)] > i / static_cast<size_t>(readers_);
  }

  void write_frames() {
    for (size_t i = 0; i < n_; ++i)
      if (!step(i, [&] { return converted_ > i; }, stages_.write, [&] { written_ = i + 1; }))
        return;
  }

  // Reports the frames written so far, none at or past the limit: after a report has thrown, a
  // frame the writer had already finished is not reported (the lock held on entry and on return).
  void report(std::unique_lock<std::mutex>& lock) {
    while (reported_ < written_ && reported_ < limit_) {
      const size_t i = reported_++;
      lock.unlock();
      try {
        stages_.written(i);
      } catch (...) {
        fail(i + 1);  // (the frame is written; none after it)
      }
      lock.lock();
    }
  }

  // On the calling thread, reporting written frames while it waits for the next one's turn.
  void convert_frames() {
    for (size_t i = 0; i < n_; ++i) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
          report(lock);
          // (written + 1 >= i: write(i - 2) has returned, so convert(i - 2)'s output is free)
          changed_.wait(lock, [&] {
            return i >= limit_ || reported_ < written_ || (is_read(i) && written_ + 1 >= i);
          });
          if (i >= limit_) return;
          if (reported_ == written_) break;
        }
      }
      try {
        stages_.convert(i);
      } catch (...) {
        fail(i);
        return;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      converted_ = i + 1;
      changed_.notify_all();
    }
  }

  const size_t n_;
  const int readers_;
  const FrameStages& stages_;
  std::mutex mutex_;
  std::condition_variable changed_;
  size_t limit_;
  std::exception_ptr error_;
  std::vector<size_t> read_;                           // per reader, the frames it has read
  size_t converted_ = 0, written_ = 0, reported_ = 0;  // frames done by each stage, from the first
};

}  // namespace

void run_frame_pipeline(size_t n, int readers, const FrameStages& stages) {
  Pipeline(n, readers, stages).run();
}

}  // namespace panoproj
