// Gmsh MSH: the test files Gmsh wrote (tests/data/gmsh: the tets in MSH 4.1 and 2.2, ascii and
// binary, with three steps of node and element views; the mixed mesh; the second-order ones; the
// mixed mesh with overlapping physical groups in 4.1 ascii, binary and partitioned, and 2.2
// binary) with one of them patched or truncated, read step by step as `convert` reads them,
// every element or the physical groups "top" and 11 alone (the first byte's high bit).
#include "fuzz_util.h"
#include "volstream/io/gmsh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  namespace fs = std::filesystem;
  static const auto dir = fuzz::scratch("gmsh");
  static const fs::path kData = fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/gmsh";
  static const fs::path kBases[] = {
      kData / "gmsh_tets_41a.msh",   kData / "gmsh_tets_41b.msh",  kData / "gmsh_tets_22a.msh",
      kData / "gmsh_tets_22b.msh",   kData / "gmsh_mixed.msh",     kData / "gmsh_serendipity.msh",
      kData / "gmsh_quadratic.msh",  kData / "gmsh_groups_41.msh", kData / "gmsh_groups_41b.msh",
      kData / "gmsh_groups_41p.msh", kData / "gmsh_groups_22.msh"};
  if (size < 1) return 0;
  const fs::path work = dir / "work.msh";
  fuzz::copy_file_contents(kBases[(data[0] & 0x7f) % std::size(kBases)], work);
  if (!fuzz::apply_patch({work}, data, size)) return 0;
  fuzz::expect_clean([&] {
    const GmshFile msh(work, (data[0] & 0x80) ? std::vector<std::string>{"top", "11"} : std::vector<std::string>{});
    for (size_t step = 0; step < msh.step_count(); ++step) msh.read_step(step);
  });
  return 0;
}
