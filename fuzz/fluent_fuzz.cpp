// Fluent: the test cases of tests/data/fluent (an ASCII case and data file; binary ones with
// float64 nodes and data; a binary case of polyhedra with float32 nodes and data) with the case
// or the data file patched or truncated, read step by step as `convert` reads them, all cell
// zones or the mixed cases' solid alone (the first byte's high bit).
#include <iterator>
#include <string>

#include "fuzz_util.h"
#include "volstream/io/fluent.h"

namespace {
const char* const kCases[] = {"fluent_mixed", "fluent_mixed_bin", "fluent_poly"};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  namespace fs = std::filesystem;
  static const auto dir = fuzz::scratch("fluent");
  const fs::path base = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "fluent";
  if (size < 1) return 0;
  const std::string name = kCases[(data[0] & 0x7f) % std::size(kCases)];
  const std::vector<fs::path> files = {dir / "work.cas", dir / "work.dat"};
  fuzz::copy_file_contents(base / (name + ".cas"), files[0]);
  fuzz::copy_file_contents(base / (name + ".dat"), files[1]);
  if (!fuzz::apply_patch(files, data + 1, size - 1)) return 0;
  fuzz::expect_clean([&] {
    const bool one_zone = (data[0] & 0x80) && name != "fluent_poly";  // the mixed cases' solid
    FluentFile fluent(files[0], {}, one_zone ? std::vector<std::string>{"solid"} : std::vector<std::string>{});
    for (size_t step = 0; step < fluent.step_count(); ++step) fluent.read_step(step);
  });
  return 0;
}
