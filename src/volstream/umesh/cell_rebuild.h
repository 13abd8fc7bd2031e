// What the readers' cell replacements share (polyhedra.h, quadratic.h: some cells of a MeshData
// replaced by linear elements on the cells' vertices and on points they add; mesh_pieces.h:
// ghost cells dropped).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

// InputError naming `file` (with `what`, the cells being replaced) unless the cell offsets span
// the connectivity and every data array matches the points or the cells: the replacements index
// by them before check_mesh runs.
void check_rebuild_input(const MeshData& mesh, const char* what, const std::string& file);

// A new point of `mesh` at sum(weights[i] * points[vertices[i]]), its data the same sum of the
// vertices' data; returns its index.
uint64_t add_combined_point(MeshData& mesh, std::span<const uint64_t> vertices, std::span<const double> weights);

// The new cells of a mesh, collected in order; finish() puts them in the mesh's place, each with
// the cell data of the cell it came from.
class CellRebuild {
 public:
  void add(uint8_t type, std::span<const uint64_t> vertices, uint64_t from_cell);
  void keep(const MeshData& mesh, uint64_t cell);  // cell as it is
  void finish(MeshData& mesh);

 private:
  std::vector<uint8_t> types_;
  std::vector<uint64_t> offsets_{0}, connectivity_, source_;
};

}  // namespace vs
