#include "volstream/umesh/subset.h"

#include <algorithm>

#include "volstream/umesh/compact_store.h"

namespace vs {
namespace {

// Sorted distinct values; position_in finds one among them.
std::vector<uint32_t> distinct_sorted(std::vector<uint32_t> values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}
uint32_t position_in(const std::vector<uint32_t>& sorted, uint32_t v) {
  return uint32_t(std::lower_bound(sorted.begin(), sorted.end(), v) - sorted.begin());
}

// The leaf's vertex table entries (sub-mesh-local indices).
std::vector<uint32_t> table_of(const CompactMeshView& view, const CompactLeaf& leaf) {
  std::vector<uint32_t> out(leaf.table_size());
  for (uint32_t t = 0; t < leaf.table_size(); ++t) out[t] = view.table_entry(leaf, t);
  return out;
}

}  // namespace

UMesh mesh_subset(const UMesh& mesh, const std::vector<uint32_t>& elements, std::vector<uint32_t>& source_vertex) {
  std::vector<uint32_t> used;
  for (uint32_t e : elements) {
    const UElement& el = mesh.elements.at(e);
    used.insert(used.end(), el.v, el.v + el.vertex_count());
  }
  source_vertex = distinct_sorted(std::move(used));
  UMesh part;
  part.vertices.reserve(source_vertex.size());
  for (uint32_t v : source_vertex) part.vertices.push_back(mesh.vertices[v]);
  part.elements.reserve(elements.size());
  for (uint32_t e : elements) {
    UElement el = mesh.elements[e];
    const int n = el.vertex_count();
    for (int k = 0; k < n; ++k) el.v[k] = position_in(source_vertex, el.v[k]);
    part.elements.push_back(el);
    ++part.count_by_type[type_slot(n)];
  }
  return part;
}

CompactMesh compact_subset(const CompactMesh& mesh, const std::vector<uint32_t>& leaves,
                           std::vector<uint32_t>& source_vertex) {
  const CompactMeshView view = view_of(mesh);
  CompactMesh part;
  std::vector<box3f> boxes;
  source_vertex.clear();
  for (size_t begin = 0; begin < leaves.size();) {
    // The run of asked-for leaves in one sub-mesh becomes one sub-mesh of the part.
    const uint16_t submesh = mesh.leaves.at(leaves[begin]).submesh;
    size_t end = begin;
    std::vector<uint32_t> used;
    for (; end < leaves.size() && mesh.leaves.at(leaves[end]).submesh == submesh; ++end) {
      const std::vector<uint32_t> t = table_of(view, mesh.leaves[leaves[end]]);
      used.insert(used.end(), t.begin(), t.end());
    }
    used = distinct_sorted(std::move(used));
    const uint32_t base = mesh.submeshes[submesh].first_vertex;
    part.submeshes.push_back({uint32_t(part.vertices.size()), 0, part.bytes.size()});
    for (uint32_t v : used) {
      part.vertices.push_back(mesh.vertices[base + v]);
      source_vertex.push_back(base + v);
    }
    for (size_t i = begin; i < end; ++i) {
      CompactLeaf leaf = mesh.leaves[leaves[i]];
      const uint8_t* bytes = view.leaf_bytes(leaf);
      const uint32_t size = 2u * leaf.table_size() + leaf.corner_count();
      const uint64_t at = part.bytes.size();
      part.bytes.insert(part.bytes.end(), bytes, bytes + size);
      for (uint32_t t = 0; t < leaf.table_size(); ++t) {  // renumbered table entries
        const uint32_t local = position_in(used, view.table_entry(leaf, t));
        part.bytes[at + 2 * t] = uint8_t(local & 0xff);
        part.bytes[at + 2 * t + 1] = uint8_t(local >> 8);
      }
      leaf.submesh = uint16_t(part.submeshes.size() - 1);
      leaf.first_byte = uint32_t(at - part.submeshes.back().first_byte);
      part.leaves.push_back(leaf);
      part.elements += leaf.element_count();
      part.paired_tets += 2u * leaf.tet_pairs;
      box3f b = box3f::make_empty();
      for_each_element_of_leaf(mesh, view, leaves[i],
                               [&](const CompactElement& e) { b.extend(e.box(mesh.vertices.data())); });
      boxes.push_back(b);
    }
    begin = end;
  }
  build_compact_tree(part, boxes);
  return part;
}

}  // namespace vs
