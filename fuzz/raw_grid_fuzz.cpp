// Raw grids: dimensions and type come from the first bytes, the rest is the file.
#include <fstream>

#include "fuzz_util.h"
#include "volstream/io/dataset.h"
#include "volstream/io/raw_grid.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("raw");
  if (size < 4 || size > (1 << 16)) return 0;
  static const char* kTypes[] = {"uint8", "uint16", "int16", "uint32", "int32", "float32", "float64"};
  RawGridInput in;
  in.dims = {data[0] % 9, data[1] % 9, data[2] % 9};
  std::ofstream(dir / "g.raw", std::ios::binary | std::ios::trunc)
      .write((const char*)data + 4, std::streamsize(size - 4));
  in.files = {dir / "g.raw"};
  in.big_endian = data[3] & 0x80;
  fuzz::expect_clean([&] {
    in.type = parse_raw_type(kTypes[(data[3] & 0x7f) % 7]);
    auto source = open_raw_grid(in);
    convert_to_dataset(*source, dir / "out", ConvertOptions::silent());
  });
  return 0;
}
