// The reference encoding of an unstructured mesh (issue 12; the compact encoding of paper 002 is
// measured against it): float vertices in grid units, one fixed 8-slot record of 32-bit vertex
// indices per element in VTK's vertex order, unused slots kNoVertex. The element's type follows
// from its used slots (4 tet, 5 pyramid, 6 wedge, 8 hex), so no type array: 32 B per element.
// Field values are one float per vertex (vertex-centred, as FUN3D writes them; cell data is
// averaged to the vertices at convert, docs/formats.md).
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/core/host_array.h"
#include "volstream/core/math.h"
#if defined(__GNUC__) && !defined(__CUDACC__)
#include "volstream/core/simd.h"  // element_box's lanes
#endif

namespace vs {

inline constexpr uint32_t kNoVertex = 0xffffffffu;

struct UElement {
  uint32_t v[8];
  // VTK cell type id: 10 tet, 14 pyramid, 13 wedge, 12 hex.
  VS_HOST_DEVICE int vertex_count() const {
    return v[4] == kNoVertex ? 4 : v[5] == kNoVertex ? 5 : v[6] == kNoVertex ? 6 : 8;
  }
};
static_assert(sizeof(UElement) == 32);

VS_HOST_DEVICE constexpr uint32_t vtk_type_of(int vertex_count) {
  return vertex_count == 4 ? 10u : vertex_count == 5 ? 14u : vertex_count == 6 ? 13u : 12u;
}

// Index of a VTK type in per-type tables: tet 0, pyramid 1, wedge 2, hex 3.
VS_HOST_DEVICE constexpr int type_slot(int vertex_count) {
  return vertex_count == 4 ? 0 : vertex_count == 5 ? 1 : vertex_count == 6 ? 2 : 3;
}
inline constexpr const char* kTypeSlotNames[4] = {"tetra", "pyramid", "wedge", "hexahedron"};

struct UMesh {
  HostArray<vec3f> vertices;  // grid units: world = transform.to_world(vertex)
  HostArray<UElement> elements;
  uint64_t count_by_type[4] = {};  // type_slot order
};

#if defined(__GNUC__) && !defined(__CUDACC__)
// A box as lanes (x, y, z, and 0 in the fourth).
struct BoxLanes {
  simd::f4 lower, upper;
};
using simd::lanes_of;
// corners_box on the host's lanes (below), for callers that go on with lanes.
template <typename Corner>
VS_FORCE_INLINE BoxLanes corners_box_lanes(int n, Corner&& corner) {
  BoxLanes b{{INFINITY, INFINITY, INFINITY, 0.f}, {-INFINITY, -INFINITY, -INFINITY, 0.f}};
  for (int i = 0; i < n; ++i) {
    const simd::f4 x = lanes_of(corner(i));
    b.lower = b.lower < x ? b.lower : x;
    b.upper = b.upper > x ? b.upper : x;
  }
  return b;
}
// outer.contains(b) (box3f::contains: both corners of b inside, NaN false) on lanes.
VS_FORCE_INLINE bool box_contains(const box3f& outer, const BoxLanes& b) {
  const simd::f4 lo = lanes_of(outer.lower), hi = lanes_of(outer.upper);
  const simd::i4 in = (b.lower >= lo) & (b.lower <= hi) & (b.upper >= lo) & (b.upper <= hi);
  return simd::all_equal(in, simd::i4{} - 1);
}
#endif

// The box of corners corner(0..n) (each a vec3f). On the host the three axes go on one SSE
// register, with the comparisons of box3f::extend in the same order, so the floats are the
// same: a load checks and bins every element's box two or three times over.
template <typename Corner>
VS_HOST_DEVICE VS_FORCE_INLINE box3f corners_box(int n, Corner&& corner) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  const BoxLanes b = corners_box_lanes(n, corner);
  return {{b.lower[0], b.lower[1], b.lower[2]}, {b.upper[0], b.upper[1], b.upper[2]}};
#else
  box3f b = box3f::make_empty();
  for (int i = 0; i < n; ++i) b.extend(corner(i));
  return b;
#endif
}

VS_HOST_DEVICE inline box3f element_box(const vec3f* vertices, const UElement& e) {
  return corners_box(e.vertex_count(), [&](int i) -> const vec3f& { return vertices[e.v[i]]; });
}
#if defined(__GNUC__) && !defined(__CUDACC__)
VS_FORCE_INLINE BoxLanes element_box_lanes(const vec3f* vertices, const UElement& e) {
  return corners_box_lanes(e.vertex_count(), [&](int i) -> const vec3f& { return vertices[e.v[i]]; });
}
#endif

}  // namespace vs
