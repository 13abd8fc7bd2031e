#include "volstream/amr/probe.h"

#include "volstream/backend/parallel.h"

namespace vs {

std::vector<float> probe_points(const AmrTopology& topology, const Bvh& bvh, const float* values,
                                const std::vector<vec3f>& grid_points) {
  std::vector<float> out(grid_points.size());
  const AmrView view = make_view(topology, values);
  const BvhNode* nodes = bvh.nodes.data();
  const uint32_t node_count = uint32_t(bvh.nodes.size());
  parallel_for("probe", int64_t(out.size()),
               [&](int64_t i) { out[size_t(i)] = sample_point(view, nodes, node_count, grid_points[size_t(i)]); });
  return out;
}

}  // namespace vs
