// AFLR3 UGRID grids: round trips through every encoding, the committed samples, the pyramid and
// prism vertex order checked geometrically, raw scalars, and bad input.
#include "volstream/io/ugrid.h"

#include <gtest/gtest.h>

#include "mixed_mesh.h"
#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/byte_order.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

struct EncodingCase {
  UgridEncoding encoding;
  const char* suffix;
  bool float32;
};
const EncodingCase kEncodings[] = {{UgridEncoding::ascii, ".ugrid", false},
                                   {UgridEncoding::b8, ".b8.ugrid", false},
                                   {UgridEncoding::lb8, ".lb8.ugrid", false},
                                   {UgridEncoding::lb4, ".lb4.ugrid", true},
                                   {UgridEncoding::b4, ".b4.ugrid", true}};

MeshData mixed_geometry() {
  MeshData m = test::mixed_mesh();
  m.point_data.clear();  // UGRID holds geometry only
  m.cell_data.clear();
  return m;
}

TEST(Ugrid, RoundTripsEveryEncoding) {
  const auto dir = test::scratch_dir("roundtrip");
  const MeshData mesh = mixed_geometry();
  for (const EncodingCase& e : kEncodings) {
    SCOPED_TRACE(e.suffix);
    const fs::path file = dir / (std::string("mixed") + e.suffix);
    write_ugrid(file, mesh, e.encoding);
    const MeshData back = read_ugrid(file);
    test::expect_same_geometry(mesh, back, e.float32);
    EXPECT_TRUE(back.point_data.empty());
  }
}

fs::path data_file(const std::string& name) { return fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/ugrid" / name; }

// Regenerates tests/data/ugrid (run with --gtest_also_run_disabled_tests).
TEST(Ugrid, DISABLED_WriteCommittedFiles) {
  for (const EncodingCase& e : kEncodings)
    write_ugrid(data_file(std::string("mixed") + e.suffix), mixed_geometry(), e.encoding);
}

TEST(Ugrid, CommittedFilesReadWithKnownValues) {
  for (const EncodingCase& e : kEncodings) {
    SCOPED_TRACE(e.suffix);
    const MeshData m = read_ugrid(data_file(std::string("mixed") + e.suffix));
    ASSERT_EQ(m.points.size(), 12u);
    EXPECT_EQ(m.cell_types, (std::vector<uint8_t>{10, 14, 13, 12}));
    EXPECT_EQ(m.points[8].z, e.float32 ? double(2.1f) : 2.1);
    EXPECT_EQ(m.points[11].x, e.float32 ? double(0.1f) : 0.1);
    EXPECT_EQ(m.connectivity[m.cell_offsets[1] + 4], 8u);  // pyramid apex last, as in VTK
    EXPECT_EQ(m.connectivity[m.cell_offsets[2] + 2], 9u);  // wedge
  }
}

// A pyramid and a prism written by hand in UGRID's own order (ugrid.h): pyramid base on nodes
// 1-2-5-4, apex node 3; prism triangle 1-2-3 with 4-5-6 above. Both first faces turn so that their
// right-hand normal points out of the element, as UGRID orders them.
TEST(Ugrid, PyramidAndPrismComeOutInVtkOrder) {
  const auto dir = test::scratch_dir("order");
  test::write_bytes(dir / "order.ugrid",
                    "11 0 0 0 1 1 0\n"
                    "0 0 0\n0 1 0\n0.5 0.5 1\n1 0 0\n1 1 0\n"     // pyramid nodes 1-5
                    "0 0 5\n0 1 5\n1 0 5\n0 0 6\n0 1 6\n1 0 6\n"  // prism nodes 6-11
                    "1 2 3 4 5\n6 7 8 9 10 11\n");
  const MeshData m = read_ugrid(dir / "order.ugrid");
  ASSERT_EQ(m.cell_types, (std::vector<uint8_t>{14, 13}));
  const auto p = [&](uint64_t cell, int v) { return m.points[m.connectivity[m.cell_offsets[cell] + uint64_t(v)]]; };

  // VTK pyramid: apex is vertex 4; base 0-1-2-3 with its normal towards the apex, so both tets
  // of the base split have positive volume.
  EXPECT_EQ(p(0, 4), vec3d(0.5, 0.5, 1));
  EXPECT_GT(test::tet_volume6(p(0, 0), p(0, 1), p(0, 2), p(0, 4)), 0);
  EXPECT_GT(test::tet_volume6(p(0, 0), p(0, 2), p(0, 3), p(0, 4)), 0);

  // VTK wedge: triangles 0-1-2 (z = 5) and 3-4-5 (z = 6), vertex i+3 above vertex i, and the
  // normal of 0-1-2 pointing away from 3-4-5 (VTK's wedge orientation).
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(p(1, v).z, 5);
    EXPECT_EQ(p(1, v + 3), p(1, v) + vec3d(0, 0, 1));
  }
  EXPECT_LT(test::tet_volume6(p(1, 0), p(1, 1), p(1, 2), p(1, 3)), 0);
}

// What we write in UGRID order reads back as the same VTK cells; and the mixed mesh's pyramid
// (positive in VTK) is stored with its apex as UGRID node 3.
TEST(Ugrid, WriterStoresPyramidsInUgridOrder) {
  const auto dir = test::scratch_dir("writer");
  write_ugrid(dir / "m.ugrid", mixed_geometry(), UgridEncoding::ascii);
  const std::string text = test::file_bytes(dir / "m.ugrid");
  // Lines: header, 12 points, tet, pyramid. VTK pyramid 4 5 6 7 | 8 is UGRID (1-based) 6 5 9 7 8.
  size_t line_start = 0;
  for (int i = 0; i < 14; ++i) line_start = text.find('\n', line_start) + 1;
  EXPECT_EQ(text.substr(line_start, text.find('\n', line_start) - line_start), "6 5 9 7 8");
}

TEST(Ugrid, RawScalarsAttachToPoints) {
  const auto dir = test::scratch_dir("raw");
  MeshData m = mixed_geometry();
  std::string bytes;
  for (size_t i = 0; i < m.points.size(); ++i) append_value(bytes, float(i) * 0.5f - 1.0f, false);
  test::write_bytes(dir / "t.raw", bytes);
  attach_raw_scalars(m, "t", dir / "t.raw");
  ASSERT_EQ(m.point_data.size(), 1u);
  EXPECT_EQ(m.point_data[0].name, "t");
  EXPECT_EQ(m.point_data[0].values[3], 0.5);
  check_mesh(m, "t");

  test::write_bytes(dir / "short.raw", bytes.substr(4));
  try {
    attach_raw_scalars(m, "t", dir / "short.raw");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "short.raw").string());
    EXPECT_NE(std::string(e.what()).find("size 44 bytes, expected 48"), std::string::npos) << e.what();
  }
}

std::string error_of(const std::string& content, const fs::path& file) {
  test::write_bytes(file, content);
  try {
    read_ugrid(file);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << file;
  return "";
}

const std::string kOneTet = "4 0 0 1 0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 2 3 4\n";

TEST(Ugrid, BadInputIsAnInputError) {
  const auto dir = test::scratch_dir("bad");
  const fs::path f = dir / "bad.ugrid";
  test::write_bytes(f, kOneTet);
  EXPECT_EQ(read_ugrid(f).cell_count(), 1u);
  EXPECT_NE(error_of("4 0 0 1 0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 2 3 4\n", f).find("node index 0"),
            std::string::npos);
  EXPECT_NE(error_of("4 0 0 1 0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 2 3 5\n", f).find("out of range 1..4"),
            std::string::npos);
  EXPECT_NE(error_of("4 0 0 1 0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 2 -3 4\n", f).find("-3"), std::string::npos);
  EXPECT_NE(error_of("4 0 0 1 0 0 0\n0 0 0\n1 0 zero\n0 1 0\n0 0 1\n1 2 3 4\n", f).find("'zero'"), std::string::npos);
  EXPECT_NE(error_of(kOneTet.substr(0, kOneTet.size() - 3), f).find("end of file"), std::string::npos);
  EXPECT_NE(error_of("2000000000 0 0 1 0 0 0\n0 0 0\n", f).find("cannot fit"), std::string::npos);
  EXPECT_NE(error_of("4 0 0 -1 0 0 0\n", f).find("bad tet count"), std::string::npos);
  EXPECT_NE(error_of("4 0 0 0 0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n", f).find("no cells"), std::string::npos);
  EXPECT_NE(error_of(kOneTet, dir / "bad.r8.ugrid").find("not supported"), std::string::npos);
  EXPECT_NE(error_of(kOneTet, dir / "bad.grid").find("not a UGRID file name"), std::string::npos);
}

TEST(Ugrid, TruncatedOrPaddedBinaryFiles) {
  const auto dir = test::scratch_dir("binary");
  write_ugrid(dir / "m.b8.ugrid", mixed_geometry(), UgridEncoding::b8);
  const std::string full = test::file_bytes(dir / "m.b8.ugrid");
  for (size_t cut : {size_t(0), size_t(10), size_t(28), full.size() / 2, full.size() - 1}) {
    SCOPED_TRACE(cut);
    error_of(full.substr(0, cut), dir / "cut.b8.ugrid");
  }
  // Trailing optional records (AFLR's BL data) are ignored.
  test::write_bytes(dir / "padded.b8.ugrid", full + std::string(64, '\0'));
  EXPECT_EQ(read_ugrid(dir / "padded.b8.ugrid").cell_count(), 4u);
  // Read as little endian, the counts are absurd: refused before allocating.
  test::write_bytes(dir / "swapped.lb8.ugrid", full);
  EXPECT_FALSE(error_of(full, dir / "swapped.lb8.ugrid").empty());
}

}  // namespace
}  // namespace vs
