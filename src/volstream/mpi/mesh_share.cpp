#include "volstream/mpi/mesh_share.h"

namespace vs {
namespace {

// The grid cells of the macrocells the region's rank samples (one byte per grid cell).
std::vector<uint8_t> held_cells(const MacroCells& cells, const Box3<double>& region, const IntegratorSettings& settings,
                                double& margin) {
  std::vector<RegionExtent> extents(cells.region_count());
  for (size_t r = 0; r < extents.size(); ++r) extents[r] = {cells.box(r), cells.step_width[r]};
  const HeldRegions held = held_regions(extents, region, settings);
  margin = held.margin;
  std::vector<uint8_t> is_held(cells.region_count(), 0);
  for (uint32_t r : held.indices) is_held[r] = 1;
  std::vector<uint8_t> marked(cells.region_of_cell.size(), 0);
  for (size_t c = 0; c < marked.size(); ++c) {
    const int32_t r = cells.region_of_cell[c];
    marked[c] = r >= 0 && is_held[size_t(r)];
  }
  return marked;
}

}  // namespace

MeshShare mesh_share(const MeshIndex& index, const std::vector<vec3d>& item_points, const Box3<double>& region,
                     const IntegratorSettings& settings) {
  MeshShare share;
  const std::vector<uint8_t> marked = held_cells(index.cells, region, settings, share.margin);
  for (uint32_t l = 0; l < index.item_boxes.size(); ++l) {
    if (box_touches(index.cells.grid, index.item_boxes[l], marked)) {
      share.items.push_back(l);
      share.held_elements += index.item_elements[l];
    }
    if (in_region(region, item_points[l])) share.owned_elements += index.item_elements[l];
  }
  return share;
}

}  // namespace vs
