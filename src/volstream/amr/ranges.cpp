#include "volstream/amr/ranges.h"

#include <algorithm>
#include <mutex>

#include "volstream/backend/parallel.h"

namespace vs {

std::vector<uint64_t> macrocell_offsets(const std::vector<Brick>& bricks) {
  std::vector<uint64_t> offsets(bricks.size() + 1, 0);
  for (size_t i = 0; i < bricks.size(); ++i) {
    const vec3i n = macrocell_dims(bricks[i]);
    offsets[i + 1] = offsets[i] + uint64_t(n.x) * uint32_t(n.y) * uint32_t(n.z);
  }
  return offsets;
}

std::vector<Range> compute_abr_ranges(const AmrTopology& topology, const float* values,
                                      const std::vector<uint64_t>* macro_offset, RangeMode mode) {
  const std::vector<uint64_t> own = macro_offset ? std::vector<uint64_t>{} : macrocell_offsets(topology.bricks);
  const std::vector<uint64_t>& offsets = macro_offset ? *macro_offset : own;
  std::vector<Range> macro(offsets.back());
  const RangeView view{make_view(topology, values), offsets.data(), macro.data()};
  parallel_for("macrocells", int64_t(topology.bricks.size()), [&](int64_t brick) {
    const Brick& b = topology.bricks[size_t(brick)];
    const vec3i n = macrocell_dims(b);
    Range* out = macro.data() + offsets[size_t(brick)];
    for (int32_t z = 0; z < n.z; ++z)
      for (int32_t y = 0; y < n.y; ++y)
        for (int32_t x = 0; x < n.x; ++x) *out++ = macrocell_range(b, values, {x, y, z});
  });
  std::vector<Range> ranges(topology.abrs.size());
  if (mode == RangeMode::tight) {
    parallel_for("abr_ranges", int64_t(ranges.size()),
                 [&](int64_t i) { ranges[size_t(i)] = widen_for_rounding(abr_lane_range(view, uint32_t(i), 0, 1)); });
    return ranges;
  }
  std::vector<Range> brick_ranges(topology.bricks.size(), Range{INFINITY, -INFINITY});
  parallel_for("brick_ranges", int64_t(brick_ranges.size()), [&](int64_t b) {
    for (uint64_t m = offsets[size_t(b)]; m < offsets[size_t(b) + 1]; ++m)
      extend_range(brick_ranges[size_t(b)], macro[m]);
  });
  parallel_for("abr_ranges", int64_t(ranges.size()), [&](int64_t i) {
    const Abr& a = topology.abrs[size_t(i)];
    Range r{INFINITY, -INFINITY};
    for (uint32_t k = 0; k < a.brick_count; ++k) extend_range(r, brick_ranges[topology.abr_bricks[a.first_brick + k]]);
    ranges[size_t(i)] = widen_for_rounding(r);
  });
  return ranges;
}

Range value_range(const float* values, uint64_t count) {
  Range total{INFINITY, -INFINITY};
  std::mutex m;
  parallel_for_ranges(
      int64_t(count),
      [&](int64_t begin, int64_t end) {
        Range r{INFINITY, -INFINITY};
        for (int64_t i = begin; i < end; ++i) extend_range(r, values[i]);
        const std::lock_guard lock(m);
        total = {std::min(total.lo, r.lo), std::max(total.hi, r.hi)};
      },
      1 << 16);
  return total;
}

}  // namespace vs
