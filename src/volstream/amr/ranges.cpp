#include "volstream/amr/ranges.h"

#include <algorithm>
#include <mutex>

#include "volstream/core/parallel.h"

namespace vs {

std::vector<Range> compute_abr_ranges(const AmrTopology& topology, const float* values) {
  std::vector<Range> ranges(topology.abrs.size());
  const AmrView view = make_view(topology, values);
  parallel_for("abr_ranges", int64_t(ranges.size()),
               [&](int64_t i) { ranges[size_t(i)] = widen_for_rounding(abr_lane_range(view, uint32_t(i), 0, 1)); });
  return ranges;
}

Range value_range(const float* values, uint64_t count) {
  Range total{INFINITY, -INFINITY};
  std::mutex m;
  parallel_for_ranges(int64_t(count), [&](int64_t begin, int64_t end) {
    Range r{INFINITY, -INFINITY};
    for (int64_t i = begin; i < end; ++i) extend_range(r, values[i]);
    const std::lock_guard lock(m);
    total = {std::min(total.lo, r.lo), std::max(total.hi, r.hi)};
  }, 1 << 16);
  return total;
}

}  // namespace vs
