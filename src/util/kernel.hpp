// Internal: run-time CPU dispatch for hot loops, and a small pool that shares tasks among threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

// On x86-64 a hot loop is also compiled for AVX2 + FMA and picked at run time, so a portable
// build still uses the wider vectors where the processor has them.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MTCAL_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MTCAL_KERNEL_CLONES
#endif

namespace mtcal::detail {

// The worker count for a request (0: all hardware threads), never more than the tasks.
inline std::size_t worker_count(int requested, std::size_t tasks) {
  const std::size_t hw = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t want = requested > 0 ? static_cast<std::size_t>(requested) : hw;
  return std::max<std::size_t>(1, std::min(want, tasks));
}

// Calls f(task, worker) for every task in [0, tasks), tasks taken in order by `workers` threads
// (the calling thread is one of them). Which worker runs a task varies from run to run, so f
// must make results independent of it (per-worker partial sums combined in task order, or
// per-task results).
template <class F>
void run_tasks(std::size_t tasks, std::size_t workers, F&& f) {
  std::atomic<std::size_t> next{0};
  auto work = [&](std::size_t w) {
    for (std::size_t t; (t = next.fetch_add(1)) < tasks;) f(t, w);
  };
  std::vector<std::jthread> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
  work(0);
}

}  // namespace mtcal::detail
