// VTK XML unstructured grids and ParaView collections: round trips through write_vtu in every
// encoding, the committed files of tests/data/vtu, and bad input.
#include "volstream/io/vtu.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <tuple>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/vtk_legacy.h"
#include "volstream/umesh/mesh_pieces.h"

namespace vs {
namespace {
namespace fs = std::filesystem;
using Format = VtuWriteOptions::Format;

const fs::path kDataDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "vtu";

// A hex, a wedge, a pyramid and two tets on 13 points (coordinates not exact in float32), with a
// point scalar, a 3-component point vector and a cell scalar.
MeshData mixed_mesh() {
  MeshData m;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) m.points.push_back(vec3d(0.1 * i, 0.3 * j - 1.0 / 3.0, 0.7 * k + 1e-9));
  m.points.push_back(vec3d(0.1, 0.15, 1.2));  // 12: a pyramid apex
  auto add = [&](CellType type, std::vector<uint64_t> v) {
    m.cell_types.push_back(uint8_t(type));
    m.connectivity.insert(m.connectivity.end(), v.begin(), v.end());
    m.cell_offsets.push_back(m.connectivity.size());
  };
  m.cell_offsets = {0};
  add(CellType::hex, {0, 1, 4, 3, 6, 7, 10, 9});
  add(CellType::wedge, {1, 2, 4, 7, 8, 10});
  add(CellType::pyramid, {6, 7, 10, 9, 12});
  add(CellType::tet, {2, 5, 4, 11});
  add(CellType::tet, {7, 8, 11, 12});
  MeshArray scalar{"temperature", 1, {}}, vector{"velocity <m/s>", 3, {}}, cell{"rank & id", 1, {}};
  for (size_t i = 0; i < m.points.size(); ++i) {
    scalar.values.push_back(300.0 + 0.1 * double(i));
    for (int c = 0; c < 3; ++c) vector.values.push_back(double(i) / 3.0 - c);
  }
  for (size_t i = 0; i < m.cell_count(); ++i) cell.values.push_back(double(i) * 1.1);
  m.point_data = {scalar, vector};
  m.cell_data = {cell};
  return m;
}

double as_float(double v) { return double(float(v)); }

void expect_arrays(const std::vector<MeshArray>& got, const std::vector<MeshArray>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t a = 0; a < want.size(); ++a) {
    EXPECT_EQ(got[a].name, want[a].name);
    EXPECT_EQ(got[a].components, want[a].components);
    ASSERT_EQ(got[a].values.size(), want[a].values.size());
    for (size_t i = 0; i < want[a].values.size(); ++i) EXPECT_EQ(got[a].values[i], as_float(want[a].values[i]));
  }
}

// Exact equality, up to the float32 rounding of what was written as Float32.
void expect_same_mesh(const MeshData& got, const MeshData& want, bool points_float64) {
  ASSERT_EQ(got.points.size(), want.points.size());
  for (size_t i = 0; i < want.points.size(); ++i)
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(got.points[i][a], points_float64 ? want.points[i][a] : as_float(want.points[i][a])) << i;
  EXPECT_EQ(got.cell_types, want.cell_types);
  EXPECT_EQ(got.cell_offsets, want.cell_offsets);
  EXPECT_EQ(got.connectivity, want.connectivity);
  expect_arrays(got.point_data, want.point_data);
  expect_arrays(got.cell_data, want.cell_data);
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void write_file(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

// The file written with `options`, then `edit`ed as text.
fs::path edited_file(const std::string& test, const MeshData& mesh, const VtuWriteOptions& options,
                     const std::function<void(std::string&)>& edit) {
  const fs::path file = test::scratch_dir(test) / "mesh.vtu";
  write_vtu(file, mesh, options);
  std::string text = read_file(file);
  edit(text);
  write_file(file, text);
  return file;
}

void replace_once(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

// The InputError message of read_vtu(file), or "" when it reads.
std::string vtu_error(const fs::path& file) {
  try {
    read_vtu(file);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    return e.what();
  }
  return "";
}

const char* compressor_name(VtuCompressor c) {
  switch (c) {
    case VtuCompressor::none:
      return "";
    case VtuCompressor::zlib:
      return " zlib";
    case VtuCompressor::lz4:
      return " LZ4";
    case VtuCompressor::lzma:
      return " LZMA";
  }
  return "?";
}
constexpr VtuCompressor kCompressors[] = {VtuCompressor::none, VtuCompressor::zlib, VtuCompressor::lz4,
                                          VtuCompressor::lzma};

const char* format_name(Format f) {
  switch (f) {
    case Format::ascii:
      return "ascii";
    case Format::base64:
      return "base64";
    case Format::appended_base64:
      return "appended_base64";
    case Format::appended_raw:
      return "appended_raw";
  }
  return "?";
}

TEST(Vtu, RoundTripsEveryEncoding) {
  const MeshData mesh = mixed_mesh();
  const fs::path dir = test::scratch_dir("vtu_round_trip");
  int files = 0;
  for (Format format : {Format::ascii, Format::base64, Format::appended_base64, Format::appended_raw})
    for (VtuCompressor compressor : kCompressors)
      for (bool header64 : {false, true})
        for (bool points64 : {false, true})
          for (bool indices64 : {false, true}) {
            VtuWriteOptions o;
            o.format = format;
            o.compressor = compressor;
            o.header_uint64 = header64;
            o.points_float64 = points64;
            o.indices_int64 = indices64;
            o.block_size = 40;  // several blocks per array, a partial last one
            std::ostringstream trace;
            trace << format_name(format) << compressor_name(compressor) << (header64 ? " UInt64" : " UInt32")
                  << (points64 ? " Float64" : " Float32") << (indices64 ? " Int64" : " Int32");
            SCOPED_TRACE(trace.str());
            const fs::path file = dir / (std::to_string(files++) + ".vtu");
            write_vtu(file, mesh, o);
            expect_same_mesh(read_vtu(file), mesh, points64);
          }
}

TEST(Vtu, BlockSizeDividingTheData) {
  const MeshData mesh = mixed_mesh();
  for (VtuCompressor compressor : kCompressors) {
    SCOPED_TRACE(compressor_name(compressor));
    VtuWriteOptions o;
    o.compressor = compressor;
    o.block_size = 8;  // every array is a whole number of blocks: the last-block size is 0
    const fs::path file = test::scratch_dir("vtu_block_size") / "m.vtu";
    write_vtu(file, mesh, o);
    expect_same_mesh(read_vtu(file), mesh, false);
  }
}

// Run with --gtest_also_run_disabled_tests to regenerate tests/data/vtu after a writer change.
TEST(Vtu, DISABLED_WriteDataFiles) {
  using C = VtuCompressor;
  struct File {
    const char* name;
    Format format;
    VtuCompressor compressor;
    bool header64;
  };
  for (const File& f : {File{"ascii", Format::ascii, C::none, true}, File{"base64", Format::base64, C::none, true},
                        File{"base64_zlib", Format::base64, C::zlib, true},
                        File{"appended_base64", Format::appended_base64, C::none, true},
                        File{"appended_raw", Format::appended_raw, C::none, true},
                        File{"appended_raw_zlib", Format::appended_raw, C::zlib, true},
                        File{"uint32_header", Format::appended_base64, C::zlib, false},
                        File{"appended_raw_lz4", Format::appended_raw, C::lz4, true},
                        File{"base64_lzma", Format::base64, C::lzma, true}}) {
    VtuWriteOptions o;
    o.format = f.format;
    o.compressor = f.compressor;
    o.header_uint64 = f.header64;
    o.points_float64 = !f.header64;  // the UInt32 file also has Float64 points and Int32 indices
    o.indices_int64 = f.header64;
    o.block_size = 64;
    write_vtu(kDataDir / (std::string(f.name) + ".vtu"), mixed_mesh(), o);
  }
  write_pvd(kDataDir / "series.pvd", {{0.5, {kDataDir / "ascii.vtu"}}, {1.5, {kDataDir / "appended_raw.vtu"}}});
}

TEST(Vtu, ReadsCommittedFiles) {
  for (const char* name : {"ascii", "base64", "base64_zlib", "appended_base64", "appended_raw", "appended_raw_zlib",
                           "uint32_header", "appended_raw_lz4", "base64_lzma"}) {
    SCOPED_TRACE(name);
    const MeshData m = read_vtu(kDataDir / (std::string(name) + ".vtu"));
    ASSERT_EQ(m.points.size(), 13u);
    ASSERT_EQ(m.cell_count(), 5u);
    EXPECT_EQ(m.cell_types, (std::vector<uint8_t>{12, 13, 14, 10, 10}));
    EXPECT_EQ(m.cell_offsets, (std::vector<uint64_t>{0, 8, 14, 19, 23, 27}));
    EXPECT_EQ(m.connectivity[8], 1u);
    EXPECT_EQ(m.connectivity[26], 12u);
    const bool float64 = std::string(name) == "uint32_header";
    EXPECT_EQ(m.points[12].z, float64 ? 1.2 : as_float(1.2));
    EXPECT_EQ(m.points[2].y, float64 ? -1.0 / 3.0 : as_float(-1.0 / 3.0));
    ASSERT_EQ(m.point_data.size(), 2u);
    EXPECT_EQ(m.point_data[0].name, "temperature");
    EXPECT_EQ(m.point_data[0].values[3], as_float(300.3));
    EXPECT_EQ(m.point_data[1].name, "velocity <m/s>");
    EXPECT_EQ(m.point_data[1].components, 3);
    EXPECT_EQ(m.point_data[1].values[3 * 7 + 2], as_float(7.0 / 3.0 - 2));
    ASSERT_EQ(m.cell_data.size(), 1u);
    EXPECT_EQ(m.cell_data[0].name, "rank & id");
    EXPECT_EQ(m.cell_data[0].values[4], as_float(4.4));
  }
}

// Two <Piece>s of the mesh, the second moved up by 2 in z and with a String array: no point is
// shared, so the second piece's points and cells follow the first's.
TEST(Vtu, ConcatenatesPiecesAndSkipsStringArrays) {
  const fs::path file = edited_file("vtu_pieces", mixed_mesh(), {.format = Format::ascii}, [](std::string& text) {
    const size_t begin = text.find("    <Piece"), end = text.find("    </Piece>\n") + 13;
    std::string piece = text.substr(begin, end - begin);
    replace_once(piece, "<PointData>",
                 "<PointData>\n<DataArray type=\"String\" Name=\"label\" format=\"ascii\">97 0</DataArray>");
    const size_t points = piece.find('>', piece.find("Name=\"Points\"")) + 1;
    const size_t points_end = piece.find("</DataArray>", points);
    std::istringstream in(piece.substr(points, points_end - points));
    std::string moved = "\n";
    double x, y, z;
    while (in >> x >> y >> z) moved += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z + 2) + "\n";
    piece.replace(points, points_end - points, moved);
    text.insert(end, piece);
  });
  const MeshData m = read_vtu(file);
  ASSERT_EQ(m.points.size(), 26u);
  ASSERT_EQ(m.cell_count(), 10u);
  EXPECT_EQ(m.connectivity[27], 13u);  // the second piece's first hex vertex, 0 + 13 points
  EXPECT_EQ(m.cell_offsets.back(), 54u);
  EXPECT_EQ(m.point_data[0].values.size(), 26u);
  EXPECT_EQ(m.cell_data[0].values.size(), 10u);
}

// The same piece twice: every point of the second is one of the first's (join_pieces welds
// them, tests/umesh/mesh_pieces_test.cpp), the cells are both pieces'.
TEST(Vtu, PiecesShareTheirCommonPoints) {
  const fs::path file = edited_file("vtu_shared", mixed_mesh(), {.format = Format::base64}, [](std::string& text) {
    const size_t begin = text.find("    <Piece"), end = text.find("    </Piece>\n") + 13;
    text.insert(end, text.substr(begin, end - begin));
  });
  const MeshData m = read_vtu(file);
  EXPECT_EQ(m.points.size(), 13u);
  ASSERT_EQ(m.cell_count(), 10u);
  EXPECT_EQ(std::vector<uint64_t>(m.connectivity.begin() + 27, m.connectivity.end()),
            std::vector<uint64_t>(m.connectivity.begin(), m.connectivity.begin() + 27));
}

// A series' second step on the same polyhedra, with other values (the file's fields f and g
// swapped), split with the first step's memo, reads as it does alone; so does the first step
// again through a .vtm naming it.
TEST(Vtu, SeriesStepsOnOneMeshSplitAsTheFirstDid) {
  const fs::path dir = test::scratch_dir("vtu_series");
  const fs::path first = kDataDir / "vtk_polyhedra.vtu", second = dir / "swapped.vtu", vtm = dir / "first.vtm";
  std::string text = read_file(first);
  for (auto [from, to] :
       {std::pair{"Name=\"f\"", "Name=\"t\""}, {"Name=\"g\"", "Name=\"f\""}, {"Name=\"t\"", "Name=\"g\""}})
    text.replace(text.find(from), std::strlen(from), to);
  write_file(second, text);
  std::ofstream(vtm) << "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet>"
                     << "<DataSet index=\"0\" file=\"" << first.string() << "\"/></vtkMultiBlockDataSet></VTKFile>\n";
  SeriesSplits splits;
  const MeshData step0 = read_vtu(first, &splits), step1 = read_vtu(second, &splits), again = read_vtm(vtm, &splits);
  const MeshData alone = read_vtu(second);
  for (const MeshData* m : {&step1, &again}) {
    EXPECT_EQ(m->points, alone.points);
    EXPECT_EQ(m->connectivity, alone.connectivity);
    EXPECT_EQ(m->cell_types, alone.cell_types);
  }
  EXPECT_EQ(test::array_named(step1.point_data, "f").values, test::array_named(alone.point_data, "f").values);
  EXPECT_EQ(test::array_named(step1.point_data, "f").values, test::array_named(step0.point_data, "g").values);
  EXPECT_EQ(test::array_named(again.point_data, "f").values, test::array_named(step0.point_data, "f").values);
  EXPECT_EQ(test::array_named(step1.cell_data, "cell_id").values, test::array_named(alone.cell_data, "cell_id").values);
}

// A hand-made BigEndian file: one tet, Float64 points, Int32 cells, raw appended data.
TEST(Vtu, ReadsBigEndian) {
  std::string data;
  auto put = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    for (size_t i = sizeof(v); i-- > 0;) data += b[i];
  };
  put(uint32_t(96));
  for (double v : {0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 2.5}) put(v);
  put(uint32_t(16));
  for (int32_t v : {0, 1, 2, 3}) put(v);
  put(uint32_t(4));
  put(int32_t(4));
  put(uint32_t(1));
  data += char(10);
  const std::string text =
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"BigEndian\"><UnstructuredGrid>"
      "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points>"
      "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points><Cells>"
      "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\"100\"/>"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\"120\"/>"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"128\"/>"
      "</Cells></Piece></UnstructuredGrid><AppendedData encoding=\"raw\">_" +
      data + "</AppendedData></VTKFile>";
  const fs::path file = test::scratch_dir("vtu_big_endian") / "be.vtu";
  write_file(file, text);
  const MeshData m = read_vtu(file);
  EXPECT_EQ(m.points[3].z, 2.5);
  EXPECT_EQ(m.connectivity, (std::vector<uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(m.cell_types, (std::vector<uint8_t>{10}));
}

TEST(Vtu, TruncatedFiles) {
  for (Format format : {Format::ascii, Format::base64, Format::appended_raw}) {
    SCOPED_TRACE(format_name(format));
    const fs::path file = edited_file("vtu_truncated", mixed_mesh(), {.format = format},
                                      [](std::string& text) { text.resize(text.size() * 2 / 3); });
    EXPECT_NE(vtu_error(file), "");
  }
}

TEST(Vtu, CorruptBase64) {
  const fs::path file = edited_file("vtu_bad_base64", mixed_mesh(), {.format = Format::base64}, [](std::string& text) {
    const size_t at = text.find("format=\"binary\">", text.find("Name=\"Points\"")) + 30;
    text[at] = '*';
  });
  EXPECT_NE(vtu_error(file).find("bad base64"), std::string::npos) << vtu_error(file);
}

TEST(Vtu, CorruptCompressedBlocks) {
  for (VtuCompressor compressor : {VtuCompressor::zlib, VtuCompressor::lz4, VtuCompressor::lzma}) {
    const std::string name = compressor_name(compressor);
    SCOPED_TRACE(name);
    const VtuWriteOptions o{.format = Format::appended_raw, .compressor = compressor};
    const fs::path file = edited_file("vtu_bad_blocks", mixed_mesh(), o, [](std::string& text) {
      const size_t data = text.find('_', text.find("<AppendedData")) + 1;
      // The first block's first bytes, after the UInt64 header's four words. (Its literal bytes
      // further on would not do for LZ4: a block has no checksum, so they decode to other values.)
      for (size_t i = 32; i < 40; ++i) text[data + i] = char(0xA5);
    });
    EXPECT_NE(vtu_error(file).find("corrupt" + name + " data"), std::string::npos) << vtu_error(file);
  }
}

TEST(Vtu, ConnectivityOutOfRange) {
  MeshData mesh = mixed_mesh();
  mesh.connectivity[5] = 13;
  const fs::path file = edited_file("vtu_index", mesh, {}, [](std::string&) {});
  EXPECT_NE(vtu_error(file).find("out of range"), std::string::npos) << vtu_error(file);
}

TEST(Vtu, UnsupportedCellType) {
  MeshData mesh = mixed_mesh();
  mesh.cell_types = {12, 13, 14, 5, 5};
  mesh.cell_offsets = {0, 8, 14, 19, 22, 25};
  mesh.connectivity.resize(25);
  const fs::path file = edited_file("vtu_triangles", mesh, {}, [](std::string&) {});
  EXPECT_NE(vtu_error(file).find("unsupported cell type 5 (triangle) in 2 cells"), std::string::npos)
      << vtu_error(file);
}

TEST(Vtu, NumberOfPointsMismatch) {
  for (Format format : {Format::ascii, Format::base64, Format::appended_raw}) {
    SCOPED_TRACE(format_name(format));
    const fs::path file = edited_file("vtu_points", mixed_mesh(), {.format = format}, [](std::string& text) {
      replace_once(text, "NumberOfPoints=\"13\"", "NumberOfPoints=\"14\"");
    });
    EXPECT_NE(vtu_error(file).find("Points"), std::string::npos) << vtu_error(file);
  }
}

TEST(Vtu, AbsurdSizesAreRefusedBeforeAllocating) {
  for (const char* count : {"1000000000000", "99999999999999999999", "-1"}) {
    SCOPED_TRACE(count);
    const VtuWriteOptions zlib{.compressor = VtuCompressor::zlib};
    const fs::path file = edited_file("vtu_absurd", mixed_mesh(), zlib, [&](std::string& text) {
      replace_once(text, "NumberOfPoints=\"13\"", std::string("NumberOfPoints=\"") + count + "\"");
    });
    EXPECT_NE(vtu_error(file), "");
  }
  // A compression header of the Points claiming 2^36 * 12 bytes in one block of a few bytes.
  for (VtuCompressor compressor : {VtuCompressor::zlib, VtuCompressor::lz4, VtuCompressor::lzma}) {
    SCOPED_TRACE(compressor_name(compressor));
    const VtuWriteOptions o{.format = Format::appended_raw, .compressor = compressor};
    const fs::path file = edited_file("vtu_absurd_blocks", mixed_mesh(), o, [](std::string& text) {
      replace_once(text, "NumberOfPoints=\"13\"", "NumberOfPoints=\"68719476736\"");
      const size_t offset_at = text.find("offset=\"", text.find("Name=\"Points\"")) + 8;
      const size_t data = text.find('_', text.find("<AppendedData")) + 1 + std::stoull(text.substr(offset_at, 20));
      const uint64_t block = (uint64_t(1) << 36) * 12, last = 0;
      std::memcpy(text.data() + data + 8, &block, 8);
      std::memcpy(text.data() + data + 16, &last, 8);
    });
    EXPECT_NE(vtu_error(file).find("cannot hold"), std::string::npos) << vtu_error(file);
  }
}

TEST(Vtu, NegativeOffsetsAndMissingArrays) {
  const VtuWriteOptions ascii{.format = Format::ascii};
  const fs::path negative = edited_file("vtu_negative", mixed_mesh(), ascii, [](std::string& text) {
    const size_t at = text.find("Name=\"offsets\"");
    replace_once(text, text.substr(text.find('>', at) + 1, text.find("</DataArray>", at) - text.find('>', at) - 1),
                 "\n8 14 -19 23 27\n");
  });
  EXPECT_NE(vtu_error(negative).find("negative value -19"), std::string::npos) << vtu_error(negative);
  const fs::path missing = edited_file("vtu_missing", mixed_mesh(), ascii,
                                       [](std::string& text) { replace_once(text, "\"connectivity\"", "\"conn\""); });
  EXPECT_NE(vtu_error(missing).find("no DataArray named connectivity"), std::string::npos) << vtu_error(missing);
}

TEST(Vtu, NotAVtuFile) {
  const fs::path dir = test::scratch_dir("vtu_not_vtu");
  write_file(dir / "empty.vtu", "");
  write_file(dir / "text.vtu", "hello");
  write_file(dir / "image.vtu", "<VTKFile type=\"ImageData\"><ImageData/></VTKFile>");
  write_file(dir / "zstd.vtu", "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZstdDataCompressor\"/>");
  for (const char* name : {"empty.vtu", "text.vtu", "image.vtu", "zstd.vtu", "absent.vtu"})
    EXPECT_NE(vtu_error(dir / name), "") << name;
  EXPECT_NE(vtu_error(dir / "zstd.vtu").find("unsupported compressor vtkZstdDataCompressor"), std::string::npos);
}

// Entities in attribute values: unknown, empty (found by vtu_fuzz: "&;" threw out_of_range) and
// character references without digits are one InputError line each.
TEST(Vtu, BadEntitiesInAttributes) {
  const fs::path dir = test::scratch_dir("vtu_entities");
  for (const char* entity : {"&;", "&#;", "&#x;", "&bogus;", "&#0;"}) {
    write_file(dir / "e.vtu", std::string("<VTKFile type=\"UnstructuredGrid") + entity + "\"/>");
    EXPECT_NE(vtu_error(dir / "e.vtu"), "") << entity;
  }
}

TEST(Pvd, RoundTrip) {
  const fs::path dir = test::scratch_dir("pvd_round_trip");
  fs::create_directories(dir / "steps");
  const std::vector<PvdStep> steps{{2.5, {dir / "steps" / "b.vtu", dir / "steps" / "c.vtu"}},
                                   {0.1, {dir / "steps" / "a&b.vtu"}}};
  write_pvd(dir / "series.pvd", steps);
  EXPECT_NE(read_file(dir / "series.pvd").find("file=\"steps/a&amp;b.vtu\""), std::string::npos);
  const std::vector<PvdStep> got = read_pvd(dir / "series.pvd");
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].time, 0.1);
  EXPECT_EQ(got[0].parts, std::vector<fs::path>{dir / "steps" / "a&b.vtu"});
  EXPECT_EQ(got[1].time, 2.5);
  EXPECT_EQ(got[1].parts, (std::vector<fs::path>{dir / "steps" / "b.vtu", dir / "steps" / "c.vtu"}));
  EXPECT_NE(read_file(dir / "series.pvd").find("part=\"1\" file=\"steps/c.vtu\""), std::string::npos);
}

TEST(Pvd, ReadsCommittedSeries) {
  const std::vector<PvdStep> steps = read_pvd(kDataDir / "series.pvd");
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[1].time, 1.5);
  EXPECT_EQ(read_vtu(steps[1].parts.at(0)).cell_count(), 5u);
}

TEST(Pvd, BadCollections) {
  const fs::path dir = test::scratch_dir("pvd_bad");
  const std::string head = "<VTKFile type=\"Collection\"><Collection>";
  const std::string tail = "</Collection></VTKFile>";
  const std::pair<const char*, std::string> cases[] = {
      {"no entries", head + tail},
      {"no timestep", head + "<DataSet file=\"a.vtu\"/>" + tail},
      {"no file", head + "<DataSet timestep=\"1\"/>" + tail},
      {"bad time", head + "<DataSet timestep=\"soon\" file=\"a.vtu\"/>" + tail},
      {"duplicate", head + "<DataSet timestep=\"1\" file=\"a.vtu\"/><DataSet timestep=\"1.0\" file=\"b.vtu\"/>" + tail},
      {"duplicate part",
       head + "<DataSet timestep=\"1\" part=\"2\" file=\"a.vtu\"/><DataSet timestep=\"1\" part=\"2\" file=\"b.vtu\"/>" +
           tail},
      {"bad part", head + "<DataSet timestep=\"1\" part=\"-1\" file=\"a.vtu\"/>" + tail},
      {"truncated", head + "<DataSet timestep=\"1\" file=\"a.vtu\"/>"},
      {"not a collection", "<VTKFile type=\"UnstructuredGrid\"></VTKFile>"},
  };
  for (const auto& [name, text] : cases) {
    write_file(dir / "bad.pvd", text);
    EXPECT_THROW(read_pvd(dir / "bad.pvd"), InputError) << name;
  }
}

// Entries of one time with different parts are one step, its parts in part order.
TEST(Pvd, PartsOfAStep) {
  const fs::path dir = test::scratch_dir("pvd_parts");
  write_file(dir / "p.pvd",
             "<VTKFile type=\"Collection\"><Collection><DataSet timestep=\"2\" part=\"1\" file=\"b1.vtu\"/>"
             "<DataSet timestep=\"1\" part=\"1\" file=\"a1.vtu\"/><DataSet timestep=\"1\" file=\"a0.vtu\"/>"
             "<DataSet timestep=\"2\" part=\"0\" file=\"b0.vtu\"/></Collection></VTKFile>");
  const std::vector<PvdStep> steps = read_pvd(dir / "p.pvd");
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].parts, (std::vector<fs::path>{dir / "a0.vtu", dir / "a1.vtu"}));
  EXPECT_EQ(steps[1].parts, (std::vector<fs::path>{dir / "b0.vtu", dir / "b1.vtu"}));
}

TEST(FileSeries, StepsByTime) {
  const fs::path dir = test::scratch_dir("file_series");
  write_file(dir / "case.vtm.series",
             "{\n  \"file-series-version\" : \"1.0\",\n  \"files\" : [\n    { \"name\" : \"case_20/case_20.vtm\", "
             "\"time\" : 0.2 },\n    { \"name\" : \"case_0.vtm\", \"time\" : 0 },\n    { \"name\" : \"/abs/c.vtm\", "
             "\"time\" : 1e-1 }\n  ]\n}\n");
  const std::vector<PvdStep> steps = read_file_series(dir / "case.vtm.series");
  ASSERT_EQ(steps.size(), 3u);
  EXPECT_EQ(steps[0].time, 0.0);
  EXPECT_EQ(steps[0].parts, std::vector<fs::path>{dir / "case_0.vtm"});
  EXPECT_EQ(steps[1].parts, std::vector<fs::path>{"/abs/c.vtm"});
  EXPECT_EQ(steps[2].time, 0.2);
  EXPECT_EQ(steps[2].parts, std::vector<fs::path>{dir / "case_20" / "case_20.vtm"});
}

TEST(FileSeries, BadSeries) {
  const fs::path dir = test::scratch_dir("file_series_bad");
  const std::pair<const char*, std::string> cases[] = {
      {"not JSON", "files: a.vtu"},
      {"not an object", "[1, 2]"},
      {"no files", "{\"file-series-version\": \"1.0\"}"},
      {"empty files", "{\"files\": []}"},
      {"other version", "{\"file-series-version\": \"2.0\", \"files\": [{\"name\": \"a.vtu\", \"time\": 0}]}"},
      {"no name", "{\"files\": [{\"time\": 0}]}"},
      {"no time", "{\"files\": [{\"name\": \"a.vtu\"}]}"},
      {"string time", "{\"files\": [{\"name\": \"a.vtu\", \"time\": \"0\"}]}"},
      {"same time", "{\"files\": [{\"name\": \"a.vtu\", \"time\": 1}, {\"name\": \"b.vtu\", \"time\": 1.0}]}"},
      {"entry not an object", "{\"files\": [\"a.vtu\"]}"},
      {"bad UTF-8", "{\"files\": [{\"name\": \"a\xff.vtu\", \"time\": 0}]}"},
      {"a numeric version", "{\"file-series-version\": 7, \"files\": [{\"name\": \"a.vtu\", \"time\": 0}]}"},
  };
  for (const auto& [name, text] : cases) {
    write_file(dir / "bad.vtu.series", text);
    EXPECT_THROW(read_file_series(dir / "bad.vtu.series"), InputError) << name;
  }
}

// Files VTK 9.1 wrote itself (tests/data/vtu/make_vtk_files.py): its wavelet source on 4x4x4
// points as 135 tets, with the point scalar RTData.
void expect_wavelet(const MeshData& m) {
  EXPECT_EQ(m.points.size(), 64u);
  EXPECT_EQ(m.cell_count(), 135u);
  EXPECT_EQ(m.cell_types, std::vector<uint8_t>(135, 10));
  ASSERT_EQ(m.point_data.size(), 1u);  // no vtkGhostType left
  EXPECT_EQ(m.point_data[0].name, "RTData");
  EXPECT_TRUE(m.cell_data.empty());
  // The range VTK wrote in the file's RangeMin and RangeMax attributes.
  const auto [low, high] = std::minmax_element(m.point_data[0].values.begin(), m.point_data[0].values.end());
  EXPECT_NEAR(*low, -21.386102676, 1e-5);
  EXPECT_EQ(*high, 260.0);
}

TEST(Vtu, ReadsVtksOwnCompressedFiles) {
  const MeshData zlib = read_vtu(kDataDir / "vtk_zlib.vtu");
  expect_wavelet(zlib);
  for (const char* name : {"vtk_lz4.vtu", "vtk_lzma.vtu"}) {
    SCOPED_TRACE(name);
    EXPECT_NE(read_file(kDataDir / name)
                  .find(std::string(name) == "vtk_lz4.vtu" ? "vtkLZ4DataCompressor" : "vtkLZMADataCompressor"),
              std::string::npos);
    expect_same_mesh(read_vtu(kDataDir / name), zlib, false);
  }
}

// A mesh's cells as the positions of their corners (sorted), and its points as position -> point
// values: equal for meshes that differ only in how their points are numbered.
using Position = std::array<double, 3>;
std::multiset<std::vector<Position>> cells_by_corners(const MeshData& m) {
  std::multiset<std::vector<Position>> cells;
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    std::vector<Position> corners;
    for (uint64_t k = m.cell_offsets[c]; k < m.cell_offsets[c + 1]; ++k) {
      const vec3d& p = m.points[m.connectivity[k]];
      corners.push_back({p.x, p.y, p.z});
    }
    std::sort(corners.begin(), corners.end());
    cells.insert(corners);
  }
  return cells;
}
std::map<Position, double> values_by_position(const MeshData& m) {
  std::map<Position, double> values;
  for (size_t i = 0; i < m.points.size(); ++i)
    values[{m.points[i].x, m.points[i].y, m.points[i].z}] = m.point_data.at(0).values[i];
  return values;
}

double total_volume(const MeshData& m) {
  double volume = 0;
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    const uint64_t* v = &m.connectivity[m.cell_offsets[c]];
    const vec3d a = m.points[v[1]] - m.points[v[0]], b = m.points[v[2]] - m.points[v[0]],
                d = m.points[v[3]] - m.points[v[0]];
    volume += std::abs(dot(a, cross(b, d))) / 6.0;
  }
  return volume;
}

// VTK's parallel writer's pieces, without and with a layer of ghost cells: joined, the mesh VTK
// wrote whole (its seams welded, its ghosts dropped).
TEST(Pvtu, ReadsVtksParallelFiles) {
  const MeshData whole = read_vtu(kDataDir / "vtk_zlib.vtu");
  for (const char* name : {"vtk_pieces.pvtu", "vtk_ghosts.pvtu"}) {
    SCOPED_TRACE(name);
    const MeshData m = read_pvtu(kDataDir / name);
    expect_wavelet(m);
    EXPECT_EQ(values_by_position(m), values_by_position(whole));
    // Each piece was cut into tets on its own, so the tets differ from the whole's; they fill
    // the same box (3 x 3 x 3) without overlap.
    EXPECT_NEAR(total_volume(m), 27.0, 1e-9);
    EXPECT_NEAR(total_volume(whole), 27.0, 1e-9);
  }
  // The ghost files do hold ghost cells: 90 cells in the first piece, 45 of them its own.
  EXPECT_NE(read_file(kDataDir / "vtk_ghosts_0.vtu").find("NumberOfCells=\"90\""), std::string::npos);
}

// write_pvtu's pieces (each with its own points, some with ghosts) read back as the mesh they
// were cut from, in every encoding.
TEST(Pvtu, RoundTrip) {
  MeshData mesh = mixed_mesh();
  for (Format format : {Format::ascii, Format::base64, Format::appended_raw}) {
    SCOPED_TRACE(format_name(format));
    const fs::path file = test::scratch_dir("pvtu_round_trip") / "cut.pvtu";
    write_pvtu(file, cut_into_pieces(mesh, 3, 1), {.format = format, .compressor = VtuCompressor::lz4});
    EXPECT_TRUE(fs::exists(file.parent_path() / "cut_2.vtu"));
    const MeshData m = read_pvtu(file);
    EXPECT_EQ(m.points.size(), mesh.points.size());
    EXPECT_EQ(cells_by_corners(m), cells_by_corners(read_vtu(kDataDir / "appended_raw.vtu")));
    EXPECT_EQ(values_by_position(m), values_by_position(read_vtu(kDataDir / "appended_raw.vtu")));
  }
}

// The InputError message of read_pvtu(file), or "" when it reads.
std::string pvtu_error(const fs::path& file) {
  try {
    read_pvtu(file);
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    return e.file() + ": " + e.what();
  }
  return "";
}

TEST(Pvtu, BadFiles) {
  const fs::path dir = test::scratch_dir("pvtu_bad");
  write_vtu(dir / "a.vtu", mixed_mesh());
  MeshData renamed = mixed_mesh();
  renamed.point_data[0].name = "pressure";
  write_vtu(dir / "b.vtu", renamed);
  const std::string head = "<VTKFile type=\"PUnstructuredGrid\"><PUnstructuredGrid>";
  const std::string tail = "</PUnstructuredGrid></VTKFile>";
  write_pvtu(dir / "nested.pvtu", {mixed_mesh()});
  const std::pair<std::string, std::string> cases[] = {
      {"no pieces", head + tail},
      {"no Source", head + "<Piece/>" + tail},
      {"missing file", head + "<Piece Source=\"absent.vtu\"/>" + tail},
      {"other arrays", head + "<Piece Source=\"a.vtu\"/><Piece Source=\"b.vtu\"/>" + tail},
      {"a .pvtu as a piece", head + "<Piece Source=\"nested.pvtu\"/>" + tail},
      {"truncated", head + "<Piece Source=\"a.vtu\"/>"},
      {"not a pvtu", "<VTKFile type=\"UnstructuredGrid\"></VTKFile>"},
  };
  for (const auto& [name, text] : cases) {
    write_file(dir / "bad.pvtu", text);
    EXPECT_NE(pvtu_error(dir / "bad.pvtu"), "") << name;
  }
  write_file(dir / "bad.pvtu", head + "<Piece Source=\"absent.vtu\"/>" + tail);
  EXPECT_NE(pvtu_error(dir / "bad.pvtu").find("absent.vtu"), std::string::npos);
  write_file(dir / "bad.pvtu", head + "<Piece Source=\"a.vtu\"/><Piece Source=\"b.vtu\"/>" + tail);
  EXPECT_NE(pvtu_error(dir / "bad.pvtu").find("other point or cell arrays"), std::string::npos);
}

// VTK's multiblock writer's output: two zones of the tets and a boundary surface (skipped).
TEST(Vtm, ReadsVtksMultiblock) {
  const MeshData whole = read_vtu(kDataDir / "vtk_zlib.vtu");
  MeshData m = read_vtm(kDataDir / "vtk_blocks.vtm");
  ASSERT_EQ(m.cell_data.size(), 1u);  // the zones' vtkOriginalCellIds: each cell of the whole once
  EXPECT_EQ(m.cell_data[0].name, "vtkOriginalCellIds");
  std::vector<double> ids = m.cell_data[0].values;
  std::sort(ids.begin(), ids.end());
  for (size_t c = 0; c < ids.size(); ++c) EXPECT_EQ(ids[c], double(c));
  m.cell_data.clear();
  expect_wavelet(m);  // 64 points: the zones' seam welded
  EXPECT_EQ(cells_by_corners(m), cells_by_corners(whole));
  EXPECT_EQ(values_by_position(m), values_by_position(whole));
}

// The cell ids (vtkOriginalCellIds) of the blocks of vtk_blocks.vtm that `blocks` names.
std::vector<double> original_cells(const std::vector<std::string>& blocks) {
  const MeshData m = read_vtm(kDataDir / "vtk_blocks.vtm", nullptr, blocks);
  std::vector<double> ids = m.cell_data.at(0).values;
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<double> counting_from(double first, size_t n) {
  std::vector<double> v(n);
  std::iota(v.begin(), v.end(), first);
  return v;
}

std::string vtm_error(const fs::path& file, const std::vector<std::string>& blocks) {
  try {
    read_vtm(file, nullptr, blocks);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

// --region on a .vtm: each zone alone is its cells of the whole (VTK wrote their ids), both
// are the whole; a block of surfaces only, or a name the file lacks, is refused.
TEST(Vtm, BlocksAskedForAlone) {
  EXPECT_EQ(original_cells({"zone_0"}), counting_from(0, 68));
  EXPECT_EQ(original_cells({"zone_1"}), counting_from(68, 67));
  EXPECT_EQ(original_cells({"zone_1", "zone_0"}), counting_from(0, 135));
  const fs::path file = kDataDir / "vtk_blocks.vtm";
  EXPECT_EQ(vtm_error(file, {"boundary"}),
            "no unstructured grid (.vtu or .pvtu) among its blocks asked for (--region)");
  EXPECT_EQ(vtm_error(file, {"boundary/walls"}), vtm_error(file, {"boundary"}));
  EXPECT_EQ(vtm_error(file, {"zone_0", "zone_2"}),
            "no block or data set 'zone_2' in this multiblock (its blocks: zone_0, zone_1, boundary, boundary/walls)");
}

// A multi-region case as foamToVTK writes it: each region a block holding its "internal" volume
// and a block of boundary patches. A region by name, a data set by its path, and a name that
// several data sets share (every one of them).
TEST(Vtm, BlocksByNameAndPath) {
  const fs::path dir = test::scratch_dir("vtm_regions");
  MeshData fluid = mixed_mesh(), solid = mixed_mesh();
  for (auto& p : solid.points) p.x += 10;  // apart from the fluid: no point welded
  write_vtu(dir / "fluid.vtu", fluid);
  write_pvtu(dir / "solid.pvtu", cut_into_pieces(solid, 2));
  write_file(dir / "case.vtm",
             "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet>"
             "<Block index=\"0\" name=\"fluid\"><DataSet index=\"0\" name=\"internal\" file=\"fluid.vtu\"/>"
             "<Block index=\"1\" name=\"boundary\"><DataSet index=\"0\" name=\"inlet\" file=\"inlet.vtp\"/>"
             "</Block></Block>"
             "<Block index=\"1\" name=\"solid\"><DataSet index=\"0\" name=\"internal\" file=\"solid.pvtu\"/>"
             "</Block></vtkMultiBlockDataSet></VTKFile>");
  const auto x_range = [&](const std::vector<std::string>& blocks) {
    const MeshData m = read_vtm(dir / "case.vtm", nullptr, blocks);
    double lo = m.points.front().x, hi = lo;
    for (const auto& p : m.points) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
    return std::make_tuple(m.cell_count(), m.points.size(), lo, hi);
  };
  const auto [cells, points, lo, hi] = x_range({"fluid"});
  EXPECT_EQ(cells, fluid.cell_count());
  EXPECT_EQ(points, fluid.points.size());
  EXPECT_LT(hi, 5.0);
  EXPECT_EQ(x_range({"fluid/internal"}), x_range({"fluid"}));
  const auto [solid_cells, solid_points, solid_lo, solid_hi] = x_range({"solid/internal"});
  EXPECT_EQ(solid_cells, solid.cell_count());
  EXPECT_GT(solid_lo, 5.0);
  EXPECT_EQ(std::get<0>(x_range({"internal"})), fluid.cell_count() + solid.cell_count());
  EXPECT_EQ(x_range({"internal"}), x_range({}));
  // A .pvd of .vtm steps reads the same blocks at every step; one with a .vtu step is refused.
  write_pvd(dir / "case.pvd", {{0.0, {dir / "case.vtm"}}, {1.0, {dir / "case.vtm"}}});
  const auto series = open_mesh_files({dir / "case.pvd"}, {}, {"solid"});
  EXPECT_EQ(series->read_step(1).cell_count(), solid.cell_count());
  EXPECT_NE(series->description().find("(2 steps; blocks solid)"), std::string::npos) << series->description();
  write_pvd(dir / "mixed.pvd", {{0.0, {dir / "case.vtm"}}, {1.0, {dir / "fluid.vtu"}}});
  EXPECT_THROW(open_mesh_files({dir / "mixed.pvd"}, {}, {"solid"}), UsageError);
  EXPECT_EQ(vtm_error(dir / "case.vtm", {"fluid/inlet"}),
            "no block or data set 'fluid/inlet' in this multiblock (its blocks: fluid, fluid/internal, "
            "fluid/boundary, fluid/boundary/inlet, solid, solid/internal)");
}

TEST(Vtm, BadFiles) {
  const fs::path dir = test::scratch_dir("vtm_bad");
  write_vtu(dir / "a.vtu", mixed_mesh());
  write_pvtu(dir / "p.pvtu", cut_into_pieces(mixed_mesh(), 2));
  const std::string head = "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet>";
  const std::string tail = "</vtkMultiBlockDataSet></VTKFile>";
  const std::pair<std::string, std::string> cases[] = {
      {"no blocks", head + tail},
      {"surfaces only", head + "<DataSet index=\"0\" file=\"walls.vtp\"/>" + tail},
      {"a structured grid", head + "<DataSet index=\"0\" file=\"a.vtu\"/><DataSet index=\"1\" file=\"g.vts\"/>" + tail},
      {"missing file", head + "<Block><DataSet index=\"0\" file=\"absent.vtu\"/></Block>" + tail},
      {"not a vtm", "<VTKFile type=\"Collection\"></VTKFile>"},
  };
  for (const auto& [name, text] : cases) {
    write_file(dir / "bad.vtm", text);
    EXPECT_THROW(read_vtm(dir / "bad.vtm"), InputError) << name;
  }
  // A .pvtu block in a nested block, beside a skipped surface and an empty block: the mesh.
  write_file(dir / "ok.vtm", head +
                                 "<Block index=\"0\"><Piece index=\"0\"><DataSet index=\"0\" file=\"p.pvtu\"/>"
                                 "</Piece></Block><DataSet index=\"1\" file=\"walls.vtp\"/><DataSet index=\"2\"/>" +
                                 tail);
  const MeshData m = read_vtm(dir / "ok.vtm");
  EXPECT_EQ(m.points.size(), 13u);
  EXPECT_EQ(m.cell_count(), 5u);
}

// VTK's voxels (x-fastest corners) come out as hexahedra in VTK's hex order, from XML and legacy
// files alike: corner 1 one step along x from corner 0, corner 2 along x and y, corner 3 along y,
// corners 4-7 the same one step up in z (VTK's wavelet has unit spacing).
TEST(Vtu, VoxelsAreReadAsHexahedra) {
  for (const MeshData& m :
       {read_vtu(kDataDir / "vtk_voxels.vtu"), read_vtk_legacy(kDataDir.parent_path() / "vtk" / "vtk_voxels.vtk")}) {
    ASSERT_EQ(m.cell_count(), 27u);
    EXPECT_EQ(m.cell_types, std::vector<uint8_t>(27, uint8_t(CellType::hex)));
    const vec3d step[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (uint64_t c = 0; c < m.cell_count(); ++c)
      for (int k = 0; k < 8; ++k) {
        const vec3d& origin = m.points[m.connectivity[8 * c]];
        ASSERT_EQ(m.points[m.connectivity[8 * c + uint64_t(k)]] - origin, step[k]) << "cell " << c << " corner " << k;
      }
  }
}

}  // namespace
}  // namespace vs
