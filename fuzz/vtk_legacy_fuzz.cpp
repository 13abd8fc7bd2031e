// Legacy VTK: valid files of every writer option (ascii/binary, 4.2/5.1), of polyhedra and of
// VTK's quadratic and Lagrange cells (tests/data/vtk/vtk_quadratic.vtk, vtk_lagrange_42.vtk), with
// one of them patched or truncated.
#include <fstream>
#include <string>

#include "fuzz_util.h"
#include "volstream/io/vtk_legacy.h"

namespace {
vs::MeshData small_mesh() {
  vs::MeshData m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {0.5, 0.5, 2}};
  m.cell_types = {10, 14};
  m.cell_offsets = {0, 4, 9};
  m.connectivity = {0, 1, 2, 3, 1, 4, 2, 0, 5};
  m.point_data = {{"s", 1, {1, 2, 3, 4, 5, 6}}, {"uv", 2, std::vector<double>(12, 0.5)}};
  m.cell_data = {{"v", 3, {1, 2, 3, 4, 5, 6}}};
  return m;
}

// A "house" polyhedron (a cube with a pyramid roof), a tet given as a polyhedron and a tet, whose
// cell lists are the polyhedra's face streams: file versions 4.2 and 5.1 (ascii).
const char* const kHouseStream =
    "9 4 0 3 2 1 4 0 1 5 4 4 1 2 6 5 4 2 3 7 6 4 3 0 4 7 3 4 5 8 3 5 6 8 3 6 7 8 3 7 4 8\n";
const char* const kTetStream = "4 3 0 3 1 3 0 1 4 3 1 3 4 3 0 4 3\n";
std::string polyhedra_vtk(bool version5) {
  std::string text = std::string("# vtk DataFile Version ") + (version5 ? "5.1" : "4.2") +
                     "\npolyhedra\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 9 float\n0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 "
                     "1 0 1 1 1 1 0 1 1 0.5 0.5 1.6\n";
  if (version5)
    text += std::string("CELLS 4 63\nOFFSETS vtktypeint64\n0 42 59 63\nCONNECTIVITY vtktypeint64\n") + kHouseStream +
            kTetStream + "0 1 3 4\n";
  else
    text += std::string("CELLS 3 66\n42 ") + kHouseStream + "17 " + kTetStream + "4 0 1 3 4\n";
  return text +
         "CELL_TYPES 3\n42\n42\n10\nPOINT_DATA 9\nSCALARS p float 1\nLOOKUP_TABLE default\n1 2 3 4 5 6 7 8 "
         "9\nCELL_DATA 3\nSCALARS c int 1\nLOOKUP_TABLE default\n0 1 2\n";
}

std::vector<std::filesystem::path> make_bases(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (int i = 0; i < 4; ++i) {
    files.push_back(dir / ("base" + std::to_string(i) + ".vtk"));
    vs::write_vtk_legacy(files.back(), small_mesh(), {i >= 2, i % 2 == 1, false});
  }
  for (bool version5 : {false, true}) {
    files.push_back(dir / (version5 ? "polyhedra51.vtk" : "polyhedra42.vtk"));
    std::ofstream(files.back()) << polyhedra_vtk(version5);
  }
  for (const char* name : {"vtk_quadratic.vtk", "vtk_lagrange_42.vtk"})
    files.push_back(std::filesystem::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "vtk" / name);
  return files;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("vtk_legacy");
  static const auto bases = make_bases(dir);
  if (size < 1) return 0;
  const auto work = dir / "work.vtk";
  fuzz::copy_file_contents(bases[(data[0] & 0x7f) % bases.size()], work);
  if (!fuzz::apply_patch({work}, data, size)) return 0;
  fuzz::expect_clean([&] { read_vtk_legacy(work); });
  return 0;
}
