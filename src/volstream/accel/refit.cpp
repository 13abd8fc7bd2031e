#include "volstream/accel/refit.h"

#include <algorithm>

namespace vs {

bool children_after_parents(const std::vector<BvhNode>& nodes) {
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].is_leaf && (nodes[i].index <= i || size_t(nodes[i].index) + 1 >= nodes.size())) return false;
  return true;
}

void refit_bvh(std::vector<BvhNode>& nodes, const std::vector<box3f>& item_boxes, const std::vector<uint8_t>& keep) {
  // build_bvh_sah appends children after their parent, so a reverse sweep sees children first.
  // This is a serial pass over 2N nodes (a few ms for a million ABRs): cheap next to rendering.
  const auto item_box = [&](uint32_t i) { return item_boxes[i]; };
  const uint8_t* kept = keep.empty() ? nullptr : keep.data();
  for (size_t i = nodes.size(); i-- > 0;) refit_node(nodes.data(), uint32_t(i), item_box, kept);
}

RefitSchedule refit_schedule(const std::vector<BvhNode>& nodes) {
  // Breadth-first from the root gives the groups shallowest first; reversed, deepest first.
  std::vector<std::vector<uint32_t>> levels;
  std::vector<uint32_t> level = nodes.empty() ? std::vector<uint32_t>{} : std::vector<uint32_t>{0};
  while (!level.empty()) {
    std::vector<uint32_t> next;
    for (uint32_t i : level)
      if (!nodes[i].is_leaf) next.insert(next.end(), {nodes[i].index, nodes[i].index + 1});
    levels.push_back(std::move(level));
    level = std::move(next);
  }
  RefitSchedule s;
  s.nodes.reserve(nodes.size());
  for (auto it = levels.rbegin(); it != levels.rend(); ++it) {
    s.group_begin.push_back(uint32_t(s.nodes.size()));
    s.nodes.insert(s.nodes.end(), it->begin(), it->end());
  }
  s.group_begin.push_back(uint32_t(s.nodes.size()));
  return s;
}

}  // namespace vs
