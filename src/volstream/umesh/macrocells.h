// The regions an unstructured mesh gives the integrator (volume/umesh_volume.h): the non-empty
// cells of a uniform macrocell grid over the mesh's bounds, about kElementsPerMacrocell elements
// each. They are disjoint boxes, so a ray visits them front to back through the same refit
// region BVH as ABRs (render/skipping.h); each carries the value range of the elements
// overlapping it (empty-space skipping and isosurfaces, recomputed per step: only scalars
// change) and the size of its smallest element (the adaptive step). Macrocells no element
// touches are not regions at all, so rays skip holes, cavities and the gaps between the parts of
// a mesh without sampling them. A ray finds its macrocells front to back by a walk over the
// grid (for_each_cell_along), not through a BVH: the cells are implicit, so the walk needs no
// tree and no boxes, and culled regions cost a flag each (volume/umesh_volume.h).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "volstream/accel/bvh_traverse.h"
#include "volstream/amr/model.h"
#include "volstream/core/host_array.h"
#include "volstream/core/math.h"
#include "volstream/umesh/compact.h"
#include "volstream/umesh/macro_grid.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr double kElementsPerMacrocell = 128;

// Every cell of g in the block of cells [lo, hi] (inclusive, clamped to the grid) that the ray
// org + t dir (t >= 0) crosses, front to back, as visit(index, t0, t1): the cell's g.index and
// the ray's interval in its cell_box as ray_box gives it (so the intervals are those a BVH over
// the same boxes gives); visit returns false to stop. A frame's visible macrocells lie in a block
// smaller than the grid where empty-space skipping culls (MeshVolume::shown_lo), and the walk
// starts and ends at that block's faces, not the grid's: the cells outside it would only have
// been stepped over. Each step crosses the face through which the ray leaves the cell, so the
// walk ends after at most dims.x + dims.y + dims.z cells. A step changes one axis's cell, so
// the walk updates only that axis: its two face distances (ray_box's interval is the largest of
// the axes' near-face distances to the smallest of their far-face ones: the same floats as
// ray_box on the whole box), its bounds test and the index by that axis's stride (the per-ray
// code around a blobs render's samples, mostly this walk, was a quarter of its instructions).
template <typename Visit>
VS_HOST_DEVICE inline void for_each_cell_along(const MacroGrid& g, vec3i lo, vec3i hi, const vec3f& org,
                                               const vec3f& dir, Visit&& visit) {
  box3f block;  // the cells' block; the whole grid's is exactly g.bounds (layer_faces)
  for (int a = 0; a < 3; ++a) {
    lo[a] = lo[a] > 0 ? lo[a] : 0;
    hi[a] = hi[a] < g.dims[a] - 1 ? hi[a] : g.dims[a] - 1;
    if (lo[a] > hi[a]) return;
    float unused;
    g.layer_faces(a, lo[a], block.lower[a], unused);
    g.layer_faces(a, hi[a], unused, block.upper[a]);
  }
  const SlabRay ray(org, dir);
  float t_in, t_out;
  ray_box(ray, block, t_in, t_out);
  t_in = t_in > 0.f ? t_in : 0.f;
  if (!(t_in <= t_out)) return;
  vec3i c = g.cell_of(org + dir * t_in);  // a rounding error here only adds or drops an empty interval
  for (int a = 0; a < 3; ++a) c[a] = c[a] < lo[a] ? lo[a] : (c[a] > hi[a] ? hi[a] : c[a]);
  float near[3], far[3];  // per axis: ray_box's distances to cell_box(c)'s two faces
  const auto faces_of_layer = [&](int a) {
    float lower, upper;
    g.layer_faces(a, c[a], lower, upper);
    ray_slab(ray, a, lower, upper, near[a], far[a]);
  };
  for (int a = 0; a < 3; ++a) faces_of_layer(a);
  const int64_t stride[3] = {1, int64_t(g.dims.x), int64_t(g.dims.x) * int64_t(g.dims.y)};
  uint64_t index = g.index(c);
  for (;;) {
    float t0 = -INFINITY, t1 = INFINITY;
    int axis = 0;  // the axis of the face the ray leaves by: the first of the nearest far faces
    for (int a = 0; a < 3; ++a) {
      t0 = near[a] > t0 ? near[a] : t0;
      if (far[a] < t1) t1 = far[a], axis = a;
    }
    t0 = t0 > 0.f ? t0 : 0.f;
    if (t0 <= t1 && t1 > 0.f && !visit(index, t0, t1)) return;
    const int step = ray.inv_dir[axis] >= 0.f ? 1 : -1;
    c[axis] += step;
    if (c[axis] < lo[axis] || c[axis] > hi[axis]) return;
    index += uint64_t(step * stride[axis]);
    faces_of_layer(axis);
  }
}
// Every cell of the grid (as above).
template <typename Visit>
VS_HOST_DEVICE inline void for_each_cell_along(const MacroGrid& g, const vec3f& org, const vec3f& dir, Visit&& visit) {
  for_each_cell_along(g, vec3i(0, 0, 0), g.dims - vec3i(1, 1, 1), org, dir, visit);
}

struct MacroCells {
  MacroGrid grid;
  std::vector<int32_t> region_of_cell;   // grid cell -> region, -1 where no element overlaps
  std::vector<uint32_t> cell_of_region;  // region -> grid cell (grid.index)
  std::vector<float> step_width;         // per region: its smallest element's size, at least min_step,
                                         // rounded down to eighth octaves (ladder_width)
  // Which subcells some element's corner box overlaps (SubcellOccupancy), kept only for the
  // regions where some subcell is empty (at the mesh's boundary, holes): 4 B a region and 64 B
  // a mask. Empty: not known.
  struct SubcellMasks {
    std::vector<uint32_t> of_region;  // its mask's index, or SubcellOccupancy::kAllOccupied
    std::vector<SubcellMask> masks;
    bool operator==(const SubcellMasks&) const = default;
  } subcells;
  size_t region_count() const { return cell_of_region.size(); }
  // The finest step a macrocell is marched with: 1/1000 of the grid cell's longest side (as an
  // element's size is at least 1/1000 of its extent, macrocells.cpp). A degenerate element (a
  // damaged dataset: every corner at one point) would otherwise ask for a step of zero, and each
  // ray for 16.7 M samples per macrocell; a boundary layer finer than this is sampled at this step.
  float min_step() const { return 1e-3f * reduce_max(grid.cell_size); }
  box3f box(size_t region) const;  // its grid cell's box
  uint64_t bytes() const {
    return region_of_cell.size() * sizeof(int32_t) + cell_of_region.size() * sizeof(uint32_t) +
           step_width.size() * sizeof(float) + subcells.of_region.size() * sizeof(uint32_t) +
           subcells.masks.size() * sizeof(SubcellMask);
  }
};

// From either encoding's elements (the same cells: they depend on the element boxes only). With
// `grid`, on that grid instead of one over the mesh's own bounds, in one pass over the elements
// (`seen` gets their boxes' union): a data-parallel rank's share of a mesh keeps the whole mesh's
// grid, so that its macrocells are the whole mesh's where it holds every element overlapping them
// (mpi/mesh_share.h); a whole load takes the grid convert stored (io/dataset.h).
MacroCells build_macrocells(const UMesh& mesh, const MacroGrid* grid = nullptr, box3f* seen = nullptr);
MacroCells build_macrocells(const CompactMesh& mesh, const MacroGrid* grid = nullptr, box3f* seen = nullptr);

// Every element's centroid (the mean of its vertices): in element order, or for a compact mesh
// leaf after leaf in slot order.
std::vector<vec3d> element_centroids(const UMesh& mesh);
std::vector<vec3d> element_centroids(const CompactMesh& mesh);

// The grid build_macrocells makes over elements with these bounds (of their boxes): cubic cells,
// about kElementsPerMacrocell elements each, at most 256 per axis.
MacroGrid macro_grid(const box3f& bounds, uint64_t elements);

// A step width rounded down to a power of 2^(1/8) (MacroCells::step_width).
float ladder_width(float width);
// The box overlaps a grid cell marked in `cells` (one byte per cell of `grid`), by the overlap
// test of the macrocells.
bool box_touches(const MacroGrid& grid, const box3f& box, const std::vector<uint8_t>& cells);

// Per region: the range of the finite values at the vertices of the elements overlapping it
// (shape functions are convex combinations, so no value inside an element leaves its vertices'
// range); empty (lo > hi) where none is finite.
std::vector<Range> macrocell_ranges(const UMesh& mesh, const MacroCells& cells, const float* values);
// The same over the compact encoding, with values per local vertex (CompactMesh::gather order).
std::vector<Range> macrocell_ranges(const CompactMesh& mesh, const MacroCells& cells, const float* local_values);

// Per region, the vertices (value indices) of the elements overlapping it, ascending and without
// repeats: ranges from these read each of a region's values once (about 5 per vertex of a 1 M-tet
// mesh), where the pass above reads every element's corners and box and merges with atomics per
// region (151 M instructions on 1 M tets, 14-25 ms of a render command on two cores). Built
// once per mesh, at the cost of 5 to 6 such passes: convert stores the reference encoding's
// (mesh_region_first.bin, mesh_region_vertices.bin), so that a render maps them; a time series
// builds them at its second step where they are not stored (bench/RESULTS.md).
struct RegionVertices {
  HostArray<uint64_t> first;   // per region, and one past the last: where its list starts in `vertex`
  HostArray<uint32_t> vertex;  // the lists, region after region
  uint64_t bytes() const { return first.size() * sizeof(uint64_t) + vertex.size() * sizeof(uint32_t); }
};
// The build first writes every overlap's corners (4 B each, about 42 B per tet) and then drops
// the repeats: where that would take more than `budget` bytes (a mesh of tens of millions of
// elements), it gives nothing and a series keeps the pass over the elements.
inline constexpr uint64_t kRegionVerticesBudget = uint64_t(1) << 30;
std::optional<RegionVertices> region_vertices(const UMesh& mesh, const MacroCells& cells,
                                              uint64_t budget = kRegionVerticesBudget);
std::optional<RegionVertices> region_vertices(const CompactMesh& mesh, const MacroCells& cells,
                                              uint64_t budget = kRegionVerticesBudget);  // local vertices
// Why `lists` (stored, from a file) cannot stand for the mesh's own, or empty when they can: one
// offset per region of `cells` and one more, from 0, non-decreasing, to the entry count; each
// list strictly ascending, of vertices below the mesh's count; and every corner of every element
// in the list of each region the element overlaps. A vertex too many would only widen a range
// (a region kept that could be culled), never cull what shows, so it is not looked for.
std::string region_vertices_fault(const UMesh& mesh, const MacroCells& cells, const RegionVertices& lists);
// The same ranges as macrocell_ranges over the mesh the lists were built from.
std::vector<Range> macrocell_ranges(const RegionVertices& lists, const float* values);

}  // namespace vs
