#include "volstream/umesh/element_bvh.h"

#include <tbb/task_group.h>

#include <algorithm>
#include <numeric>

namespace vs {
namespace {

// Descendants of a node over n items (median splits: the layout is known before the build).
uint32_t descendants(uint32_t n) {
  if (n <= kElementLeafSize) return 0;
  const uint32_t left = n / 2;
  return 2 + descendants(left) + descendants(n - left);
}

// Subtrees are laid out [children][left's descendants][right's descendants], so each subtree
// owns a known range of nodes and large ones are built in parallel.
struct Builder {
  const std::vector<box3f>& boxes;
  std::vector<vec3f> centroids;
  ElementBvh bvh;

  // Node `index` over items [begin, end), its descendants from node `free` on.
  void build(uint32_t index, uint32_t begin, uint32_t end, uint32_t free) {
    box3f bounds = box3f::make_empty(), centres = box3f::make_empty();
    for (uint32_t i = begin; i < end; ++i) {
      bounds.extend(boxes[bvh.items[i]]);
      centres.extend(centroids[bvh.items[i]]);
    }
    ElementBvhNode& node = bvh.nodes[index];
    node.box = bounds;
    if (end - begin <= kElementLeafSize) {
      node.first = begin;
      node.count = end - begin;
      return;
    }
    const vec3f extent = centres.size();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(bvh.items.begin() + begin, bvh.items.begin() + mid, bvh.items.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    node.first = free;
    node.count = 0;
    const uint32_t right_free = free + 2 + descendants(mid - begin);
    auto left = [&] { build(free, begin, mid, free + 2); };
    auto right = [&] { build(free + 1, mid, end, right_free); };
    if (end - begin < (1u << 16)) {
      left();
      right();
      return;
    }
    tbb::task_group both;
    both.run(left);
    right();
    both.wait();
  }
};

}  // namespace

ElementBvh build_element_bvh(const std::vector<box3f>& boxes) {
  if (boxes.empty()) return {};
  Builder b{boxes, std::vector<vec3f>(boxes.size()), {}};
  for (size_t i = 0; i < boxes.size(); ++i) b.centroids[i] = boxes[i].center();
  b.bvh.items.resize(boxes.size());
  std::iota(b.bvh.items.begin(), b.bvh.items.end(), 0u);
  b.bvh.nodes.resize(1 + descendants(uint32_t(boxes.size())));
  b.build(0, 0, uint32_t(boxes.size()), 1);
  return std::move(b.bvh);
}

}  // namespace vs
