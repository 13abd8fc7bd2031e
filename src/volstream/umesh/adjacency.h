// Face adjacency of a mesh, for the walk of point location (element_bvh.h): per element and per
// face (shape.h's face numbering) the element on the other side, or kNoNeighbor on the mesh's
// boundary and where faces do not match vertex for vertex (a quad against two triangles).
// kMaxFaces slots per element: 24 B per element. Built by buckets of each face's smallest vertex
// (16 B a face while building; adjacency.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/umesh/shape.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr uint32_t kNoNeighbor = 0xffffffffu;

using shape::local_face;
using shape::LocalFace;

// neighbors[e * kMaxFaces + f]: the element across face f of element e.
std::vector<uint32_t> build_face_neighbors(const UMesh& mesh);

}  // namespace vs
