#include "volstream/accel/bvh.h"

#include <tbb/task_group.h>

#include <algorithm>
#include <numeric>

namespace vs {
namespace {

// A subtree over k items uses exactly 2k-1 nodes, so every subtree's node range is known before
// it is built: subtrees are built in parallel and the layout is still deterministic.
struct Builder {
  const std::vector<box3f>& boxes;
  std::vector<uint32_t> items;
  std::vector<BvhNode> nodes;
  static constexpr uint32_t kParallelThreshold = 1 << 14;

  box3f bounds(uint32_t begin, uint32_t end) const {
    box3f b = box3f::make_empty();
    for (uint32_t i = begin; i < end; ++i) b.extend(boxes[items[i]]);
    return b;
  }

  // Fills nodes[node] for items [begin, end); its descendants go to nodes[free ...].
  void build(uint32_t node, uint32_t begin, uint32_t end, uint32_t free, tbb::task_group& tasks) {
    nodes[node].box = bounds(begin, end);
    if (end - begin == 1) {
      nodes[node].index = items[begin];
      nodes[node].is_leaf = 1;
      return;
    }
    box3f centroids = box3f::make_empty();
    for (uint32_t i = begin; i < end; ++i) centroids.extend(boxes[items[i]].center());
    const vec3f extent = centroids.size();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end, [&](uint32_t a, uint32_t b) {
      const float ca = boxes[a].lower[axis] + boxes[a].upper[axis], cb = boxes[b].lower[axis] + boxes[b].upper[axis];
      return ca < cb || (ca == cb && a < b);
    });
    nodes[node].index = free;
    nodes[node].is_leaf = 0;
    const uint32_t left_free = free + 2, right_free = left_free + 2 * (mid - begin) - 2;
    if (end - begin > kParallelThreshold) {
      tasks.run([=, this, &tasks] { build(free, begin, mid, left_free, tasks); });
    } else {
      build(free, begin, mid, left_free, tasks);
    }
    build(free + 1, mid, end, right_free, tasks);
  }
};

}  // namespace

Bvh build_bvh(const std::vector<box3f>& boxes) {
  Bvh bvh;
  if (boxes.empty()) return bvh;
  Builder b{boxes, std::vector<uint32_t>(boxes.size()), std::vector<BvhNode>(2 * boxes.size() - 1)};
  std::iota(b.items.begin(), b.items.end(), 0u);
  tbb::task_group tasks;
  b.build(0, 0, uint32_t(boxes.size()), 1, tasks);
  tasks.wait();
  bvh.nodes = std::move(b.nodes);
  return bvh;
}

}  // namespace vs
