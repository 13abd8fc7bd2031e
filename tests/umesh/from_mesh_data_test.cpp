// From a file's mesh to the reference encoding: bad geometry is refused with a message naming
// the element; cell data is averaged to vertices; vector arrays become magnitude and components;
// a time series must keep its mesh.
#include "volstream/umesh/from_mesh_data.h"

#include <gtest/gtest.h>

#include <cmath>

#include "volstream/core/error.h"

namespace vs {
namespace {

// Two tets sharing the face 1-2-3, in VTK's orientation.
MeshData two_tets() {
  MeshData m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.cell_types = {10, 10};
  m.connectivity = {0, 1, 2, 3, 1, 2, 3, 4};
  m.cell_offsets = {0, 4, 8};
  m.point_data.push_back({"p", 1, {0, 1, 2, 3, 4}});
  m.point_data.push_back({"velocity", 3, std::vector<double>(15, 0.0)});
  m.point_data[1].values[3 * 4 + 0] = 3;
  m.point_data[1].values[3 * 4 + 1] = 4;
  m.cell_data.push_back({"p", 1, {10, 20}});
  return m;
}

std::string error_of(const MeshData& m) {
  try {
    make_umesh(m, mesh_transform(m), "mesh.vtu");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FromMeshData, EncodesElementsAndCountsTypes) {
  const MeshData m = two_tets();
  const UMesh u = make_umesh(m, mesh_transform(m), "mesh.vtu");
  ASSERT_EQ(u.elements.size(), 2u);
  EXPECT_EQ(u.elements[1].v[3], 4u);
  EXPECT_EQ(u.elements[0].vertex_count(), 4);
  EXPECT_EQ(u.count_by_type[0], 2u);
}

TEST(FromMeshData, RefusesDegenerateTangledAndInvertedElements) {
  MeshData flat = two_tets();
  flat.points[3] = {0.5, 0.5, 0};  // tet 0 loses its volume
  EXPECT_NE(error_of(flat).find("tetra 0 is degenerate"), std::string::npos) << error_of(flat);

  MeshData inverted = two_tets();
  inverted.cell_types.push_back(10);  // a third tet, mirrored: the minority orientation
  for (uint64_t v : {0, 2, 1, 3}) inverted.connectivity.push_back(v);
  inverted.cell_offsets.push_back(12);
  inverted.cell_data.clear();
  EXPECT_NE(error_of(inverted).find("tetra 2 is inverted"), std::string::npos) << error_of(inverted);

  MeshData tangled;  // a hex whose top face is turned half around: corners disagree in sign
  tangled.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 1, 1}, {0, 1, 1}, {0, 0, 1}, {1, 0, 1}};
  tangled.cell_types = {12};
  tangled.connectivity = {0, 1, 2, 3, 4, 5, 6, 7};
  tangled.cell_offsets = {0, 8};
  const std::string e = error_of(tangled);
  EXPECT_TRUE(e.find("tangled") != std::string::npos || e.find("degenerate") != std::string::npos) << e;
}

TEST(FromMeshData, ReportsUnsupportedTypesAndBadIndices) {
  MeshData tri = two_tets();
  tri.cell_types[1] = 5;
  tri.cell_offsets = {0, 4, 7};
  tri.connectivity.pop_back();
  EXPECT_NE(error_of(tri).find("unsupported cell type 5 (triangle) in 1 cells"), std::string::npos) << error_of(tri);
  MeshData out_of_range = two_tets();
  out_of_range.connectivity[7] = 99;
  EXPECT_NE(error_of(out_of_range).find("out of range"), std::string::npos);
}

TEST(FromMeshData, FieldsNameVectorsAndAverageCellData) {
  const MeshData m = two_tets();
  const auto fields = mesh_fields(m);
  std::vector<std::string> names;
  for (const auto& f : fields) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"p", "velocity", "velocity_x", "velocity_y", "velocity_z", "p_cell"}));
  EXPECT_FLOAT_EQ(mesh_field_values(m, fields[1])[4], 5.f);  // |(3, 4, 0)|
  EXPECT_FLOAT_EQ(mesh_field_values(m, fields[3])[4], 4.f);
  const std::vector<float> cell = mesh_field_values(m, fields[5]);
  EXPECT_FLOAT_EQ(cell[0], 10.f);  // only in tet 0
  EXPECT_FLOAT_EQ(cell[1], 15.f);  // shared
  EXPECT_FLOAT_EQ(cell[4], 20.f);  // only in tet 1
  // A cell without data (NaN) is left out of the means: its points of no other cell have none.
  MeshData half = m;
  half.cell_data[0].values[1] = NAN;
  const std::vector<float> one = mesh_field_values(half, fields[5]);
  EXPECT_FLOAT_EQ(one[1], 10.f);
  EXPECT_TRUE(std::isnan(one[4]));
}

TEST(FromMeshData, ATimeSeriesMustKeepItsMesh) {
  const MeshData a = two_tets();
  MeshData b = a;
  EXPECT_NO_THROW(check_same_mesh(a, b, "step1.vtu"));
  b.points[4].x += 0.5;
  EXPECT_THROW(check_same_mesh(a, b, "step1.vtu"), InputError);
}

}  // namespace
}  // namespace vs
