// Refit: recompute a BVH's boxes bottom-up for new item boxes, keeping its topology (the tree
// built once over all ABRs). Items that are not kept get an inverted (empty) box, so rays never
// enter them and subtrees with no kept item become empty too ("refit cuts").
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/accel/bvh.h"

namespace vs {

// Refits node i from its item (leaf; keep may be null: keep all) or from its two children,
// which must be refit already. item_box(i) gives item i's box. Shared by the CPU and GPU refits.
template <typename ItemBox>
VS_HOST_DEVICE inline void refit_node(BvhNode* nodes, uint32_t i, ItemBox&& item_box, const uint8_t* keep) {
  BvhNode& n = nodes[i];
  if (n.is_leaf) {
    n.box = (!keep || keep[n.index]) ? item_box(n.index) : box3f::make_empty();
  } else {
    box3f b = nodes[n.index].box;
    b.extend(nodes[n.index + 1].box);  // empty boxes are neutral: min/max with +-inf
    n.box = b;
  }
}

// nodes: a tree from build_bvh_sah (subtrees_are_runs). keep[i] != 0 keeps item i
// with box item_boxes[i]; keep may be empty (keep all).
// Subtrees with more than serial_subtree descendants refit their two halves in parallel (tests
// lower it to split small trees everywhere).
inline constexpr size_t kRefitSerialSubtree = size_t(1) << 15;
void refit_bvh(std::vector<BvhNode>& nodes, const std::vector<box3f>& item_boxes, const std::vector<uint8_t>& keep,
               size_t serial_subtree = kRefitSerialSubtree);

// True when the tree has the layout build_bvh_sah gives it and refit_bvh relies on: the root
// first, then for every inner node its two children side by side, followed by the nodes of the
// left child's subtree, then those of the right child's, so every subtree's descendants are one
// run of nodes that starts at its first child.
bool subtrees_are_runs(const std::vector<BvhNode>& nodes);

// Empty when `nodes` (boxes ignored) is a tree over items 0..item_count-1 as build_bvh_sah makes
// them: 2 * item_count - 1 nodes laid out as subtrees_are_runs requires, at most kMaxBvhDepth
// deep, every item in exactly one leaf; else what is wrong. Trees read from files are checked so.
std::string bvh_tree_problem(const std::vector<BvhNode>& nodes, size_t item_count);

// The nodes grouped by depth, deepest first: the nodes of one group are independent and every
// node's children lie in earlier groups, so a GPU refits one group per launch.
struct RefitSchedule {
  std::vector<uint32_t> nodes;        // node indices, group after group
  std::vector<uint32_t> group_begin;  // group g is nodes[group_begin[g], group_begin[g + 1])
};
RefitSchedule refit_schedule(const std::vector<BvhNode>& nodes);

}  // namespace vs
