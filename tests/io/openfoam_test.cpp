// OpenFOAM cases made by OpenFOAM v1912 itself (tests/data/openfoam/make_openfoam_files.sh: a
// 6x5x4 box with two corners refined, so the cells beside them are polyhedra; ascii, binary and
// gzipped copies) read as VTK's own OpenFOAM reader read them (reference.vtu); each cell's split
// pieces fill it (their volumes sum to its volume, computed here from the faces by the
// divergence theorem, and to OpenFOAM's own cell volumes V; their centroid is OpenFOAM's cell
// centre C); and damaged copies, edited here, refused with one line.
#include "volstream/io/openfoam.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "openfoam";
constexpr uint64_t kCells = 232;

void expect_cell_values_equal(const MeshData& a, const MeshData& b, double tolerance = 0) {
  for (const char* name : {"T", "U", "C", "V"}) {
    SCOPED_TRACE(name);
    const MeshArray &x = test::array_named(a.cell_data, name), &y = test::array_named(b.cell_data, name);
    ASSERT_EQ(x.components, y.components);
    ASSERT_EQ(x.values.size(), y.values.size());
    for (size_t i = 0; i < x.values.size(); ++i) EXPECT_NEAR(x.values[i], y.values[i], tolerance) << i;
  }
}

// An ascii OpenFOAM list file's numbers after its header, parentheses dropped: a few lines to
// read the ascii case's mesh here without the reader under test.
std::vector<double> numbers_of(const fs::path& file) {
  std::string t = test::file_bytes(file);
  t = t.substr(t.find('}', t.find("FoamFile")) + 1);
  for (size_t c; (c = t.find("//")) != std::string::npos;) t.erase(c, t.find('\n', c) - c);
  for (char& c : t)
    if (c == '(' || c == ')') c = ' ';
  std::istringstream in(t);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

using P = std::array<double, 3>;
double det(P a, P b, P c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}
// The volume a closed surface of polygons (each given by its points, in order) encloses, and
// its centroid (times the volume): the divergence theorem over triangles fanned from each
// polygon's vertex mean, their tets against the origin. `sign` flips a polygon.
struct Moments {
  double volume = 0;
  P first{0, 0, 0};
  void add_polygon(const std::vector<P>& v, double sign) {
    P c{0, 0, 0};
    for (const P& p : v)
      for (int k = 0; k < 3; ++k) c[k] += p[k] / double(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
      const P &a = c, &b = v[i], &d = v[(i + 1) % v.size()];
      const double vol = sign * det(a, b, d) / 6;
      volume += vol;
      for (int k = 0; k < 3; ++k) first[k] += vol * (a[k] + b[k] + d[k]) / 4;
    }
  }
};

// Each element's volume and centroid from its faces (VTK's orders, faces outward).
Moments element_moments(const MeshData& m, uint64_t e) {
  static const std::map<int, std::vector<std::vector<int>>> kFaces = {
      {10, {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 2, 1}}},
      {14, {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}},
      {13, {{0, 1, 2}, {3, 5, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}}},
      {12, {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}}}};
  Moments mo;
  const auto& faces = kFaces.at(m.cell_types[e]);
  for (const auto& f : faces) {
    std::vector<P> v;
    for (int k : f) {
      const vec3d p = m.points[m.connectivity[m.cell_offsets[e] + uint64_t(k)]];
      v.push_back({p[0], p[1], p[2]});
    }
    mo.add_polygon(v, 1);
  }
  return mo;
}

// A copy of a case in a scratch directory (for edits).
fs::path case_copy(const std::string& name, const std::string& scratch) {
  const fs::path dir = test::scratch_dir(scratch) / name;
  fs::copy(kDir / name, dir, fs::copy_options::recursive);
  return dir;
}

TEST(OpenFoam, AsciiCaseIsWhatVtkRead) {
  OpenFoamCase foam(kDir / "box_ascii");
  ASSERT_EQ(foam.step_count(), 3u);
  EXPECT_EQ(foam.step_time(0), 0.0);
  EXPECT_EQ(foam.step_time(1), 0.1);
  EXPECT_EQ(foam.step_time(2), 0.2);
  EXPECT_EQ(foam.step_file(2), kDir / "box_ascii" / "0.2");
  EXPECT_EQ(foam.summary(),
            "232 cells, 842 faces; fields C, T, U, V; left out (not in every time step): mag(U); "
            "skipped: phi (surfaceScalarField)");
  const MeshData m = foam.read_step(2), vtu = read_vtu(kDir / "reference.vtu");
  // The same points first (VTK's and the file's), the same cells split the same way; VTK's
  // reader keeps OpenFOAM's scalars as float32.
  ASSERT_GE(m.points.size(), 406u);
  ASSERT_GE(vtu.points.size(), 406u);
  for (size_t p = 0; p < 406; ++p)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.points[p][k], vtu.points[p][k], 1e-7) << p;
  EXPECT_EQ(m.cell_count(), vtu.cell_count());
  EXPECT_EQ(m.cell_types, vtu.cell_types);
  expect_cell_values_equal(m, vtu, 1e-6);
  test::expect_probes_alike(vtu, "T", m, "T");
  test::expect_probes_alike(vtu, "U", m, "U");
  EXPECT_NO_THROW(make_umesh(m, mesh_transform(m), "openfoam"));  // every element the right way round
  // Some cells are polyhedra (not hexes): more elements than cells.
  EXPECT_GT(m.cell_count(), kCells);
}

TEST(OpenFoam, AsciiBinaryAndGzippedAreTheSame) {
  OpenFoamCase ascii(kDir / "box_ascii" / "box_ascii.foam");  // ParaView's way in
  OpenFoamCase binary(kDir / "box_binary" / "system" / "controlDict");
  OpenFoamCase gz(kDir / "box_gz");
  ASSERT_EQ(binary.step_count(), 1u);
  ASSERT_EQ(gz.step_count(), 1u);
  EXPECT_EQ(binary.step_time(0), 0.2);
  const MeshData a = ascii.read_step(2), b = binary.read_step(0), g = gz.read_step(0);
  for (const MeshData* other : {&b, &g}) {
    EXPECT_EQ(other->points, a.points);
    EXPECT_EQ(other->cell_types, a.cell_types);
    EXPECT_EQ(other->cell_offsets, a.cell_offsets);
    EXPECT_EQ(other->connectivity, a.connectivity);
    expect_cell_values_equal(*other, a, 1e-9);  // ascii values are written to 10 digits
  }
  EXPECT_EQ(test::array_named(g.cell_data, "mag(U)").components, 1);  // in its one step, not left out
}

TEST(OpenFoam, PiecesFillTheirCellsAndKeepItsCentre) {
  // A field of each cell's index (written here, as OpenFOAM writes one) tells which cell a piece
  // is of.
  const fs::path dir = case_copy("box_ascii", "openfoam_pieces");
  std::string ids =
      "FoamFile { version 2.0; format ascii; class volScalarField; object id; }\n"
      "dimensions [0 0 0 0 0 0 0];\ninternalField nonuniform List<scalar> " +
      std::to_string(kCells) + "\n(\n";
  for (uint64_t c = 0; c < kCells; ++c) ids += std::to_string(c) + "\n";
  ids += ");\nboundaryField { }\n";
  for (const char* t : {"0", "0.1", "0.2"}) test::write_bytes(dir / t / "id", ids);
  OpenFoamCase foam(dir);
  const MeshData m = foam.read_step(2);
  const std::vector<double>& id = test::array_named(m.cell_data, "id").values;
  const std::vector<double>& volume = test::array_named(m.cell_data, "V").values;
  const std::vector<double>& centre = test::array_named(m.cell_data, "C").values;
  std::vector<Moments> pieces(kCells);
  std::vector<uint64_t> any_piece(kCells);
  for (uint64_t e = 0; e < m.cell_count(); ++e) {
    const uint64_t c = uint64_t(id[e]);
    ASSERT_LT(c, kCells);
    const Moments mo = element_moments(m, e);
    EXPECT_GT(mo.volume, 0) << "element " << e << " of cell " << c;
    pieces[c].volume += mo.volume;
    for (int k = 0; k < 3; ++k) pieces[c].first[k] += mo.first[k];
    any_piece[c] = e;
  }

  // Each cell's volume and centroid from its faces (face normals point out of the owner).
  const std::vector<double> xyz = numbers_of(dir / "constant" / "polyMesh" / "points");
  const std::vector<double> faces = numbers_of(dir / "constant" / "polyMesh" / "faces");
  const std::vector<double> owner = numbers_of(dir / "constant" / "polyMesh" / "owner");
  const std::vector<double> neighbour = numbers_of(dir / "constant" / "polyMesh" / "neighbour");
  std::vector<Moments> cells(kCells);
  size_t at = 1;
  for (size_t f = 0; f < size_t(faces[0]); ++f) {
    std::vector<P> v;
    const size_t n = size_t(faces[at++]);
    for (size_t k = 0; k < n; ++k, ++at) {
      const size_t p = size_t(faces[at]);
      v.push_back({xyz[1 + 3 * p], xyz[2 + 3 * p], xyz[3 + 3 * p]});
    }
    cells[size_t(owner[1 + f])].add_polygon(v, 1);
    if (f < size_t(neighbour[0])) cells[size_t(neighbour[1 + f])].add_polygon(v, -1);
  }
  ASSERT_EQ(at, faces.size());

  for (uint64_t c = 0; c < kCells; ++c) {
    SCOPED_TRACE("cell " + std::to_string(c));
    EXPECT_NEAR(pieces[c].volume, cells[c].volume, 1e-12);
    EXPECT_NEAR(pieces[c].volume, volume[any_piece[c]], 1e-9);  // OpenFOAM's own volume
    for (int k = 0; k < 3; ++k) {
      // A linear field (the position) stays exact: the pieces' centroid is the cell's, and
      // OpenFOAM's cell centre.
      EXPECT_NEAR(pieces[c].first[k] / pieces[c].volume, cells[c].first[k] / cells[c].volume, 1e-12);
      EXPECT_NEAR(pieces[c].first[k] / pieces[c].volume, centre[3 * any_piece[c] + uint64_t(k)], 1e-9);
    }
  }
}

TEST(OpenFoam, ConvertReadsTheCaseDirectory) {
  const auto series = open_mesh_files({kDir / "box_ascii"});
  EXPECT_EQ(series->step_count(), 3);
  EXPECT_EQ(series->step_time(1), 0.1);
  EXPECT_EQ(series->description(),
            "OpenFOAM case box_ascii (232 cells, 842 faces; fields C, T, U, V; left out (not in every time step): "
            "mag(U); skipped: phi (surfaceScalarField); 3 steps)");
  // A later step's values alone (what convert reads) are those of its whole step.
  const MeshData first = series->read_step(0);
  for (int step : {1, 2}) {
    const MeshData whole = series->read_step(step);
    const StepData alone = series->read_step_data(step, first);
    ASSERT_EQ(alone.cell_data.size(), whole.cell_data.size());
    for (size_t a = 0; a < whole.cell_data.size(); ++a) EXPECT_EQ(alone.cell_data[a].values, whole.cell_data[a].values);
    EXPECT_TRUE(alone.point_data.empty());
  }
  EXPECT_TRUE(is_mesh_file(kDir / "box_gz" / "box_gz.foam"));
  EXPECT_TRUE(is_mesh_file(kDir / "box_gz"));
  EXPECT_FALSE(is_mesh_file(kDir));
  EXPECT_THROW(open_mesh_files({kDir / "box_ascii", kDir / "box_gz"}), UsageError);
}

// A one-tet case written here in binary with 64-bit labels and 32-bit scalars (`arch`), little-
// or big-endian, faces as a faceCompactList: what OpenFOAM built with WM_LABEL_SIZE=64 and
// WM_PRECISION_OPTION=SP (or on a big-endian machine) writes.
template <typename T>
std::string raw(std::initializer_list<T> values, bool big_endian) {
  std::string bytes;
  for (T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    bytes.append(b, sizeof(T));
  }
  return bytes;
}
// `first_vertex`: the first face's first vertex (0 in the tet).
void write_tet_case(const fs::path& dir, bool big_endian, int64_t first_vertex = 0) {
  fs::create_directories(dir / "constant" / "polyMesh");
  fs::create_directories(dir / "1.5");
  const auto header = [&](const char* cls) {
    return std::string("FoamFile\n{\n    format binary;\n    class ") + cls + ";\n    arch \"" +
           (big_endian ? "MSB" : "LSB") + ";label=64;scalar=32\";\n}\n// a comment\n";
  };
  const fs::path m = dir / "constant" / "polyMesh";
  test::write_bytes(m / "points", header("vectorField") + "4\n(" +
                                      raw<float>({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, big_endian) + ")\n");
  test::write_bytes(m / "faces", header("faceCompactList") + "5\n(" + raw<int64_t>({0, 3, 6, 9, 12}, big_endian) +
                                     ")\n12\n(" +
                                     raw<int64_t>({first_vertex, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2}, big_endian) + ")\n");
  test::write_bytes(m / "owner", header("labelList") + "4\n(" + raw<int64_t>({0, 0, 0, 0}, big_endian) + ")\n");
  test::write_bytes(m / "neighbour", header("labelList") + "0()\n");
  test::write_bytes(dir / "1.5" / "T",
                    header("volScalarField") + "dimensions [0 0 0 1 0 0 0];\ninternalField nonuniform " +
                        "List<scalar> 1(" + raw<float>({2.5f}, big_endian) + ");\nboundaryField {}\n");
  test::write_bytes(dir / "1.5" / "U", header("volVectorField") + "internalField uniform (1 2 3);\n");
}

TEST(OpenFoam, BinaryOf64BitLabelsAnd32BitScalarsEitherEndian) {
  for (bool big_endian : {false, true}) {
    SCOPED_TRACE(big_endian ? "MSB" : "LSB");
    const fs::path dir = test::scratch_dir(big_endian ? "openfoam_tet_msb" : "openfoam_tet_lsb") / "tet";
    write_tet_case(dir, big_endian);
    OpenFoamCase foam(dir);
    ASSERT_EQ(foam.step_count(), 1u);
    EXPECT_EQ(foam.step_time(0), 1.5);
    const MeshData m = foam.read_step(0);
    ASSERT_EQ(m.cell_count(), 1u);
    EXPECT_EQ(m.cell_types[0], 10);  // the faces of a tet: a tet
    ASSERT_EQ(m.points.size(), 4u);
    EXPECT_EQ(m.points[3], (vec3d{0, 0, 1}));
    EXPECT_EQ(test::array_named(m.cell_data, "T").values, std::vector<double>{2.5});
    EXPECT_EQ(test::array_named(m.cell_data, "U").values, (std::vector<double>{1, 2, 3}));
  }
}

// Face vertices are kept in 32 bits (PolyhedronFaces): a 64-bit label past them is out of range,
// not wrapped to a point of the mesh (2^32 would be point 0), and so is a negative one.
TEST(OpenFoam, FaceVertexPast32BitsIsOutOfRange) {
  for (const int64_t label : {int64_t(1) << 32, (int64_t(1) << 32) + 2, int64_t(-1)}) {
    SCOPED_TRACE(label);
    const fs::path dir = test::scratch_dir("openfoam_tet_wide") / "tet";
    write_tet_case(dir, false, label);
    const std::string error = test::input_error_line([&] { OpenFoamCase(dir).read_step(0); });
    EXPECT_NE(error.find("point 4294967295 out of range 0..3"), std::string::npos) << error;
  }
}

// A copy of the ascii case, its files edited, read step by step as `convert` reads it.
class EditedOpenFoam : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = case_copy("box_ascii", "openfoam_edit"); }
  fs::path mesh(const std::string& name) const { return dir_ / "constant" / "polyMesh" / name; }
  void replace(const fs::path& file, const std::string& from, const std::string& to) {
    std::string t = test::file_bytes(file);
    const size_t at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    test::write_bytes(file, t);
  }
  std::string error(const fs::path& input = {}) {
    return test::input_error_line([&] {
      OpenFoamCase f(input.empty() ? dir_ : input);
      for (size_t s = 0; s < f.step_count(); ++s) f.read_step(s);
    });
  }
  fs::path dir_;
};

TEST_F(EditedOpenFoam, CutShortAnywhere) {
  for (const char* name : {"points", "faces", "owner", "neighbour"}) {
    const std::string full = test::file_bytes(mesh(name));
    for (size_t cut : {size_t(0), size_t(1), size_t(20), size_t(700), full.size() / 2, full.size() - 120}) {
      SCOPED_TRACE(std::string(name) + " cut at " + std::to_string(cut));
      test::write_bytes(mesh(name), full.substr(0, cut));
      const std::string e = error();
      EXPECT_NE(e, "accepted");
      EXPECT_NE(e.find(name), std::string::npos) << e;
    }
    test::write_bytes(mesh(name), full);
  }
  const std::string field = test::file_bytes(dir_ / "0.1" / "T");
  test::write_bytes(dir_ / "0.1" / "T", field.substr(0, field.size() / 2));
  EXPECT_NE(error().find("0.1/T"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, BinaryCutShortOrCountTooLarge) {
  dir_ = case_copy("box_binary", "openfoam_edit_binary");
  const std::string full = test::file_bytes(mesh("faces"));
  test::write_bytes(mesh("faces"), full.substr(0, full.size() * 3 / 4));
  EXPECT_NE(error().find("faces"), std::string::npos) << error();
  std::string t = full;
  const size_t at = t.find("\n843\n(");
  ASSERT_NE(at, std::string::npos);
  t.replace(at, 5, "\n999999999999\n");
  test::write_bytes(mesh("faces"), t);
  EXPECT_NE(error().find("faces"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, FaceVertexOutOfRange) {
  replace(mesh("faces"), "\n4(390 226 398 210)\n", "\n4(390 226 398 4300)\n");
  EXPECT_NE(error().find("point 4300 out of range 0..405"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, FaceOfTwoVertices) {
  replace(mesh("faces"), "\n4(390 226 398 210)\n", "\n2(390 226)\n");
  EXPECT_NE(error().find("of 2 vertices"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, OwnerOutOfRange) {
  replace(mesh("owner"), "\n(\n0\n", "\n(\n-3\n");
  EXPECT_NE(error().find("owner of face 0: cell -3 out of range 0..231"), std::string::npos) << error();
  replace(mesh("owner"), "\n(\n-3\n", "\n(\n232\n");
  EXPECT_NE(error().find("cell 232 out of range"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, MissingNeighbourFile) {
  fs::remove(mesh("neighbour"));
  EXPECT_NE(error().find("neighbour: missing"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, UnbalancedParentheses) {
  replace(mesh("faces"), "\n4(390 226 398 210)\n", "\n4(390 226 398 210\n");
  EXPECT_NE(error().find("faces"), std::string::npos) << error();
  replace(mesh("faces"), "\n4(390 226 398 210\n", "\n4(390 226 398 210)\n");
  replace(dir_ / "0" / "T", "dimensions", "dimensions (");
  EXPECT_NE(error(), "accepted");
  fs::copy_file(kDir / "box_ascii" / "0" / "T", dir_ / "0" / "T", fs::copy_options::overwrite_existing);
  replace(dir_ / "0" / "T", "dimensions", ") dimensions");
  EXPECT_NE(error().find("unbalanced"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, UnknownFormatOrClass) {
  replace(mesh("points"), "format      ascii;", "format      hdf5;");
  EXPECT_NE(error().find("unknown format 'hdf5'"), std::string::npos) << error();
  replace(mesh("points"), "format      hdf5;", "format      ascii;");
  replace(mesh("faces"), "class       faceList;", "class       cellList;");
  EXPECT_NE(error().find("class 'cellList'"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, CellOfTooFewFacesNamesTheOwnerFile) {
  // Face 0 (internal: cells 0 and 120) given to a new cell 232, which then has one face. (The
  // mesh alone: the fields have 232 values.)
  for (const char* t : {"0", "0.1", "0.2"}) fs::remove_all(dir_ / t);
  replace(mesh("owner"), "nCells:232", "nCells:233");
  replace(mesh("neighbour"), "\n(\n120\n", "\n(\n232\n");
  const std::string e = error();
  EXPECT_NE(e.find("polyhedron cell"), std::string::npos) << e;
  EXPECT_NE(e.find("polyMesh/owner"), std::string::npos) << e;
}

TEST_F(EditedOpenFoam, FieldOfAnotherLength) {
  replace(dir_ / "0.1" / "T", "List<scalar> \n232", "List<scalar> \n231");
  EXPECT_NE(error().find("not 232"), std::string::npos) << error();
}

// A value below the smallest double reads as the subnormal it is, one above the largest as
// infinity (which convert refuses when it writes the values), not as 0: from_chars calls both
// out of range and leaves its result alone.
TEST_F(EditedOpenFoam, ValuesOutOfDoubleRange) {
  for (const auto& [text, value] : {std::pair{"1e-320", 1e-320}, {"1e400", HUGE_VAL}}) {
    const std::string file = test::file_bytes(dir_ / "0.1" / "T");
    replace(dir_ / "0.1" / "T", "(\n0.9181658193\n", std::string("(\n") + text + "\n");
    OpenFoamCase foam(dir_);
    EXPECT_EQ(test::array_named(foam.read_step(1).cell_data, "T").values.front(), value) << text;
    test::write_bytes(dir_ / "0.1" / "T", file);
  }
}

TEST_F(EditedOpenFoam, MovingMeshIsRefused) {
  fs::copy_file(mesh("points"), dir_ / "0" / "polyMesh" / "points");
  EXPECT_NE(error().find("moving or changing mesh"), std::string::npos) << error();
  fs::remove(dir_ / "0" / "polyMesh" / "points");
  // Without constant/polyMesh, an empty processor0 is a decomposed case without its mesh.
  fs::create_directories(dir_ / "processor0");
  fs::remove_all(dir_ / "constant" / "polyMesh");
  EXPECT_NE(error().find("processor0/constant/polyMesh/points: missing"), std::string::npos) << error();
}

TEST_F(EditedOpenFoam, CutShortGzipStream) {
  dir_ = case_copy("box_gz", "openfoam_edit_gz");
  std::string damaged = test::file_bytes(mesh("points.gz"));
  damaged.resize(damaged.size() / 2);
  test::write_bytes(mesh("points.gz"), damaged);
  EXPECT_NE(error().find("points.gz"), std::string::npos) << error();
}

// box_decomposed is box_ascii as decomposePar splits it for 3 processors.

// Each element of a split mesh by its vertices' coordinates, sorted, rounded to 1e-9 (the points
// the split adds are means over a cell's vertices, summed in the order of its faces, which each
// processor numbers its own way).
using ElementKey = std::vector<std::array<int64_t, 3>>;
std::map<ElementKey, uint64_t> elements_by_vertices(const MeshData& m) {
  std::map<ElementKey, uint64_t> elements;
  for (uint64_t e = 0; e < m.cell_count(); ++e) {
    ElementKey key;
    for (uint64_t i = m.cell_offsets[e]; i < m.cell_offsets[e + 1]; ++i) {
      const vec3d p = m.points[m.connectivity[i]];
      key.push_back({std::llround(p[0] * 1e9), std::llround(p[1] * 1e9), std::llround(p[2] * 1e9)});
    }
    std::sort(key.begin(), key.end());
    EXPECT_TRUE(elements.emplace(key, e).second) << "two elements of the same vertices: " << e;
  }
  return elements;
}

TEST(OpenFoam, DecomposedCaseIsTheCaseItCameFrom) {
  OpenFoamCase whole(kDir / "box_ascii"), decomposed(kDir / "box_decomposed");
  EXPECT_EQ(decomposed.summary(),
            "232 cells, 928 faces, decomposed into 3 processors (the faces between them counted in each); fields C, "
            "T, U, V; left out (not in every time step): mag(U); skipped: phi (surfaceScalarField)");
  ASSERT_EQ(decomposed.step_count(), 3u);
  EXPECT_EQ(decomposed.step_file(1), kDir / "box_decomposed" / "processor0" / "0.1");
  for (size_t step = 0; step < 3; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    EXPECT_EQ(decomposed.step_time(step), whole.step_time(step));
    const MeshData a = whole.read_step(step), b = decomposed.read_step(step);
    // The processors' points joined are the points of the whole case, in its order (each its
    // pointProcAddressing number), before those the split adds.
    ASSERT_EQ(b.points.size(), a.points.size());
    EXPECT_TRUE(std::equal(a.points.begin(), a.points.begin() + 406, b.points.begin()));
    ASSERT_EQ(b.cell_count(), a.cell_count());
    const std::map<ElementKey, uint64_t> in_a = elements_by_vertices(a), in_b = elements_by_vertices(b);
    ASSERT_EQ(in_a.size(), a.cell_count());
    ASSERT_EQ(in_b.size(), b.cell_count());
    for (const auto& [key, ea] : in_a) {
      const auto it = in_b.find(key);
      ASSERT_NE(it, in_b.end()) << "element " << ea << " of box_ascii is not in box_decomposed";
      const uint64_t eb = it->second;
      EXPECT_EQ(a.cell_types[ea], b.cell_types[eb]);
      for (const char* name : {"T", "U", "C", "V"}) {
        const MeshArray &x = test::array_named(a.cell_data, name), &y = test::array_named(b.cell_data, name);
        ASSERT_EQ(x.components, y.components);
        for (int k = 0; k < x.components; ++k)
          EXPECT_EQ(x.values[ea * uint64_t(x.components) + uint64_t(k)],
                    y.values[eb * uint64_t(y.components) + uint64_t(k)])
              << name << " of element " << ea;
      }
    }
  }
}

TEST(OpenFoam, DecomposedCaseConvertsAsTheCaseItCameFrom) {
  const auto whole = open_mesh_files({kDir / "box_ascii"});
  const auto decomposed = open_mesh_files({kDir / "box_decomposed" / "box_decomposed.foam"});
  EXPECT_NE(decomposed->description().find("decomposed into 3 processors"), std::string::npos)
      << decomposed->description();
  ASSERT_EQ(decomposed->step_count(), whole->step_count());
  for (int step = 0; step < whole->step_count(); ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const MeshData a = whole->read_step(step), b = decomposed->read_step(step);
    for (const char* name : {"T", "U"}) test::expect_probes_alike(a, name, b, name);
  }
  const MeshConvertStats a = convert_mesh_to_dataset(
      *open_mesh_files({kDir / "box_ascii"}), test::scratch_dir("openfoam_convert_whole"), ConvertOptions::silent());
  const MeshConvertStats b =
      convert_mesh_to_dataset(*open_mesh_files({kDir / "box_decomposed"}),
                              test::scratch_dir("openfoam_convert_decomposed"), ConvertOptions::silent());
  EXPECT_EQ(a.elements, b.elements);
  EXPECT_EQ(a.vertices, b.vertices);
}

// A multi-region case (box_regions: box_ascii's cells split by splitMeshRegions into regions
// fluid, cell centres x > 0.5, and solid; the solid has no U) read as the whole case it came from: every piece
// of a split cell carries its cell's values, so each piece is matched to the whole case's by its
// cell centre C (OpenFOAM's, unique to a cell), and the two meshes must hold the same pieces of
// the same cells with the same T and V; U is the whole case's in the fluid and NaN in the solid.
void expect_regions_of_whole(const MeshData& regions, const MeshData& whole) {
  using Key = std::array<double, 3>;
  const auto centre = [](const MeshData& m, size_t e) {
    const std::vector<double>& c = test::array_named(m.cell_data, "C").values;
    return Key{c[3 * e], c[3 * e + 1], c[3 * e + 2]};
  };
  std::map<Key, size_t> cell_of;                                // a piece of each of the whole case's cells
  std::map<Key, std::vector<uint8_t>> types, types_in_regions;  // the types of each cell's pieces
  for (size_t e = 0; e < whole.cell_types.size(); ++e) {
    cell_of.try_emplace(centre(whole, e), e);
    types[centre(whole, e)].push_back(whole.cell_types[e]);
  }
  for (size_t e = 0; e < regions.cell_types.size(); ++e) {
    const Key c = centre(regions, e);
    const auto it = cell_of.find(c);
    ASSERT_NE(it, cell_of.end()) << "piece " << e << ": no cell of the whole case has its centre";
    types_in_regions[c].push_back(regions.cell_types[e]);
    const size_t w = it->second;
    for (const char* name : {"T", "V"})
      EXPECT_EQ(test::array_named(regions.cell_data, name).values[e],
                test::array_named(whole.cell_data, name).values[w])
          << name << " of piece " << e;
    const bool solid = c[0] <= 0.5;  // topoSet's box, x up to 0.5 inclusive
    for (size_t k = 0; k < 3; ++k) {
      const double u = test::array_named(regions.cell_data, "U").values[3 * e + k];
      if (solid)
        EXPECT_TRUE(std::isnan(u)) << "U of solid piece " << e;
      else
        EXPECT_EQ(u, test::array_named(whole.cell_data, "U").values[3 * w + k]) << "U of fluid piece " << e;
    }
  }
  for (auto& [c, t] : types) {
    std::sort(t.begin(), t.end());
    std::sort(types_in_regions[c].begin(), types_in_regions[c].end());
    EXPECT_EQ(types_in_regions[c], t);
  }
}

TEST(OpenFoam, MultiRegionCaseReadsEveryRegionAsTheWholeCase) {
  OpenFoamCase whole(kDir / "box_ascii");
  OpenFoamCase regions(kDir / "box_regions" / "box_regions.foam");
  const std::string s = regions.summary();
  EXPECT_NE(s.find("232 cells, 862 faces; regions (cells) fluid 116, solid 116 (not constant/polyMesh: --region "
                   "region0 reads it); fields C, T, U, V; no data (NaN) for U in solid"),
            std::string::npos)
      << s;
  ASSERT_EQ(regions.step_count(), whole.step_count());
  for (size_t step = 0; step < whole.step_count(); ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    EXPECT_EQ(regions.step_time(step), whole.step_time(step));
    expect_regions_of_whole(regions.read_step(step), whole.read_step(step));
  }
  // The regions share no points: each keeps its own copy of the 30 points on the faces between
  // them (x = 0.6 is 6x5 points of the 6x5x4 box's grid).
  EXPECT_EQ(regions.read_step(0).points.size(), whole.read_step(0).points.size() + 30);
}

TEST(OpenFoam, DecomposedMultiRegionCaseReadsAsTheCaseItCameFrom) {
  OpenFoamCase regions(kDir / "box_regions");
  OpenFoamCase decomposed(kDir / "box_regions_decomposed");
  EXPECT_NE(decomposed.summary().find("decomposed into 2 processors"), std::string::npos) << decomposed.summary();
  ASSERT_EQ(decomposed.step_count(), 1u);
  EXPECT_EQ(decomposed.step_time(0), 0.2);
  const MeshData a = regions.read_step(2), b = decomposed.read_step(0);
  for (const char* name : {"T", "U"}) test::expect_probes_alike(a, name, b, name);
  EXPECT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(a.cell_types.size(), b.cell_types.size());
}

TEST(OpenFoam, RegionsAskedForAreRead) {
  const fs::path dir = kDir / "box_regions";
  // region0, constant/polyMesh, is the whole case before the split, with the time directories' own fields.
  OpenFoamCase region0(dir, {"region0"});
  OpenFoamCase whole(kDir / "box_ascii");
  EXPECT_EQ(region0.summary().find("regions"), std::string::npos) << region0.summary();
  EXPECT_NE(region0.summary().find("232 cells, 842 faces; fields C, T, U, V"), std::string::npos) << region0.summary();
  expect_cell_values_equal(region0.read_step(2), whole.read_step(2));
  // In the order asked for, each once.
  OpenFoamCase solid_first(dir, {"solid", "fluid", "solid"});
  EXPECT_NE(solid_first.summary().find("regions (cells) solid 116, fluid 116; fields C, T, U, V; no data (NaN) for U "
                                       "in solid"),
            std::string::npos)
      << solid_first.summary();
  expect_regions_of_whole(solid_first.read_step(1), whole.read_step(1));
  // A region alone, with its own fields.
  OpenFoamCase solid(dir, {"solid"});
  EXPECT_NE(solid.summary().find("116 cells, 431 faces; regions (cells) solid 116; fields C, T, V"), std::string::npos)
      << solid.summary();
  const std::string e = test::input_error_line([&] { OpenFoamCase c(dir, {"fluid", "gas"}); });
  EXPECT_NE(e.find("box_regions/constant/gas: no region 'gas' in this case (its regions: region0, fluid, solid)"),
            std::string::npos)
      << e;
  EXPECT_THROW(open_mesh_files({kDir / "box_ascii" / ".." / "reference.vtu"}, {}, {"fluid"}), UsageError);
  EXPECT_NO_THROW(open_mesh_files({dir}, {}, {"fluid"}));
}

// An ascii OpenFOAM list file of `items`, as decomposePar writes one.
void write_list(const fs::path& file, const char* class_name, const std::vector<std::string>& items) {
  std::string t = std::string("FoamFile\n{\n    version     2.0;\n    format      ascii;\n    class       ") +
                  class_name + ";\n}\n\n" + std::to_string(items.size()) + "\n(\n";
  for (const std::string& item : items) t += item + "\n";
  test::write_bytes(file, t + ")\n");
}
std::vector<int64_t> labels_of(const fs::path& file) {
  const std::vector<double> v = numbers_of(file);
  return std::vector<int64_t>(v.begin() + 1, v.end());
}
void write_labels(const fs::path& file, const std::vector<int64_t>& labels) {
  std::vector<std::string> items;
  for (int64_t l : labels) items.push_back(std::to_string(l));
  write_list(file, "labelList", items);
}

// A copy of the decomposed case, edited.
class EditedDecomposedOpenFoam : public EditedOpenFoam {
 protected:
  void SetUp() override { dir_ = case_copy("box_decomposed", "openfoam_edit_decomposed"); }
  fs::path processor_mesh(int k, const std::string& name) const {
    return dir_ / ("processor" + std::to_string(k)) / "constant" / "polyMesh" / name;
  }
};

TEST_F(EditedDecomposedOpenFoam, PointAddressingMissing) {
  fs::remove(processor_mesh(1, "pointProcAddressing"));
  const std::string e = error();
  EXPECT_NE(e.find("processor1/constant/polyMesh/pointProcAddressing: missing"), std::string::npos) << e;
  EXPECT_NE(e.find("decomposePar"), std::string::npos) << e;
  EXPECT_NE(e.find("reconstructPar"), std::string::npos) << e;
}

TEST_F(EditedDecomposedOpenFoam, PointAddressingTooShortOrOutOfRange) {
  const fs::path file = processor_mesh(2, "pointProcAddressing");
  std::vector<int64_t> ids = labels_of(file);
  const size_t points = ids.size();
  ids.pop_back();
  write_labels(file, ids);
  EXPECT_NE(error().find("processor2/constant/polyMesh/pointProcAddressing: offset"), std::string::npos) << error();
  EXPECT_NE(error().find(std::to_string(points - 1) + " point numbers for the processor's " + std::to_string(points)),
            std::string::npos)
      << error();
  ids = labels_of(processor_mesh(0, "pointProcAddressing"));
  ids[3] = 5000;
  write_labels(processor_mesh(0, "pointProcAddressing"), ids);
  fs::copy_file(kDir / "box_decomposed" / "processor2" / "constant" / "polyMesh" / "pointProcAddressing", file,
                fs::copy_options::overwrite_existing);
  EXPECT_NE(error().find("processor0/constant/polyMesh/pointProcAddressing: point 3: number 5000 out of range"),
            std::string::npos)
      << error();
  ids[3] = -1;
  write_labels(processor_mesh(0, "pointProcAddressing"), ids);
  EXPECT_NE(error().find("processor0/constant/polyMesh/pointProcAddressing: offset"), std::string::npos) << error();
  EXPECT_NE(error().find("point 3: a negative number -1"), std::string::npos) << error();
}

TEST_F(EditedDecomposedOpenFoam, PointInNoProcessor) {
  // Processor 0's last point numbered 407, past the whole mesh's points 0..405: point 406 is in
  // no processor.
  std::vector<int64_t> ids = labels_of(processor_mesh(0, "pointProcAddressing"));
  ids.back() = 407;
  write_labels(processor_mesh(0, "pointProcAddressing"), ids);
  const std::string e = error();
  EXPECT_NE(e.find("pointProcAddressing"), std::string::npos) << e;
  EXPECT_NE(e.find("point 406 of the whole mesh is in no processor"), std::string::npos) << e;
}

// A case run in parallel from a whole mesh has both layouts: its own mesh and time 0, and the
// processors' meshes and every time. The processors are read where their last time is later.
TEST_F(EditedDecomposedOpenFoam, ProcessorsWithLaterTimesAreReadBesideTheCasesOwnMesh) {
  fs::copy(kDir / "box_ascii" / "constant", dir_ / "constant", fs::copy_options::recursive);
  fs::copy(kDir / "box_ascii" / "0", dir_ / "0", fs::copy_options::recursive);
  auto series = open_mesh_files({dir_});
  EXPECT_EQ(series->step_count(), 3);
  EXPECT_NE(series->description().find("decomposed into 3 processors"), std::string::npos) << series->description();
  for (int k = 0; k < 3; ++k)
    for (const char* t : {"0.1", "0.2"}) fs::remove_all(dir_ / ("processor" + std::to_string(k)) / t);
  series = open_mesh_files({dir_});
  EXPECT_EQ(series->step_count(), 1);
  EXPECT_EQ(series->description().find("decomposed into"), std::string::npos) << series->description();
  EXPECT_NE(series->description().find("842 faces"), std::string::npos) << series->description();
}

// The collated layout (decomposePar -fileHandler collated: processors3/, each file holding
// every processor's) of the same decomposition reads as the same mesh and values, exactly: the
// ascii case at every step, the binary one (foamFormatConvert of the ascii, so the same numbers)
// at its one.
TEST(OpenFoam, CollatedCaseReadsAsTheUncollatedOne) {
  OpenFoamCase uncollated(kDir / "box_decomposed"), collated(kDir / "box_collated" / "box_collated.foam"),
      binary(kDir / "box_collated_binary");
  EXPECT_NE(collated.summary().find("decomposed into 3 processors"), std::string::npos) << collated.summary();
  ASSERT_EQ(collated.step_count(), 3u);
  ASSERT_EQ(binary.step_count(), 1u);
  const auto expect_same = [](const MeshData& a, const MeshData& b) {
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.cell_types, b.cell_types);
    EXPECT_EQ(a.cell_offsets, b.cell_offsets);
    EXPECT_EQ(a.connectivity, b.connectivity);
    expect_cell_values_equal(a, b);
  };
  for (size_t step = 0; step < 3; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    EXPECT_EQ(collated.step_time(step), uncollated.step_time(step));
    expect_same(collated.read_step(step), uncollated.read_step(step));
  }
  expect_same(binary.read_step(0), uncollated.read_step(2));
}

// A copy of the collated case, edited.
class EditedCollatedOpenFoam : public EditedOpenFoam {
 protected:
  void SetUp() override { dir_ = case_copy("box_collated", "openfoam_edit_collated"); }
  fs::path collated(const std::string& name) const { return dir_ / "processors3" / name; }
};

TEST_F(EditedCollatedOpenFoam, CutShortAnywhere) {
  for (const char* name : {"constant/polyMesh/points", "constant/polyMesh/faces", "constant/polyMesh/owner",
                           "constant/polyMesh/pointProcAddressing", "0.2/T"}) {
    const std::string full = test::file_bytes(collated(name));
    for (size_t cut : {size_t(0), size_t(700), full.size() / 3, full.size() / 2, full.size() - 2}) {
      // A field file cut inside its header is no field file (left out, as an uncollated one).
      if (std::string_view(name) == "0.2/T" && cut < 1000) continue;
      SCOPED_TRACE(std::string(name) + " cut at " + std::to_string(cut));
      test::write_bytes(collated(name), full.substr(0, cut));
      const std::string e = error();
      EXPECT_NE(e, "accepted");
      EXPECT_NE(e.find(fs::path(name).filename().string()), std::string::npos) << e;
    }
    test::write_bytes(collated(name), full);
  }
}

TEST_F(EditedCollatedOpenFoam, NotABlockFileOrBlocksMiscounted) {
  replace(collated("constant/polyMesh/owner"), "decomposedBlockData", "labelList");
  EXPECT_NE(error().find("processors3/constant/polyMesh/owner: offset"), std::string::npos) << error();
  EXPECT_NE(error().find("class 'labelList', not decomposedBlockData"), std::string::npos) << error();
  replace(collated("constant/polyMesh/owner"), "labelList;", "decomposedBlockData;");
  // Named for 2 processors, a file holds 3 blocks; for 4, it lacks one.
  fs::rename(dir_ / "processors3", dir_ / "processors2");
  EXPECT_NE(error().find("more than the 2 processors' blocks that the directory's name counts"), std::string::npos)
      << error();
  fs::rename(dir_ / "processors2", dir_ / "processors4");
  EXPECT_NE(error().find("processors4/constant/polyMesh/points: offset"), std::string::npos) << error();
  EXPECT_NE(error().find("a processor's block size"), std::string::npos) << error();
}

TEST_F(EditedCollatedOpenFoam, TwoDecompositionsOrIoRanksAreNamed) {
  fs::create_directories(dir_ / "processors5" / "constant");
  EXPECT_NE(error().find("processors5: a second collated decomposition beside processors3"), std::string::npos)
      << error();
  fs::remove_all(dir_ / "processors5");
  fs::rename(dir_ / "processors3", dir_ / "processors3_0-1");
  EXPECT_NE(error().find("processors3_0-1: a collated case split over I/O ranks"), std::string::npos) << error();
}

TEST_F(EditedDecomposedOpenFoam, GapInProcessorNumbers) {
  fs::rename(dir_ / "processor1", dir_ / "processor3");
  EXPECT_NE(error().find("processor1: missing, though processor2 is there"), std::string::npos) << error();
}

TEST_F(EditedDecomposedOpenFoam, StepMissingInOneProcessor) {
  fs::remove_all(dir_ / "processor2" / "0.1");
  EXPECT_NE(error().find("processor2/0.1: missing, though processor0 has time 0.1"), std::string::npos) << error();
}

TEST_F(EditedDecomposedOpenFoam, FieldMissingInOneProcessorIsLeftOut) {
  fs::remove(dir_ / "processor1" / "0.1" / "V");
  OpenFoamCase foam(dir_);
  EXPECT_NE(foam.summary().find("fields C, T, U; left out (not in every time step): V, mag(U)"), std::string::npos)
      << foam.summary();
}

TEST_F(EditedDecomposedOpenFoam, SharedPointsDisagree) {
  // A point of processor 1 that processor 0 has too, moved by a little (refused) or by a
  // rounding error (accepted).
  const std::vector<int64_t> ids0 = labels_of(processor_mesh(0, "pointProcAddressing")),
                             ids1 = labels_of(processor_mesh(1, "pointProcAddressing"));
  const auto shared = std::find_if(ids1.begin(), ids1.end(),
                                   [&](int64_t id) { return std::find(ids0.begin(), ids0.end(), id) != ids0.end(); });
  ASSERT_NE(shared, ids1.end());
  const size_t p = size_t(shared - ids1.begin());
  const std::vector<double> xyz = numbers_of(processor_mesh(1, "points"));
  for (const double factor : {1 + 1e-6, 1 + 1e-13}) {
    std::vector<std::string> points;
    for (size_t q = 0; q + 3 < xyz.size(); q += 3) {
      char text[100];
      const double f = q / 3 == p ? factor : 1;
      std::snprintf(text, sizeof text, "(%.17g %.17g %.17g)", xyz[q + 1] * f, xyz[q + 2] * f, xyz[q + 3] * f);
      points.push_back(text);
    }
    write_list(processor_mesh(1, "points"), "vectorField", points);
    const std::string e = error();
    if (factor > 1 + 1e-9) {
      EXPECT_NE(e.find("processor1/constant/polyMesh/pointProcAddressing: point " + std::to_string(p) + " (point " +
                       std::to_string(*shared) + " of the whole mesh) is at ("),
                std::string::npos)
          << e;
      EXPECT_NE(e.find("in processor0"), std::string::npos) << e;
    } else {
      EXPECT_EQ(e, "accepted");
    }
  }
}

}  // namespace
}  // namespace vs
