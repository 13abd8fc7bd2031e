// VTK XML unstructured grids and ParaView collections: valid files in several encodings (ascii,
// inline base64 + zlib, appended raw, appended raw + LZ4, appended raw + LZMA, appended base64 +
// zlib with UInt32 headers and two pieces' worth of arrays), a .pvd, a .pvtu of two ascii pieces
// with ghost cells (pieces_0.vtu and pieces_1.vtu, also read alone), a .vtm of a .vtu, the .pvtu
// and a surface, and a JSON .series, one of them patched or truncated.
#include <algorithm>
#include <fstream>

#include "fuzz_util.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/mesh_pieces.h"

namespace {
vs::MeshData small_mesh() {
  using namespace vs;
  MeshData m;
  for (int i = 0; i < 7; ++i) m.points.push_back(vec3d(i & 1, (i >> 1) & 1, (i >> 2) + 0.5 * i));
  m.cell_types = {10, 14};
  m.cell_offsets = {0, 4, 9};
  m.connectivity = {0, 1, 2, 4, 0, 1, 3, 2, 6};
  m.point_data = {{"p", 1, {1, 2, 3, 4, 5, 6, 7}}};
  m.cell_data = {{"v", 3, {1, 2, 3, 4, 5, 6}}};
  return m;
}

void make_base(const std::filesystem::path& dir) {
  using namespace vs;
  using Format = VtuWriteOptions::Format;
  std::filesystem::create_directories(dir);
  const MeshData mesh = small_mesh();
  write_vtu(dir / "ascii.vtu", mesh, {.format = Format::ascii});
  write_vtu(dir / "base64_zlib.vtu", mesh,
            {.format = Format::base64, .compressor = VtuCompressor::zlib, .block_size = 16});
  write_vtu(dir / "raw_lz4.vtu", mesh, {.compressor = VtuCompressor::lz4, .block_size = 16});
  write_vtu(dir / "raw_lzma.vtu", mesh, {.compressor = VtuCompressor::lzma, .block_size = 32});
  write_vtu(dir / "raw.vtu", mesh, {.format = Format::appended_raw, .points_float64 = true});
  write_vtu(dir / "appended_base64.vtu", mesh,
            {.format = Format::appended_base64,
             .compressor = VtuCompressor::zlib,
             .header_uint64 = false,
             .indices_int64 = false});
  write_pvd(dir / "series.pvd", {{0, {dir / "ascii.vtu"}}, {1, {dir / "raw.vtu"}}});
  write_pvtu(dir / "pieces.pvtu", cut_into_pieces(mesh, 2, 1), {.format = Format::ascii});
  std::ofstream(dir / "blocks.vtm") << "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><Block>"
                                       "<DataSet file=\"ascii.vtu\"/><DataSet file=\"pieces.pvtu\"/></Block>"
                                       "<DataSet file=\"walls.vtp\"/></vtkMultiBlockDataSet></VTKFile>\n";
  std::ofstream(dir / "steps.series") << "{\"file-series-version\": \"1.0\", \"files\": [{\"name\": \"raw.vtu\", "
                                         "\"time\": 1}, {\"name\": \"ascii.vtu\", \"time\": 0.5}]}\n";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("vtu");
  static const bool made = (make_base(dir / "base"), true);
  (void)made;
  const auto work = dir / "work";
  fuzz::copy_tree(dir / "base", work);
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(work)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (!fuzz::apply_patch(files, data, size)) return 0;
  for (const auto& file : files) {
    if (file.extension() == ".pvd")
      fuzz::expect_clean([&] { read_pvd(file); });
    else if (file.extension() == ".pvtu")
      fuzz::expect_clean([&] { read_pvtu(file); });
    else if (file.extension() == ".vtm")
      fuzz::expect_clean([&] { read_vtm(file); });
    else if (file.extension() == ".series")
      fuzz::expect_clean([&] { read_file_series(file); });
    else
      fuzz::expect_clean([&] { read_vtu(file); });
  }
  return 0;
}
