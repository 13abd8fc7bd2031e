// Point sampling through the ABRs: locate the ABR with the BVH, then reconstruct from its bricks.
#pragma once
#include <cmath>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/amr/model.h"
#include "volstream/amr/sampler.h"

namespace vs {

// Value at p (grid units), NaN outside every ABR.
VS_HOST_DEVICE inline float sample_point(const AmrView& v, const BvhNode* nodes, uint32_t node_count, const vec3f& p) {
  const int64_t abr = bvh_locate(
      nodes, node_count, [&](uint32_t i) { return v.abrs[i].box; }, p);
  return abr < 0 ? NAN : sample_abr(v, uint32_t(abr), p);
}

// Samples many points (grid units) in parallel on the CPU.
std::vector<float> probe_points(const AmrTopology& topology, const Bvh& bvh, const float* values,
                                const std::vector<vec3f>& grid_points);

}  // namespace vs
