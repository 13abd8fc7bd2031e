// The regions an unstructured mesh gives the integrator (volume/umesh_volume.h): the non-empty
// cells of a uniform macrocell grid over the mesh's bounds, about kElementsPerMacrocell elements
// each. They are disjoint boxes, so a ray visits them front to back through the same refit
// region BVH as ABRs (render/skipping.h); each carries the value range of the elements
// overlapping it (empty-space skipping and isosurfaces, recomputed per step: only scalars
// change) and the size of its smallest element (the adaptive step). Macrocells no element
// touches are not regions at all, so rays skip holes, cavities and the gaps between the parts of
// a mesh without sampling them.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/amr/model.h"
#include "volstream/core/math.h"
#include "volstream/umesh/compact.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr double kElementsPerMacrocell = 128;

struct MacroGrid {
  box3f bounds;
  vec3i dims{1, 1, 1};
  vec3f cell_size{1.f, 1.f, 1.f};
  // Grid cell of p, clamped into the grid.
  VS_HOST_DEVICE vec3i cell_of(const vec3f& p) const {
    vec3i c;
    for (int a = 0; a < 3; ++a) {  // clamped as floats: far points must not overflow an int
      const float i = floorf((p[a] - bounds.lower[a]) / cell_size[a]);
      c[a] = i >= 0.f ? (i < float(dims[a]) ? int(i) : dims[a] - 1) : 0;
    }
    return c;
  }
  VS_HOST_DEVICE uint64_t index(const vec3i& c) const {
    return (uint64_t(c.z) * uint64_t(dims.y) + uint64_t(c.y)) * uint64_t(dims.x) + uint64_t(c.x);
  }
  uint64_t cell_count() const { return uint64_t(dims.x) * uint64_t(dims.y) * uint64_t(dims.z); }
};

struct MacroCells {
  MacroGrid grid;
  std::vector<int32_t> region_of_cell;  // grid cell -> region, -1 where no element overlaps
  std::vector<box3f> boxes;             // per region
  std::vector<float> step_width;        // per region: its smallest element's size
  uint64_t bytes() const {
    return region_of_cell.size() * sizeof(int32_t) + boxes.size() * sizeof(box3f) + step_width.size() * sizeof(float);
  }
};

// A feature size of an element: the cube root of its box's volume, at least 1/1000 of its
// largest extent (a flat, axis-aligned element has a box of no volume).
float element_size(const box3f& element_box);

// From either encoding's elements (the same cells: they depend on the element boxes only). With
// `grid`, on that grid instead of one over the mesh's own bounds: a data-parallel rank's share of
// a mesh keeps the whole mesh's grid, so that its macrocells are the whole mesh's where it holds
// every element overlapping them (mpi/mesh_share.h).
MacroCells build_macrocells(const UMesh& mesh, const MacroGrid* grid = nullptr);
MacroCells build_macrocells(const CompactMesh& mesh, const MacroGrid* grid = nullptr);

// Every element's centroid (the mean of its vertices): in element order, or for a compact mesh
// leaf after leaf in slot order.
std::vector<vec3d> element_centroids(const UMesh& mesh);
std::vector<vec3d> element_centroids(const CompactMesh& mesh);

// The grid build_macrocells makes over elements with these bounds (of their boxes): cubic cells,
// about kElementsPerMacrocell elements each, at most 256 per axis.
MacroGrid macro_grid(const box3f& bounds, uint64_t elements);
// The box of grid cell c (the last layer ends exactly on the bounds).
box3f macrocell_box(const MacroGrid& grid, const vec3i& c);
// The box overlaps a grid cell marked in `cells` (one byte per cell of `grid`), by the overlap
// test of the macrocells.
bool box_touches(const MacroGrid& grid, const box3f& box, const std::vector<uint8_t>& cells);

// Per region: the range of the finite values at the vertices of the elements overlapping it
// (shape functions are convex combinations, so no value inside an element leaves its vertices'
// range); empty (lo > hi) where none is finite.
std::vector<Range> macrocell_ranges(const UMesh& mesh, const MacroCells& cells, const float* values);
// The same over the compact encoding, with values per local vertex (CompactMesh::gather order).
std::vector<Range> macrocell_ranges(const CompactMesh& mesh, const MacroCells& cells, const float* local_values);

}  // namespace vs
