// Refit: recompute a BVH's boxes bottom-up for new item boxes, keeping its topology (the tree
// built once over all ABRs). Items that are not kept get an inverted (empty) box, so rays never
// enter them and subtrees with no kept item become empty too ("refit cuts").
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/accel/bvh.h"

namespace vs {

// nodes: a tree from build_bvh_sah (children stored after their parent). keep[i] != 0 keeps item i
// with box item_boxes[i]; keep may be empty (keep all).
void refit_bvh(std::vector<BvhNode>& nodes, const std::vector<box3f>& item_boxes, const std::vector<uint8_t>& keep);

// True when every inner node's children come after it (the order refit_bvh relies on).
bool children_after_parents(const std::vector<BvhNode>& nodes);

}  // namespace vs
