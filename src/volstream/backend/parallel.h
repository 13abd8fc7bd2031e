// parallel_for: the one way kernels are launched. On the CPU it is a oneTBB loop over chunks,
// timed per name (launch_times.h); the CUDA backend (cuda/launch.cuh) provides the same
// signature as a grid launch, timed with CUDA events.
#pragma once
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <vector>

#include "volstream/backend/launch_times.h"
#include "volstream/core/stopwatch.h"

namespace vs {

template <typename F>
void parallel_for(const char* name, int64_t n, F&& f) {
  if (n <= 0) return;
  const Stopwatch watch;
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, n), [&](const tbb::blocked_range<int64_t>& r) {
    for (int64_t i = r.begin(); i != r.end(); ++i) f(i);
  });
  launch_times().add(name, watch.seconds());
}

// Like parallel_for, but hands each task a contiguous [begin, end) range (for per-task state).
// Not timed: used inside larger steps (format conversion, demo generation) that time themselves.
template <typename F>
void parallel_for_ranges(int64_t n, F&& f, int64_t grain = 1) {
  if (n <= 0) return;
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, n, grain),
                    [&](const tbb::blocked_range<int64_t>& r) { f(r.begin(), r.end()); });
}

// The smallest i in [0, n) for which ok(i) is false, or -1 where there is none: the serial loop's
// answer found in parallel, so that a check's error message names the same item whatever the
// threads did (for the checks of a dataset's load over millions of records).
// Items are tested in blocks without a branch or an atomic load per item (the load's neighbour
// check: 14 -> 8 instructions an item); only a failing block is searched item by item.
template <typename Ok>
int64_t first_failing(int64_t n, Ok&& ok, int64_t grain = 4096) {
  constexpr int64_t kBlock = 256;
  std::atomic<int64_t> first{n};
  parallel_for_ranges(
      n,
      [&](int64_t begin, int64_t end) {
        for (int64_t at = begin; at < end && at < first.load(std::memory_order_relaxed); at += kBlock) {
          const int64_t stop = std::min(at + kBlock, end);
          bool all = true;
          for (int64_t i = at; i < stop; ++i) all &= bool(ok(i));
          if (all) continue;
          int64_t i = at;
          while (ok(i)) ++i;
          int64_t seen = first.load(std::memory_order_relaxed);
          while (i < seen && !first.compare_exchange_weak(seen, i, std::memory_order_relaxed)) {
          }
          return;
        }
      },
      grain);
  const int64_t found = first.load();
  return found == n ? -1 : found;
}

// Runs first() and second() in parallel and then throws what the serial order `first(); second();`
// would have thrown: first's exception if it threw, else second's (so that a damaged input's
// message does not depend on which thread failed sooner).
template <typename First, typename Second>
void parallel_invoke_in_order(First&& first, Second&& second) {
  std::exception_ptr errors[2];
  auto catching = [&](auto& f, std::exception_ptr& error) {
    try {
      f();
    } catch (...) {
      error = std::current_exception();
    }
  };
  tbb::parallel_invoke([&] { catching(first, errors[0]); }, [&] { catching(second, errors[1]); });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// Runs f(i) for every i in [0, n) in parallel, one item a task (for coarse items: a file each),
// and then throws what the serial loop would have thrown: the exception of the smallest i that
// threw, whichever thread failed first.
template <typename F>
void parallel_each_in_order(int64_t n, F&& f) {
  if (n <= 0) return;
  std::vector<std::exception_ptr> errors(static_cast<size_t>(n));
  parallel_for_ranges(n, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      try {
        f(i);
      } catch (...) {
        errors[size_t(i)] = std::current_exception();
      }
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace vs
