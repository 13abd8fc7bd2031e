// Fluent case and data files written from the format's description
// (tests/data/fluent/make_fluent_files.py, whose files VTK's own Fluent reader reads as the same
// cells and values) read as the .vtu files VTK wrote of the same meshes and cell values: ASCII and
// binary sections alike, a case with two data files as two steps, polyhedra, gzipped files; and
// damaged files, edited here, refused with one line.
#include "volstream/io/fluent.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "fluent";

void expect_cell_values_equal(const MeshData& a, const MeshData& b, double tolerance = 0) {
  for (const char* name : {"pressure", "temperature", "velocity"}) {
    SCOPED_TRACE(name);
    const MeshArray &x = test::array_named(a.cell_data, name), &y = test::array_named(b.cell_data, name);
    ASSERT_EQ(x.components, y.components);
    ASSERT_EQ(x.values.size(), y.values.size());
    for (size_t i = 0; i < x.values.size(); ++i) EXPECT_NEAR(x.values[i], y.values[i], tolerance) << i;
  }
}

TEST(Fluent, AsciiCaseAndDataAreTheVtuVtkWrote) {
  FluentFile fluent(kDir / "fluent_mixed.cas");  // its .dat found by name
  ASSERT_EQ(fluent.step_count(), 1u);
  EXPECT_EQ(fluent.step_time(0), 0.5);
  EXPECT_EQ(fluent.step_file(0), kDir / "fluent_mixed.dat");
  const MeshData m = fluent.read_step(0), vtu = read_vtu(kDir / "fluent_mixed.vtu");
  EXPECT_EQ(fluent.summary(), "2 cell zones (fluid, solid): hex x 8, pyramid x 48, tet x 48, wedge x 16");
  // Each cell's faces are those of a tet, pyramid, wedge or hex: it stays one, on the same points.
  EXPECT_EQ(m.cell_count(), vtu.cell_count());
  EXPECT_EQ(m.cell_types, vtu.cell_types);
  EXPECT_EQ(m.points.size(), vtu.points.size());
  EXPECT_EQ(m.cell_data.size(), 3u);  // the wall's pressure (a face zone's) is not among them
  expect_cell_values_equal(m, vtu);
  test::expect_probes_alike(vtu, "temperature", m, "temperature");
  test::expect_probes_alike(vtu, "velocity", m, "velocity");
  EXPECT_NO_THROW(make_umesh(m, mesh_transform(m), "fluent"));  // every element the right way round
}

TEST(Fluent, AsciiAndBinarySectionsAreTheSameMesh) {
  const MeshData ascii = FluentFile(kDir / "fluent_mixed.cas").read_step(0);
  const MeshData binary = FluentFile(kDir / "fluent_mixed_bin.cas").read_step(0);
  EXPECT_EQ(binary.points, ascii.points);
  EXPECT_EQ(binary.cell_types, ascii.cell_types);
  EXPECT_EQ(binary.cell_offsets, ascii.cell_offsets);
  EXPECT_EQ(binary.connectivity, ascii.connectivity);
  expect_cell_values_equal(binary, ascii);
}

TEST(Fluent, DataFilesAreStepsInTheOrderGiven) {
  FluentFile fluent(kDir / "fluent_mixed_bin.cas", {kDir / "fluent_mixed_bin.dat", kDir / "fluent_mixed_bin-2.dat"});
  ASSERT_EQ(fluent.step_count(), 2u);
  EXPECT_EQ(fluent.step_time(0), 0.5);
  EXPECT_EQ(fluent.step_time(1), 1.25);
  expect_cell_values_equal(fluent.read_step(1), read_vtu(kDir / "fluent_mixed_2.vtu"));
  expect_cell_values_equal(fluent.read_step(0), read_vtu(kDir / "fluent_mixed.vtu"));
  // A later step's values alone (what convert reads) are those of its whole step.
  MeshData values_alone = fluent.read_step(0);
  values_alone.cell_data = fluent.read_cell_data(1);
  expect_cell_values_equal(values_alone, read_vtu(kDir / "fluent_mixed_2.vtu"));
  // The CLI's way in: the case, then its data files.
  const auto series = open_mesh_files({kDir / "fluent_mixed_bin.cas", kDir / "fluent_mixed_bin-2.dat"});
  EXPECT_EQ(series->step_count(), 1);
  EXPECT_EQ(series->step_time(0), 1.25);
  EXPECT_TRUE(is_mesh_file(kDir / "fluent_mixed.cas"));
  EXPECT_TRUE(is_mesh_file(kDir / "fluent_mixed_gz.cas.gz"));
  EXPECT_FALSE(is_mesh_file(kDir / "fluent_mixed.dat"));
  EXPECT_THROW(open_mesh_files({kDir / "fluent_mixed.cas", kDir / "fluent_mixed.vtu"}), UsageError);
}

TEST(Fluent, PolyhedraAndSinglePrecisionAreTheVtu) {
  FluentFile fluent(kDir / "fluent_poly.cas");
  EXPECT_EQ(fluent.summary(), "1 cell zone (cells): polyhedron x 11");
  const MeshData m = fluent.read_step(0), vtu = read_vtu(kDir / "fluent_poly.vtu");
  test::expect_probes_alike(vtu, "temperature", m, "temperature");
  test::expect_probes_alike(vtu, "pressure", m, "pressure");
  EXPECT_NO_THROW(make_umesh(m, mesh_transform(m), "fluent"));
}

TEST(Fluent, GzippedFilesAreTheSame) {
  const MeshData gz = FluentFile(kDir / "fluent_mixed_gz.cas.gz").read_step(0);
  const MeshData plain = FluentFile(kDir / "fluent_mixed.cas").read_step(0);
  EXPECT_EQ(gz.points, plain.points);
  EXPECT_EQ(gz.connectivity, plain.connectivity);
  expect_cell_values_equal(gz, plain);
}

TEST(Fluent, CaseWithoutDataIsTheMeshAlone) {
  const fs::path dir = test::scratch_dir("fluent_mesh_only");
  fs::copy_file(kDir / "fluent_mixed.cas", dir / "mesh.cas");
  FluentFile fluent(dir / "mesh.cas");
  EXPECT_EQ(fluent.step_count(), 1u);
  EXPECT_EQ(fluent.step_time(0), 0.0);
  const MeshData m = fluent.read_step(0);
  EXPECT_EQ(m.cell_count(), 120u);
  EXPECT_TRUE(m.cell_data.empty());
}

// The ASCII case and data copied to a scratch directory, one of them edited.
class EditedFluent : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("fluent");
    for (const char* f : {"fluent_mixed.cas", "fluent_mixed.dat", "fluent_mixed_bin.cas", "fluent_mixed_bin.dat"})
      fs::copy_file(kDir / f, dir_ / f);
  }
  void replace(const std::string& name, const std::string& from, const std::string& to) {
    std::string t = test::file_bytes(dir_ / name);
    const size_t at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    test::write_bytes(dir_ / name, t);
  }
  // The `token`th number (0-based) of the first row after `header` replaced by `to`.
  void replace_in_first_row(const std::string& name, const std::string& header, int token, const std::string& to) {
    std::string t = test::file_bytes(dir_ / name);
    size_t at = t.find(header);
    ASSERT_NE(at, std::string::npos) << header;
    at = t.find('\n', at) + 1;
    for (int k = 0; k < token; ++k) at = t.find(' ', at) + 1;
    t.replace(at, t.find_first_of(" \n", at) - at, to);
    test::write_bytes(dir_ / name, t);
  }
  // The error of reading every step of `case_name` (with its data file of the same name).
  std::string error(const std::string& case_name = "fluent_mixed.cas") {
    return test::input_error_line([&] {
      FluentFile f(dir_ / case_name);
      for (size_t s = 0; s < f.step_count(); ++s) f.read_step(s);
    });
  }
  fs::path dir_;
};

TEST_F(EditedFluent, CutShortAnywhere) {
  for (const char* name : {"fluent_mixed.cas", "fluent_mixed_bin.cas", "fluent_mixed.dat", "fluent_mixed_bin.dat"}) {
    const std::string full = test::file_bytes(kDir / name);
    for (size_t cut : {size_t(0), size_t(1), size_t(7), size_t(60), size_t(120), full.size() / 3, full.size() / 2,
                       full.size() * 3 / 4, full.size() - 2}) {
      SCOPED_TRACE(std::string(name) + " cut at " + std::to_string(cut));
      test::write_bytes(dir_ / name, full.substr(0, cut));
      const std::string e =
          error(std::string(name).find("bin") == std::string::npos ? "fluent_mixed.cas" : "fluent_mixed_bin.cas");
      EXPECT_NE(e, "accepted");
    }
    test::write_bytes(dir_ / name, full);
  }
}

TEST_F(EditedFluent, FaceNodeOutOfRange) {
  replace_in_first_row("fluent_mixed.cas", "(13 (4 1 d8 2 0)(", 1, "fff");
  EXPECT_NE(error().find("node 4095 out of range"), std::string::npos) << error();
}

TEST_F(EditedFluent, FaceCellOutOfRange) {
  replace_in_first_row("fluent_mixed.cas", "(13 (4 1 d8 2 0)(", 4, "79");  // a tet's face: 3 nodes, then c0
  EXPECT_NE(error().find("out of range 1..120"), std::string::npos) << error();
}

TEST_F(EditedFluent, HugeCount) {
  replace("fluent_mixed.cas", "(10 (0 1 74 0 3))", "(10 (0 1 fffffffffff 0 3))");
  EXPECT_NE(error().find("declares"), std::string::npos) << error();
}

TEST_F(EditedFluent, HugeBinaryCount) {
  replace("fluent_mixed_bin.cas", "(13 (0 1 158 0))", "(13 (0 1 ffffffff 0))");
  replace("fluent_mixed_bin.cas", "(2013 (4 1 d8 2 0)", "(2013 (4 1 fffffff0 2 0)");
  EXPECT_NE(error("fluent_mixed_bin.cas"), "accepted");
}

TEST_F(EditedFluent, TwoDimensionalCase) {
  replace("fluent_mixed.cas", "(2 3)", "(2 2)");
  EXPECT_NE(error().find("only 3D cases"), std::string::npos) << error();
}

TEST_F(EditedFluent, UnbalancedParentheses) {
  replace("fluent_mixed.cas", "(45 (5 wall walls)())", "(45 (5 wall walls)()");
  EXPECT_NE(error().find("unbalanced"), std::string::npos) << error();
  replace("fluent_mixed.cas", "(0 \"zones\")", "(0 \"zones\"))");
  EXPECT_NE(error(), "accepted");
}

TEST_F(EditedFluent, HangingNodeAdaptionIsRefused) {
  replace("fluent_mixed.cas", "(0 \"zones\")", "(58 (1 2 2 2)(\n2 3 4\n))");
  EXPECT_NE(error().find("hanging-node"), std::string::npos) << error();
}

TEST_F(EditedFluent, DataOutsideItsZone) {
  replace("fluent_mixed.dat", "(300 (1 2 1 0 0 1 56)", "(300 (1 2 1 0 0 2 57)");
  EXPECT_NE(error().find("in cell zone 2"), std::string::npos) << error();
}

// The cell zones asked for alone: the fluid's cells (1..56) and the solid's (57..120) are the
// whole case's pieces, first and last, the same elements at the same places with the same values;
// each zone keeps only its own nodes; a zone the case lacks is one line naming the case's zones.
TEST(Fluent, CellZonesAskedForAreTheWholeCasesPieces) {
  const fs::path cas = kDir / "fluent_mixed.cas";
  FluentFile whole_case(cas), fluid_case(cas, {}, {"fluid"}), solid_case(cas, {}, {"solid"});
  const MeshData whole = whole_case.read_step(0), fluid = fluid_case.read_step(0), solid = solid_case.read_step(0);
  EXPECT_NE(fluid_case.summary().find("2 cell zones (fluid, solid; read: fluid): hex x 8, tet x 48"), std::string::npos)
      << fluid_case.summary();
  ASSERT_EQ(fluid.cell_types.size() + solid.cell_types.size(), whole.cell_types.size());
  EXPECT_LT(fluid.points.size(), whole.points.size());
  EXPECT_LT(solid.points.size(), whole.points.size());
  const auto expect_piece = [&](const MeshData& part, size_t e, size_t w) {
    ASSERT_EQ(part.cell_types[e], whole.cell_types[w]);
    const uint64_t n = part.cell_offsets[e + 1] - part.cell_offsets[e];
    ASSERT_EQ(n, whole.cell_offsets[w + 1] - whole.cell_offsets[w]);
    for (uint64_t k = 0; k < n; ++k)
      EXPECT_EQ(part.points[part.connectivity[part.cell_offsets[e] + k]],
                whole.points[whole.connectivity[whole.cell_offsets[w] + k]])
          << "piece " << e << " corner " << k;
    for (size_t a = 0; a < whole.cell_data.size(); ++a) {
      const MeshArray &x = test::array_named(part.cell_data, whole.cell_data[a].name), &y = whole.cell_data[a];
      for (int c = 0; c < y.components; ++c)
        EXPECT_EQ(x.values[e * size_t(y.components) + size_t(c)], y.values[w * size_t(y.components) + size_t(c)]);
    }
  };
  for (size_t e = 0; e < fluid.cell_types.size(); ++e) expect_piece(fluid, e, e);
  for (size_t e = 0; e < solid.cell_types.size(); ++e) expect_piece(solid, e, fluid.cell_types.size() + e);
  const std::string error = test::input_error_line([&] { FluentFile f(cas, {}, {"fluid", "air"}); });
  EXPECT_NE(error.find("no cell zone 'air' in this case (its cell zones: fluid, solid)"), std::string::npos) << error;
  EXPECT_NO_THROW(open_mesh_files({cas}, {}, {"solid"}));
}

// A zone without a variable (as Fluent writes a conjugate heat transfer case's solid, without
// velocity): the variable is kept, NaN (no data) on that zone's cells, and the summary says so;
// a variable on part of a zone's cells is left out.
TEST_F(EditedFluent, VariableMissingOnAZoneIsNoDataThere) {
  std::string t = test::file_bytes(dir_ / "fluent_mixed.dat");
  const size_t at = t.find("(300 (111 3 1 0 0 57 120)(");
  ASSERT_NE(at, std::string::npos);
  const std::string section = t.substr(at, t.find("))\n", at) + 3 - at);
  t.erase(at, section.size());
  test::write_bytes(dir_ / "fluent_mixed.dat", t);
  FluentFile fluent(dir_ / "fluent_mixed.cas");
  const MeshData m = fluent.read_step(0), whole = FluentFile(kDir / "fluent_mixed.cas").read_step(0);
  ASSERT_EQ(m.cell_data.size(), whole.cell_data.size());
  const MeshArray &v = test::array_named(m.cell_data, "velocity"), &w = test::array_named(whole.cell_data, "velocity");
  // Zone 3 is cells 57..120, the last, and a cell's pieces come in its place: the pieces
  // without x come last.
  size_t first_without = m.cell_types.size();
  while (first_without > 0 && std::isnan(v.values[3 * (first_without - 1)])) --first_without;
  EXPECT_GT(first_without, 0u);
  EXPECT_LT(first_without, m.cell_types.size());
  for (size_t e = 0; e < m.cell_types.size(); ++e) {
    if (e < first_without) {
      EXPECT_EQ(v.values[3 * e], w.values[3 * e]) << e;
    }
    for (size_t k = 1; k < 3; ++k) EXPECT_EQ(v.values[3 * e + k], w.values[3 * e + k]) << e;
  }
  EXPECT_NE(fluent.summary().find("; no data (NaN) for x_velocity in solid"), std::string::npos) << fluent.summary();

  // The section on cells 58..120 alone: part of the zone.
  std::string part = section;
  part.replace(0, std::string("(300 (111 3 1 0 0 57 120)(").size(), "(300 (111 3 1 0 0 58 120)(");
  part.erase(part.find('(', 10) + 1, part.find('\n', part.find('(', 10) + 2) - part.find('(', 10));
  t.insert(at, part);
  test::write_bytes(dir_ / "fluent_mixed.dat", t);
  FluentFile partly(dir_ / "fluent_mixed.cas");
  const MeshData p = partly.read_step(0);
  EXPECT_THROW(test::array_named(p.cell_data, "velocity"), std::runtime_error);
  EXPECT_EQ(test::array_named(p.cell_data, "y_velocity").values.size(), m.cell_types.size());
  EXPECT_NE(partly.summary().find("left out (on part of a cell zone's cells, or on no zone read): x_velocity"),
            std::string::npos)
      << partly.summary();
}

}  // namespace
}  // namespace vs
