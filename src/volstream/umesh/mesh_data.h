// An unstructured mesh as the file readers hand it over (io/vtu.h, io/vtk_legacy.h, io/ugrid.h):
// VTK's conventions, whatever the file's: VTK cell type ids, VTK's vertex order per type,
// 0-based point indices, one CSR connectivity. Readers check the file's own structure (sizes,
// encodings, truncation); check_mesh() checks the mesh itself (supported types, vertex counts,
// indices in range, finite coordinates, array sizes) for every reader alike.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/core/math.h"

namespace vs {

// VTK cell type ids of the linear 3D elements the renderer samples.
enum class CellType : uint8_t { tet = 10, hex = 12, wedge = 13, pyramid = 14 };

// Vertices of a supported VTK cell type (4, 8, 6, 5); 0 for any other id.
constexpr int cell_vertex_count(uint32_t vtk_type) {
  switch (vtk_type) {
    case 10:
      return 4;
    case 12:
      return 8;
    case 13:
      return 6;
    case 14:
      return 5;
    default:
      return 0;
  }
}
const char* cell_type_name(uint32_t vtk_type);  // "tetra", "hexahedron", ..., or "unknown"

// A data array: `components` values per point (or per cell), interleaved as in VTK.
struct MeshArray {
  std::string name;
  int components = 1;
  std::vector<double> values;  // tuple count * components
};

struct MeshData {
  std::vector<vec3d> points;
  std::vector<uint8_t> cell_types;     // VTK ids as read (check_mesh refuses unsupported ones)
  std::vector<uint64_t> cell_offsets;  // cell i: connectivity[cell_offsets[i] .. cell_offsets[i+1]); cells + 1 entries
  std::vector<uint64_t> connectivity;  // 0-based point indices, VTK vertex order
  std::vector<MeshArray> point_data, cell_data;
  uint64_t cell_count() const { return cell_types.size(); }
};

// VTK's voxels (type 11: axis-aligned boxes, vertices in x-fastest order, as ParaView's threshold
// of image data writes them) as the hexahedra they are (type 12, VTK's hex order: the same
// trilinear field). Readers of VTK formats call this before check_mesh; a voxel without 8
// vertices is left for check_mesh to refuse.
void voxels_to_hexahedra(MeshData& mesh);

// InputError naming `file` unless the mesh can be converted: at least one cell, only tets, hexes,
// wedges and pyramids (else "unsupported cell type 5 (triangle) in 12 cells"), offsets
// consistent with the types, indices < points, finite coordinates, array sizes matching.
void check_mesh(const MeshData& mesh, const std::string& file);

}  // namespace vs
