#include "volstream/render/abr_ranges.h"

#include "volstream/core/parallel.h"

namespace vs {

std::vector<Range> compute_tight_abr_ranges(const AmrTopology& topology, const float* values) {
  std::vector<Range> ranges(topology.abrs.size());
  const AmrView view = make_view(topology, values);
  parallel_for("abr_ranges", int64_t(ranges.size()), [&](int64_t i) { ranges[size_t(i)] = tight_abr_range(view, uint32_t(i)); });
  return ranges;
}

}  // namespace vs
