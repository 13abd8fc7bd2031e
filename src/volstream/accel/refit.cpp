#include "volstream/accel/refit.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>

namespace vs {

namespace {

// The end of the run of node n's descendants if the subtree at n is laid out as
// subtrees_are_runs() requires (descendants from `first` on), else 0.
size_t run_end(const std::vector<BvhNode>& nodes, uint32_t n, size_t first, int depth) {
  if (nodes[n].is_leaf) return first;
  if (depth >= kMaxBvhDepth || nodes[n].index != first || first + 2 > nodes.size()) return 0;
  const size_t left_end = run_end(nodes, uint32_t(first), first + 2, depth + 1);
  return left_end ? run_end(nodes, uint32_t(first + 1), left_end, depth + 1) : 0;
}

// Where the descendants of inner node n end: build_bvh_sah stores them as one run [n.index, end):
// the two children, the left child's descendants, then the right child's. So the run ends with
// the right child's run if that child is inner, else with the left child's, else after the pair.
size_t descendants_end(const std::vector<BvhNode>& nodes, uint32_t n) {
  for (;;) {
    const uint32_t left = nodes[n].index;
    if (!nodes[left + 1].is_leaf)
      n = left + 1;
    else if (!nodes[left].is_leaf)
      n = left;
    else
      return size_t(left) + 2;
  }
}

// A subtree with at most `serial` descendants is refit by one thread, sweeping its run backwards.
template <typename ItemBox>
void refit_subtree(std::vector<BvhNode>& nodes, uint32_t n, const ItemBox& item_box, const uint8_t* keep,
                   size_t serial) {
  if (!nodes[n].is_leaf) {
    const uint32_t first = nodes[n].index;
    const size_t end = descendants_end(nodes, n);
    if (end - first <= serial) {
      for (size_t i = end; i-- > first;) refit_node(nodes.data(), uint32_t(i), item_box, keep);
    } else {
      tbb::parallel_invoke([&] { refit_subtree(nodes, first, item_box, keep, serial); },
                           [&] { refit_subtree(nodes, first + 1, item_box, keep, serial); });
    }
  }
  refit_node(nodes.data(), n, item_box, keep);
}

}  // namespace

bool subtrees_are_runs(const std::vector<BvhNode>& nodes) {
  return nodes.empty() || run_end(nodes, 0, 1, 0) == nodes.size();
}

std::string bvh_tree_problem(const std::vector<BvhNode>& nodes, size_t item_count) {
  if (item_count == 0) return nodes.empty() ? "" : "nodes without items";
  if (nodes.size() != 2 * item_count - 1)
    return std::to_string(nodes.size()) + " nodes for " + std::to_string(item_count) + " items";
  std::vector<uint8_t> seen(item_count, 0);
  for (const BvhNode& n : nodes) {
    if (n.is_leaf > 1) return "a node is neither leaf nor inner";
    if (!n.is_leaf) continue;
    if (n.index >= item_count || seen[n.index]) return "item " + std::to_string(n.index) + " out of range or twice";
    seen[n.index] = 1;
  }
  // With 2n - 1 nodes and n distinct leaves, every inner node is a pair of children: the run
  // layout (checked to the depth limit) then makes it one binary tree.
  if (!subtrees_are_runs(nodes)) return "nodes out of order or deeper than " + std::to_string(kMaxBvhDepth);
  return "";
}

void refit_bvh(std::vector<BvhNode>& nodes, const std::vector<box3f>& item_boxes, const std::vector<uint8_t>& keep,
               size_t serial_subtree) {
  // Children come after their parent and each subtree is one run of nodes, so the two subtrees
  // of a large node refit in parallel and a small one in a single backward sweep.
  if (nodes.empty()) return;
  const auto item_box = [&](uint32_t i) { return item_boxes[i]; };
  refit_subtree(nodes, 0, item_box, keep.empty() ? nullptr : keep.data(), serial_subtree);
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
