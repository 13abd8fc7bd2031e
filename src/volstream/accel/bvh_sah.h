// Binned SAH build of the binary BVH (one item per leaf, the two
// children adjacent and after their parent, so refit_bvh applies unchanged).
//
// ABRs mix a few huge coarse regions with very many small ones near refinement boundaries; a
// median split by count then lumps huge and tiny boxes together and rays visit many nodes per
// leaf found. The surface area heuristic keeps large boxes near the root.
#pragma once
#include <vector>

#include "volstream/accel/bvh.h"

namespace vs {

// Depth stays below kMaxBvhDepth (bvh.h): near that depth the build falls back to median splits,
// which halve the item count.
Bvh build_bvh_sah(const std::vector<box3f>& boxes);

}  // namespace vs
