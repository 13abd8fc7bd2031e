// The order a mesh is stored in: elements by the Morton code of their centres, vertices by their
// first use in that order. A sample's walk goes from element to face neighbour and reads their
// corners, so neighbours near in memory keep it in cache whatever order the file had (a solver's
// partition order, a generator's front order): the 1M-tet demo mesh shuffled at random rendered
// 1.5x slower than the same mesh in order (bench/RESULTS.md). `convert` applies it to the mesh
// and to every (field, step) of vertex values.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/umesh/umesh.h"

namespace vs {

struct MeshOrder {
  std::vector<uint32_t> element_source;  // stored element i is the input's element_source[i]
  std::vector<uint32_t> vertex_target;   // the input's vertex v is stored as vertex_target[v]
};

MeshOrder spatial_order(const UMesh& mesh);

// The mesh stored in `order`: the same elements (corners in the same local order) and vertices.
UMesh reordered(const UMesh& mesh, const MeshOrder& order);

// Per-vertex values of the input in the stored vertex order.
std::vector<float> reordered_values(const std::vector<float>& values, const MeshOrder& order);

}  // namespace vs
