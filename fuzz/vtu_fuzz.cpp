// VTK XML unstructured grids and ParaView collections: valid files in several encodings (ascii,
// inline base64 + zlib, appended raw, appended raw + LZ4, appended raw + LZMA, appended base64 +
// zlib with UInt32 headers and two pieces' worth of arrays), a .pvd, a .pvtu of two ascii pieces
// with ghost cells (pieces_0.vtu and pieces_1.vtu, also read alone), a .vtm of a .vtu, the .pvtu
// and a surface (read whole, or two of its blocks by name), a JSON .series, polyhedra in both of
// VTK's layouts and VTK's quadratic cells (tests/data/vtu/vtk_quadratic.vtu), one of them
// patched or truncated.
#include <algorithm>
#include <fstream>
#include <string>

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

// A "house" polyhedron (a cube with a pyramid roof: nine faces, split from its centroid), a tet
// given as a polyhedron and a tet, in the face streams of VTK 9.3 and before or the face tables
// of VTK 9.4 (ascii: VTK's own files of polyhedra are in tests/data/vtu).
std::string polyhedra_vtu(bool tables) {
  const std::string cells =
      tables
          ? "<DataArray type=\"Int64\" Name=\"face_connectivity\" format=\"ascii\">0 3 2 1 0 1 5 4 1 2 6 5 2 3 7 "
            "6 3 0 4 7 4 5 8 5 6 8 6 7 8 7 4 8 0 3 1 0 1 4 1 3 4 0 4 3</DataArray>\n"
            "<DataArray type=\"Int64\" Name=\"face_offsets\" format=\"ascii\">4 8 12 16 20 23 26 29 32 35 38 "
            "41 44</DataArray>\n<DataArray type=\"Int64\" Name=\"polyhedron_to_faces\" format=\"ascii\">0 1 2 3 "
            "4 5 6 7 8 9 10 11 12</DataArray>\n<DataArray type=\"Int64\" Name=\"polyhedron_offsets\" "
            "format=\"ascii\">9 13 13</DataArray>\n"
          : "<DataArray type=\"Int64\" Name=\"faces\" format=\"ascii\">9 4 0 3 2 1 4 0 1 5 4 4 1 2 6 5 4 2 3 7 6 4 3 "
            "0 4 7 3 4 5 8 3 5 6 8 3 6 7 8 3 7 4 8 4 3 0 3 1 3 0 1 4 3 1 3 4 3 0 4 3</DataArray>\n"
            "<DataArray type=\"Int64\" Name=\"faceoffsets\" format=\"ascii\">42 59 -1</DataArray>\n";
  return "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"9\" NumberOfCells=\"3\">\n"
         "<PointData><DataArray type=\"Float64\" Name=\"p\" format=\"ascii\">1 2 3 4 5 6 7 8 9</DataArray>"
         "</PointData>\n<CellData><DataArray type=\"Int32\" Name=\"c\" format=\"ascii\">0 1 2</DataArray>"
         "</CellData>\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 1 "
         "1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1 0.5 0.5 1.6</DataArray></Points>\n<Cells>"
         "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5 6 7 8 0 1 3 4 0 1 3 4"
         "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">9 13 17</DataArray>\n"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">42 42 10</DataArray>\n" +
         cells + "</Cells></Piece></UnstructuredGrid></VTKFile>\n";
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
  std::ofstream(dir / "blocks.vtm")
      << "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><Block name=\"zone\">"
         "<DataSet name=\"a\" file=\"ascii.vtu\"/><DataSet file=\"pieces.pvtu\"/></Block>"
         "<DataSet name=\"walls\" file=\"walls.vtp\"/></vtkMultiBlockDataSet></VTKFile>\n";
  std::ofstream(dir / "polyhedra_streams.vtu") << polyhedra_vtu(false);
  std::ofstream(dir / "polyhedra_tables.vtu") << polyhedra_vtu(true);
  std::filesystem::copy_file(
      std::filesystem::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "vtu" / "vtk_quadratic.vtu",
      dir / "quadratic.vtu", std::filesystem::copy_options::overwrite_existing);
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
  // The first byte's high bit: the .vtm's blocks by --region (a name, a path), or all of them.
  const std::vector<std::string> blocks =
      size > 0 && (data[0] & 0x80) ? std::vector<std::string>{"zone/a", "walls"} : std::vector<std::string>{};
  for (const auto& file : files) {
    if (file.extension() == ".pvd")
      fuzz::expect_clean([&] { read_pvd(file); });
    else if (file.extension() == ".pvtu")
      fuzz::expect_clean([&] { read_pvtu(file); });
    else if (file.extension() == ".vtm")
      fuzz::expect_clean([&] { read_vtm(file, nullptr, blocks); });
    else if (file.extension() == ".series")
      fuzz::expect_clean([&] { read_file_series(file); });
    else
      fuzz::expect_clean([&] { read_vtu(file); });
  }
  return 0;
}
