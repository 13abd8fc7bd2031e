#include "volstream/umesh/mesh_index.h"

#include <algorithm>
#include <cmath>

#include "volstream/core/error.h"

namespace vs {

std::vector<StoredMacrocell> stored_macrocells(const MacroCells& cells) {
  std::vector<StoredMacrocell> out(cells.region_count());
  for (size_t r = 0; r < out.size(); ++r) out[r] = {cells.cell_of_region[r], cells.step_width[r]};
  return out;
}

namespace {

bool finite(const vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The grid is the one build_macrocells makes over its bounds (so a rank renders on one
// process's grid, and every cell index is in range).
void check_grid(const MacroGrid& grid, uint64_t elements, const std::string& file) {
  const box3f& b = grid.bounds;
  input_check(
      finite(b.lower) && finite(b.upper) && b.lower.x <= b.upper.x && b.lower.y <= b.upper.y && b.lower.z <= b.upper.z,
      file, "the macrocell grid's bounds are not a finite box");
  const MacroGrid expected = macro_grid(b, elements);
  for (int a = 0; a < 3; ++a)
    input_check(grid.dims[a] == expected.dims[a] && grid.cell_size[a] == expected.cell_size[a], file,
                "the macrocell grid is not the one its bounds and element count give");
}

}  // namespace

MacroCells macrocells_from_stored(const MacroGrid& grid, const std::vector<StoredMacrocell>& stored, uint64_t elements,
                                  const std::string& file) {
  check_grid(grid, elements, file);
  MacroCells m;
  m.grid = grid;
  m.region_of_cell.assign(grid.cell_count(), -1);
  for (size_t r = 0; r < stored.size(); ++r) {
    const StoredMacrocell& s = stored[r];
    if (!(s.cell < grid.cell_count() && (r == 0 || s.cell > stored[r - 1].cell)))
      input_error(file, "macrocell " + std::to_string(r) + " is outside the grid or out of order");
    if (!(std::isfinite(s.step_width) && s.step_width >= 0.f))
      input_error(file, "macrocell " + std::to_string(r) + " has a bad step width");
    m.region_of_cell[s.cell] = int32_t(r);
    m.cell_of_region.push_back(s.cell);
    m.step_width.push_back(std::max(s.step_width, m.min_step()));  // written before min_step existed
  }
  return m;
}

std::vector<vec3d> MeshIndex::item_points() const {
  std::vector<vec3d> points;
  points.reserve(item_boxes.size());
  for (const box3f& b : item_boxes) points.push_back((vec3d(b.lower) + vec3d(b.upper)) * 0.5);
  return points;
}

MeshIndex compact_mesh_index(const CompactMesh& mesh, MacroCells cells) {
  MeshIndex index;
  index.item_boxes.reserve(mesh.leaves.size());
  for (uint32_t l = 0; l < mesh.leaves.size(); ++l) {
    index.item_boxes.push_back(mesh.nodes[mesh.leaf_parents + l / kCompactWidth].child_box(int(l % kCompactWidth)));
    index.item_elements.push_back(mesh.leaves[l].element_count());
  }
  index.cells = std::move(cells);
  return index;
}

std::vector<box3f> reference_chunk_boxes(const UMesh& mesh, std::span<const uint32_t> bvh_items) {
  const uint64_t elements = bvh_items.size();
  std::vector<box3f> boxes(chunk_count(elements), box3f::make_empty());
  for (uint32_t c = 0; c < boxes.size(); ++c)
    for (uint64_t i = chunk_first(c); i < chunk_first(c) + chunk_size(c, elements); ++i)
      boxes[c].extend(element_box(mesh.vertices.data(), mesh.elements[bvh_items[i]]));
  return boxes;
}

std::vector<uint32_t> chunk_elements(const std::vector<uint32_t>& chunks, std::span<const uint32_t> bvh_items) {
  std::vector<uint32_t> elements;
  for (uint32_t c : chunks) {
    if (c >= chunk_count(bvh_items.size())) throw std::out_of_range("chunk_elements: no chunk " + std::to_string(c));
    for (uint64_t i = chunk_first(c); i < chunk_first(c) + chunk_size(c, bvh_items.size()); ++i)
      elements.push_back(bvh_items[i]);
  }
  std::sort(elements.begin(), elements.end());
  return elements;
}

MeshIndex reference_mesh_index(std::vector<box3f> chunk_boxes, uint64_t elements, MacroCells cells) {
  MeshIndex index;
  index.item_boxes = std::move(chunk_boxes);
  for (uint32_t c = 0; c < index.item_boxes.size(); ++c) index.item_elements.push_back(chunk_size(c, elements));
  index.cells = std::move(cells);
  return index;
}

}  // namespace vs
