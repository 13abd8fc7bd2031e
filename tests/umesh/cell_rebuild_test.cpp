// SplitMemo (umesh/cell_rebuild.h): a series' next step on the same points and cells reuses the
// split of the step before, and gives exactly the mesh and values its own split gives; a step on
// other points, cells or faces is split anew. Checked for polyhedra (a cube whose top is two
// triangles: a centroid added) and a quadratic hexahedron (face and body centres added). And
// FixedMeshSplit, a solver case's split made once, against split_polyhedra.
#include "volstream/umesh/cell_rebuild.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "volstream/core/error.h"
#include "volstream/umesh/polyhedra.h"
#include "volstream/umesh/quadratic.h"

namespace vs {
namespace {

void expect_same_arrays(const std::vector<MeshArray>& a, const std::vector<MeshArray>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].components, b[i].components);
    EXPECT_EQ(a[i].values, b[i].values) << a[i].name;
  }
}

void expect_same_mesh(const MeshData& a, const MeshData& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].x, b.points[i].x) << i;
    EXPECT_EQ(a.points[i].y, b.points[i].y) << i;
    EXPECT_EQ(a.points[i].z, b.points[i].z) << i;
  }
  EXPECT_EQ(a.cell_types, b.cell_types);
  EXPECT_EQ(a.cell_offsets, b.cell_offsets);
  EXPECT_EQ(a.connectivity, b.connectivity);
  expect_same_arrays(a.point_data, b.point_data);
  expect_same_arrays(a.cell_data, b.cell_data);
}

// Step `step`'s values on m: a point array (two components) and a cell array.
MeshData with_step_values(MeshData m, int step) {
  MeshArray f{"f", 2, {}}, c{"c", 1, {}};
  for (const vec3d& p : m.points) f.values.insert(f.values.end(), {p.x * p.y + step, p.z - 3.0 * step});
  for (uint64_t i = 0; i < m.cell_count(); ++i) c.values.push_back(double(10 * step + int(i)));
  m.point_data = {f};
  m.cell_data = {c};
  return m;
}

// A unit cube (a warped corner) whose top is two triangles, as one polyhedron, and a tet beside it.
MeshData cube_and_tet(PolyhedronFaces& faces) {
  MeshData m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1.1, 1.2, 1.1}, {0, 1, 1}, {2, 0, 0}};
  m.cell_types = {kVtkPolyhedron, 10};
  m.cell_offsets = {0, 0, 4};
  m.connectivity = {1, 8, 2, 5};
  const std::vector<std::vector<uint64_t>> cube = {{0, 3, 2, 1}, {4, 5, 6},    {4, 6, 7},   {0, 1, 5, 4},
                                                   {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::vector<uint64_t> stream{cube.size()};
  for (const auto& f : cube) {
    stream.push_back(f.size());
    stream.insert(stream.end(), f.begin(), f.end());
  }
  faces.add_face_stream(stream, 0, "cube");
  faces.add_other_cell();
  return m;
}

TEST(SplitMemo, PolyhedraOfTheNextStepAreSplitAsItsOwnSplitWould) {
  PolyhedronFaces faces;
  const MeshData mesh = cube_and_tet(faces);
  SplitMemo memo;
  MeshData first = with_step_values(mesh, 0);
  split_polyhedra(first, faces, "step 0", &memo);
  ASSERT_GT(first.points.size(), mesh.points.size());  // the cube's centroid

  for (int step : {1, 2}) {
    MeshData reused = with_step_values(mesh, step), own = reused;
    EXPECT_TRUE(memo.reuse(reused, faces.key(), "step"));
    split_polyhedra(own, faces, "step");
    expect_same_mesh(reused, own);
  }

  // A moved point, or other faces: not the remembered mesh, so split anew (and remembered).
  MeshData moved = with_step_values(mesh, 3);
  moved.points[6].z = 1.3;
  MeshData moved_own = moved;
  split_polyhedra(moved, faces, "moved", &memo);
  split_polyhedra(moved_own, faces, "moved");
  expect_same_mesh(moved, moved_own);
  PolyhedronFaces turned = faces;
  std::swap(turned.face_vertices[0], turned.face_vertices[1]);
  MeshData other = with_step_values(mesh, 4);
  EXPECT_FALSE(memo.reuse(other, turned.key(), "other"));
}

// FixedMeshSplit (polyhedra.h), for a solver case's steps: its mesh and each step's data combined
// are split_polyhedra's, exactly; arrays of the wrong length are refused; a mesh without
// polyhedra keeps its cells and data.
TEST(FixedMeshSplit, EachStepIsWhatItsOwnSplitGives) {
  PolyhedronFaces faces;
  const MeshData mesh = cube_and_tet(faces);
  const FixedMeshSplit split(mesh, faces, "case");
  for (int step : {0, 1, 2}) {
    MeshData own = with_step_values(mesh, step);
    split_polyhedra(own, faces, "step");
    MeshData kept = split.mesh();
    MeshData values = with_step_values(mesh, step);
    split.split_data(values.point_data, values.cell_data, "step");
    kept.point_data = values.point_data;
    kept.cell_data = values.cell_data;
    expect_same_mesh(kept, own);
  }
  MeshData short_cells = with_step_values(mesh, 1);
  short_cells.cell_data[0].values.pop_back();
  EXPECT_THROW(split.split_data(short_cells.point_data, short_cells.cell_data, "step"), InputError);
  MeshData split_points = with_step_values(split.mesh(), 1);  // the split's points, not the case's
  EXPECT_THROW(split.split_data(split_points.point_data, split_points.cell_data, "step"), InputError);

  MeshData tet;
  tet.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.cell_types = {10};
  tet.cell_offsets = {0, 4};
  tet.connectivity = {0, 1, 2, 3};
  PolyhedronFaces none;
  none.add_other_cell();
  const FixedMeshSplit unsplit(tet, none, "tet");
  MeshData values = with_step_values(tet, 2);
  const MeshData before = values;
  unsplit.split_data(values.point_data, values.cell_data, "tet");
  expect_same_mesh(values, before);
  EXPECT_EQ(unsplit.mesh().connectivity, tet.connectivity);
}

// take_mesh_with hands the split mesh over as mesh_with would copy it; after it, the mesh is
// gone (mesh_with and take_mesh_with throw) and steps' data still split.
TEST(FixedMeshSplit, TakenMeshIsTheCopyAndDataStillSplit) {
  PolyhedronFaces faces;
  const MeshData mesh = cube_and_tet(faces);
  FixedMeshSplit split(mesh, faces, "case");
  MeshData values = with_step_values(mesh, 1);
  split.split_data(values.point_data, values.cell_data, "step");
  const MeshData copied = split.mesh_with(values.cell_data, "step");
  const MeshData taken = split.take_mesh_with(values.cell_data, "step");
  expect_same_mesh(taken, copied);
  EXPECT_THROW(split.mesh_with(values.cell_data, "step"), std::logic_error);
  EXPECT_THROW(split.take_mesh_with(values.cell_data, "step"), std::logic_error);
  MeshData later = with_step_values(mesh, 2);
  split.split_data(later.point_data, later.cell_data, "step");
  MeshData own = with_step_values(mesh, 2);
  split_polyhedra(own, faces, "step");
  EXPECT_EQ(later.cell_data[0].values, own.cell_data[0].values);
}

// A quadratic hexahedron on the 3x3x3 grid of the cube [0, 1]^3 (VTK's node order), one node
// moved off its edge so that the cell is curved.
MeshData curved_hex20() {
  MeshData m;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) m.points.push_back(vec3d(i, j, k) * 0.5);
  m.points[1].y = -0.1;
  m.cell_types = {25};
  m.connectivity = {0, 2, 8, 6, 18, 20, 26, 24, 1, 5, 7, 3, 19, 23, 25, 21, 9, 11, 17, 15};
  m.cell_offsets = {0, 20};
  return m;
}

TEST(SplitMemo, QuadraticCellsOfTheNextStepAreSplitAsTheirOwnSplitWould) {
  const MeshData mesh = curved_hex20();
  SplitMemo memo;
  MeshData first = with_step_values(mesh, 0);
  split_quadratic_cells(first, "step 0", &memo);
  ASSERT_GT(first.points.size(), mesh.points.size());  // face and body centres
  MeshData reused = with_step_values(mesh, 1), own = reused;
  EXPECT_TRUE(memo.reuse(reused, {}, "step 1"));
  split_quadratic_cells(own, "step 1");
  expect_same_mesh(reused, own);

  // Data that does not match the points is refused, as the split itself refuses it.
  MeshData short_data = with_step_values(mesh, 2);
  short_data.point_data[0].values.pop_back();
  EXPECT_THROW(memo.reuse(short_data, {}, "short"), InputError);
}

}  // namespace
}  // namespace vs
