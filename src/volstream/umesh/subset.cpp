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

}  // namespace

UMesh mesh_part(std::vector<UElement> elements, std::vector<uint32_t>& source_vertex) {
  std::vector<uint32_t> used;
  for (const UElement& el : elements) used.insert(used.end(), el.v, el.v + el.vertex_count());
  source_vertex = distinct_sorted(std::move(used));
  UMesh part;
  part.elements = std::move(elements);
  for (UElement& el : part.elements) {
    const int n = el.vertex_count();
    for (int k = 0; k < n; ++k) el.v[k] = position_in(source_vertex, el.v[k]);
    ++part.count_by_type[type_slot(n)];
  }
  return part;
}

UMesh mesh_subset(const UMesh& mesh, const std::vector<uint32_t>& elements, std::vector<uint32_t>& source_vertex) {
  std::vector<UElement> records;
  records.reserve(elements.size());
  for (uint32_t e : elements) records.push_back(mesh.elements.at(e));
  UMesh part = mesh_part(std::move(records), source_vertex);
  part.vertices.reserve(source_vertex.size());
  for (uint32_t v : source_vertex) part.vertices.push_back(mesh.vertices[v]);
  return part;
}

CompactMesh compact_part(const CompactPieces& pieces, const HostArray<CompactSubmesh>& submeshes,
                         std::vector<uint32_t>& source_vertex) {
  CompactMesh part;
  source_vertex.clear();
  const auto table_entry = [](const uint8_t* bytes, uint32_t t) {
    return uint32_t(bytes[2 * t] | bytes[2 * t + 1] << 8);
  };
  for (size_t begin = 0; begin < pieces.leaves.size();) {
    // The run of asked-for leaves in one sub-mesh becomes one sub-mesh of the part.
    const uint16_t submesh = pieces.leaves[begin].submesh;
    size_t end = begin;
    std::vector<uint32_t> used;
    for (; end < pieces.leaves.size() && pieces.leaves[end].submesh == submesh; ++end)
      for (uint32_t t = 0; t < pieces.leaves[end].table_size(); ++t) used.push_back(table_entry(pieces.bytes[end], t));
    used = distinct_sorted(std::move(used));
    const uint32_t base = submeshes.at(submesh).first_vertex;
    part.submeshes.push_back({uint32_t(source_vertex.size()), 0, part.bytes.size()});
    for (uint32_t v : used) source_vertex.push_back(base + v);
    for (size_t i = begin; i < end; ++i) {
      CompactLeaf leaf = pieces.leaves[i];
      const uint8_t* bytes = pieces.bytes[i];
      const uint64_t at = part.bytes.size();
      part.bytes.append(bytes, bytes + leaf_byte_count(leaf));
      for (uint32_t t = 0; t < leaf.table_size(); ++t) {  // renumbered table entries
        const uint32_t local = position_in(used, table_entry(bytes, t));
        part.bytes[at + 2 * t] = uint8_t(local & 0xff);
        part.bytes[at + 2 * t + 1] = uint8_t(local >> 8);
      }
      leaf.submesh = uint16_t(part.submeshes.size() - 1);
      leaf.first_byte = uint32_t(at - part.submeshes.back().first_byte);
      part.leaves.push_back(leaf);
      part.elements += leaf.element_count();
      part.paired_tets += 2u * leaf.tet_pairs;
    }
    begin = end;
  }
  return part;
}

std::vector<box3f> finish_compact_part(CompactMesh& part, std::vector<vec3f> vertices) {
  part.vertices = std::move(vertices);
  const CompactMeshView view = view_of(part);
  std::vector<box3f> boxes(part.leaves.size(), box3f::make_empty());
  for (uint32_t l = 0; l < part.leaves.size(); ++l)
    for_each_element_of_leaf(part, view, l,
                             [&](const CompactElement& e) { boxes[l].extend(e.box(part.vertices.data())); });
  build_compact_tree(part, boxes);
  return boxes;
}

CompactMesh compact_subset(const CompactMesh& mesh, const std::vector<uint32_t>& leaves,
                           std::vector<uint32_t>& source_vertex) {
  const CompactMeshView view = view_of(mesh);
  CompactPieces pieces;
  for (uint32_t l : leaves) {
    pieces.leaves.push_back(mesh.leaves.at(l));
    pieces.bytes.push_back(view.leaf_bytes(mesh.leaves[l]));
  }
  CompactMesh part = compact_part(pieces, mesh.submeshes, source_vertex);
  std::vector<vec3f> vertices;
  vertices.reserve(source_vertex.size());
  for (uint32_t v : source_vertex) vertices.push_back(mesh.vertices[v]);
  finish_compact_part(part, std::move(vertices));
  return part;
}

}  // namespace vs
