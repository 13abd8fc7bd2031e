// Pyramids, wedges and hexahedra split into tetrahedra over the same vertices (convert and demo
// --split-into-tets): what VTK users do with vtkDataSetTriangleFilter before its ray cast mapper,
// which takes tets only. A tet is sampled by one affine solve (its walk record, element_bvh.h)
// where the other types need Newton's iteration, so a mixed mesh renders faster split; the price
// is the interpolation, linear over each tet instead of VTK's shape functions of the element
// (the same at the corners and along the edges the split keeps; a linear field is still exact).
//
// The split is conforming without new vertices: each quad face is cut along the diagonal through
// its vertex of lowest index (the mesh's numbering), which both elements sharing the face choose
// alike; an element is then the cone from its own lowest vertex over the faces not holding it
// (their triangles, or their quads cut as above), which cuts the faces holding that vertex along
// diagonals through it, as the rule asks. Pyramids give 2 tets, wedges 3, hexahedra 6.
// On an element that is not convex (a strongly twisted hex) the cone's tets may overlap or fold;
// point location then takes one of them.
#pragma once
#include <cstdint>

#include "volstream/umesh/umesh.h"

namespace vs {

// Tets per element of n vertices (4: 1, 5: 2, 6: 3, 8: 6).
constexpr uint64_t tets_per_element(int vertex_count) {
  return vertex_count == 4 ? 1 : vertex_count == 5 ? 2 : vertex_count == 6 ? 3 : 6;
}

// The mesh's elements as tets (element i's tets in a row, in order), the vertices unchanged (moved
// over, not copied), so every per-vertex field goes with it as it is. Each tet is ordered as
// VTK's tet with the orientation its element has (positive in the element's parametric space).
UMesh split_into_tets(UMesh mesh);

}  // namespace vs
