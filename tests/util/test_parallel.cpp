// parallel_for: every task once, worker exceptions rethrown, results independent of threads.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "mtcal/util/parallel.hpp"

namespace mtcal {
namespace {

TEST(ParallelFor, RunsEveryTaskExactlyOnce) {
  for (int threads : {1, 2, 3, 8, 0}) {
    std::vector<std::atomic<int>> seen(1000);
    parallel_for(seen.size(), threads, [&](std::size_t t, std::size_t) { ++seen[t]; });
    for (std::size_t t = 0; t < seen.size(); ++t)
      EXPECT_EQ(seen[t].load(), 1) << "task " << t << ", " << threads << " threads";
  }
}

TEST(ParallelFor, WorkerIndexWithinWorkerCount) {
  const std::size_t workers = worker_count(4, 100);
  EXPECT_EQ(workers, 4u);
  std::atomic<bool> bad{false};
  parallel_for(100, 4, [&](std::size_t, std::size_t w) {
    if (w >= workers) bad = true;
  });
  EXPECT_FALSE(bad);
  EXPECT_EQ(worker_count(8, 3), 3u);  // never more workers than tasks
  EXPECT_EQ(worker_count(0, 0), 1u);
  EXPECT_GE(worker_count(0, 1000), 1u);
}

TEST(ParallelFor, NoTasksCallsNothing) {
  bool called = false;
  parallel_for(0, 4, [&](std::size_t, std::size_t) { called = true; });
  parallel_for_ranges(0, 4, 4, [&](std::size_t, std::size_t, std::size_t) { called = true; });
  EXPECT_FALSE(called);
}

TEST(ParallelFor, ExceptionOfAWorkerReachesTheCaller) {
  for (int threads : {1, 4}) {
    try {
      parallel_for(64, threads, [&](std::size_t t, std::size_t) {
        if (t == 17 || t == 40) throw std::runtime_error("task " + std::to_string(t));
      });
      FAIL() << "no exception with " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "task 17") << threads << " threads";  // the lowest failed task
    }
  }
}

// Per-task sums combined in task order: the same bits with 1 thread and with many.
TEST(ParallelFor, OneThreadEqualsManyThreads) {
  auto run = [](int threads) {
    std::vector<double> part(97, 0.0);
    parallel_for(part.size(), threads, [&](std::size_t t, std::size_t) {
      for (int i = 1; i < 10000; ++i) part[t] += std::sin(static_cast<double>(t * 10000 + i)) / i;
    });
    double s = 0;
    for (double p : part) s += p;
    return s;
  };
  const double one = run(1);
  for (int threads : {2, 3, 7, 0}) EXPECT_EQ(run(threads), one) << threads << " threads";
}

TEST(ParallelFor, RangesCoverEveryElementOnce) {
  for (std::size_t chunks : {1u, 3u, 7u, 200u}) {
    std::vector<std::atomic<int>> seen(101);
    parallel_for_ranges(seen.size(), chunks, 0, [&](std::size_t b, std::size_t e, std::size_t) {
      for (std::size_t i = b; i < e; ++i) ++seen[i];
    });
    for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i].load(), 1) << chunks << " chunks";
  }
}

}  // namespace
}  // namespace mtcal
