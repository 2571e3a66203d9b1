// Work over threads: every task runs once, and an exception thrown on any thread reaches the
// caller (instead of ending the process) after all threads have joined.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

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

}  // namespace
}  // namespace panoproj
