#include "volstream/accel/bvh.h"

#include <algorithm>
#include <numeric>

namespace vs {
namespace {

struct Builder {
  const std::vector<box3f>& boxes;
  std::vector<uint32_t> items;
  std::vector<BvhNode> nodes;

  box3f bounds(uint32_t begin, uint32_t end) const {
    box3f b = box3f::make_empty();
    for (uint32_t i = begin; i < end; ++i) b.extend(boxes[items[i]]);
    return b;
  }

  // Fills nodes[node] for items [begin, end). Depth stays below 64 because splits are medians.
  void build(uint32_t node, uint32_t begin, uint32_t end) {
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
    const uint32_t left = uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    nodes[node].index = left;
    nodes[node].is_leaf = 0;
    build(left, begin, mid);
    build(left + 1, mid, end);
  }
};

}  // namespace

Bvh build_bvh(const std::vector<box3f>& boxes) {
  Bvh bvh;
  if (boxes.empty()) return bvh;
  Builder b{boxes, std::vector<uint32_t>(boxes.size()), {}};
  std::iota(b.items.begin(), b.items.end(), 0u);
  b.nodes.reserve(2 * boxes.size());
  b.nodes.resize(1);
  b.build(0, 0, uint32_t(boxes.size()));
  bvh.nodes = std::move(b.nodes);
  return bvh;
}

}  // namespace vs
