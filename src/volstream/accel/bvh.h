// A binary BVH over boxes (the ABRs), one box per leaf so that a leaf can be culled on its own.
// Built by build_bvh_sah (bvh_sah.h).
// Children of a node are stored next to each other: right child = left child + 1.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/core/math.h"

namespace vs {

// Trees stay at most this deep (traversal stacks hold 64 entries); build_bvh_sah keeps to it and
// stored trees are checked against it (refit.h, bvh_tree_problem).
inline constexpr int kMaxBvhDepth = 60;

struct BvhNode {
  box3f box;
  uint32_t index;  // inner node: first child; leaf: item index
  uint32_t is_leaf;
};

struct Bvh {
  std::vector<BvhNode> nodes;  // nodes[0] is the root (when not empty)
};

// Index of an item whose box contains p (closed boxes), or -1. For disjoint items (ABRs) any
// point on a shared face belongs to either, both give the same reconstruction.
template <typename ItemBox>
VS_HOST_DEVICE int64_t bvh_locate(const BvhNode* nodes, uint32_t node_count, ItemBox&& item_box, const vec3f& p) {
  if (node_count == 0) return -1;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& n = nodes[stack[--top]];
    if (!n.box.contains(p)) continue;
    if (n.is_leaf) {
      if (item_box(n.index).contains(p)) return n.index;
      continue;
    }
    stack[top++] = n.index + 1;
    stack[top++] = n.index;
  }
  return -1;
}

}  // namespace vs
