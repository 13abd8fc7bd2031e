#include "volstream/umesh/element_bvh.h"

#include <algorithm>
#include <numeric>

namespace vs {
namespace {

struct Builder {
  const std::vector<box3f>& boxes;
  std::vector<vec3f> centroids;
  ElementBvh bvh;

  // Fills node `index` with items [begin, end) (already placed in bvh.items).
  void build(uint32_t index, uint32_t begin, uint32_t end) {
    box3f bounds = box3f::make_empty(), centres = box3f::make_empty();
    for (uint32_t i = begin; i < end; ++i) {
      bounds.extend(boxes[bvh.items[i]]);
      centres.extend(centroids[bvh.items[i]]);
    }
    bvh.nodes[index].box = bounds;
    if (end - begin <= kElementLeafSize) {
      bvh.nodes[index].first = begin;
      bvh.nodes[index].count = end - begin;
      return;
    }
    const vec3f extent = centres.size();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(bvh.items.begin() + begin, bvh.items.begin() + mid, bvh.items.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    const uint32_t left = uint32_t(bvh.nodes.size());
    bvh.nodes.push_back({});
    bvh.nodes.push_back({});
    bvh.nodes[index].first = left;
    bvh.nodes[index].count = 0;
    build(left, begin, mid);
    build(left + 1, mid, end);
  }
};

}  // namespace

ElementBvh build_element_bvh(const std::vector<box3f>& boxes) {
  Builder b{boxes, std::vector<vec3f>(boxes.size()), {}};
  if (boxes.empty()) return {};
  for (size_t i = 0; i < boxes.size(); ++i) b.centroids[i] = boxes[i].center();
  b.bvh.items.resize(boxes.size());
  std::iota(b.bvh.items.begin(), b.bvh.items.end(), 0u);
  b.bvh.nodes.reserve(2 * boxes.size() / kElementLeafSize + 2);
  b.bvh.nodes.push_back({});
  b.build(0, 0, uint32_t(boxes.size()));
  return std::move(b.bvh);
}

}  // namespace vs
