// ExaBrick cells + scalars: the input is split into a cells file and a scalars file.
#include <cstring>
#include <fstream>

#include "fuzz_util.h"
#include "volstream/io/dataset.h"
#include "volstream/io/exabrick.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("exabrick");
  if (size < 2 || size > (1 << 16)) return 0;
  const size_t split = std::min<size_t>(size - 1, size_t(data[0]) * 16 + 1);
  std::ofstream(dir / "a.cells", std::ios::binary | std::ios::trunc)
      .write((const char*)data + 1, std::streamsize(split - 1));
  std::ofstream(dir / "a.scalars", std::ios::binary | std::ios::trunc)
      .write((const char*)data + split, std::streamsize(size - split));
  fuzz::expect_clean([&] {
    auto source = open_exabrick({dir / "a.cells", {dir / "a.scalars"}});
    convert_to_dataset(*source, dir / "out", ConvertOptions::silent());
    Dataset ds(dir / "out");
    (void)ds.load_values(0, 0);
  });
  return 0;
}
