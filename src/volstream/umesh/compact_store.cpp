#include "volstream/umesh/compact_store.h"

#include <algorithm>
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

void check_vertices(const CompactMesh& c, const fs::path& dir) {
  for (size_t i = 0; i < c.vertices.size(); ++i) {
    const vec3f& v = c.vertices[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      input_error(in(dir, "compact_vertices.bin"), "vertex " + std::to_string(i) + " is not finite");
  }
}

}  // namespace

SubmeshRuns submesh_runs(std::span<const CompactSubmesh> submeshes, uint32_t s, uint64_t vertex_count,
                         uint64_t byte_count) {
  const bool last = s + 1 >= submeshes.size();
  return {(last ? vertex_count : submeshes[s + 1].first_vertex) - submeshes[s].first_vertex, submeshes[s].first_byte,
          last ? byte_count : submeshes[s + 1].first_byte};
}

std::string leaf_record_problem(const CompactLeaf& leaf, uint64_t submesh_count) {
  const uint32_t elements = leaf.element_count();
  if (elements == 0 || elements > kMultiLeafSize) return "holds " + std::to_string(elements) + " elements";
  if (2u * leaf.tet_pairs > leaf.counts[0]) return "pairs more tets than it holds";
  if (leaf.submesh >= submesh_count) return "names a sub-mesh that does not exist";
  return {};
}

void check_submeshes(std::span<const CompactSubmesh> submeshes, uint64_t vertex_count, uint64_t byte_count,
                     const fs::path& dir) {
  const std::string file = in(dir, "compact_submeshes.bin");
  input_check(!submeshes.empty() && submeshes[0].first_vertex == 0 && submeshes[0].first_byte == 0, file,
              "the first sub-mesh must start at 0");
  for (uint32_t s = 0; s < submeshes.size(); ++s) {
    const uint64_t begin = submeshes[s].first_vertex;
    const uint64_t end = s + 1 < submeshes.size() ? submeshes[s + 1].first_vertex : vertex_count;
    if (!(begin < end && end <= vertex_count && end - begin <= kMaxSubmeshVertices))
      input_error(file, "sub-mesh " + std::to_string(s) + " has a bad vertex range");
    const uint64_t bytes_end = s + 1 < submeshes.size() ? submeshes[s + 1].first_byte : byte_count;
    if (!(submeshes[s].first_byte <= bytes_end && bytes_end <= byte_count))
      input_error(file, "sub-mesh " + std::to_string(s) + " has a bad byte range");
  }
}

void check_leaf_records(const CompactMesh& c, const uint64_t by_type[4], const fs::path& dir) {
  const std::string file = in(dir, "compact_leaves.bin");
  uint64_t counted[4] = {};
  for (size_t l = 0; l < c.leaves.size(); ++l) {
    if (const std::string problem = leaf_record_problem(c.leaves[l], c.submeshes.size()); !problem.empty())
      input_error(file, "leaf " + std::to_string(l) + " " + problem);
    for (int t = 0; t < 4; ++t) counted[t] += c.leaves[l].counts[t];
  }
  for (int t = 0; t < 4; ++t)
    if (counted[t] != by_type[t])
      input_error(file, std::string("the manifest's ") + kTypeSlotNames[t] + " count does not match the leaves");
}

uint64_t leaf_byte_count(const CompactLeaf& leaf) { return 2u * leaf.table_size() + leaf.corner_count(); }

std::string leaf_bytes_problem(const CompactLeaf& leaf, const uint8_t* bytes, uint64_t submesh_vertices) {
  for (uint32_t t = 0; t < leaf.table_size(); ++t)
    if (uint32_t(bytes[2 * t] | bytes[2 * t + 1] << 8) >= submesh_vertices)
      return "names a vertex outside its sub-mesh";
  for (uint64_t i = 2u * leaf.table_size(); i < leaf_byte_count(leaf); ++i)
    if (bytes[i] >= leaf.table_size()) return "has a corner outside its vertex table";
  return {};
}

namespace {

// Leaves: byte runs inside their sub-mesh's, table entries and corners in range.
void check_leaf_bytes(const CompactMesh& c, const fs::path& dir) {
  for (size_t l = 0; l < c.leaves.size(); ++l) {
    const CompactLeaf& leaf = c.leaves[l];
    const SubmeshRuns runs = submesh_runs(c.submeshes, leaf.submesh, c.vertices.size(), c.bytes.size());
    const uint64_t begin = runs.bytes_begin + leaf.first_byte;
    if (begin + leaf_byte_count(leaf) > runs.bytes_end)
      input_error(in(dir, "compact_leaves.bin"), "leaf " + std::to_string(l) + " has bytes beyond its sub-mesh's");
    if (const std::string problem = leaf_bytes_problem(leaf, c.bytes.data() + begin, runs.vertices); !problem.empty())
      input_error(in(dir, "compact_bytes.bin"), "leaf " + std::to_string(l) + " " + problem);
  }
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

// The nodes by levels as the sampler addresses them (CompactMeshView::level_first): the level
// sizes follow from the leaf count (ceil(n / 8) up to one root), levels are stored root first,
// and the node at position i of a level has children 8 i .. 8 i + 7 of the next level (or of
// the leaves), as many as there are.
void check_levels(const CompactMesh& c, const fs::path& dir) {
  const std::string file = in(dir, "compact_nodes.bin");
  std::vector<uint64_t> sizes;  // bottom-up: leaves, then each level of nodes
  sizes.push_back(c.leaves.size());
  while (sizes.back() > 1 || sizes.size() == 1) sizes.push_back((sizes.back() + kCompactWidth - 1) / kCompactWidth);
  uint64_t total = 0;
  for (size_t k = 1; k < sizes.size(); ++k) total += sizes[k];
  input_check(total == c.nodes.size(), file, "the node count does not follow from the leaf count");
  uint64_t level_first = 0;
  for (size_t k = sizes.size() - 1; k >= 1; --k) {  // root level first
    const uint64_t below_first = k == 1 ? 0 : level_first + sizes[k];
    for (uint64_t i = 0; i < sizes[k]; ++i) {
      const CompactNode& node = c.nodes[level_first + i];
      const uint64_t count = std::min<uint64_t>(kCompactWidth, sizes[k - 1] - kCompactWidth * i);
      if ((node.leaf_children != 0) != (k == 1) || node.first != below_first + kCompactWidth * i || node.count != count)
        input_error(file, "node " + std::to_string(level_first + i) + " is not where the level layout puts it");
    }
    if (k == 1) input_check(level_first == c.leaf_parents, file, "leaf_parents is not the last level");
    level_first += sizes[k];
  }
}

// Bottom-up (children come after their parents): each child box holds what its child holds.
void check_boxes(const CompactMesh& c, const fs::path& dir) {
  std::vector<box3f> leaf_box(c.leaves.size(), box3f::make_empty());
  const CompactMeshView view = view_of(c);
  parallel_for("compact leaf boxes", int64_t(c.leaves.size()), [&](int64_t l) {
    for_each_element_of_leaf(c, view, uint32_t(l),
                             [&](const CompactElement& e) { leaf_box[size_t(l)].extend(e.box(c.vertices.data())); });
  });
  std::vector<box3f> content(c.nodes.size(), box3f::make_empty());
  for (size_t i = c.nodes.size(); i-- > 0;) {
    const CompactNode& node = c.nodes[i];
    for (int k = 0; k < node.count; ++k) {
      const box3f& child = node.leaf_children ? leaf_box[node.first + uint32_t(k)] : content[node.first + uint32_t(k)];
      if (!node.child_box(k).contains(child))
        input_error(in(dir, "compact_nodes.bin"),
                    "node " + std::to_string(i) + " has a box that does not hold child " + std::to_string(k));
      content[i].extend(child);
    }
  }
}

}  // namespace

void check_compact_tree(const CompactMesh& c, const fs::path& dir) {
  check_tree(c, dir);
  check_levels(c, dir);
}

void check_compact_mesh(const CompactMesh& c, const uint64_t by_type[4], const fs::path& dir) {
  check_vertices(c, dir);
  check_submeshes(c.submeshes, c.vertices.size(), c.bytes.size(), dir);
  check_leaf_records(c, by_type, dir);
  check_leaf_bytes(c, dir);
  check_compact_tree(c, dir);
  check_boxes(c, dir);
}

}  // namespace vs
