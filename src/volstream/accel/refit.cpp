#include "volstream/accel/refit.h"


namespace vs {

bool children_after_parents(const std::vector<BvhNode>& nodes) {
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].is_leaf && (nodes[i].index <= i || size_t(nodes[i].index) + 1 >= nodes.size())) return false;
  return true;
}

void refit_bvh(std::vector<BvhNode>& nodes, const std::vector<box3f>& item_boxes, const std::vector<uint8_t>& keep) {
  // build_bvh_sah appends children after their parent, so a reverse sweep sees children first.
  // This is a serial pass over 2N nodes (a few ms for a million ABRs): cheap next to rendering.
  for (size_t i = nodes.size(); i-- > 0;) {
    BvhNode& n = nodes[i];
    if (n.is_leaf) {
      const bool kept = keep.empty() || keep[n.index] != 0;
      n.box = kept ? item_boxes[n.index] : box3f::make_empty();
    } else {
      box3f b = nodes[n.index].box;
      b.extend(nodes[n.index + 1].box);  // empty boxes are neutral: min/max with +-inf
      n.box = b;
    }
  }
}

}  // namespace vs
