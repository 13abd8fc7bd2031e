// What the readers' cell replacements share (polyhedra.h, quadratic.h: some cells of a MeshData
// replaced by linear elements on the cells' vertices and on points they add; mesh_pieces.h:
// ghost cells dropped).
#pragma once
#include <cstddef>
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

// True when each array has at least one component and `tuples` tuples of them.
bool arrays_match(const std::vector<MeshArray>& arrays, uint64_t tuples);

// The new cells of a mesh, and the points they add, collected in order; finish() puts them in
// the mesh's place, each cell with the cell data of the cell it came from, each added point's data
// the same sum of its vertices' data as its place. finish() leaves the rebuild as it was, so a
// SplitMemo can apply it again to the next step of a series.
class CellRebuild {
 public:
  // A new point of `mesh` at sum(weights[i] * points[vertices[i]]), at its place now (the
  // splits look at it) and with its data at finish(); returns its index.
  uint64_t add_point(MeshData& mesh, std::span<const uint64_t> vertices, std::span<const double> weights);
  void add(uint8_t type, std::span<const uint64_t> vertices, uint64_t from_cell);
  void keep(const MeshData& mesh, uint64_t cell);  // cell as it is
  void finish(MeshData& mesh) const&;              // the rebuild kept (for a SplitMemo)
  void finish(MeshData& mesh) &&;                  // its cells moved into the mesh

  // finish() in two halves, for a mesh whose every step has the same cells (FixedMeshSplit in
  // polyhedra.h): the cells moved into `mesh` once, then each step's data (on the points and
  // cells before the rebuild) combined as finish() combines them.
  void move_cells(MeshData& mesh);
  void finish_data(std::vector<MeshArray>& point_data, std::vector<MeshArray>& cell_data) const;

 private:
  void add_point_data(std::vector<MeshArray>& point_data) const;
  void gather_cell_data(std::vector<MeshArray>& cell_data) const;

  std::vector<uint8_t> types_;
  std::vector<uint64_t> offsets_{0}, connectivity_, source_;
  uint64_t first_added_ = 0;  // the index of the first added point
  std::vector<uint64_t> added_offsets_{0}, added_vertices_;
  std::vector<double> added_weights_;
};

// What else a split read besides the mesh (polyhedron faces: PolyhedronFaces::key), as bytes.
using SplitKey = std::span<const std::span<const std::byte>>;

// The last split (polyhedra.h, quadratic.h) of a reader's series, kept for its next step: a time
// series' steps mostly have the same points and cells, and then the split need not run again;
// only the step's data is combined, as the split combined the first's. Readers pass theirs only
// for a series of more than one step: remembering copies the mesh's points and cells.
class SplitMemo {
 public:
  // True, with `mesh` split as the remembered one was, when its points, cell types, offsets and
  // connectivity, and `key` (what else the split read: polyhedron faces), are that one's.
  // InputError naming `file` when its data arrays do not match its points or cells.
  bool reuse(MeshData& mesh, SplitKey key, const std::string& file) const;
  // A split remembered in two halves: the mesh and key before it, then the rebuild and the
  // points after it (when it did not throw).
  void split_begins(const MeshData& source, SplitKey key);
  void split_ends(CellRebuild rebuild, const std::vector<vec3d>& points);

 private:
  MeshData source_;  // points and cells only
  std::vector<vec3d> split_points_;
  std::vector<std::vector<std::byte>> key_;
  CellRebuild rebuild_;
  bool remembered_ = false;
};

}  // namespace vs
