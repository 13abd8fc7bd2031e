#include "volstream/umesh/compact_store.h"

#include <cmath>
#include <string>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

constexpr uint32_t kMaxSubmeshVertices = 65536;
// for_each_leaf_holding's stack holds 64 nodes and a node pushes at most kCompactWidth children:
// below this depth of inner nodes no child is ever dropped.
constexpr int kMaxInnerDepth = 8;

std::string in(const fs::path& dir, const char* file) { return (dir / file).string(); }

bool box_holds(const box3f& outer, const box3f& inner) {
  return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y && outer.lower.z <= inner.lower.z &&
         outer.upper.x >= inner.upper.x && outer.upper.y >= inner.upper.y && outer.upper.z >= inner.upper.z;
}

void check_vertices_and_submeshes(const CompactMesh& c, const fs::path& dir) {
  for (size_t i = 0; i < c.vertices.size(); ++i) {
    const vec3f& v = c.vertices[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      input_error(in(dir, "compact_vertices.bin"), "vertex " + std::to_string(i) + " is not finite");
  }
  const std::string file = in(dir, "compact_submeshes.bin");
  input_check(!c.submeshes.empty() && c.submeshes[0].first_vertex == 0, file, "the first sub-mesh must start at 0");
  for (size_t s = 0; s < c.submeshes.size(); ++s) {
    const uint64_t begin = c.submeshes[s].first_vertex;
    const uint64_t end = s + 1 < c.submeshes.size() ? c.submeshes[s + 1].first_vertex : c.vertices.size();
    if (!(begin < end && end <= c.vertices.size() && end - begin <= kMaxSubmeshVertices))
      input_error(file, "sub-mesh " + std::to_string(s) + " has a bad vertex range");
  }
}

// Leaves: counts, index runs and indices in range; the element counts by type.
void check_leaves(const CompactMesh& c, const uint64_t by_type[4], const fs::path& dir) {
  constexpr uint32_t kVertices[4] = {4, 5, 6, 8};
  const std::string file = in(dir, "compact_leaves.bin");
  uint64_t counted[4] = {};
  for (size_t l = 0; l < c.leaves.size(); ++l) {
    const CompactLeaf& leaf = c.leaves[l];
    auto fail = [&](const std::string& what) { input_error(file, "leaf " + std::to_string(l) + " " + what); };
    const uint32_t elements = leaf_element_count(leaf);
    if (elements == 0 || elements > kMultiLeafSize) fail("holds " + std::to_string(elements) + " elements");
    if (leaf.submesh >= c.submeshes.size()) fail("names a sub-mesh that does not exist");
    uint64_t indices = 0;
    for (int t = 0; t < 4; ++t) indices += uint64_t(leaf.counts[t]) * kVertices[t], counted[t] += leaf.counts[t];
    if (uint64_t(leaf.first_index) + indices > c.indices.size()) fail("has indices beyond the index array");
    const uint64_t begin = c.submeshes[leaf.submesh].first_vertex;
    const uint64_t end =
        leaf.submesh + 1 < c.submeshes.size() ? c.submeshes[leaf.submesh + 1].first_vertex : c.vertices.size();
    for (uint64_t i = leaf.first_index; i < leaf.first_index + indices; ++i)
      if (c.indices[i] >= end - begin)
        input_error(in(dir, "compact_indices.bin"),
                    "index " + std::to_string(i) + " is outside the sub-mesh of leaf " + std::to_string(l));
  }
  for (int t = 0; t < 4; ++t)
    if (counted[t] != by_type[t])
      input_error(file, std::string("the manifest's ") + kTypeSlotNames[t] + " count does not match the leaves");
}

// Every node reached once from the root by forward links, within the depth the search handles,
// every leaf reached once, and leaf l the child l % 8 of node leaf_parents + l / 8.
void check_tree(const CompactMesh& c, const fs::path& dir) {
  const std::string file = in(dir, "compact_nodes.bin");
  const size_t n = c.nodes.size();
  input_check(n > 0, file, "no nodes");
  auto fail = [&](size_t i, const char* what) { input_error(file, "node " + std::to_string(i) + " " + what); };
  std::vector<uint8_t> node_seen(n, 0), leaf_seen(c.leaves.size(), 0), depth(n, 0);
  node_seen[0] = 1;
  for (size_t i = 0; i < n; ++i) {
    const CompactNode& node = c.nodes[i];
    if (!node_seen[i]) fail(i, "is not reached from the root");
    if (node.count < 1 || node.count > kCompactWidth) fail(i, "has a bad child count");
    if (node.leaf_children) {
      if (uint64_t(node.first) + node.count > c.leaves.size()) fail(i, "has leaves that do not exist");
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        if (leaf_seen[k]) fail(i, "reaches a leaf reached before");
        leaf_seen[k] = 1;
      }
      continue;
    }
    if (!(node.first > i && uint64_t(node.first) + node.count <= n)) fail(i, "has bad children");
    if (depth[i] >= kMaxInnerDepth) fail(i, "is too deep");
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      if (node_seen[k]) fail(i, "reaches a node reached before");
      node_seen[k] = 1;
      depth[k] = uint8_t(depth[i] + 1);
    }
  }
  for (size_t l = 0; l < c.leaves.size(); ++l)
    if (!leaf_seen[l]) input_error(file, "leaf " + std::to_string(l) + " is not reached from the root");
  for (size_t l = 0; l < c.leaves.size(); ++l) {
    const uint64_t p = uint64_t(c.leaf_parents) + l / kCompactWidth;
    if (!(p < n && c.nodes[p].leaf_children && c.nodes[p].first + l % kCompactWidth == l))
      input_error(file, "leaf_parents does not name leaf " + std::to_string(l) + "'s node");
  }
}

// Bottom-up (children come after their parents): each child box holds what its child holds.
void check_boxes(const CompactMesh& c, const fs::path& dir) {
  std::vector<box3f> leaf_box(c.leaves.size(), box3f::make_empty());
  parallel_for("compact leaf boxes", int64_t(c.leaves.size()), [&](int64_t l) {
    for_each_element_of_leaf(c, uint32_t(l),
                             [&](const CompactElement& e) { leaf_box[size_t(l)].extend(e.box(c.vertices.data())); });
  });
  std::vector<box3f> content(c.nodes.size(), box3f::make_empty());
  for (size_t i = c.nodes.size(); i-- > 0;) {
    const CompactNode& node = c.nodes[i];
    for (int k = 0; k < node.count; ++k) {
      const box3f& child = node.leaf_children ? leaf_box[node.first + uint32_t(k)] : content[node.first + uint32_t(k)];
      if (!box_holds(node.child_box(k), child))
        input_error(in(dir, "compact_nodes.bin"),
                    "node " + std::to_string(i) + " has a box that does not hold child " + std::to_string(k));
      content[i].extend(child);
    }
  }
}

}  // namespace

void check_compact_mesh(const CompactMesh& c, const uint64_t by_type[4], const fs::path& dir) {
  check_vertices_and_submeshes(c, dir);
  check_leaves(c, by_type, dir);
  check_tree(c, dir);
  check_boxes(c, dir);
}

}  // namespace vs
