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

template <typename Mesh, typename ElementsOf>
MeshShare share_of(const Mesh& mesh, const MacroCells& cells, const std::vector<vec3d>& centroids,
                   const Box3<double>& region, const IntegratorSettings& settings, ElementsOf&& elements_of) {
  MeshShare share;
  const std::vector<uint8_t> touching =
      items_touching(mesh, cells.grid, held_cells(cells, region, settings, share.margin));
  for (uint32_t i = 0; i < touching.size(); ++i)
    if (touching[i]) {
      share.items.push_back(i);
      share.held_elements += elements_of(i);
    }
  for (const vec3d& c : centroids) share.owned_elements += in_region(region, c);
  return share;
}

}  // namespace

MeshShare mesh_share(const UMesh& mesh, const MacroCells& cells, const std::vector<vec3d>& centroids,
                     const Box3<double>& region, const IntegratorSettings& settings) {
  return share_of(mesh, cells, centroids, region, settings, [](uint32_t) { return 1u; });
}

MeshShare mesh_share(const CompactMesh& mesh, const MacroCells& cells, const std::vector<vec3d>& centroids,
                     const Box3<double>& region, const IntegratorSettings& settings) {
  return share_of(mesh, cells, centroids, region, settings,
                  [&](uint32_t leaf) { return mesh.leaves[leaf].element_count(); });
}

}  // namespace vs
