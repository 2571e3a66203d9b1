#include "base/parallel.hpp"

#include <pthread.h>

#include <string>

#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <system_error>
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

// Threads kept for the process's life: starting threads per call cost 60 us each, and a new
// thread could wait a scheduler tick (4-5 ms) on its parent's core while the caller did every
// task alone (measured: 2-thread runs of 2.8 ms took 5.3 ms in some processes). A call queues
// a job wanting helpers; idle threads join it, each as the next worker index; the caller works
// as worker 0, closes the job (helpers that have not joined never will) and waits for those
// that did. The caller alone finishes every job, so nested and concurrent calls cannot wait on
// each other.
class WorkerPool {
 public:
  static WorkerPool& get() {
    static const bool registered = (pthread_atfork(nullptr, nullptr, [] { instance() = new WorkerPool; }), true);
    (void)registered;
    return *instance();
  }

  void run(int helpers, const std::function<void(int)>& body) {
    Job job;
    job.body = &body;
    job.wanted = helpers;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      try {  // (a thread the system refuses leaves the work to those there are)
        for (; threads_ < std::min(helpers, kMaxThreads); ++threads_) std::thread([this] { loop(); }).detach();
      } catch (const std::system_error&) {
      }
      queue_.push_back(&job);
    }
    if (helpers == 1)
      wake_.notify_one();
    else
      wake_.notify_all();
    body(0);
    std::unique_lock<std::mutex> lock(mutex_);
    job.closed = true;
    std::erase(queue_, &job);
    job.done.wait(lock, [&] { return job.active == 0; });
  }

 private:
  struct Job {
    const std::function<void(int)>* body = nullptr;
    int wanted = 0;
    int joined = 0;
    int active = 0;
    bool closed = false;
    std::condition_variable done;
  };

  // After fork only the forking thread exists: the child starts a new pool (the old one's
  // mutex may be held by a thread that is gone, so it is left, not destroyed).
  static WorkerPool*& instance() {
    static WorkerPool* pool = new WorkerPool;
    return pool;
  }

  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return !queue_.empty(); });
      Job* job = queue_.front();
      const int w = ++job->joined;
      if (job->joined == job->wanted) queue_.pop_front();
      ++job->active;
      lock.unlock();
      (*job->body)(w);  // (never throws: parallel_tasks's worker keeps the first error)
      lock.lock();
      if (--job->active == 0 && job->closed) job->done.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job*> queue_;  // jobs that want more helpers
  int threads_ = 0;
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
  parallel_tasks(n, static_cast<int>(n), [&](int64_t i, int) { band(rows * i / n, rows * (i + 1) / n); });
}

void parallel_row_blocks(int64_t rows, int threads,
                         const std::function<void(int64_t, int64_t)>& band, int64_t block) {
  const int64_t n = (rows + block - 1) / block;
  parallel_tasks(n, threads,
                 [&](int64_t t, int) { band(t * block, std::min(rows, (t + 1) * block)); });
}

int workers_for(int64_t n, int threads) {
  return static_cast<int>(std::clamp<int64_t>(n, 1, resolve_threads(threads)));
}

void parallel_tasks(int64_t n, int threads, const std::function<void(int64_t, int)>& fn) {
  std::atomic<int64_t> next{0};
  FirstError error;
  // After a failure no new task starts; the ones running finish. The calling thread (worker 0)
  // runs its interrupt check before each task it takes.
  const std::function<void(int)> worker = [&](int w) {
    error.run([&] {
      for (int64_t t; !error.failed() && (t = next.fetch_add(1)) < n;) {
        if (w == 0) check_interrupt();
        fn(t, w);
      }
    });
  };
  const int helpers = workers_for(n, threads) - 1;
  if (helpers == 0)
    worker(0);
  else
    WorkerPool::get().run(helpers, worker);
  error.rethrow();
}

}  // namespace panoproj
