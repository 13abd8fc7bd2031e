// EnSight Gold: the test cases of tests/data/ensight (ASCII, big-endian C Binary: two parts of
// volume elements with polyhedra, a boundary part, node and element ids, two steps, scalar and
// vector variables per node and per element; VTK's little-endian C Binary, of linear and of
// quadratic elements) with one of their
// files patched or truncated, read step by step as `convert` reads them, every part or part 2
// alone (the first byte's high bit).
#include <algorithm>
#include <iterator>

#include "fuzz_util.h"
#include "volstream/io/ensight.h"

namespace {
const std::filesystem::path kCases[] = {"ascii/mesh.case", "big_endian/mesh.case", "vtk/mixed.0.case",
                                        "vtk_quadratic/quadratic.0.case"};

void read_all_steps(const std::filesystem::path& file, const std::vector<std::string>& parts) {
  const vs::EnsightCase c = vs::read_ensight_case(file);
  for (size_t step = 0; step < c.times.size(); ++step)
    vs::read_ensight_step(c, vs::read_ensight_geometry(vs::ensight_step_file(c, c.geometry, step), parts), step);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  namespace fs = std::filesystem;
  static const auto dir = fuzz::scratch("ensight");
  const fs::path base = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "ensight";
  if (size < 1) return 0;
  const fs::path& which = kCases[(data[0] & 0x7f) % std::size(kCases)];
  const fs::path work = dir / "work";
  fuzz::copy_tree(base / which.parent_path(), work);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(work))
    if (e.path().extension() != ".vtu") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (!fuzz::apply_patch(files, data + 1, size - 1)) return 0;
  const std::vector<std::string> parts = (data[0] & 0x80) ? std::vector<std::string>{"2"} : std::vector<std::string>{};
  fuzz::expect_clean([&] { read_all_steps(work / which.filename(), parts); });
  return 0;
}
