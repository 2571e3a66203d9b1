// A batch's pipeline (jobs/convert/frame_pipeline.hpp): each stage takes the frames in order, a
// frame's buffers are reused only once the stage before is done with them, the stages do overlap,
// and a failure anywhere ends the batch as one frame after another would: the frames before it
// written, none after it, its exception rethrown (the earliest frame's of several).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "jobs/convert/frame_pipeline.hpp"

namespace panoproj {
namespace {

// Each stage logs its frames; the checks below read the logs.
struct Log {
  std::mutex mutex;
  std::vector<size_t> read_started, read_done, converted_started, converted_done, written_started, written_done,
      reported;
  std::atomic<int> busy_readers{0};
  std::atomic<int> most_readers{0};
  void add(std::vector<size_t>& v, size_t i) {
    std::lock_guard<std::mutex> lock(mutex);
    v.push_back(i);
  }
  bool has(const std::vector<size_t>& v, size_t i) {
    std::lock_guard<std::mutex> lock(mutex);
    return std::find(v.begin(), v.end(), i) != v.end();
  }
  size_t count(const std::vector<size_t>& v) {
    std::lock_guard<std::mutex> lock(mutex);
    return v.size();
  }
};

enum class Stage { Read, Convert, Write, Report };

struct Failure {
  Stage stage;
  size_t frame;
};

// Runs n frames (or, with `end`, frames until read says frame `end` is none); each stage sleeps a
// little (so they overlap) and throws "<stage> <frame>" where told. Returns the exception's
// message, "" if none.
std::string run(size_t n, int readers, Log& log, std::vector<Failure> failures = {},
                size_t end = SIZE_MAX) {
  auto step = [&](Stage stage, size_t i, std::vector<size_t>& started, std::vector<size_t>& done, int micros) {
    log.add(started, i);
    auto fail = [&] {
      for (const Failure& f : failures)
        if (f.stage == stage && f.frame == i) throw std::runtime_error("stage " + std::to_string(int(stage)) + " frame " + std::to_string(i));
    };
    if (stage == Stage::Read) fail();  // (reads fail at once, the others after their work)
    std::this_thread::sleep_for(std::chrono::microseconds(micros));
    fail();
    log.add(done, i);
  };
  FrameStages stages;
  stages.read = [&](size_t i) {
    if (i >= end) return false;
    const int now = ++log.busy_readers;
    for (int m = log.most_readers; now > m && !log.most_readers.compare_exchange_weak(m, now);) {
    }
    // The first `readers` frames may all decode at once: each waits (at most 5 s) until all have
    // been busy together, so that the overlap checked below does not hang on the scheduler.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (i < static_cast<size_t>(readers) && log.most_readers < readers && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    // Reuse: frame i's read slot was frame i - slots's, whose convert must have returned.
    const size_t slots = static_cast<size_t>(readers) + 1;
    if (i >= slots && log.count(log.converted_done) < i - slots + 1)
      ADD_FAILURE() << "read " << i << " before convert " << i - slots;
    try {
      step(Stage::Read, i, log.read_started, log.read_done, 3000);
    } catch (...) {
      --log.busy_readers;
      throw;
    }
    --log.busy_readers;
    return true;
  };
  stages.convert = [&](size_t i) {
    if (!log.has(log.read_done, i)) ADD_FAILURE() << "convert " << i << " before its read";
    if (i >= 2 && log.count(log.written_done) < i - 1) ADD_FAILURE() << "convert " << i << " before write " << i - 2;
    step(Stage::Convert, i, log.converted_started, log.converted_done, 1500);
  };
  stages.write = [&](size_t i) {
    if (log.count(log.converted_done) <= i) ADD_FAILURE() << "write " << i << " before its convert";
    step(Stage::Write, i, log.written_started, log.written_done, 1000);
  };
  const std::thread::id caller = std::this_thread::get_id();
  stages.written = [&](size_t i) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    std::vector<size_t> unused;
    step(Stage::Report, i, log.reported, unused, 0);
  };
  try {
    run_frame_pipeline(n, readers, stages);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

std::vector<size_t> first(size_t k) {
  std::vector<size_t> v(k);
  for (size_t i = 0; i < k; ++i) v[i] = i;
  return v;
}

TEST(FramePipeline, EveryStageTakesTheFramesInOrderAndTheyOverlap) {
  for (int readers : {1, 2, 3}) {
    Log log;
    EXPECT_EQ(run(12, readers, log), "");
    EXPECT_EQ(log.converted_done, first(12));
    EXPECT_EQ(log.written_done, first(12));
    EXPECT_EQ(log.reported, first(12));
    std::vector<size_t> reads = log.read_done;
    std::sort(reads.begin(), reads.end());
    EXPECT_EQ(reads, first(12));
    EXPECT_EQ(log.most_readers.load(), readers) << "the readers decode at once";
  }
  Log none;
  EXPECT_EQ(run(0, 2, none), "");
  EXPECT_TRUE(none.read_started.empty());
}

TEST(FramePipeline, AFailureWritesTheFramesBeforeItAndNoneAfter) {
  for (Stage stage : {Stage::Read, Stage::Convert, Stage::Write})
    for (size_t k : {size_t{0}, size_t{1}, size_t{4}, size_t{9}}) {
      Log log;
      const std::string error = run(10, 2, log, {{stage, k}});
      EXPECT_EQ(error, "stage " + std::to_string(int(stage)) + " frame " + std::to_string(k));
      EXPECT_EQ(log.written_done, first(k)) << int(stage) << " " << k;
      EXPECT_EQ(log.reported, first(k));
      for (size_t i : log.converted_started) EXPECT_LE(i, k + 1) << "no frame converted past the failure's next";
    }
}

TEST(FramePipeline, OfSeveralFailuresTheEarliestFramesIsRethrown) {
  // The later frame's read fails first (it starts as frame 2's convert ends, and fails at
  // once), frame 3's convert or frame 2's write after.
  Log log;
  EXPECT_EQ(run(10, 2, log, {{Stage::Read, 5}, {Stage::Convert, 3}}), "stage 1 frame 3");
  EXPECT_EQ(log.written_done, first(3));
  Log log2;
  EXPECT_EQ(run(10, 2, log2, {{Stage::Write, 2}, {Stage::Read, 4}}), "stage 2 frame 2");
  EXPECT_EQ(log2.written_done, first(2));
}

TEST(FramePipeline, AReportThatThrowsEndsTheBatch) {
  // Reports trail the writes: frame 4's comes after its write, perhaps after frame 5's; no frame
  // is taken once it has thrown.
  Log log;
  EXPECT_EQ(run(10, 2, log, {{Stage::Report, 4}}), "stage 3 frame 4");
  EXPECT_EQ(log.reported, first(5));
  ASSERT_GE(log.written_done.size(), 5u);
  EXPECT_LT(log.written_done.size(), 10u);
  EXPECT_EQ(log.written_done, first(log.written_done.size()));
}

TEST(FramePipeline, AStreamOfUnknownLengthEndsWhereReadSaysSo) {
  for (int readers : {1, 2})
    for (size_t end : {size_t{0}, size_t{1}, size_t{7}}) {
      Log log;
      EXPECT_EQ(run(kUnknownFrames, readers, log, {}, end), "");
      EXPECT_EQ(log.written_done, first(end)) << readers << " " << end;
      EXPECT_EQ(log.reported, first(end));
    }
  Log log;  // a failure before the end still ends it with its error
  EXPECT_EQ(run(kUnknownFrames, 2, log, {{Stage::Convert, 3}}, 7), "stage 1 frame 3");
  EXPECT_EQ(log.written_done, first(3));
}

}  // namespace
}  // namespace panoproj
