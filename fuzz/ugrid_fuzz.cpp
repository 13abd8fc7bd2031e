// UGRID: valid files of every encoding with one of them patched or truncated.
#include "fuzz_util.h"
#include "volstream/io/ugrid.h"

namespace {
vs::MeshData small_mesh() {
  vs::MeshData m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0.5, 0.5, 2}, {1, 0, 1}};
  m.cell_types = {10, 14, 13};
  m.cell_offsets = {0, 4, 9, 15};
  m.connectivity = {0, 1, 2, 3, 0, 1, 4, 2, 5, 0, 1, 2, 3, 6, 5};
  return m;
}

std::vector<std::filesystem::path> make_bases(const std::filesystem::path& dir) {
  using vs::UgridEncoding;
  const std::pair<const char*, UgridEncoding> kEncodings[] = {{"base.ugrid", UgridEncoding::ascii},
                                                              {"base.b8.ugrid", UgridEncoding::b8},
                                                              {"base.lb8.ugrid", UgridEncoding::lb8},
                                                              {"base.lb4.ugrid", UgridEncoding::lb4},
                                                              {"base.b4.ugrid", UgridEncoding::b4}};
  std::vector<std::filesystem::path> files;
  for (const auto& [name, encoding] : kEncodings) {
    files.push_back(dir / name);
    vs::write_ugrid(files.back(), small_mesh(), encoding);
  }
  return files;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("ugrid");
  static const auto bases = make_bases(dir);
  if (size < 1) return 0;
  // The work file keeps its base's suffix, which selects the encoding.
  const auto& base = bases[(data[0] & 0x7f) % bases.size()];
  const auto work = dir / ("work" + base.filename().string().substr(4));
  fuzz::copy_file_contents(base, work);
  if (!fuzz::apply_patch({work}, data, size)) return 0;
  fuzz::expect_clean([&] { read_ugrid(work); });
  return 0;
}
