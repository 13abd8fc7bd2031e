// Paper 002's compact encoding (compact.h) as a dataset stores it (issue 13): which arrays are
// files, the checks that make a read-back CompactMesh safe to sample, and the per-element decoding
// that everything but sampling (macrocells, brute-force probes, checks) goes through, so that no
// reference UMesh is ever built from a compact dataset.
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "volstream/core/math.h"
#include "volstream/umesh/compact.h"

namespace vs {

// The arrays of a CompactMesh a dataset stores, one raw little-endian file of records each (the
// structs of compact.h as they are in memory): f(file name, array). Storing one more array is one
// more line here; the manifest records each file's record count under its name.
template <typename Mesh, typename F>
void for_each_compact_array(Mesh& c, F&& f) {
  f("compact_nodes.bin", c.nodes);
  f("compact_leaves.bin", c.leaves);
  f("compact_bytes.bin", c.bytes);
  f("compact_submeshes.bin", c.submeshes);
  f("compact_vertices.bin", c.vertices);
}

// One element decoded from its leaf: vertex count and absolute local vertex indices (into
// CompactMesh::vertices and into the values of a (field, step)).
struct CompactElement {
  int n = 0;
  uint32_t vertex[8];
  box3f box(const vec3f* vertices) const {
    return corners_box(n, [&](int i) -> const vec3f& { return vertices[vertex[i]]; });
  }
};

// Calls f(element) for each element of leaf l, in slot order: the elements of CompactMeshView::
// element(leaf, k) for k = 0, 1, ..., decoded in one pass along the leaf's corner runs instead of
// finding each element's run afresh (the load's and the ranges' passes decode every element).
template <typename F>
void for_each_element_of_leaf(const CompactMesh& c, const CompactMeshView& view, uint32_t l, F&& f) {
  const CompactLeaf& leaf = c.leaves[l];
  const uint32_t base = c.submeshes[leaf.submesh].first_vertex;
  const uint8_t* table = view.leaf_bytes(leaf);
  const uint8_t* corner = table + 2u * leaf.table_size();
  auto vertex = [&](uint8_t b) { return base + CompactMeshView::entry_of(table, b); };
  CompactElement e;
  e.n = 4;
  for (uint32_t pair = 0; pair < leaf.tet_pairs; ++pair, corner += 5) {  // 3 shared corners, then each tet's own
    for (int i = 0; i < 4; ++i) e.vertex[i] = vertex(corner[i]);
    f(std::as_const(e));
    e.vertex[3] = vertex(corner[4]);
    f(std::as_const(e));
  }
  const uint32_t counts[4] = {leaf.counts[0] - 2u * leaf.tet_pairs, leaf.counts[1], leaf.counts[2], leaf.counts[3]};
  constexpr int kVertices[4] = {4, 5, 6, 8};
  for (int type = 0; type < 4; ++type) {
    e.n = kVertices[type];
    for (uint32_t k = 0; k < counts[type]; ++k, corner += e.n) {
      for (int i = 0; i < e.n; ++i) e.vertex[i] = vertex(corner[i]);
      f(std::as_const(e));
    }
  }
}

// InputError naming the file at fault (in `dir`) unless `c` as read is safe and right to sample:
// finite vertices; sub-meshes ascending from 0, each of at most 65536 vertices, their byte runs
// ascending inside the byte array; every leaf of 1 .. kMultiLeafSize elements (at most all its
// tets paired), in a sub-mesh, its vertex table and corners inside its sub-mesh's bytes, every
// table entry inside its sub-mesh and every corner inside its table; the element counts by type
// those of the manifest; nodes of 1 .. 8 children that point forward and form a tree (every
// node and leaf reached once from the root, depth within the search stack) laid out by levels
// as the sampler addresses them (a node at position i of its level has its children at 8 i .. of
// the next); leaf_parents the nodes whose children are the leaves in order; every quantized
// child box holding its child.
void check_compact_mesh(const CompactMesh& c, const uint64_t by_type[4], const std::filesystem::path& dir);

// The parts of those checks that a reader of only some leaves (Dataset::restrict_to on a dataset
// opened with its topology deferred) makes on what it reads, each naming the file at fault:
// the tree over the leaf records (nodes and leaves only: links, levels, leaf_parents); the
// sub-mesh records against the vertex and byte counts; the leaf records (element counts, tet
// pairs, sub-mesh; the counts by type the manifest's); one leaf record (empty string: sound);
// one leaf's bytes (table entries inside its sub-mesh of `submesh_vertices`, corners inside
// its table).
void check_compact_tree(const CompactMesh& c, const std::filesystem::path& dir);
void check_submeshes(std::span<const CompactSubmesh> submeshes, uint64_t vertex_count, uint64_t byte_count,
                     const std::filesystem::path& dir);
void check_leaf_records(const CompactMesh& c, const uint64_t by_type[4], const std::filesystem::path& dir);
std::string leaf_record_problem(const CompactLeaf& leaf, uint64_t submesh_count);
std::string leaf_bytes_problem(const CompactLeaf& leaf, const uint8_t* bytes, uint64_t submesh_vertices);
// A leaf's bytes: its vertex table and corners.
uint64_t leaf_byte_count(const CompactLeaf& leaf);
// Sub-mesh s's vertex count and the [begin, end) of its bytes, in a mesh of vertex_count local
// vertices and byte_count bytes.
struct SubmeshRuns {
  uint64_t vertices, bytes_begin, bytes_end;
};
SubmeshRuns submesh_runs(std::span<const CompactSubmesh> submeshes, uint32_t s, uint64_t vertex_count,
                         uint64_t byte_count);

}  // namespace vs
