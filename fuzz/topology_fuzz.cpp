// The topology of a native dataset, mutated by value rather than by bytes: each 8-byte record of
// the input picks a topology or values file, a 4-byte slot in it and a new value (a float for ABR
// boxes, widths and values, an integer for brick fields and brick lists). Sizes stay valid, so
// every input reaches the geometry checks, the BVH build, ranges and point location.
#include <cstring>
#include <fstream>
#include <vector>

#include "fuzz_util.h"
#include "volstream/amr/abrs.h"
#include "volstream/amr/probe.h"
#include "volstream/amr/ranges.h"
#include "volstream/io/dataset.h"
#include "volstream/io/raw_grid.h"

namespace {
namespace fs = std::filesystem;

fs::path make_base(const fs::path& dir) {
  using namespace vs;
  std::vector<float> v(6 * 5 * 4);
  for (size_t i = 0; i < v.size(); ++i) v[i] = float(i % 7);
  std::ofstream(dir / "g.raw", std::ios::binary).write((const char*)v.data(), std::streamsize(v.size() * 4));
  RawGridInput in;
  in.files = {dir / "g.raw"};
  in.dims = {6, 5, 4};
  auto source = open_raw_grid(in);
  convert_to_dataset(*source, dir / "base", ConvertOptions::silent());
  return dir / "base";
}

// Overwrites the 4-byte slot `slot` (modulo the file's slot count) with `bits`.
void poke(const fs::path& file, uint32_t slot, uint32_t bits) {
  std::fstream f(file, std::ios::binary | std::ios::in | std::ios::out);
  f.seekg(0, std::ios::end);
  const auto slots = uint32_t(f.tellg() / 4);
  if (slots == 0) return;
  f.seekp(std::streamoff(slot % slots) * 4);
  f.write(reinterpret_cast<const char*>(&bits), 4);
}

// Values worth trying in a float slot: specials and edges as well as the raw bits.
uint32_t float_bits(uint8_t kind, uint32_t raw) {
  static const float specials[] = {NAN, INFINITY, -INFINITY, 0.f, -0.f, 0.5f, 1e6f, -1e6f, 1e-25f, 3.4e38f, 2.f, 64.f};
  if (kind >= sizeof(specials) / sizeof(float)) return raw;
  uint32_t bits;
  std::memcpy(&bits, &specials[kind], 4);
  return bits;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("topology");
  static const auto base = make_base(dir);
  const auto work = dir / "work";
  fuzz::copy_tree(base, work);
  const fs::path files[] = {work / "abrs.bin", work / "bricks.bin", work / "abr_bricks.bin",
                            work / "fields/0_scalar/step_000000.f32"};
  for (size_t k = 0; k + 8 <= size && k < 8 * 16; k += 8) {
    const uint8_t which = data[k] % 4, kind = data[k + 1];
    uint32_t slot, raw;
    std::memcpy(&slot, data + k + 2, 2);
    slot &= 0xffff;
    std::memcpy(&raw, data + k + 4, 4);
    const bool is_float = which == 0 || which == 3;
    poke(files[which], slot, is_float ? float_bits(kind % 16, raw) : (kind & 1 ? raw : raw % 256));
  }
  fuzz::expect_clean([&] {
    Dataset ds(work);
    const auto values = ds.load_values(0, 0);
    (void)compute_abr_ranges(ds.topology(), values.data());
    const Bvh bvh = build_abr_bvh(ds.topology());
    (void)probe_points(ds.topology(), bvh, values.data(),
                       {vec3f(1.f, 1.f, 1.f), vec3f(3.5f, 2.5f, 1.5f), vec3f(-1.f, 0.f, 0.f), vec3f(NAN, 0.f, 0.f)});
  });
  return 0;
}
