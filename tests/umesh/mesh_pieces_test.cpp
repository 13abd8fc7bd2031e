// Joining a parallel writer's pieces: a demo mesh cut into pieces (cut_into_pieces: each with its
// own copy of the points it uses, as a rank writes them, with or without ghost cells) joins back into
// the mesh it was cut from, cell by cell and point for point; points at one place with different
// values stay apart; pieces with other arrays are refused.
#include "volstream/umesh/mesh_pieces.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/umesh/demo.h"

namespace vs {
namespace {

// Cell by cell: the same types, corners at the same places with the same point values, the
// same cell values.
void expect_same_cells(const MeshData& got, const MeshData& want) {
  ASSERT_EQ(got.cell_count(), want.cell_count());
  EXPECT_EQ(got.cell_types, want.cell_types);
  EXPECT_EQ(got.cell_offsets, want.cell_offsets);
  ASSERT_EQ(got.point_data.size(), want.point_data.size());
  for (uint64_t k = 0; k < want.connectivity.size(); ++k) {
    const uint64_t g = got.connectivity[k], w = want.connectivity[k];
    ASSERT_EQ(got.points[g], want.points[w]) << k;
    for (size_t a = 0; a < want.point_data.size(); ++a) {
      const uint64_t n = uint64_t(want.point_data[a].components);
      for (uint64_t i = 0; i < n; ++i)
        ASSERT_EQ(got.point_data[a].values[g * n + i], want.point_data[a].values[w * n + i]) << k;
    }
  }
  ASSERT_EQ(got.cell_data.size(), want.cell_data.size());
  for (size_t a = 0; a < want.cell_data.size(); ++a) EXPECT_EQ(got.cell_data[a].values, want.cell_data[a].values);
}

MeshData demo_mesh(const char* name) {
  MeshData m = make_mesh_demo({name, 3000, 1}, 0);
  MeshArray id{"id", 1, {}};
  for (uint64_t c = 0; c < m.cell_count(); ++c) id.values.push_back(double(c));
  m.cell_data.push_back(id);
  return m;
}

TEST(MeshPieces, CutMeshesJoinBackWithTheirPointsWelded) {
  for (const char* name : {"tets", "mixed"}) {
    const MeshData whole = demo_mesh(name);
    for (int count : {2, 5}) {
      SCOPED_TRACE(std::string(name) + ", " + std::to_string(count) + " pieces");
      std::vector<MeshData> pieces = cut_into_pieces(whole, count, 0);
      uint64_t copies = 0;
      for (const MeshData& p : pieces) copies += p.points.size();
      ASSERT_GT(copies, whole.points.size());  // the seams' points are in two pieces or more
      const MeshData joined = join_pieces(std::move(pieces), "pieces");
      EXPECT_EQ(joined.points.size(), whole.points.size());
      expect_same_cells(joined, whole);
    }
  }
}

TEST(MeshPieces, GhostCellsAreDroppedWithTheirArrays) {
  const MeshData whole = demo_mesh("mixed");
  const MeshData joined = join_pieces(cut_into_pieces(whole, 3, 40), "pieces");
  EXPECT_EQ(joined.points.size(), whole.points.size());
  expect_same_cells(joined, whole);  // also: no vtkGhostType arrays left (same array count)
  // One piece with ghosts: its ghost cells and the points only they use go.
  MeshData first_150 = whole;  // the mesh's first 150 cells
  first_150.cell_types.resize(150);
  first_150.cell_offsets.resize(151);
  first_150.connectivity.resize(first_150.cell_offsets.back());
  for (MeshArray& a : first_150.cell_data) a.values.resize(150 * size_t(a.components));
  const MeshData with_ghosts = cut_into_pieces(first_150, 2, 50).front();  // cells 0-74 and 75-124 as ghosts
  const MeshData single = join_pieces({with_ghosts}, "piece");
  const MeshData own = cut_into_pieces(first_150, 2, 0).front();
  expect_same_cells(single, own);
  EXPECT_EQ(single.points.size(), own.points.size());
  EXPECT_LT(own.points.size(), with_ghosts.points.size());
}

TEST(MeshPieces, OnePieceIsKeptAsItIs) {
  MeshData m = demo_mesh("tets");
  m.points.push_back(m.points[0]);  // a duplicate point: one piece is not welded
  for (MeshArray& a : m.point_data)
    for (int i = 0; i < a.components; ++i) a.values.push_back(a.values[size_t(i)]);
  const MeshData joined = join_pieces({m}, "piece");
  EXPECT_EQ(joined.points, m.points);
  EXPECT_EQ(joined.connectivity, m.connectivity);
}

TEST(MeshPieces, PointsWithOtherValuesStayApart) {
  const MeshData whole = demo_mesh("tets");
  std::vector<MeshData> pieces = cut_into_pieces(whole, 2, 0);
  for (double& v : pieces[1].point_data[0].values) v += 1.0;  // a discontinuity at the seam
  const uint64_t copies = pieces[0].points.size() + pieces[1].points.size();
  const MeshData joined = join_pieces(std::move(pieces), "pieces");
  EXPECT_EQ(joined.points.size(), copies);
}

TEST(MeshPieces, EmptyPiecesAreSkipped) {
  const MeshData whole = demo_mesh("tets");
  std::vector<MeshData> pieces = cut_into_pieces(whole, 2, 0);
  pieces.insert(pieces.begin() + 1, MeshData{});  // no arrays declared at all
  pieces.insert(pieces.begin(), MeshData{});
  expect_same_cells(join_pieces(std::move(pieces), "pieces"), whole);
  EXPECT_THROW(join_pieces({MeshData{}, MeshData{}}, "pieces"), InputError);
}

TEST(MeshPieces, PiecesWithOtherArraysAreRefused) {
  const MeshData whole = demo_mesh("tets");
  std::vector<MeshData> renamed = cut_into_pieces(whole, 2, 0);
  renamed[1].point_data[0].name = "other";
  EXPECT_THROW(join_pieces(std::move(renamed), "pieces"), InputError);
  std::vector<MeshData> missing = cut_into_pieces(whole, 2, 0);
  missing[1].cell_data.clear();
  EXPECT_THROW(join_pieces(std::move(missing), "pieces"), InputError);
  std::vector<MeshData> out_of_range = cut_into_pieces(whole, 2, 0);
  out_of_range[1].connectivity[0] = out_of_range[1].points.size();
  EXPECT_THROW(join_pieces(std::move(out_of_range), "pieces"), InputError);
}

// The parts of a model (MissingArrays::no_data): an array a part lacks is NaN on that part's
// points or cells, the others' values as they were; an array of other components is refused.
TEST(MeshPieces, PartsWithoutAnArrayHaveNoDataThere) {
  const MeshData whole = demo_mesh("tets");
  std::vector<MeshData> parts = cut_into_pieces(whole, 2, 0);
  ASSERT_FALSE(parts[0].cell_data.empty());
  const std::string cell_name = parts[1].cell_data[0].name, point_name = parts[0].point_data[0].name;
  parts[1].cell_data.erase(parts[1].cell_data.begin());
  parts[0].point_data.erase(parts[0].point_data.begin());
  const uint64_t cells_0 = parts[0].cell_count();
  const std::vector<double> first_cells = test::array_named(parts[0].cell_data, cell_name).values;
  const MeshData joined = join_pieces(parts, "parts", MissingArrays::no_data);
  EXPECT_THROW(join_pieces(parts, "parts"), InputError);
  const MeshArray& c = test::array_named(joined.cell_data, cell_name);
  ASSERT_EQ(c.values.size(), joined.cell_count() * uint64_t(c.components));
  for (uint64_t e = 0; e < joined.cell_count(); ++e)
    for (int k = 0; k < c.components; ++k) {
      const double v = c.values[e * uint64_t(c.components) + uint64_t(k)];
      if (e < cells_0)
        EXPECT_EQ(v, first_cells[e * uint64_t(c.components) + uint64_t(k)]);
      else
        EXPECT_TRUE(std::isnan(v)) << e;
    }
  const MeshArray& p = test::array_named(joined.point_data, point_name);
  size_t nan = 0;
  for (double v : p.values) nan += std::isnan(v);
  EXPECT_GT(nan, 0u);
  EXPECT_LT(nan, p.values.size());
  parts[1].cell_data.push_back({cell_name, 7, std::vector<double>(parts[1].cell_count() * 7, 0.0)});
  EXPECT_THROW(join_pieces(parts, "parts", MissingArrays::no_data), InputError);
}

}  // namespace
}  // namespace vs
