// The uniform grid of macrocells over an unstructured mesh's bounds (umesh/macrocells.h), and
// the occupancy of each macrocell's 8x8x8 subcells, which lets a point location rule out a point
// that no element's box holds without searching for its element (SubcellOccupancy).
#pragma once
#include <cstdint>

#include "volstream/core/math.h"
#if defined(__GNUC__) && !defined(__CUDACC__)
#include "volstream/core/simd.h"  // cell_of's lanes
#endif

namespace vs {

struct MacroGrid {
  static constexpr int kSubcells = 8;  // per cell and axis (subcell_of)
  box3f bounds;
  vec3i dims{1, 1, 1};
  vec3f cell_size{1.f, 1.f, 1.f};
  // Grid cell of p, clamped into the grid. The quotient is clamped as a float (far points must
  // not overflow an int; NaN gives 0) to [0, dims - 1] and then truncated: for a quotient in that
  // range truncation is its floor, so this is floor-then-clamp without a floor or a branch (the
  // load runs it twice per element and pass).
#if defined(__GNUC__) && !defined(__CUDACC__)
  // On the host the three axes go on one SSE register (scalar, GCC branches on each comparison),
  // with the grid's constants as lanes that a pass over the elements makes once (Lanes).
  struct Lanes {
    simd::f4 lower, size, last, last_subcell;
  };
  Lanes lanes() const {
    Lanes g;
    g.lower = simd::lanes_of(bounds.lower);
    g.size = simd::f4{cell_size.x, cell_size.y, cell_size.z, 1.f};
    g.last = simd::f4{float(dims.x - 1), float(dims.y - 1), float(dims.z - 1), 0.f};
    g.last_subcell =
        simd::f4{float(kSubcells * dims.x - 1), float(kSubcells * dims.y - 1), float(kSubcells * dims.z - 1), 0.f};
    return g;
  }
  // q truncated after clamping it to [0, last] (NaN gives 0), lanes x, y, z (the fourth is 0).
  static VS_FORCE_INLINE simd::i4 clamped_floor(const simd::f4& q, const simd::f4& last) {
    const simd::f4 zero = {}, above = q > zero ? q : zero;
    return __builtin_convertvector(above < last ? above : last, simd::i4);
  }
  static VS_FORCE_INLINE simd::i4 cell_of(const Lanes& g, const vec3f& p) {
    return clamped_floor((simd::lanes_of(p) - g.lower) / g.size, g.last);
  }
  // subcell_of(p) below as lanes, with the same operations in the same order (the same ints).
  static VS_FORCE_INLINE simd::i4 subcell_of(const Lanes& g, const vec3f& p) {
    return clamped_floor(float(kSubcells) * ((simd::lanes_of(p) - g.lower) / g.size), g.last_subcell);
  }
  VS_FORCE_INLINE vec3i cell_of(const vec3f& p) const {
    const simd::i4 c = cell_of(lanes(), p);
    return {c[0], c[1], c[2]};
  }
#else
  VS_HOST_DEVICE VS_FORCE_INLINE vec3i cell_of(const vec3f& p) const {
    vec3i c;
    for (int a = 0; a < 3; ++a) {
      const float q = (p[a] - bounds.lower[a]) / cell_size[a], last = float(dims[a] - 1);
      c[a] = int(q > 0.f ? (q < last ? q : last) : 0.f);
    }
    return c;
  }
#endif
  VS_HOST_DEVICE uint64_t index(const vec3i& c) const {
    return (uint64_t(c.z) * uint64_t(dims.y) + uint64_t(c.y)) * uint64_t(dims.x) + uint64_t(c.x);
  }
  // The cell of grid index i (index's inverse).
  VS_HOST_DEVICE vec3i cell_at(uint64_t i) const {
    const uint64_t row = uint64_t(dims.x), plane = row * uint64_t(dims.y);
    return {int(i % row), int(i / row % uint64_t(dims.y)), int(i / plane)};
  }
  uint64_t cell_count() const { return uint64_t(dims.x) * uint64_t(dims.y) * uint64_t(dims.z); }
  // Axis a's faces of the cells in layer k; the last layer ends exactly on the bounds (no
  // rounding gap at the far faces).
  VS_HOST_DEVICE void layer_faces(int a, int k, float& lower, float& upper) const {
    lower = bounds.lower[a] + float(k) * cell_size[a];
    upper = k == dims[a] - 1 ? bounds.upper[a] : lower + cell_size[a];
  }
  // The box of cell c.
  VS_HOST_DEVICE box3f cell_box(const vec3i& c) const {
    box3f b;
    for (int a = 0; a < 3; ++a) layer_faces(a, c[a], b.lower[a], b.upper[a]);
    return b;
  }
  // The subcell of p, clamped into the grid, where each cell has kSubcells^3 subcells:
  // cell_of's quotient times kSubcells (a power of 2: exact), so the cell of subcell s is
  // s / kSubcells = cell_of(p), and like cell_of it is monotonic in each axis: a point in a box
  // lies between the subcells of the box's corners.
  VS_HOST_DEVICE vec3i subcell_of(const vec3f& p) const {
    vec3i s;
    for (int a = 0; a < 3; ++a) {
      const float q = float(kSubcells) * ((p[a] - bounds.lower[a]) / cell_size[a]);
      const float last = float(kSubcells * dims[a] - 1);
      s[a] = int(q > 0.f ? (q < last ? q : last) : 0.f);
    }
    return s;
  }
};

// A cell's kSubcells^3 subcells as bits: word z holds layer z, bit x + 8y in it.
struct SubcellMask {
  uint64_t layer[MacroGrid::kSubcells] = {};
  bool operator==(const SubcellMask&) const = default;
  static_assert(MacroGrid::kSubcells == 8, "a layer of subcells is one 64-bit word");
};

// Which subcells of each non-empty macrocell some element's corner box overlaps (MacroCells::
// subcells). A point in any other subcell lies in no element: point location tests an element
// only where the element's corner box holds the point (UMeshView::in_element, CompactMeshView::
// test_element), so a search for it (the element BVH, the compact tree's leaves) would find
// nothing. On a mesh that does not fill its macrocells (the twisted
// boundary of the mixed demo, holes, the space around a body) rays sample such points, and each
// cost a search from the BVH's root.
struct SubcellOccupancy {
  static constexpr uint32_t kAllOccupied = 0xffffffffu;
  MacroGrid grid;
  const int32_t* region_of_cell = nullptr;  // MacroCells::region_of_cell
  // Per region, its mask in `masks`, or kAllOccupied (MacroCells::SubcellMasks); null: nothing
  // is ruled out.
  const uint32_t* mask_of_region = nullptr;
  const SubcellMask* masks = nullptr;
  // True when p lies in no element's corner box (outside the grid too: the grid's bounds are
  // the boxes' union).
  VS_HOST_DEVICE bool rules_out(const vec3f& p) const {
    if (!mask_of_region) return false;
    constexpr int n = MacroGrid::kSubcells;
    const vec3i s = grid.subcell_of(p);
    const int32_t region = region_of_cell[grid.index({s.x / n, s.y / n, s.z / n})];
    if (region < 0) return true;
    const uint32_t mask = mask_of_region[region];
    return mask != kAllOccupied && !((masks[mask].layer[s.z % n] >> (s.x % n + n * (s.y % n))) & 1u);
  }
};

}  // namespace vs
