// VTK's quadratic and Lagrange cells as linear elements on their nodes. Finite-element codes write
// second-order meshes (Abaqus C3D10 and C3D20, ANSYS SOLID187, COMSOL, FEniCS, deal.II and MOOSE's
// HEX27) as the quadratic cells, high-order and spectral-element codes (dolfinx, deal.II, MFEM,
// Nektar++, FLEXI) as Lagrange cells, and ParaView's volume mappers draw them the same way: split
// into linear pieces.
#pragma once
#include <string>

#include "volstream/umesh/cell_rebuild.h"
#include "volstream/umesh/mesh_data.h"

namespace vs {

// VTK ids of the cells split_quadratic_cells() splits.
enum class QuadraticCell : uint8_t {
  tet10 = 24,         // quadratic tetra
  hex20 = 25,         // quadratic hexahedron (serendipity)
  wedge15 = 26,       // quadratic wedge
  pyramid13 = 27,     // quadratic pyramid
  hex27 = 29,         // triquadratic hexahedron
  wedge18 = 32,       // biquadratic-quadratic wedge
  hex24 = 33,         // biquadratic-quadratic hexahedron
  lagrange_tet = 71,  // Lagrange tetra of order 2 to 10 ((p + 1)(p + 2)(p + 3) / 6 nodes)
  lagrange_hex = 72,  // Lagrange hexahedron of order 2 to 10 ((p + 1)^3 nodes)
};

// Nodes of a quadratic cell type above (10, 20, 15, 13, 27, 18, 24); 0 for any other id.
int quadratic_node_count(uint32_t vtk_type);

// VTK's Lagrange cells (71 tetrahedron, 72 hexahedron, 73 wedge, 74 pyramid) of order 1 have the
// nodes of the linear cells, and the wedge of order 2 those of the biquadratic-quadratic wedge
// (18), in the same order; split_quadratic_cells() reads them as those. A Lagrange hexahedron or
// tetra of order p from 2 to 10 is split into the p^3 hexes or tets of its node lattice (at order
// 2 its nodes are the triquadratic hexahedron's and the quadratic tetra's). Returns the type a
// Lagrange cell of `nodes` nodes is read as (71 and 72 for cells split so); 0 for another order
// (or the 15-node tetra and 21-node wedge variants), and for any other type.
uint8_t lagrange_as_fixed_type(uint32_t vtk_type, uint64_t nodes);

// Before VTK 9.1 a Lagrange hexahedron listed the nodes of its edges (2,6) and (3,7) the other way
// round. Files older than that (XML version below 2.2, legacy below 5.1) are read as VTK reads
// them: their readers call this, which swaps the nodes inside those two edges (18 and 19 at order
// 2) of each Lagrange hexahedron of order 2 or more of `mesh`. Other cells, and cells whose
// offsets do not span the connectivity, are left as they are (for the checks after).
void lagrange_hexahedra_from_pre_vtk91_order(MeshData& mesh);

// Replaces each quadratic cell of `mesh` by the linear elements of its nodes, halving each of its
// edges: a tet10 by 8 tets (its inner octahedron cut along its shortest diagonal), a hex by 8
// hexes, a wedge by 8 wedges, a pyramid by 6 pyramids and 4 tets. The nodes a cell lacks for that
// (the centres of a serendipity quad face and of a hex's body) are added as points where the
// cell's own shape functions put them, with the values those functions give there: -1/4 of each
// corner and +1/2 of each mid-edge node for a quad face, as VTK's cells give. A face's centre is
// shared by the two cells on it. The pieces keep the cell's orientation and its cell data. So the
// field is exact at every node and piecewise linear (trilinear) between them, and exact
// everywhere for a field linear in space; a curved cell's faces become flat or bilinear pieces
// through its nodes. Lagrange cells are read as lagrange_as_fixed_type() says first. Other cells
// are left as they are. InputError naming `file` for a quadratic cell with the wrong number of
// vertices or a vertex index out of range, and a Lagrange cell of another order. With a `memo`
// (a reader's, for its series), a mesh with the points and cells of the one split last is split
// as that one was, only its data combined.
void split_quadratic_cells(MeshData& mesh, const std::string& file, SplitMemo* memo = nullptr);

}  // namespace vs
