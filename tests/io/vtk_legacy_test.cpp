// Legacy VTK unstructured grids: round trips through every writer option, the committed sample
// files, hand-written files (METADATA, dataset FIELD, SCALARS without LOOKUP_TABLE) and bad input.
#include "volstream/io/vtk_legacy.h"

#include <gtest/gtest.h>

#include "mixed_mesh.h"
#include "test_util.h"
#include "volstream/core/error.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

std::string option_name(const VtkLegacyWriteOptions& o) {
  return std::string(o.binary ? "binary" : "ascii") + (o.version51 ? "_51" : "_42") +
         (o.points_float64 ? "_f64" : "_f32");
}

std::vector<VtkLegacyWriteOptions> all_options() {
  std::vector<VtkLegacyWriteOptions> out;
  for (bool binary : {false, true})
    for (bool v51 : {false, true})
      for (bool f64 : {false, true}) out.push_back({binary, v51, f64});
  return out;
}

TEST(VtkLegacy, RoundTripsEveryWriterOption) {
  const auto dir = test::scratch_dir("roundtrip");
  const MeshData mesh = test::mixed_mesh();
  for (const VtkLegacyWriteOptions& o : all_options()) {
    SCOPED_TRACE(option_name(o));
    const fs::path file = dir / (option_name(o) + ".vtk");
    write_vtk_legacy(file, mesh, o);
    const MeshData back = read_vtk_legacy(file);
    test::expect_same_geometry(mesh, back, !o.points_float64);
    test::expect_same_arrays(mesh.point_data, back.point_data);
    test::expect_same_arrays(mesh.cell_data, back.cell_data);
  }
}

fs::path data_file(const std::string& name) { return fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/vtk" / name; }
const char* kCommitted[] = {"mixed_ascii_42.vtk", "mixed_ascii_51.vtk", "mixed_binary_42.vtk", "mixed_binary_51.vtk"};

// Regenerates tests/data/vtk (run with --gtest_also_run_disabled_tests).
TEST(VtkLegacy, DISABLED_WriteCommittedFiles) {
  const MeshData mesh = test::mixed_mesh();
  for (int i = 0; i < 4; ++i) write_vtk_legacy(data_file(kCommitted[i]), mesh, {i >= 2, i % 2 == 1, false});
}

TEST(VtkLegacy, CommittedFilesReadWithKnownValues) {
  for (const char* name : kCommitted) {
    SCOPED_TRACE(name);
    const MeshData m = read_vtk_legacy(data_file(name));
    ASSERT_EQ(m.points.size(), 12u);
    ASSERT_EQ(m.cell_count(), 4u);
    EXPECT_EQ(m.cell_types, (std::vector<uint8_t>{10, 14, 13, 12}));
    EXPECT_EQ(m.points[8].z, double(2.1f));
    EXPECT_EQ(m.connectivity[m.cell_offsets[1] + 4], 8u);  // the pyramid's apex
    ASSERT_EQ(m.point_data.size(), 3u);
    EXPECT_EQ(m.point_data[0].name, "temperature");
    EXPECT_EQ(m.point_data[0].values[3], 301.0);
    EXPECT_EQ(m.point_data[1].components, 3);
    EXPECT_EQ(m.point_data[1].values[3 * 4 + 1], -0.2);
    EXPECT_EQ(m.point_data[2].name, "uv");
    ASSERT_EQ(m.cell_data.size(), 1u);
    EXPECT_EQ(m.cell_data[0].values[2], 1e5);
  }
}

// What VTK itself writes: METADATA after arrays, dataset-level FIELD, SCALARS with a component
// count and without LOOKUP_TABLE, blank lines, lower-case keywords.
TEST(VtkLegacy, ReadsHandWrittenAscii) {
  const auto dir = test::scratch_dir("hand");
  test::write_bytes(
      dir / "t.vtk",
      "# vtk DataFile Version 5.1\nhand written\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "FIELD FieldData 1\nTIME 1 1 double\n2.5\n"
      "POINTS 4 float\n0 0 0 1 0 0 0 1 0\n0 0 1\n"
      "METADATA\nINFORMATION 2\nNAME L2_NORM_RANGE LOCATION vtkDataArray\nDATA 2 0 1\n"
      "NAME L2_NORM_FINITE_RANGE LOCATION vtkDataArray\nDATA 2 0 1\n\n"
      "CELLS 2 4\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2 3\n"
      "cell_types 1\n10\n\n"
      "POINT_DATA 4\nSCALARS pair float 2\n1 2 3 4 5 6 7 8\n"
      "FIELD FieldData 3\nids 1 4 int\n9 8 7 6\nMETADATA\nINFORMATION 0\n\nNULL_ARRAY\nvel 3 4 double\n0 0 0 1 1 1 2 "
      "2 2 3 3 3\n"
      "CELL_DATA 1\nSCALARS c int\nLOOKUP_TABLE default\n42\n");
  const MeshData m = read_vtk_legacy(dir / "t.vtk");
  ASSERT_EQ(m.point_data.size(), 3u);
  EXPECT_EQ(m.point_data[0].components, 2);
  EXPECT_EQ(m.point_data[0].values[7], 8.0);
  EXPECT_EQ(m.point_data[1].name, "ids");
  EXPECT_EQ(m.point_data[2].values[11], 3.0);
  ASSERT_EQ(m.cell_data.size(), 1u);
  EXPECT_EQ(m.cell_data[0].values[0], 42.0);
}

const std::string kGoodAscii42 =
    "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
    "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n";

std::string error_of(const std::string& content, const fs::path& file) {
  test::write_bytes(file, content);
  try {
    read_vtk_legacy(file);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << content;
  return "";
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

TEST(VtkLegacy, BadInputIsAnInputError) {
  const auto dir = test::scratch_dir("bad");
  const fs::path f = dir / "bad.vtk";
  test::write_bytes(f, kGoodAscii42);
  EXPECT_EQ(read_vtk_legacy(f).cell_count(), 1u);  // the base case is fine

  EXPECT_NE(error_of(kGoodAscii42.substr(0, kGoodAscii42.size() - 3), f).find("cell types"), std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "4 0 1 2 3", "4 0 1 2 9"), f).find("out of range"), std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "4 0 1 2 3", "4 0 1 2 -3"), f).find("negative"), std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "0 0 1\n", "0 0 x1\n"), f).find("'x1'"), std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "CELL_TYPES", "CELL_TYPOS"), f).find("unknown keyword"), std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "POINTS 4", "POINTS 99999999999999"), f).find("cannot fit"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "CELLS 1 5", "CELLS 1 6"), f).find("CELL_TYPES"), std::string::npos);
  EXPECT_NE(error_of(replaced(kGoodAscii42, "UNSTRUCTURED_GRID", "POLYDATA"), f).find("POLYDATA"), std::string::npos);
  EXPECT_NE(error_of("not vtk\n", f).find("not a legacy VTK file"), std::string::npos);
  EXPECT_NE(error_of(kGoodAscii42 + "POINT_DATA 3\n", f).find("POINT_DATA 3, expected 4"), std::string::npos);
}

TEST(VtkLegacy, TrianglesAreRefusedWithTypeAndCount) {
  const auto dir = test::scratch_dir("tri");
  const std::string tris =
      "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
      "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 2 8\n3 0 1 2\n3 0 1 3\nCELL_TYPES 2\n5 5\n";
  EXPECT_NE(error_of(tris, dir / "tri.vtk").find("unsupported cell type 5 (triangle) in 2 cells"), std::string::npos);
}

TEST(VtkLegacy, TruncatedBinaryFilesAreInputErrors) {
  const auto dir = test::scratch_dir("trunc");
  for (bool v51 : {false, true}) {
    write_vtk_legacy(dir / "m.vtk", test::mixed_mesh(), {true, v51, true});
    const std::string full = test::file_bytes(dir / "m.vtk");
    for (size_t cut : {size_t(120), full.size() / 2, full.size() - 9}) {
      SCOPED_TRACE(cut);
      error_of(full.substr(0, cut), dir / "cut.vtk");
    }
  }
}

TEST(VtkLegacy, WriterRefusesNamesWithWhitespace) {
  MeshData m = test::mixed_mesh();
  m.point_data[0].name = "two words";
  EXPECT_THROW(write_vtk_legacy(test::scratch_dir("names") / "m.vtk", m), UsageError);
}

}  // namespace
}  // namespace vs
