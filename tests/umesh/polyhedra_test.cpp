// VTK polyhedra split into tets and pyramids from their vertex centroids: VTK's own files (XML
// face streams, legacy 5.1 and 4.2) against the geometry they describe (volumes summed
// independently, every point of the boxes found, a linear field exact, the BVH probe equal to
// the brute force), VTK 9.4's XML layout against the older one, and bad polyhedra refused.
#include "volstream/umesh/polyhedra.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

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

// tests/data/vtu/make_vtk_files.py's polyhedra_mesh(): a cube [0,2]^3 (its face x = 2 in four
// quads, the four faces that meet it pentagons), eight hexes in [2,4]x[0,2]^2, a pyramid on the
// cube's face x = 0 (apex (-1,1,1)), and a hexagonal
// prism of circumradius 0.5 around (5.5, 1), z in [0,1].
std::vector<MeshData> vtk_files() {
  return {read_vtu(kDataDir / "vtu" / "vtk_polyhedra.vtu"), read_vtk_legacy(kDataDir / "vtk" / "vtk_polyhedra.vtk"),
          read_vtk_legacy(kDataDir / "vtk" / "vtk_polyhedra_42.vtk")};
}
const double kHexagonArea = 1.5 * std::sqrt(3.0) * 0.25;
const double kVolume = 8.0 + 8.0 + 4.0 / 3.0 + kHexagonArea;

double linear(const vec3d& p) { return 1 + 2 * p.x + 3 * p.y + 4 * p.z; }

// Six times the volume of tet (a, b, c, d), positive in VTK's orientation.
double tet6(const vec3d& a, const vec3d& b, const vec3d& c, const vec3d& d) { return dot(cross(b - a, c - a), d - a); }

// Each element's volume, from tets alone (a pyramid of a planar base as two), independent of the
// renderer's shape functions.
std::vector<double> element_volumes(const MeshData& m) {
  std::vector<double> volumes;
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    const uint64_t* v = m.connectivity.data() + m.cell_offsets[c];
    auto p = [&](int k) { return m.points[v[k]]; };
    if (m.cell_types[c] == uint8_t(CellType::tet)) volumes.push_back(tet6(p(0), p(1), p(2), p(3)) / 6);
    if (m.cell_types[c] == uint8_t(CellType::pyramid))
      volumes.push_back((tet6(p(0), p(1), p(2), p(4)) + tet6(p(0), p(2), p(3), p(4))) / 6);
    if (m.cell_types[c] == uint8_t(CellType::hex)) volumes.push_back(1.0);  // the unit hexes of the file
  }
  return volumes;
}

TEST(Polyhedra, VtksFilesSplitIntoTetsAndPyramids) {
  for (const MeshData& m : vtk_files()) {
    std::map<uint8_t, int> types;
    for (uint8_t t : m.cell_types) ++types[t];
    // cube: 5 quads, 4 pentagons of 5 tets each; the pyramid as one; prism: 6 quads, 2 hexagons
    // of 6 tets each
    EXPECT_EQ(types[uint8_t(CellType::pyramid)], 5 + 1 + 6);
    EXPECT_EQ(types[uint8_t(CellType::tet)], 20 + 12);
    EXPECT_EQ(types[uint8_t(CellType::hex)], 8);
    EXPECT_EQ(m.points.size(), 44u + 2u + 6u);  // a centroid per split polyhedron, a centre per face of 5 or 6
    std::map<double, int> from_cell;
    for (double id : test::array_named(m.cell_data, "cell_id").values) ++from_cell[id];
    EXPECT_EQ(from_cell[0], 25);
    EXPECT_EQ(from_cell[9], 1);
    EXPECT_EQ(from_cell[10], 18);
    for (int c = 1; c <= 8; ++c) EXPECT_EQ(from_cell[c], 1);
    double total = 0;
    for (double v : element_volumes(m)) {
      EXPECT_GT(v, 0.0);  // every element in VTK's orientation
      total += v;
    }
    EXPECT_NEAR(total, kVolume, 1e-5);
    const MeshArray& f = test::array_named(m.point_data, "f");
    for (size_t i = 44; i < m.points.size(); ++i) EXPECT_NEAR(f.values[i], linear(m.points[i]), 1e-4) << i;
    check_mesh(m, "polyhedra");
  }
}

TEST(Polyhedra, XmlAndLegacyFilesGiveTheSameMesh) {
  const std::vector<MeshData> files = vtk_files();
  for (size_t k = 1; k < files.size(); ++k) {
    EXPECT_EQ(files[k].cell_types, files[0].cell_types);
    EXPECT_EQ(files[k].connectivity, files[0].connectivity);
    ASSERT_EQ(files[k].points.size(), files[0].points.size());
    for (size_t i = 0; i < files[0].points.size(); ++i)
      EXPECT_LT(length(files[k].points[i] - files[0].points[i]), 1e-5) << "file " << k << " point " << i;
  }
}

// The split mesh covers the cube, the hexes, the pyramid and the prism without a gap: every
// point of their boxes that lies in one is found, and the linear field is exact there; the BVH
// probe of the nonlinear field equals the brute force.
TEST(Polyhedra, SplitMeshIsSampledWithoutGaps) {
  const MeshData m = vtk_files()[0];
  const WorldTransform xf = mesh_transform(m);
  const UMesh mesh = make_umesh(m, xf, "polyhedra");
  const UMeshRenderer renderer(mesh, xf);
  const std::vector<float> f = test::mesh_field(m, "f"), g = test::mesh_field(m, "g");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<vec3f> points;
  std::vector<vec3d> world;
  for (int i = 0; i < 4000; ++i) {
    vec3d p;
    if (i % 2 == 0) {
      p = vec3d(4 * u(rng), 2 * u(rng), 2 * u(rng));  // the cube and the hexes
    } else {
      p = vec3d(5 + u(rng), 0.5 + u(rng), u(rng));  // the prism's box, partly outside it
      const double dx = std::fabs(p.x - 5.5), dy = std::fabs(p.y - 1.0);
      if (dy > 0.42 || dx + dy / std::sqrt(3.0) > 0.49) continue;  // inside the hexagon, clear of its sides
    }
    world.push_back(p);
    points.push_back(vec3f(xf.to_grid(p)));
  }
  const std::vector<float> probed = renderer.probe(f.data(), points);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_FALSE(std::isnan(probed[i])) << "point " << i << " (" << world[i].x << ", " << world[i].y << ", "
                                        << world[i].z << ") is in no element";
    EXPECT_NEAR(probed[i], linear(world[i]), 2e-5 * 20) << "point " << i;
  }
  EXPECT_GT(test::expect_probe_is_brute_force(mesh, xf, g.data(), test::points_around(mesh.vertices, 3000, 3)), 1000);
}

// A unit cube as one polyhedron, in the layout of VTK 9.4's XML files and in the older one.
std::string cube_vtu(bool new_layout) {
  std::string cells =
      "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5 6 7</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">8</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">42</DataArray>\n";
  const std::string faces = "0 3 2 1 4 5 6 7 0 1 5 4 1 2 6 5 2 3 7 6 3 0 4 7";
  if (new_layout)
    cells +=
        "<DataArray type=\"Int64\" Name=\"face_connectivity\" format=\"ascii\">" + faces +
        "</DataArray>\n<DataArray type=\"Int64\" Name=\"face_offsets\" format=\"ascii\">4 8 12 16 20 24</DataArray>\n"
        "<DataArray type=\"Int64\" Name=\"polyhedron_to_faces\" format=\"ascii\">0 1 2 3 4 5</DataArray>\n"
        "<DataArray type=\"Int64\" Name=\"polyhedron_offsets\" format=\"ascii\">6</DataArray>\n";
  else
    cells +=
        "<DataArray type=\"Int64\" Name=\"faces\" format=\"ascii\">6 4 0 3 2 1 4 4 5 6 7 4 0 1 5 4 4 1 2 6 5 4 2 3 7 6 "
        "4 3 0 4 7</DataArray>\n<DataArray type=\"Int64\" Name=\"faceoffsets\" format=\"ascii\">31</DataArray>\n";
  return "<VTKFile type=\"UnstructuredGrid\" version=\"" + std::string(new_layout ? "2.3" : "1.0") +
         "\"><UnstructuredGrid><Piece NumberOfPoints=\"8\" NumberOfCells=\"1\">\n"
         "<PointData><DataArray type=\"Float64\" Name=\"f\" format=\"ascii\">1 3 6 4 5 7 10 8</DataArray></PointData>\n"
         "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 1 1 0 0 1 0 0 0 "
         "1 1 0 1 1 1 1 0 1 1</DataArray></Points>\n<Cells>" +
         cells + "</Cells></Piece></UnstructuredGrid></VTKFile>\n";
}

MeshData read_text(const std::string& text, const std::string& name) {
  const fs::path path = test::scratch_dir(name) / "mesh.vtu";
  std::ofstream(path) << text;
  return read_vtu(path);
}

TEST(Polyhedra, Vtk94LayoutReadsAsTheFaceStreams) {
  const MeshData streams = read_text(cube_vtu(false), "streams"), tables = read_text(cube_vtu(true), "tables");
  EXPECT_EQ(tables.cell_types, streams.cell_types);
  EXPECT_EQ(tables.connectivity, streams.connectivity);
  EXPECT_EQ(tables.cell_types, std::vector<uint8_t>{uint8_t(CellType::hex)});  // a cube is a hex
  EXPECT_EQ(tables.connectivity, (std::vector<uint64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(tables.points.size(), 8u);
}

// One polyhedron on `points`, given by `faces`.
MeshData polyhedron(std::vector<vec3d> points, const std::vector<std::vector<uint64_t>>& faces, PolyhedronFaces& out) {
  MeshData m;
  m.points = std::move(points);
  m.cell_types = {kVtkPolyhedron};
  m.cell_offsets = {0, 0};
  std::vector<uint64_t> stream{faces.size()};
  for (const auto& f : faces) {
    stream.push_back(f.size());
    stream.insert(stream.end(), f.begin(), f.end());
  }
  out.add_face_stream(stream, 0, "polyhedron");
  return m;
}

MeshData one_cell(std::vector<vec3d> points, CellType type, std::vector<uint64_t> vertices) {
  MeshData m;
  m.points = std::move(points);
  m.cell_types = {uint8_t(type)};
  m.cell_offsets = {0, vertices.size()};
  m.connectivity = std::move(vertices);
  return m;
}

// A polyhedron with the faces of a tet, pyramid, wedge or hex (faces in any order, either
// orientation, any first vertex) is that element: it samples as the element does, everywhere.
TEST(Polyhedra, StandardShapesAreThoseElements) {
  const std::vector<vec3d> hex_points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},       {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {1.2, 1.1, 1.3}, {0, 1, 1}};  // a warped top
  const std::vector<vec3d> wedge_points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1.2}, {0, 1, 1}};
  const std::vector<vec3d> pyramid_points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.4, 1}};
  const std::vector<vec3d> tet_points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  struct Case {
    MeshData element;
    std::vector<std::vector<uint64_t>> faces;
  };
  const std::vector<Case> cases = {
      {one_cell(hex_points, CellType::hex, {0, 1, 2, 3, 4, 5, 6, 7}),
       {{2, 1, 0, 3}, {5, 6, 7, 4}, {0, 1, 5, 4}, {6, 5, 1, 2}, {3, 7, 6, 2}, {0, 4, 7, 3}}},
      {one_cell(wedge_points, CellType::wedge, {0, 2, 1, 3, 5, 4}),
       {{3, 4, 5}, {0, 1, 4, 3}, {0, 1, 2}, {1, 2, 5, 4}, {2, 0, 3, 5}}},
      {one_cell(pyramid_points, CellType::pyramid, {0, 1, 2, 3, 4}),
       {{0, 1, 4}, {3, 2, 1, 0}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}},
      {one_cell(tet_points, CellType::tet, {0, 1, 2, 3}), {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}},
  };
  for (const Case& c : cases) {
    PolyhedronFaces faces;
    MeshData split = polyhedron(c.element.points, c.faces, faces);
    split_polyhedra(split, faces, "shape");
    ASSERT_EQ(split.cell_types, c.element.cell_types);
    ASSERT_EQ(split.points.size(), c.element.points.size());  // no point added
    std::vector<float> g;
    for (const vec3d& p : split.points) g.push_back(float(p.x * p.y + p.z * p.z + 2 * p.x));
    const WorldTransform xf = mesh_transform(split);
    const UMesh a = make_umesh(split, xf, "split"), b = make_umesh(c.element, xf, "element");
    const std::vector<vec3f> points = test::points_around(a.vertices, 2000, 9);
    const std::vector<float> pa = UMeshRenderer(a, xf).probe(g.data(), points),
                             pb = UMeshRenderer(b, xf).probe(g.data(), points);
    int inside = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      ASSERT_EQ(std::isnan(pa[i]), std::isnan(pb[i])) << "type " << int(c.element.cell_types[0]) << " point " << i;
      if (std::isnan(pa[i])) continue;
      ++inside;
      EXPECT_NEAR(pa[i], pb[i], 1e-5) << "type " << int(c.element.cell_types[0]) << " point " << i;
    }
    EXPECT_GT(inside, 200);
  }
}

// A unit cube as one polyhedron given by `faces` (point indices 0-7 as in cube_vtu).
MeshData cube_polyhedron(const std::vector<std::vector<uint64_t>>& faces, PolyhedronFaces& out) {
  return polyhedron({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, faces,
                    out);
}
const std::vector<std::vector<uint64_t>> kCubeFaces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                       {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
// The same cube with its top split into two triangles: no standard element, so it is split.
const std::vector<std::vector<uint64_t>> kSplitTopCubeFaces = {{0, 3, 2, 1}, {4, 5, 6},    {4, 6, 7},   {0, 1, 5, 4},
                                                               {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

std::string split_error(std::vector<std::vector<uint64_t>> faces) {
  PolyhedronFaces pf;
  try {
    MeshData m = cube_polyhedron(std::move(faces), pf);
    split_polyhedra(m, pf, "cube");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Polyhedra, FacesOrientedEitherWayGiveTheSameVolume) {
  std::vector<std::vector<uint64_t>> faces = kSplitTopCubeFaces;
  std::reverse(faces[3].begin(), faces[3].end());  // one face inward: not oriented alike
  for (const auto& set : {kSplitTopCubeFaces, faces}) {
    PolyhedronFaces pf;
    MeshData m = cube_polyhedron(set, pf);
    split_polyhedra(m, pf, "cube");
    EXPECT_EQ(m.cell_count(), 5u + 2u);  // a pyramid on each quad, a tet on each triangle
    double total = 0;
    for (double v : element_volumes(m)) {
      EXPECT_GT(v, 0);
      total += v;
    }
    EXPECT_NEAR(total, 1.0, 1e-12);
  }
}

TEST(Polyhedra, BadPolyhedraAreRefused) {
  EXPECT_NE(split_error({kCubeFaces.begin(), kCubeFaces.end() - 1}).find("is not closed"), std::string::npos);
  EXPECT_NE(split_error({{0, 1, 2}, {0, 2, 3}, {0, 3, 1}}).find("has 3 faces"), std::string::npos);
  std::vector<std::vector<uint64_t>> two = kCubeFaces;
  two.push_back({0, 6});
  EXPECT_NE(split_error(two).find("a face of 2 vertices"), std::string::npos);
  std::vector<std::vector<uint64_t>> out_of_range = kCubeFaces;
  out_of_range[0][0] = 8;
  EXPECT_NE(split_error(out_of_range).find("out of range"), std::string::npos);

  // An L-shaped prism: its vertex centroid (23/6, 11/3) lies outside the L.
  MeshData l;
  const double xy[6][2] = {{0, 0}, {10, 0}, {10, 1}, {1, 1}, {1, 10}, {0, 10}};
  for (int z = 0; z < 2; ++z)
    for (const auto& p : xy) l.points.push_back(vec3d(p[0], p[1], z));
  l.cell_types = {kVtkPolyhedron};
  l.cell_offsets = {0, 0};
  std::vector<uint64_t> stream{8, 6, 5, 4, 3, 2, 1, 0, 6, 6, 7, 8, 9, 10, 11};
  for (uint64_t k = 0; k < 6; ++k) stream.insert(stream.end(), {4, k, (k + 1) % 6, (k + 1) % 6 + 6, k + 6});
  PolyhedronFaces lf;
  lf.add_face_stream(stream, 0, "l");
  try {
    split_polyhedra(l, lf, "l.vtu");
    ADD_FAILURE() << "the L-shaped prism was split";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("star-shaped"), std::string::npos) << e.what();
  }
}

TEST(Polyhedra, BadFaceStreamsAreRefused) {
  auto error = [](std::vector<uint64_t> stream) {
    PolyhedronFaces pf;
    try {
      pf.add_face_stream(stream, 3, "s.vtk");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error({}).find("is empty"), std::string::npos);
  EXPECT_NE(error({2, 3, 0, 1, 2}).find("ends before face 1"), std::string::npos);
  EXPECT_NE(error({1, 4, 0, 1}).find("ends inside face 0"), std::string::npos);
  EXPECT_NE(error({1, 3, 0, 1, 2, 7}).find("holds 1 values after"), std::string::npos);
  EXPECT_NE(error({uint64_t(1) << 62}).find("ends before face 0"), std::string::npos);
  // Point indices are kept in 32 bits: one past them is refused, not wrapped (2^32 + 1 to 1).
  EXPECT_NE(error({1, 3, 0, (uint64_t(1) << 32) + 1, 2}).find("names point 4294967297 (more than 32 bits)"),
            std::string::npos);
}

// A reader's index as a FaceIndex: the largest where it does not fit, which no point has.
TEST(Polyhedra, FaceIndicesSaturate) {
  EXPECT_EQ(saturated_face_index(0), 0u);
  EXPECT_EQ(saturated_face_index(4294967294), 4294967294u);
  for (const int64_t wide : {int64_t(-1), int64_t(4294967295), int64_t(1) << 32, INT64_MAX, INT64_MIN})
    EXPECT_EQ(saturated_face_index(wide), 4294967295u) << wide;
  EXPECT_NO_THROW(check_face_index_count(4294967295, "points", "f"));
  EXPECT_THROW(check_face_index_count(4294967296, "points", "f"), InputError);
}

TEST(Polyhedra, BadPolyhedronArraysInVtuFilesAreRefused) {
  std::string bad_end = cube_vtu(false);
  bad_end.replace(bad_end.find(">31<"), 4, ">-1<");
  EXPECT_THROW(read_text(bad_end, "bad_end"), InputError);
  std::string huge_end = cube_vtu(false);  // a Float64 offset beyond any integer type
  huge_end.replace(huge_end.find("<DataArray type=\"Int64\" Name=\"faceoffsets\" format=\"ascii\">31<"),
                   std::string("<DataArray type=\"Int64\" Name=\"faceoffsets\" format=\"ascii\">31<").size(),
                   "<DataArray type=\"Float64\" Name=\"faceoffsets\" format=\"ascii\">1e300<");
  EXPECT_THROW(read_text(huge_end, "huge_end"), InputError);
  std::string bad_face = cube_vtu(true);
  bad_face.replace(bad_face.find(">0 1 2 3 4 5<"), 13, ">0 1 2 3 4 9<");
  EXPECT_THROW(read_text(bad_face, "bad_face"), InputError);
  // Point indices past 32 bits are out of range, not wrapped (2^32 + 3 would be point 3).
  std::string wide_vertex = cube_vtu(true);
  wide_vertex.replace(wide_vertex.find(">0 3 2 1 "), 9, ">0 4294967299 2 1 ");
  EXPECT_NE(test::input_error_line([&] {
              read_text(wide_vertex, "wide_vertex");
            }).find("face vertex 4294967295 is out of range (8 points)"),
            std::string::npos);
}

}  // namespace
}  // namespace vs
