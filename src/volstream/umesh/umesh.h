// The reference encoding of an unstructured mesh (issue 12; the compact encoding of paper 002 is
// measured against it): float vertices in grid units, one fixed 8-slot record of 32-bit vertex
// indices per element in VTK's vertex order, unused slots kNoVertex. The element's type follows
// from its used slots (4 tet, 5 pyramid, 6 wedge, 8 hex), so no type array: 32 B per element.
// Field values are one float per vertex (vertex-centred, as FUN3D writes them; cell data is
// averaged to the vertices at convert, docs/formats.md).
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/core/math.h"

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
  std::vector<vec3f> vertices;  // grid units: world = transform.to_world(vertex)
  std::vector<UElement> elements;
  uint64_t count_by_type[4] = {};  // type_slot order
};

VS_HOST_DEVICE inline box3f element_box(const vec3f* vertices, const UElement& e) {
  box3f b = box3f::make_empty();
  const int n = e.vertex_count();
  for (int i = 0; i < n; ++i) b.extend(vertices[e.v[i]]);
  return b;
}

}  // namespace vs
