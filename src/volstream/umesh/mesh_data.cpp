#include "volstream/umesh/mesh_data.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "volstream/core/error.h"

namespace vs {

const char* cell_type_name(uint32_t vtk_type) {
  switch (vtk_type) {
    case 1:
      return "vertex";
    case 3:
      return "line";
    case 5:
      return "triangle";
    case 7:
      return "polygon";
    case 9:
      return "quad";
    case 10:
      return "tetra";
    case 11:
      return "voxel";
    case 12:
      return "hexahedron";
    case 13:
      return "wedge";
    case 14:
      return "pyramid";
    case 24:
      return "quadratic tetra";
    case 25:
      return "quadratic hexahedron";
    case 26:
      return "quadratic wedge";
    case 27:
      return "quadratic pyramid";
    case 29:
      return "triquadratic hexahedron";
    case 32:
      return "biquadratic-quadratic wedge";
    case 33:
      return "biquadratic-quadratic hexahedron";
    case 37:
      return "triquadratic pyramid";
    case 42:
      return "polyhedron";
    case 71:
      return "Lagrange tetra";
    case 72:
      return "Lagrange hexahedron";
    case 73:
      return "Lagrange wedge";
    case 74:
      return "Lagrange pyramid";
    default:
      return "unknown";
  }
}

namespace {

void check_cells(const MeshData& m, const std::string& file) {
  const uint64_t n = m.cell_count();
  input_check(n > 0, file, "the mesh has no cells");
  input_check(
      m.cell_offsets.size() == n + 1, file,
      "cell offsets: " + std::to_string(m.cell_offsets.size()) + " entries for " + std::to_string(n) + " cells");
  std::map<uint32_t, uint64_t> unsupported;
  for (uint64_t i = 0; i < n; ++i)
    if (cell_vertex_count(m.cell_types[i]) == 0) ++unsupported[m.cell_types[i]];
  if (!unsupported.empty()) {
    const auto& [type, count] = *unsupported.begin();
    input_error(file,
                "unsupported cell type " + std::to_string(type) + " (" + cell_type_name(type) + ") in " +
                    std::to_string(count) + " cells (volstream renders tetra 10, hexahedron 12, wedge 13, " +
                    "pyramid 14; of VTK files also voxels 11, polyhedra 42 and the quadratic cells 24-27, 29, 32 " +
                    "and 33, split into those)");
  }
  input_check(m.cell_offsets[0] == 0 && m.cell_offsets[n] == m.connectivity.size(), file,
              "cell offsets do not span the connectivity array");
  for (uint64_t i = 0; i < n; ++i) {
    const uint64_t count = m.cell_offsets[i + 1] - m.cell_offsets[i];
    if (m.cell_offsets[i + 1] < m.cell_offsets[i] || count != uint64_t(cell_vertex_count(m.cell_types[i])))
      input_error(file, "cell " + std::to_string(i) + " (" + cell_type_name(m.cell_types[i]) + ") has " +
                            std::to_string(int64_t(m.cell_offsets[i + 1] - m.cell_offsets[i])) +
                            " vertices, expected " + std::to_string(cell_vertex_count(m.cell_types[i])));
  }
  for (uint64_t i = 0; i < m.connectivity.size(); ++i)
    if (m.connectivity[i] >= m.points.size())
      input_error(file, "connectivity entry " + std::to_string(i) + " = " + std::to_string(m.connectivity[i]) +
                            " is out of range (" + std::to_string(m.points.size()) + " points)");
}

void check_arrays(const std::vector<MeshArray>& arrays, uint64_t tuples, const char* kind, const std::string& file) {
  for (const MeshArray& a : arrays) {
    input_check(a.components >= 1, file, std::string(kind) + " array '" + a.name + "' has no components");
    input_check(a.values.size() == tuples * uint64_t(a.components), file,
                std::string(kind) + " array '" + a.name + "' has " + std::to_string(a.values.size()) +
                    " values, expected " + std::to_string(tuples * uint64_t(a.components)));
  }
}

}  // namespace

void voxels_to_hexahedra(MeshData& m) {
  constexpr uint8_t kVoxel = 11;
  constexpr int kHexOrder[8] = {0, 1, 3, 2, 4, 5, 7, 6};  // hex corner k is voxel corner kHexOrder[k]
  for (size_t c = 0; c < m.cell_types.size() && c + 1 < m.cell_offsets.size(); ++c) {
    const uint64_t begin = m.cell_offsets[c];
    if (m.cell_types[c] != kVoxel || m.cell_offsets[c + 1] - begin != 8 ||
        m.cell_offsets[c + 1] > m.connectivity.size())
      continue;
    uint64_t voxel[8];
    std::copy_n(m.connectivity.begin() + int64_t(begin), 8, voxel);
    for (int k = 0; k < 8; ++k) m.connectivity[begin + uint64_t(k)] = voxel[kHexOrder[k]];
    m.cell_types[c] = uint8_t(CellType::hex);
  }
}

void check_mesh(const MeshData& m, const std::string& file) {
  input_check(!m.points.empty(), file, "the mesh has no points");
  for (size_t i = 0; i < m.points.size(); ++i) {
    const vec3d& p = m.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      input_error(file, "point " + std::to_string(i) + " has a non-finite coordinate");
  }
  check_cells(m, file);
  check_arrays(m.point_data, m.points.size(), "point", file);
  check_arrays(m.cell_data, m.cell_count(), "cell", file);
}

}  // namespace vs
