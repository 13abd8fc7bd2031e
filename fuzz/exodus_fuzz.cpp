// Exodus II: the classic-format test files (64-bit offset with three steps, a block of shells
// and a vector; classic with the old one-variable layouts) with one of them patched or
// truncated, read step by step as `convert` reads them, every element block or block 20 alone
// (the first byte's high bit). The NetCDF-4 form is left out: its parsing is the HDF5 library's,
// not volstream's.
#include "fuzz_util.h"
#include "volstream/io/exodus.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  namespace fs = std::filesystem;
  static const auto dir = fuzz::scratch("exodus");
  static const fs::path kBases[] = {fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/exodus/exodus_mixed.exo",
                                    fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/exodus/exodus_old.exo"};
  if (size < 1) return 0;
  const fs::path work = dir / "work.exo";
  fuzz::copy_file_contents(kBases[(data[0] & 0x7f) % std::size(kBases)], work);
  if (!fuzz::apply_patch({work}, data, size)) return 0;
  fuzz::expect_clean([&] {
    ExodusFile exo(work, (data[0] & 0x80) ? std::vector<std::string>{"20"} : std::vector<std::string>{});
    for (size_t step = 0; step < exo.step_count(); ++step) exo.read_step(step);
  });
  return 0;
}
