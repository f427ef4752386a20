// One parallel loop for the library: tasks shared among a few threads, worker exceptions rethrown.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "mtcal/util/interrupt.hpp"

namespace mtcal {

// The number of hardware threads (at least 1).
inline std::size_t hardware_threads() { return std::max<std::size_t>(1, std::thread::hardware_concurrency()); }

// The worker count for a request (0 or less: all hardware threads), never more than the tasks
// and at least 1.
inline std::size_t worker_count(int requested, std::size_t tasks) {
  const std::size_t want = requested > 0 ? static_cast<std::size_t>(requested) : hardware_threads();
  return std::max<std::size_t>(1, std::min(want, tasks));
}

// Calls f(task, worker) once for every task in [0, tasks), on worker_count(threads, tasks)
// threads (the calling thread is worker 0). Tasks are handed out in increasing order to the
// next free worker, so tasks of unequal length balance; which worker runs a task varies from
// run to run. Results are therefore the same for any thread count as long as f writes per-task
// results (or per-worker sums of integers) and the caller combines them in task order: the
// partition of the work into tasks, not the threads, fixes the rounding.
//
// If f throws, no further task is started, the workers are joined and the exception of the
// lowest-numbered failed task is rethrown in the caller. A stop requested with request_interrupt()
// (util/interrupt.hpp) is seen before each task: Interrupted is thrown the same way.
template <class F>
void parallel_for(std::size_t tasks, int threads, F&& f) {
  const std::size_t workers = worker_count(threads, tasks);
  if (tasks == 0) return;
  if (workers == 1) {
    for (std::size_t t = 0; t < tasks; ++t) {
      check_interrupt();
      f(t, std::size_t{0});
    }
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex error_mutex;
  std::exception_ptr error;
  std::size_t error_task = tasks;
  auto work = [&](std::size_t w) {
    for (std::size_t t; !failed.load(std::memory_order_relaxed) && (t = next.fetch_add(1)) < tasks;) {
      try {
        check_interrupt();
        f(t, w);
      } catch (...) {
        const std::lock_guard lock(error_mutex);
        if (t < error_task) {
          error_task = t;
          error = std::current_exception();
        }
        failed = true;
      }
    }
  };
  {
    std::vector<std::jthread> pool;
    pool.reserve(workers - 1);
    for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
    work(0);
  }  // joins
  if (error) std::rethrow_exception(error);
}

// Splits [0, count) into `chunks` contiguous ranges of nearly equal size (the first ones one
// longer) and calls f(begin, end, worker) for each in parallel: for uniform work where one
// call per element would cost more than the element itself.
template <class F>
void parallel_for_ranges(std::size_t count, std::size_t chunks, int threads, F&& f) {
  chunks = std::max<std::size_t>(1, std::min(chunks, count));
  if (count == 0) return;
  const std::size_t per = count / chunks, extra = count % chunks;
  parallel_for(chunks, threads, [&](std::size_t c, std::size_t w) {
    const std::size_t begin = c * per + std::min(c, extra);
    f(begin, begin + per + (c < extra ? 1 : 0), w);
  });
}

}  // namespace mtcal
