// From a file's mesh (MeshData, VTK conventions) to the renderer's reference encoding (UMesh)
// and per-vertex float fields.
//
// Coordinates: grid units are world units shifted by the mesh's lower corner (transform origin),
// so float vertices keep their precision far from the world origin.
//
// Fields: every point array becomes fields; a vector array (components > 1) gives its magnitude
// under its own name and each component as NAME_x, NAME_y, NAME_z (NAME_0, NAME_1, ... beyond
// three). Cell arrays are averaged to the vertices (each vertex takes the mean over the cells
// that use it), so every field is interpolated by the same shape functions; a name used by both
// a point and a cell array keeps the point array and the cell array gets the suffix "_cell".
#pragma once
#include <string>
#include <vector>

#include "volstream/amr/source.h"
#include "volstream/umesh/mesh_data.h"
#include "volstream/umesh/umesh.h"

namespace vs {

// The mesh's geometry checked and encoded: InputError naming `file` for a degenerate element
// (no volume), a tangled one (its corners' Jacobians differ in sign) or an inverted one (its
// orientation is the opposite of most elements of its type), or more than 2^32 - 1 vertices.
UMesh make_umesh(const MeshData& data, const WorldTransform& transform, const std::string& file);
WorldTransform mesh_transform(const MeshData& data);

struct MeshFieldRef {
  std::string name;
  bool cell = false;   // a cell array, averaged to vertices
  size_t array = 0;    // index into point_data or cell_data
  int component = -1;  // -1: the value (1 component) or the magnitude; else that component
};
std::vector<MeshFieldRef> mesh_fields(const MeshData& data);
// The cells each point is a corner of, in increasing order (CSR: point p's are
// cells[offsets[p] .. offsets[p + 1])), for averaging cell data to the points.
struct PointCells {
  std::vector<uint64_t> offsets;
  std::vector<uint32_t> cells;
};
PointCells point_cells_of(const MeshData& data);  // data checked as make_umesh checks it
// One value per point (float; NaN where a vertex belongs to no cell and the field is cell data:
// each point's value the mean of its cells', summed in cell order). `cells` (point_cells_of(data),
// kept by a caller that averages several arrays) saves finding them again.
std::vector<float> mesh_field_values(const MeshData& data, const MeshFieldRef& field,
                                     const PointCells* cells = nullptr);

// InputError naming `file` unless `step` has exactly the mesh of `first` (points, cells).
void check_same_mesh(const MeshData& first, const MeshData& step, const std::string& file);

}  // namespace vs
