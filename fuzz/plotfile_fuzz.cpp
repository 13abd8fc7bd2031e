// AMReX plotfiles: a valid two-level plotfile with one of its files patched or truncated.
#include <algorithm>
#include "fuzz_util.h"
#include "volstream/io/dataset.h"
#include "volstream/io/plotfile.h"

namespace {
std::filesystem::path make_base(const std::filesystem::path& dir) {
  using namespace vs;
  PlotfileSpec spec;
  spec.components = {"density", "temperature"};
  spec.level0_domain = {vec3i(0, 0, 0), vec3i(7, 7, 3)};
  spec.ref_ratios = {2};
  spec.levels = {PlotfileLevel{{box3i{vec3i(0, 0, 0), vec3i(3, 7, 3)}, box3i{vec3i(4, 0, 0), vec3i(7, 7, 3)}}},
                 PlotfileLevel{{box3i{vec3i(2, 2, 2), vec3i(7, 9, 5)}}}};
  write_plotfile(dir / "plt00000", spec, [](int c, int l, int i, int j, int k) { return c + l + i * 0.5 + j - k; });
  return dir / "plt00000";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("plotfile");
  static const auto base = make_base(dir);
  const auto work = dir / "work";
  fuzz::copy_tree(base, work);
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(work))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (!fuzz::apply_patch(files, data, size)) return 0;
  fuzz::expect_clean([&] {
    auto source = open_plotfile_series({work});
    convert_to_dataset(*source, dir / "out", ConvertOptions::silent());
  });
  return 0;
}
