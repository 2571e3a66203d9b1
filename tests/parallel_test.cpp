// Work over threads: every task runs once, and an exception thrown on any thread reaches the
// caller (instead of ending the process) after all threads have joined. The threads are kept
// between calls: worker indices stay distinct and in range, calls from several threads at once
// and calls inside a task finish, and a forked child still works.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "base/parallel.hpp"

namespace panoproj {
namespace {

TEST(Parallel, EveryTaskRunsOnce) {
  std::vector<std::atomic<int>> runs(1000);
  parallel_tasks(1000, 4, [&](int64_t t, int) { ++runs[static_cast<size_t>(t)]; });
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
  std::vector<std::atomic<int>> rows(777);
  parallel_rows(777, 3, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) ++rows[static_cast<size_t>(y)];
  });
  for (const auto& r : rows) EXPECT_EQ(r.load(), 1);
}

TEST(Parallel, ExceptionsOnAnyThreadReachTheCaller) {
  for (int64_t bad : {0, 1, 57, 199}) {  // the calling thread's first task, others', the last
    std::atomic<int64_t> ran{0};
    EXPECT_THROW(parallel_tasks(200, 3,
                                [&](int64_t t, int) {
                                  ++ran;
                                  if (t == bad) throw std::runtime_error("task " + std::to_string(t));
                                }),
                 std::runtime_error)
        << bad;
    EXPECT_LE(ran.load(), 200);
  }
  for (int64_t bad_band : {0, 2}) {
    EXPECT_THROW(parallel_rows(300, 3,
                               [&](int64_t y0, int64_t) {
                                 if (y0 == bad_band * 100) throw std::invalid_argument("band");
                               }),
                 std::invalid_argument)
        << bad_band;
  }
  // After a failure, the same pool machinery runs again normally.
  std::atomic<int64_t> sum{0};
  parallel_tasks(100, 3, [&](int64_t t, int) { sum += t; });
  EXPECT_EQ(sum.load(), 4950);
}

// Per-worker state is indexed by worker: no two threads may share an index within a call.
TEST(Parallel, WorkerIndicesAreDistinctAndInRange) {
  for (int threads : {2, 3, 8}) {
    const int workers = workers_for(400, threads);
    std::vector<std::atomic<int>> inside(static_cast<size_t>(workers));
    std::vector<std::atomic<std::thread::id>> owner(static_cast<size_t>(workers));
    std::atomic<bool> bad{false};
    parallel_tasks(400, threads, [&](int64_t, int w) {
      if (w < 0 || w >= workers) {
        bad = true;
        return;
      }
      auto& slot = owner[static_cast<size_t>(w)];
      std::thread::id none{};
      if (!slot.compare_exchange_strong(none, std::this_thread::get_id()) && none != std::this_thread::get_id()) bad = true;
      if (++inside[static_cast<size_t>(w)] != 1) bad = true;
      std::this_thread::sleep_for(std::chrono::microseconds(20));
      --inside[static_cast<size_t>(w)];
    });
    EXPECT_FALSE(bad.load()) << threads;
  }
}

TEST(Parallel, ConcurrentAndNestedCallsFinish) {
  std::atomic<int64_t> sum{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < 4; ++c)
    callers.emplace_back([&] {
      for (int round = 0; round < 20; ++round)
        parallel_tasks(16, 3, [&](int64_t, int) {
          parallel_tasks(10, 2, [&](int64_t t, int) { sum += t; });  // a call inside a task
        });
    });
  for (auto& t : callers) t.join();
  EXPECT_EQ(sum.load(), 4 * 20 * 16 * 45);
}

TEST(Parallel, ForkedChildStillWorks) {
  parallel_tasks(100, 3, [](int64_t, int) {});  // the parent's threads exist
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::atomic<int64_t> sum{0};
    parallel_tasks(1000, 3, [&](int64_t t, int) { sum += t; });
    _exit(sum.load() == 499500 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

}  // namespace
}  // namespace panoproj
