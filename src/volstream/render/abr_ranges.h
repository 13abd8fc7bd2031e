// Transitional: the tight ranges moved to amr/ranges.h (compute_abr_ranges).
#pragma once
#include "volstream/amr/ranges.h"

namespace vs {
inline std::vector<Range> compute_tight_abr_ranges(const AmrTopology& t, const float* values) {
  return compute_abr_ranges(t, values);
}
}  // namespace vs
