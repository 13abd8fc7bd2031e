// VTK polyhedra (cell type 42: a cell given by its faces) as the tets and pyramids the renderer
// samples. OpenFOAM's foamToVTK writes every cell of a snappyHexMesh or cfMesh mesh that is not a
// hex, prism, pyramid or tet as one (the cells at a refinement step, whose faces are split to meet
// their smaller neighbours), and ParaView writes them from Fluent and CGNS polyhedral meshes.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "volstream/umesh/cell_rebuild.h"
#include "volstream/umesh/mesh_data.h"

namespace vs {

constexpr uint8_t kVtkPolyhedron = 42;

// A point index or a face id in PolyhedronFaces: 32 bits, as the encodings' vertex and element
// ids are (umesh/umesh.h), which halves the largest arrays a solver case's read holds (a mesh of
// 2^32 points or faces or more is refused, by check_face_index_count).
using FaceIndex = uint32_t;
inline constexpr uint64_t kFaceIndexLimit = uint64_t(UINT32_MAX);  // the ids below this fit
// InputError naming `file` unless `count` ids (points or faces) fit a FaceIndex.
void check_face_index_count(uint64_t count, const char* what, const std::string& file);
// A reader's point index as a FaceIndex, or the largest FaceIndex where it does not fit (negative
// or 2^32 - 1 and up): no point has that index (check_face_index_count), so the range checks
// that follow refuse it.
inline FaceIndex saturated_face_index(int64_t v) {
  return v >= 0 && uint64_t(v) < kFaceIndexLimit ? FaceIndex(v) : FaceIndex(kFaceIndexLimit);
}

// The faces of a mesh's polyhedra, in two CSR levels (the layout of VTK 9.4's XML files): cell
// c's faces are the face ids cell_faces[cell_face_offsets[c] .. cell_face_offsets[c + 1]) (none
// for a cell of another type), and face f's vertices, in order around it, are the point indices
// face_vertices[face_offsets[f] .. face_offsets[f + 1]).
struct PolyhedronFaces {
  std::vector<uint64_t> cell_face_offsets{0};
  std::vector<FaceIndex> cell_faces;
  std::vector<uint64_t> face_offsets{0};
  std::vector<FaceIndex> face_vertices;

  // The four arrays as bytes, for a SplitMemo to compare.
  std::array<std::span<const std::byte>, 4> key() const {
    return {std::as_bytes(std::span(cell_face_offsets)), std::as_bytes(std::span(cell_faces)),
            std::as_bytes(std::span(face_offsets)), std::as_bytes(std::span(face_vertices))};
  }
  // The next cell, with no faces (a cell of another type).
  void add_other_cell() { cell_face_offsets.push_back(cell_face_offsets.back()); }
  // The next cell from VTK's face stream (the faces of older XML files and of legacy files): its
  // face count, then each face's vertex count and vertices. InputError naming `file` and
  // `cell` when the stream ends early or holds more than its faces.
  void add_face_stream(std::span<const uint64_t> stream, uint64_t cell, const std::string& file);
};

// The cells on a face's two sides, 1-based; 0 where there is none (the outside of a boundary
// face).
struct FaceCells {
  uint64_t first = 0, second = 0;
};

// Polyhedra given by the cells on each side of their faces, as finite-volume solvers store them
// (Fluent's c0 and c1, OpenFOAM's owner and neighbour, CGNS's ParentElements): face f's vertices
// are face_vertices[face_offsets[f] .. face_offsets[f + 1]), and each of cells 1..cell_count has
// the faces that name it, in face order. InputError naming `file` for a cell number above
// cell_count.
PolyhedronFaces polyhedra_from_face_cells(std::vector<uint64_t> face_offsets, std::vector<FaceIndex> face_vertices,
                                          std::span<const FaceCells> face_cells, uint64_t cell_count,
                                          const std::string& file);

// The faces of the polyhedra of a legacy .vtk file, whose connectivity holds a polyhedron's face
// stream where another cell's holds its vertices.
PolyhedronFaces faces_in_connectivity(const MeshData& mesh, const std::string& file);

// Replaces each polyhedron of `mesh` (given by `faces`) by elements from its vertex centroid,
// which is added as a point: a tet on each triangle, a pyramid on each quad (whose bilinear face
// is the neighbour's, be it a hex, a wedge or another polyhedron), and on a face of more
// vertices a tet on each edge from the face's centre, also added as a point and shared with the
// polyhedron on the face's other side (a fan from one vertex would make flat tets where three
// vertices lie on a line, as they do at a refinement step). Each element is in VTK's orientation
// for its type; the elements of a cell come in its place and carry its cell data; an added
// point's data is the mean of its vertices' (so a field linear in space stays exact). Other
// cells are left as they are; with no polyhedron, nothing changes. InputError naming `file` for
// faces or indices out of range, a face of fewer than 3 vertices, a polyhedron of fewer than 4
// faces, one that is not closed (an edge not in exactly two of its faces), or one that is not
// star-shaped about its vertex centroid (a flat element, or, where the faces are oriented
// alike, elements seen from the centroid the wrong way round). With a `memo` (a reader's, for
// its series), a mesh with the points, cells and faces of the one split last is split as that
// one was, only its data combined.
void split_polyhedra(MeshData& mesh, const PolyhedronFaces& faces, const std::string& file, SplitMemo* memo = nullptr);

// The polyhedra of a mesh that every step of a series has by construction (a solver's case, whose
// mesh is read once: Fluent, OpenFOAM) split once, as split_polyhedra splits them: the split mesh,
// and each step's data, given on the unsplit mesh's points and cells, combined as the split
// combines them. Unlike a SplitMemo, nothing is compared with the first step or copied per step.
class FixedMeshSplit {
 public:
  // `unsplit`: points and cells, without data. InputError as split_polyhedra.
  FixedMeshSplit(MeshData unsplit, const PolyhedronFaces& faces, const std::string& file);
  const MeshData& mesh() const { return mesh_; }  // the split mesh, without data
  // A step's arrays, on the unsplit points and cells, as the split mesh's. InputError naming
  // `file` when an array does not match the unsplit points or cells.
  void split_data(std::vector<MeshArray>& point_data, std::vector<MeshArray>& cell_data, const std::string& file) const;
  // The same for a case's cell arrays alone (Fluent's and OpenFOAM's fields are cell data).
  void split_cell_data(std::vector<MeshArray>& cell_data, const std::string& file) const {
    std::vector<MeshArray> no_point_data;
    split_data(no_point_data, cell_data, file);
  }
  // The split mesh with a step's split cell arrays, checked (check_mesh, naming `file`).
  MeshData mesh_with(std::vector<MeshArray> cell_data, const std::string& file) const;
  // mesh_with for the split mesh's last use (a convert's first step): the mesh is moved out, not
  // copied, and mesh_with and take_mesh_with throw std::logic_error after it; split_data and
  // split_cell_data still work.
  MeshData take_mesh_with(std::vector<MeshArray> cell_data, const std::string& file);

 private:
  void check_not_taken() const;
  MeshData mesh_;
  bool taken_ = false;
  std::optional<CellRebuild> rebuild_;  // its cells moved into mesh_; none where nothing was split
  uint64_t unsplit_points_ = 0, unsplit_cells_ = 0;
};

}  // namespace vs
