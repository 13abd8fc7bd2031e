// VTK's quadratic cells split into linear elements on their nodes: VTK's own files (XML and
// legacy) against VTK's shape functions at every node and at the face and body centres the split
// adds, the pieces' volumes summed independently against straight cells', a linear field exact
// through curved cells, the BVH probe equal to the brute force, and bad cells refused.
#include "volstream/umesh/quadratic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/vtk_legacy.h"
#include "volstream/io/vtu.h"
#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDataDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data";

// tests/data/vtu/make_vtk_files.py's quadratic_mesh(): cell 0 and 1 quadratic hexahedra in
// [0,2]x[0,1]^2 sharing their face x = 1, then a triquadratic hex at x in [3,4], a quadratic tet
// at [5,6], a quadratic wedge at [7,8], a biquadratic-quadratic wedge at [9,10], a quadratic
// pyramid at [11,12] (apex above its base's centre) and a biquadratic-quadratic hex at [13,14].
enum : int { kHex20a, kHex20b, kHex27, kTet10, kWedge15, kWedge18, kPyramid13, kHex24, kCells };

double linear(const vec3d& p) { return 1 + 2 * p.x + 3 * p.y + 4 * p.z; }

// Six times the volume of tet (a, b, c, d), positive in VTK's orientation.
double tet6(const vec3d& a, const vec3d& b, const vec3d& c, const vec3d& d) { return dot(cross(b - a, c - a), d - a); }

// An element's volume from tets (positive in VTK's orientation; exact for planar faces),
// independent of the renderer's shape functions: a pyramid as two, a wedge as three, a hex as
// two wedges.
double element_volume(const MeshData& m, uint64_t c) {
  const uint64_t* v = m.connectivity.data() + m.cell_offsets[c];
  auto p = [&](int k) { return m.points[v[k]]; };
  auto wedge = [&](int a, int b, int cc, int d, int e, int f) {
    return tet6(p(a), p(b), p(cc), p(d)) + tet6(p(b), p(e), p(f), p(d)) + tet6(p(b), p(f), p(cc), p(d));
  };
  switch (CellType(m.cell_types[c])) {
    case CellType::tet:
      return tet6(p(0), p(1), p(2), p(3)) / 6;
    case CellType::pyramid:
      return (tet6(p(0), p(1), p(2), p(4)) + tet6(p(0), p(2), p(3), p(4))) / 6;
    case CellType::wedge:
      return wedge(0, 1, 2, 3, 4, 5) / 6;
    case CellType::hex:
      return (wedge(0, 1, 3, 4, 5, 7) + wedge(1, 2, 3, 5, 6, 7)) / 6;
  }
  return NAN;
}

TEST(QuadraticCells, VtksFilesSplitIntoLinearElements) {
  for (const MeshData& m :
       {read_vtu(kDataDir / "vtu" / "vtk_quadratic.vtu"), read_vtk_legacy(kDataDir / "vtk" / "vtk_quadratic.vtk")}) {
    std::map<uint8_t, int> types;
    for (uint8_t t : m.cell_types) ++types[t];
    EXPECT_EQ(types[uint8_t(CellType::hex)], 4 * 8);
    EXPECT_EQ(types[uint8_t(CellType::wedge)], 2 * 8);
    EXPECT_EQ(types[uint8_t(CellType::tet)], 8 + 4);
    EXPECT_EQ(types[uint8_t(CellType::pyramid)], 6);
    // the file's nodes (the two hex20s share 8), then: each hex20's 6 face centres (one shared)
    // and body centre, the hex24's 2 face centres and body centre, the wedge15's 3 face
    // centres, the pyramid's base centre
    EXPECT_EQ(m.points.size(), (20 + 12 + 27 + 10 + 15 + 18 + 13 + 24) + (11 + 2) + 3 + 3 + 1u);
    std::map<double, int> from_cell;
    for (double id : test::array_named(m.cell_data, "cell_id").values) ++from_cell[id];
    for (int c = 0; c < kCells; ++c) EXPECT_EQ(from_cell[c], c == kPyramid13 ? 10 : 8) << "cell " << c;
  }
}

TEST(QuadraticCells, XmlAndLegacyFilesGiveTheSameMesh) {
  const MeshData xml = read_vtu(kDataDir / "vtu" / "vtk_quadratic.vtu");
  const MeshData legacy = read_vtk_legacy(kDataDir / "vtk" / "vtk_quadratic.vtk");
  EXPECT_EQ(legacy.cell_types, xml.cell_types);
  EXPECT_EQ(legacy.connectivity, xml.connectivity);
  ASSERT_EQ(legacy.points.size(), xml.points.size());
  for (size_t i = 0; i < xml.points.size(); ++i) EXPECT_LT(length(legacy.points[i] - xml.points[i]), 1e-6) << i;
}

// Straight cells (nodes at their parametric places in unit cells): every piece is in VTK's
// orientation, and a cell's pieces fill its volume.
TEST(QuadraticCells, PiecesFillStraightCells) {
  const MeshData m = read_vtu(kDataDir / "vtu" / "vtk_quadratic_straight.vtu");
  const std::vector<double>& cell_id = test::array_named(m.cell_data, "cell_id").values;
  std::vector<double> volume(kCells, 0.0);
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    const double v = element_volume(m, c);
    EXPECT_GT(v, 0.0) << "piece " << c << " of cell " << cell_id[c];
    volume[size_t(cell_id[c])] += v;
  }
  const double expected[kCells] = {1, 1, 1, 1.0 / 6, 0.5, 0.5, 1.0 / 3, 1};
  for (int c = 0; c < kCells; ++c) EXPECT_NEAR(volume[size_t(c)], expected[c], 1e-12) << "cell " << c;
}

std::vector<std::array<double, 4>> vtk_probes() {
  std::ifstream in(kDataDir / "vtu" / "vtk_quadratic_probes.txt");
  std::vector<std::array<double, 4>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::array<double, 4> row{};
    for (double& x : row) fields >> x;
    rows.push_back(row);
  }
  return rows;
}

// At every node of the curved cells and at the parametric centres of their quad faces and
// bodies, the split mesh gives the value of VTK's quadratic shape functions there (computed by
// VTK when the file was written): the nodes are the pieces' corners, and the centres are added
// where, and with the values that, VTK's cells give. The pyramid's apex is left out: a
// pyramid's map is singular there (VTK's as well), so no element is found at that one point.
TEST(QuadraticCells, NodesAndAddedCentresCarryVtksValues) {
  const MeshData m = read_vtu(kDataDir / "vtu" / "vtk_quadratic.vtu");
  const WorldTransform xf = mesh_transform(m);
  const UMesh mesh = make_umesh(m, xf, "quadratic");
  const UMeshRenderer renderer(mesh, xf);
  const std::vector<float> g = test::mesh_field(m, "g");
  const std::vector<std::array<double, 4>> probes = vtk_probes();
  ASSERT_EQ(probes.size(), 172u);
  std::vector<vec3f> points;
  for (const auto& p : probes) points.push_back(vec3f(xf.to_grid(vec3d(p[0], p[1], p[2]))));
  const std::vector<float> probed = renderer.probe(g.data(), points);
  const size_t apex = 2 * 27 + 27 + 10 + 18 + 18 + 4;  // the probes of cells 0-5, then the pyramid's node 4
  for (size_t i = 0; i < probes.size(); ++i) {
    if (i == apex) continue;
    EXPECT_NEAR(probed[i], probes[i][3], 2e-6 * (1 + std::fabs(probes[i][3])))
        << "probe " << i << " at (" << probes[i][0] << ", " << probes[i][1] << ", " << probes[i][2] << ")";
  }
}

// Through the curved cells a field linear in space is exact wherever a piece holds the point
// (the pieces' corners lie on the cells' curved faces, so the split covers nearly all of them),
// and the BVH probe of the quadratic field equals the brute force.
TEST(QuadraticCells, LinearFieldIsExactThroughCurvedCells) {
  const MeshData m = read_vtk_legacy(kDataDir / "vtk" / "vtk_quadratic.vtk");
  const WorldTransform xf = mesh_transform(m);
  const UMesh mesh = make_umesh(m, xf, "quadratic");
  const UMeshRenderer renderer(mesh, xf);
  const std::vector<float> f = test::mesh_field(m, "f"), g = test::mesh_field(m, "g");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<vec3f> points;
  std::vector<vec3d> world;
  for (int i = 0; i < 4000; ++i) {
    const vec3d p(15 * u(rng), 1.1 * u(rng), 1.1 * u(rng));
    world.push_back(p);
    points.push_back(vec3f(xf.to_grid(p)));
  }
  const std::vector<float> probed = renderer.probe(f.data(), points);
  int found = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::isnan(probed[i])) continue;
    ++found;
    EXPECT_NEAR(probed[i], linear(world[i]), 2e-5 * 12) << "point " << i;
  }
  EXPECT_GT(found, 1000);  // the cells fill about 5.9 of the box's 18.2 units of volume
  EXPECT_GT(test::expect_probe_is_brute_force(mesh, xf, g.data(), test::points_around(mesh.vertices, 3000, 5)), 500);
}

// Builds the split mesh (make_umesh refuses tangled or inverted pieces) and expects its field f
// (add_test_arrays' linear field) to be exact at 2,000 points around it that lie in a piece;
// returns how many do.
int expect_linear_field_where_found(const MeshData& m, uint32_t seed) {
  const WorldTransform xf = mesh_transform(m);
  const UMesh mesh = make_umesh(m, xf, "split cells");
  const std::vector<float> f = test::mesh_field(m, "f");
  const std::vector<vec3f> points = test::points_around(mesh.vertices, 2000, seed);
  const std::vector<float> probed = UMeshRenderer(mesh, xf).probe(f.data(), points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::isnan(probed[i])) continue;
    ++inside;
    EXPECT_NEAR(probed[i], linear(xf.to_world(vec3d(points[i]))), 2e-5 * 25) << "point " << i;
  }
  return inside;
}

// VTK's Lagrange cells of order 1 and 2 (vtkCellTypeSource's tets, hex and wedges, curved) read as
// their twin file, the same nodes typed as the linear and quadratic cells (the generator checks
// that each Lagrange node lies where the twin's cell puts its node of the same index), and the
// split mesh is a valid one.
TEST(QuadraticCells, LagrangeCellsOfOrder1And2AreTheFixedCells) {
  const MeshData lagrange = read_vtu(kDataDir / "vtu" / "vtk_lagrange.vtu");
  const MeshData twin = read_vtu(kDataDir / "vtu" / "vtk_lagrange_twin.vtu");
  EXPECT_EQ(lagrange.cell_types, twin.cell_types);
  EXPECT_EQ(lagrange.connectivity, twin.connectivity);
  EXPECT_EQ(lagrange.points.size(), twin.points.size());
  std::map<uint8_t, int> types;
  for (uint8_t t : lagrange.cell_types) ++types[t];
  EXPECT_EQ(types[uint8_t(CellType::tet)], 12 + 12 * 8);
  EXPECT_EQ(types[uint8_t(CellType::hex)], 1 + 8);
  EXPECT_EQ(types[uint8_t(CellType::wedge)], 2 + 2 * 8);
  EXPECT_GT(expect_linear_field_where_found(lagrange, 9), 400);
}

// Lagrange hexahedra of order 3 to 6 (vtkCellTypeSource's, curved) split into the 27, 64, 125 and
// 216 hexes of their node lattices: the twin file lists them, found from where VTK puts each node.
TEST(QuadraticCells, LagrangeHexahedraOfHigherOrderSplitOnTheirLattice) {
  const MeshData m = read_vtu(kDataDir / "vtu" / "vtk_lagrange_hex.vtu");
  const MeshData twin = read_vtu(kDataDir / "vtu" / "vtk_lagrange_hex_twin.vtu");
  EXPECT_EQ(m.cell_count(), 27 + 64 + 125 + 216u);
  EXPECT_EQ(m.cell_types, twin.cell_types);
  EXPECT_EQ(m.connectivity, twin.connectivity);
  std::vector<double> from_cell;
  for (int p = 3; p <= 6; ++p) from_cell.resize(from_cell.size() + size_t(p * p * p), double(p - 3));
  EXPECT_EQ(test::array_named(m.cell_data, "cell_id").values, from_cell);
  EXPECT_GT(expect_linear_field_where_found(m, 13), 500);
}

// Lagrange tetra of order 3 to 6 (vtkCellTypeSource's, straight: 12 tets filling a unit cube for
// each order) split into the p^3 tets of their node lattices: every piece in VTK's orientation
// with 1/p^3 of its cell's volume (as each tet and octahedron quarter of the lattice has), every
// node of the cell a corner of some piece.
TEST(QuadraticCells, LagrangeTetraOfHigherOrderSplitOnTheirLattice) {
  const MeshData m = read_vtu(kDataDir / "vtu" / "vtk_lagrange_tet.vtu");
  const std::vector<double>& cell_id = test::array_named(m.cell_data, "cell_id").values;
  EXPECT_EQ(m.cell_count(), 12u * (27 + 64 + 125 + 216));
  std::vector<double> volume(48, 0.0);
  std::vector<int> pieces(48, 0);
  std::vector<bool> used(m.points.size(), false);
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    const auto source = size_t(cell_id[c]);
    volume[source] += element_volume(m, c);
    ++pieces[source];
    for (uint64_t k = m.cell_offsets[c]; k < m.cell_offsets[c + 1]; ++k) used[m.connectivity[k]] = true;
  }
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    const auto source = size_t(cell_id[c]);
    EXPECT_NEAR(element_volume(m, c), volume[source] / pieces[source], 1e-4 * volume[source] / pieces[source])
        << "piece " << c;  // float32 points
  }
  for (size_t source = 0; source < 48; ++source) {
    const int p = 3 + int(source / 12);
    EXPECT_EQ(pieces[source], p * p * p);
    EXPECT_NEAR(volume[source], 1.0 / 12, 1e-6) << "cell " << source;  // a twelfth of the unit cube
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

// Files older than VTK 9.1 (XML version 1.0, legacy 4.2) list the nodes inside a Lagrange
// hexahedron's edges 2-6 and 3-7 the other way round (18 and 19 at order 2); they read as VTK
// reads them (the generator checks that VTK reads each as the current numbering), the same mesh
// as the current files (XML 2.2, legacy 5.1).
TEST(QuadraticCells, LagrangeHexahedraOfOlderFilesAreRenumbered) {
  const MeshData current = read_vtu(kDataDir / "vtu" / "vtk_lagrange.vtu");
  for (const MeshData& m : {read_vtu(kDataDir / "vtu" / "vtk_lagrange_pre91.vtu"),
                            read_vtk_legacy(kDataDir / "vtk" / "vtk_lagrange_42.vtk"),
                            read_vtk_legacy(kDataDir / "vtk" / "vtk_lagrange.vtk")}) {
    EXPECT_EQ(m.cell_types, current.cell_types);
    EXPECT_EQ(m.connectivity, current.connectivity);
    ASSERT_EQ(m.points.size(), current.points.size());
    for (size_t i = 0; i < m.points.size(); ++i)  // legacy ascii: 6 digits
      EXPECT_LT(length(m.points[i] - current.points[i]), 2e-5) << i;
  }
  // orders 3 to 6: the nodes inside the two edges swapped as runs
  const MeshData old = read_vtu(kDataDir / "vtu" / "vtk_lagrange_hex_pre91.vtu");
  EXPECT_EQ(old.connectivity, read_vtu(kDataDir / "vtu" / "vtk_lagrange_hex.vtu").connectivity);
}

// A mesh of the given cells over the points of a unit cube's 3x3x3 grid (enough for any cell
// here), each cell's vertices the first indices.
MeshData grid_mesh(std::vector<std::pair<uint8_t, std::vector<uint64_t>>> cells) {
  MeshData m;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) m.points.push_back(vec3d(i, j, k) * 0.5);
  for (auto& [type, vertices] : cells) {
    m.cell_types.push_back(type);
    m.connectivity.insert(m.connectivity.end(), vertices.begin(), vertices.end());
    m.cell_offsets.push_back(m.connectivity.size());
  }
  m.cell_offsets.insert(m.cell_offsets.begin(), 0);
  return m;
}

std::string split_error(MeshData m) {
  try {
    split_quadratic_cells(m, "bad.vtu");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(QuadraticCells, BadCellsAreRefused) {
  std::vector<uint64_t> ten(10);
  std::iota(ten.begin(), ten.end(), 0);
  EXPECT_EQ(split_error(grid_mesh({{24, ten}})), "");
  EXPECT_NE(split_error(grid_mesh({{24, {0, 1, 2, 3, 4, 5, 6, 7, 8}}}))
                .find("cell 0 (quadratic tetra) has 9 vertices, expected 10"),
            std::string::npos);
  std::vector<uint64_t> out_of_range = ten;
  out_of_range[7] = 27;
  EXPECT_NE(split_error(grid_mesh({{24, out_of_range}})).find("connectivity entry 7 = 27 is out of range (27 points)"),
            std::string::npos);
  MeshData short_data = grid_mesh({{24, ten}});
  short_data.point_data.push_back({"f", 1, std::vector<double>(26, 0.0)});
  EXPECT_NE(split_error(short_data).find("a data array does not match"), std::string::npos);
  MeshData bad_offsets = grid_mesh({{24, ten}});
  bad_offsets.cell_offsets.back() = 11;
  EXPECT_NE(split_error(bad_offsets).find("cell offsets do not match"), std::string::npos);
  // A Lagrange wedge of order 3 (40 nodes), a hexahedron of no order (30 nodes), and the 15-node
  // tetra variant are refused.
  EXPECT_NE(split_error(grid_mesh({{73, std::vector<uint64_t>(40, 0)}}))
                .find("cell 0 (Lagrange wedge) has 40 nodes: volstream reads Lagrange hexahedra and tetra of order 1 "
                      "to 10"),
            std::string::npos);
  EXPECT_NE(split_error(grid_mesh({{72, std::vector<uint64_t>(30, 0)}})).find("has 30 nodes"), std::string::npos);
  EXPECT_NE(split_error(grid_mesh({{71, std::vector<uint64_t>(15, 0)}})).find("has 15 nodes"), std::string::npos);
  // A type volstream does not split is left for check_mesh, which names it.
  MeshData triquadratic_pyramid = grid_mesh({{37, std::vector<uint64_t>(19, 0)}});
  EXPECT_EQ(split_error(triquadratic_pyramid), "");
  EXPECT_THROW(check_mesh(triquadratic_pyramid, "bad.vtu"), InputError);
}

}  // namespace
}  // namespace vs
