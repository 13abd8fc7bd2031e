// CGNS: the test files (an unstructured MIXED zone and a structured one over three steps;
// quadratic sections with vertex and cell-centred solutions; a polyhedral zone of NFACE_n cells
// and NGON_n faces; the same zone's cells by the faces' ParentElements) with one of them patched or
// truncated, read step by step as `convert` reads them, every zone or the zone "mixed" alone (the
// first byte's high bit). The CGNS and HDF5 libraries' own leaks
// on damaged files are not volstream's, so this target runs with leak detection off (fuzz/
// CMakeLists.txt); a crash in them is caught by the reader's child process (io/solver_files.h).
#include "fuzz_util.h"
#include "volstream/io/cgns.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  namespace fs = std::filesystem;
  static const auto dir = fuzz::scratch("cgns");
  static const fs::path kBases[] = {fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/cgns/cgns_mixed.cgns",
                                    fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/cgns/cgns_quadratic.cgns",
                                    fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/cgns/cgns_polyhedra.cgns",
                                    fs::path(VOLSTREAM_SOURCE_DIR) / "tests/data/cgns/cgns_ngon_parents.cgns"};
  if (size < 1) return 0;
  const fs::path work = dir / "work.cgns";
  fuzz::copy_file_contents(kBases[(data[0] & 0x7f) % std::size(kBases)], work);
  if (!fuzz::apply_patch({work}, data, size)) return 0;
  fuzz::expect_clean([&] {
    CgnsFile cgns(work, (data[0] & 0x80) ? std::vector<std::string>{"mixed"} : std::vector<std::string>{});
    for (size_t step = 0; step < cgns.step_count(); ++step) cgns.read_step(step);
  });
  return 0;
}
