// EnSight Gold: VTK's own writer's case against the .vtu it was written from (probed alike), a
// case written from the format's description as ASCII and as big-endian C Binary (the same mesh,
// steps, times and variables, the parts' shared nodes welded, nfaced split, the boundary part
// left out, a linear field exact), and bad input refused with one line.
#include "volstream/io/ensight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/vtu.h"
#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "ensight";

MeshData read_case(const fs::path& file, size_t step, const std::vector<std::string>& parts = {}) {
  const EnsightCase c = read_ensight_case(file);
  return read_ensight_step(c, read_ensight_geometry(ensight_step_file(c, c.geometry, step), parts), step);
}

using test::expect_probes_alike;

TEST(Ensight, VtksOwnCaseProbesAsTheVtuItWasWrittenFrom) {
  const MeshData vtu = read_vtu(kDir / "vtk" / "mixed.vtu"), ens = read_case(kDir / "vtk" / "mixed.0.case", 0);
  EXPECT_EQ(ens.cell_count(), vtu.cell_count());
  EXPECT_EQ(ens.points.size(), vtu.points.size());
  expect_probes_alike(vtu, "density", ens, "density_n");
}

// tetra10, pyramid13, penta15 (its nodes reordered as penta6's) and hexa20, written by VTK from
// cells 0, 1, 3, 4 and 6 of tests/data/vtu/vtk_quadratic.vtu, split as those cells are.
TEST(Ensight, VtksQuadraticElementsProbeAsTheVtuCells) {
  const MeshData vtu = read_vtu(kDir / ".." / "vtu" / "vtk_quadratic.vtu"),
                 ens = read_case(kDir / "vtk_quadratic" / "quadratic.0.case", 0);
  EXPECT_EQ(ens.cell_count(), 2 * 8 + 8 + 8 + 10u);
  EXPECT_EQ(ens.points.size(), (20 + 12 + 10 + 15 + 13) + (11 + 2) + 3 + 1u);
  // the .vtu's other cells, absent from the case, are at x in [3,4], [9,10] and [13,14]
  expect_probes_alike(vtu, "g", ens, "g_n",
                      [](const vec3d& p) { return p.x < 2.5 || (p.x > 4.5 && p.x < 8.5) || p.x > 10.5; });
}

double linear(const vec3d& p) { return 1 + 2 * p.x + 3 * p.y + 4 * p.z; }

TEST(Ensight, AsciiAndBigEndianBinaryCasesAreTheSameMesh) {
  const EnsightCase c = read_ensight_case(kDir / "ascii" / "mesh.case");
  EXPECT_EQ(c.times, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(ensight_step_file(c, "f.*", 1), kDir / "ascii" / "f.1");
  for (size_t step = 0; step < 2; ++step) {
    const MeshData a = read_case(kDir / "ascii" / "mesh.case", step),
                   b = read_case(kDir / "big_endian" / "mesh.case", step);
    EXPECT_EQ(a.cell_types, b.cell_types);
    EXPECT_EQ(a.connectivity, b.connectivity);
    ASSERT_EQ(a.points.size(), b.points.size());
    for (size_t i = 0; i < a.points.size(); ++i) EXPECT_LT(length(a.points[i] - b.points[i]), 1e-5) << i;
    // Part 1: 4 hexes, the cube (25), the pyramid (1), the prism (18), a wedge, a tet; part 2:
    // 4 hexes on nodes of its own, welded to part 1's at x = 3; part 3 (quads) left out.
    EXPECT_EQ(a.cell_count(), 4u + 25u + 1u + 18u + 1u + 1u + 4u);
    EXPECT_EQ(a.points.size(), 45u + 18u - 9u + 2u + 6u);
    const MeshArray& f = test::array_named(a.point_data, "f");
    const MeshArray& v = test::array_named(a.point_data, "v");
    ASSERT_EQ(v.components, 3);
    for (size_t i = 0; i < a.points.size(); ++i) {
      EXPECT_NEAR(f.values[i], linear(a.points[i]) + 10.0 * double(step), 1e-4) << i;
      EXPECT_NEAR(v.values[3 * i + 1], a.points[i].y, 1e-5) << i;
    }
    std::map<double, int> per_cell;
    for (double x : test::array_named(a.cell_data, "cell").values) ++per_cell[x];
    EXPECT_EQ(per_cell[5], 25);  // the cube, element 5 of part 1
    EXPECT_EQ(per_cell[8], 1);   // the wedge
    EXPECT_EQ(per_cell[1], 2);   // a hex of each part
  }
}

TEST(Ensight, LinearFieldIsExactThroughPartsAndPolyhedra) {
  const MeshData m = read_case(kDir / "big_endian" / "mesh.case", 0);
  const WorldTransform xf = mesh_transform(m);
  const UMesh mesh = make_umesh(m, xf, "ensight");
  const std::vector<float> f = test::mesh_field(m, "f");
  std::vector<vec3f> points;
  std::vector<vec3d> world;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        world.push_back(vec3d(0.05 + 3.9 * i / 6.0, 0.05 + 1.9 * j / 4.0, 0.05 + 1.9 * k / 4.0));
        points.push_back(vec3f(xf.to_grid(world.back())));
      }
  world.push_back(vec3d(7.2, 0.2, 0.5));  // the wedge
  world.push_back(vec3d(9.1, 0.1, 0.1));  // the tet
  world.push_back(vec3d(5.5, 1.0, 0.5));  // the prism
  for (size_t i = points.size(); i < world.size(); ++i) points.push_back(vec3f(xf.to_grid(world[i])));
  const std::vector<float> probed = UMeshRenderer(mesh, xf).probe(f.data(), points);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_FALSE(std::isnan(probed[i])) << "point " << i;
    EXPECT_NEAR(probed[i], linear(world[i]), 1e-3) << "point " << i;
  }
}

// The parts asked for (--region), by number or description, alone: part 2's four hexes on its own
// 18 nodes with its values (f exact at every node, the cells' numbers 1..4); parts 1 and 2 the
// whole volume, in both encodings; the boundary part alone, or a part the geometry lacks, one line.
TEST(Ensight, PartsAskedForAlone) {
  for (const char* dir : {"ascii", "big_endian"}) {
    SCOPED_TRACE(dir);
    const fs::path file = kDir / dir / "mesh.case";
    const MeshData two = read_case(file, 1, {"2"});
    ASSERT_EQ(two.cell_count(), 4u);
    EXPECT_EQ(two.points.size(), 18u);
    const MeshArray& f = test::array_named(two.point_data, "f");
    for (size_t i = 0; i < two.points.size(); ++i) EXPECT_NEAR(f.values[i], linear(two.points[i]) + 10, 1e-3);
    EXPECT_EQ(test::array_named(two.cell_data, "cell").values, (std::vector<double>{1, 2, 3, 4}));
    const MeshData whole = read_case(file, 1);
    expect_probes_alike(whole, "f", read_case(file, 1, {"part 1", "2"}), "f");
    EXPECT_NE(test::input_error_line([&] { read_case(file, 0, {"3"}); }).find("among the parts asked for"),
              std::string::npos);
    EXPECT_NE(test::input_error_line([&] {
                read_case(file, 0, {"2", "9"});
              }).find("no part '9' in this geometry (its parts: 1 (part 1), 2 (part 2), 3 (part 3))"),
              std::string::npos);
  }
}

// The ASCII case copied to a scratch directory, with one of its files changed.
class EditedEnsight : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("case");
    fs::copy(kDir / "ascii", dir_);
  }
  std::string text(const std::string& name) {
    std::ifstream in(dir_ / name);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  void replace(const std::string& name, const std::string& from, const std::string& to) {
    std::string t = text(name);
    const size_t at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    std::ofstream(dir_ / name) << t;
  }
  std::string error() {
    try {
      read_case(dir_ / "mesh.case", 0);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

// The boundary part's quads given as nsided polygons: read past alike.
TEST_F(EditedEnsight, NsidedBoundaryIsReadPast) {
  const MeshData before = read_case(dir_ / "mesh.case", 0);
  const std::string ids = "      1001\n      1002\n      1003\n      1004\n";
  replace("mesh.geo", "quad4\n         4\n" + ids,
          "nsided\n         4\n" + ids + "         4\n         4\n         4\n         4\n");
  replace("cell.0", "quad4", "nsided");
  const MeshData after = read_case(dir_ / "mesh.case", 0);
  EXPECT_EQ(after.cell_types, before.cell_types);
  EXPECT_EQ(after.connectivity, before.connectivity);
}

// Part 2's hexes as ghost elements (g_hexa8): dropped with their values, and the part with them.
TEST_F(EditedEnsight, GhostElementsAreDropped) {
  std::string t = text("mesh.geo");
  t.replace(t.rfind("hexa8"), 5, "g_hexa8");
  std::ofstream(dir_ / "mesh.geo") << t;
  std::string c = text("cell.0");
  c.replace(c.rfind("hexa8"), 5, "g_hexa8");
  std::ofstream(dir_ / "cell.0") << c;
  const MeshData m = read_case(dir_ / "mesh.case", 0);
  EXPECT_EQ(m.cell_count(), 54u - 4u);
  EXPECT_EQ(m.points.size(), 45u + 2u + 6u);  // part 2's nodes left out with it
}

TEST_F(EditedEnsight, NotGold) {
  replace("mesh.case", "ensight gold", "ensight");
  EXPECT_NE(error().find("not an EnSight Gold case"), std::string::npos);
}
TEST_F(EditedEnsight, SeveralTimeSets) {
  replace("mesh.case", "time set: 1", "time set: 1\ntime set: 2");
  EXPECT_NE(error().find("several time sets"), std::string::npos);
}
TEST_F(EditedEnsight, TimesThatDoNotIncrease) {
  replace("mesh.case", "0.0\n0.5", "0.5\n0.5");
  EXPECT_NE(error().find("must increase"), std::string::npos);
}
TEST_F(EditedEnsight, FileNumbersOutOfRange) {  // start + i * increment would overflow
  replace("mesh.case", "filename start number: 0", "filename start number: -9223372036854775808");
  EXPECT_NE(error().find("out of range"), std::string::npos);
}
TEST_F(EditedEnsight, BlockShortOfNodes) {  // the penta6 block's 6 nodes an element read as hexa20's 20
  replace("mesh.geo", "penta6", "hexa20");
  EXPECT_NE(error().find("expected an integer (element nodes), found 'tetra4'"), std::string::npos);
}
TEST_F(EditedEnsight, StructuredPart) {
  replace("mesh.geo", "coordinates", "block");
  EXPECT_NE(error().find("structured"), std::string::npos);
}
TEST_F(EditedEnsight, NodeOutOfRange) {
  replace("mesh.geo", "tetra4\n         1\n      1001\n", "tetra4\n         1\n      1001\n      9999");
  EXPECT_NE(error().find("out of range"), std::string::npos);
}
// A part left out (--region) is read past, not into a mesh: a node out of range in part 1's tet
// stops a read of part 1, not one of part 2 alone, whose geometry keeps part 1's node count and
// no points.
TEST_F(EditedEnsight, PartsLeftOutAreReadPast) {
  replace("mesh.geo", "      1001\n        42        43", "      1001\n      9999        43");
  EXPECT_NE(error().find("element node 9999 is out of range"), std::string::npos) << error();
  EXPECT_EQ(read_case(dir_ / "mesh.case", 0, {"2"}).cell_count(), 4u);
  const EnsightGeometry g = read_ensight_geometry(dir_ / "mesh.geo", {"2"});
  EXPECT_FALSE(g.parts[0].wanted);
  EXPECT_EQ(g.parts[0].node_count, 45u);
  EXPECT_TRUE(g.parts[0].mesh.points.empty());
  EXPECT_EQ(g.parts[0].mesh.cell_count(), 0u);
  EXPECT_EQ(g.parts[0].blocks.size(), 4u);  // hexa8, nfaced, penta6, tetra4
}
TEST_F(EditedEnsight, TruncatedGeometry) {
  const std::string t = text("mesh.geo");
  std::ofstream(dir_ / "mesh.geo") << t.substr(0, t.size() / 2);
  EXPECT_FALSE(error().empty());
}
// A variable file without a part's values: NaN (no data) on that part's nodes, the other parts'
// values as they were; one without any part's values is refused.
TEST_F(EditedEnsight, VariableWithoutAPartIsNoDataThere) {
  const std::string t = text("f.0");
  std::ofstream(dir_ / "f.0") << t.substr(0, t.find("part\n         2"));
  EXPECT_EQ(error(), "");
  const MeshData edited = read_case(dir_ / "mesh.case", 0), whole = read_case(kDir / "ascii" / "mesh.case", 0);
  const MeshArray &f = test::array_named(edited.point_data, "f"), &w = test::array_named(whole.point_data, "f");
  size_t no_data = 0;
  for (uint64_t p = 0; p < edited.points.size(); ++p) {
    if (std::isnan(f.values[p])) {
      ++no_data;
      continue;
    }
    // The same value at the same place in the whole case.
    bool found = false;
    for (uint64_t q = 0; q < whole.points.size() && !found; ++q)
      found = whole.points[q] == edited.points[p] && w.values[q] == f.values[p];
    EXPECT_TRUE(found) << p;
  }
  EXPECT_GT(no_data, 0u);
  std::ofstream(dir_ / "f.0") << t.substr(0, t.find("part\n         1"));
  EXPECT_NE(error().find("no values for any part"), std::string::npos) << error();
}
TEST_F(EditedEnsight, PartialValues) {
  replace("f.0", "coordinates", "coordinates partial");
  EXPECT_NE(error().find("partial or undefined"), std::string::npos);
}
TEST_F(EditedEnsight, FortranBinary) {
  std::ofstream(dir_ / "mesh.geo") << std::string("Fortran Binary") + std::string(200, ' ');
  EXPECT_NE(error().find("Fortran"), std::string::npos);
}

}  // namespace
}  // namespace vs
