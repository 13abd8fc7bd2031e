// Legacy VTK: valid files of every writer option (ascii/binary, 4.2/5.1) with one of them patched
// or truncated.
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

std::vector<std::filesystem::path> make_bases(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (int i = 0; i < 4; ++i) {
    files.push_back(dir / ("base" + std::to_string(i) + ".vtk"));
    vs::write_vtk_legacy(files.back(), small_mesh(), {i >= 2, i % 2 == 1, false});
  }
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
