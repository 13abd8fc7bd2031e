// OpenFOAM: the test cases of tests/data/openfoam (a refined box: ascii, binary with a
// faceCompactList, gzipped, decomposed for 3 processors, uncollated and collated, split into two
// regions, and that decomposed for 2) with one of their mesh files (of a decomposed case,
// processor1's or the collated file of all, its pointProcAddressing too; of a multi-region case,
// the solid's) or the last step's fields patched or truncated, read step by step as `convert`
// reads them.
#include <iterator>
#include <string>

#include "fuzz_util.h"
#include "volstream/io/openfoam.h"

namespace {
const char* const kCases[] = {"box_ascii",    "box_binary",          "box_gz",      "box_decomposed",
                              "box_collated", "box_collated_binary", "box_regions", "box_regions_decomposed"};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  namespace fs = std::filesystem;
  static const auto dir = fuzz::scratch("openfoam");
  const fs::path base = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "openfoam";
  if (size < 1) return 0;
  const std::string name = kCases[(data[0] & 0x7f) % std::size(kCases)];
  const fs::path work = dir / "case";
  fuzz::copy_tree(base / name, work);
  const std::string gz = name == "box_gz" ? ".gz" : "";
  const bool collated = name.starts_with("box_collated"), regions = name.starts_with("box_regions");
  const bool decomposed = collated || name.ends_with("decomposed");
  const fs::path part = collated ? work / "processors3" : decomposed ? work / "processor1" : work;
  const std::string region = regions ? "solid" : "";
  const fs::path mesh = part / "constant" / region / "polyMesh", fields = part / "0.2" / region;
  std::vector<fs::path> files = {mesh / ("points" + gz),    mesh / ("faces" + gz), mesh / ("owner" + gz),
                                 mesh / ("neighbour" + gz), fields / ("T" + gz),   fields / ("V" + gz)};
  if (decomposed) files.push_back(mesh / "pointProcAddressing");
  if (!fuzz::apply_patch(files, data + 1, size - 1)) return 0;
  fuzz::expect_clean([&] {
    OpenFoamCase foam(work);
    for (size_t step = 0; step < foam.step_count(); ++step) foam.read_step(step);
  });
  return 0;
}
