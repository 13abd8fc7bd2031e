// VTK XML unstructured grids and ParaView collections: round trips through write_vtu in every
// encoding, the committed files of tests/data/vtu, and bad input.
#include "volstream/io/vtu.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>

#include "test_util.h"
#include "volstream/core/error.h"

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
    for (bool zlib : {false, true})
      for (bool header64 : {false, true})
        for (bool points64 : {false, true})
          for (bool indices64 : {false, true}) {
            VtuWriteOptions o;
            o.format = format;
            o.zlib = zlib;
            o.header_uint64 = header64;
            o.points_float64 = points64;
            o.indices_int64 = indices64;
            o.zlib_block_size = 40;  // several blocks per array, a partial last one
            std::ostringstream trace;
            trace << format_name(format) << (zlib ? " zlib" : "") << (header64 ? " UInt64" : " UInt32")
                  << (points64 ? " Float64" : " Float32") << (indices64 ? " Int64" : " Int32");
            SCOPED_TRACE(trace.str());
            const fs::path file = dir / (std::to_string(files++) + ".vtu");
            write_vtu(file, mesh, o);
            expect_same_mesh(read_vtu(file), mesh, points64);
          }
}

TEST(Vtu, ZlibBlockSizeDividingTheData) {
  const MeshData mesh = mixed_mesh();
  VtuWriteOptions o;
  o.zlib = true;
  o.zlib_block_size = 8;  // every array is a whole number of blocks: the last-block size is 0
  const fs::path file = test::scratch_dir("vtu_block_size") / "m.vtu";
  write_vtu(file, mesh, o);
  expect_same_mesh(read_vtu(file), mesh, false);
}

// Run with --gtest_also_run_disabled_tests to regenerate tests/data/vtu after a writer change.
TEST(Vtu, DISABLED_WriteDataFiles) {
  struct File {
    const char* name;
    Format format;
    bool zlib, header64;
  };
  for (const File& f :
       {File{"ascii", Format::ascii, false, true}, File{"base64", Format::base64, false, true},
        File{"base64_zlib", Format::base64, true, true}, File{"appended_base64", Format::appended_base64, false, true},
        File{"appended_raw", Format::appended_raw, false, true},
        File{"appended_raw_zlib", Format::appended_raw, true, true},
        File{"uint32_header", Format::appended_base64, true, false}}) {
    VtuWriteOptions o;
    o.format = f.format;
    o.zlib = f.zlib;
    o.header_uint64 = f.header64;
    o.points_float64 = !f.header64;  // the UInt32 file also has Float64 points and Int32 indices
    o.indices_int64 = f.header64;
    o.zlib_block_size = 64;
    write_vtu(kDataDir / (std::string(f.name) + ".vtu"), mixed_mesh(), o);
  }
  write_pvd(kDataDir / "series.pvd", {{0.5, kDataDir / "ascii.vtu"}, {1.5, kDataDir / "appended_raw.vtu"}});
}

TEST(Vtu, ReadsCommittedFiles) {
  for (const char* name :
       {"ascii", "base64", "base64_zlib", "appended_base64", "appended_raw", "appended_raw_zlib", "uint32_header"}) {
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

TEST(Vtu, ConcatenatesPiecesAndSkipsStringArrays) {
  const fs::path file = edited_file("vtu_pieces", mixed_mesh(), {.format = Format::ascii}, [](std::string& text) {
    const size_t begin = text.find("    <Piece"), end = text.find("    </Piece>\n") + 13;
    std::string piece = text.substr(begin, end - begin);
    replace_once(piece, "<PointData>",
                 "<PointData>\n<DataArray type=\"String\" Name=\"label\" format=\"ascii\">97 0</DataArray>");
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

TEST(Vtu, CorruptZlibStream) {
  const VtuWriteOptions o{.format = Format::appended_raw, .zlib = true};
  const fs::path file = edited_file("vtu_bad_zlib", mixed_mesh(), o, [](std::string& text) {
    const size_t data = text.find('_', text.find("<AppendedData")) + 1;
    for (size_t i = 34; i < 42; ++i) text[data + i] = char(0xA5);  // inside the first array's deflate stream
  });
  EXPECT_NE(vtu_error(file).find("corrupt zlib data"), std::string::npos) << vtu_error(file);
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
    const fs::path file = edited_file("vtu_absurd", mixed_mesh(), {.zlib = true}, [&](std::string& text) {
      replace_once(text, "NumberOfPoints=\"13\"", std::string("NumberOfPoints=\"") + count + "\"");
    });
    EXPECT_NE(vtu_error(file), "");
  }
  // A zlib header of the Points claiming 2^36 * 12 bytes in one block of a few bytes.
  const VtuWriteOptions o{.format = Format::appended_raw, .zlib = true};
  const fs::path file = edited_file("vtu_absurd_zlib", mixed_mesh(), o, [](std::string& text) {
    replace_once(text, "NumberOfPoints=\"13\"", "NumberOfPoints=\"68719476736\"");
    const size_t offset_at = text.find("offset=\"", text.find("Name=\"Points\"")) + 8;
    const size_t data = text.find('_', text.find("<AppendedData")) + 1 + std::stoull(text.substr(offset_at, 20));
    const uint64_t block = (uint64_t(1) << 36) * 12, last = 0;
    std::memcpy(text.data() + data + 8, &block, 8);
    std::memcpy(text.data() + data + 16, &last, 8);
  });
  EXPECT_NE(vtu_error(file).find("cannot hold"), std::string::npos) << vtu_error(file);
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
  write_file(dir / "lz4.vtu", "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkLZ4DataCompressor\"/>");
  for (const char* name : {"empty.vtu", "text.vtu", "image.vtu", "lz4.vtu", "absent.vtu"})
    EXPECT_NE(vtu_error(dir / name), "") << name;
  EXPECT_NE(vtu_error(dir / "lz4.vtu").find("vtkLZ4DataCompressor"), std::string::npos);
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
  const std::vector<PvdStep> steps{{2.5, dir / "steps" / "b.vtu"}, {0.1, dir / "steps" / "a&b.vtu"}};
  write_pvd(dir / "series.pvd", steps);
  EXPECT_NE(read_file(dir / "series.pvd").find("file=\"steps/a&amp;b.vtu\""), std::string::npos);
  const std::vector<PvdStep> got = read_pvd(dir / "series.pvd");
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].time, 0.1);
  EXPECT_EQ(got[0].file, dir / "steps" / "a&b.vtu");
  EXPECT_EQ(got[1].time, 2.5);
  EXPECT_EQ(got[1].file, dir / "steps" / "b.vtu");
}

TEST(Pvd, ReadsCommittedSeries) {
  const std::vector<PvdStep> steps = read_pvd(kDataDir / "series.pvd");
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[1].time, 1.5);
  EXPECT_EQ(read_vtu(steps[1].file).cell_count(), 5u);
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
      {"part 1", head + "<DataSet timestep=\"1\" part=\"1\" file=\"a.vtu\"/>" + tail},
      {"truncated", head + "<DataSet timestep=\"1\" file=\"a.vtu\"/>"},
      {"not a collection", "<VTKFile type=\"UnstructuredGrid\"></VTKFile>"},
  };
  for (const auto& [name, text] : cases) {
    write_file(dir / "bad.pvd", text);
    EXPECT_THROW(read_pvd(dir / "bad.pvd"), InputError) << name;
  }
}

}  // namespace
}  // namespace vs
