#include "volstream/io/raw_grid.h"

#include <algorithm>
#include <cstring>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"

namespace vs {

RawType parse_raw_type(const std::string& name) {
  static const std::pair<const char*, RawType> kNames[] = {
      {"uint8", RawType::u8},   {"uint16", RawType::u16},  {"int16", RawType::i16},
      {"uint32", RawType::u32}, {"int32", RawType::i32},   {"float32", RawType::f32},
      {"float", RawType::f32},  {"float64", RawType::f64}, {"double", RawType::f64}};
  for (const auto& [n, t] : kNames)
    if (name == n) return t;
  throw UsageError("unknown raw type '" + name + "' (uint8, uint16, int16, uint32, int32, float32, float64)");
}

size_t raw_type_size(RawType t) {
  switch (t) {
    case RawType::u8:
      return 1;
    case RawType::u16:
    case RawType::i16:
      return 2;
    case RawType::u32:
    case RawType::i32:
    case RawType::f32:
      return 4;
    case RawType::f64:
      return 8;
  }
  return 0;
}

namespace {

template <typename T>
float decode(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return float(v);
}

float decode_value(RawType t, const unsigned char* p, bool swap) {
  switch (t) {
    case RawType::u8:
      return float(*p);
    case RawType::u16:
      return decode<uint16_t>(p, swap);
    case RawType::i16:
      return decode<int16_t>(p, swap);
    case RawType::u32:
      return decode<uint32_t>(p, swap);
    case RawType::i32:
      return decode<int32_t>(p, swap);
    case RawType::f32:
      return decode<float>(p, swap);
    case RawType::f64:
      return decode<double>(p, swap);
  }
  return 0.f;
}

class RawGridSource : public AmrSource {
 public:
  explicit RawGridSource(const RawGridInput& in) : in_(in) {
    for (int a = 0; a < 3; ++a)
      if (in.dims[a] < 1 || in.dims[a] > (1 << 16)) throw UsageError("raw grid dimensions must be 1..65536 per axis");
    if (in.files.empty()) throw UsageError("no raw files given");
    count_ = uint64_t(in.dims.x) * in.dims.y * in.dims.z;
    if (count_ >= UINT32_MAX) throw UsageError("raw grid has too many cells");
    for (const auto& f : in.files) {
      const uint64_t size = file_size_checked(f), want = count_ * raw_type_size(in.type);
      if (size != want)
        input_error(f.string(), "size " + std::to_string(size) + " bytes, expected " + std::to_string(want) +
                                    " for the given dimensions and type");
    }
  }
  std::vector<Cell> take_cells() override {
    std::vector<Cell> cells(count_);
    const vec3i d = in_.dims;
    parallel_for("raw_cells", int64_t(count_), [&](int64_t i) {
      const int32_t x = int32_t(i % d.x), y = int32_t((i / d.x) % d.y), z = int32_t(i / (int64_t(d.x) * d.y));
      cells[size_t(i)] = {vec3i(x, y, z), 0};
    });
    return cells;
  }
  uint64_t cell_count() const override { return count_; }
  WorldTransform transform() const override { return {in_.origin, in_.spacing}; }
  std::vector<std::string> field_names() const override {
    if (!in_.files_are_fields) return {in_.field_name};
    std::vector<std::string> names;
    for (const auto& f : in_.files) names.push_back(f.stem().string());
    return names;
  }
  int step_count() const override { return in_.files_are_fields ? 1 : int(in_.files.size()); }
  void read_values(int field, int step, float* out) override {
    const auto& path = in_.files.at(size_t(in_.files_are_fields ? field : step));
    const size_t size = raw_type_size(in_.type);
    std::vector<unsigned char> bytes(count_ * size);
    read_exact(path, 0, bytes.data(), bytes.size());
    parallel_for("raw_decode", int64_t(count_),
                 [&](int64_t i) { out[i] = decode_value(in_.type, &bytes[size_t(i) * size], in_.big_endian); });
  }
  std::string description() const override { return "raw grid " + in_.files.front().filename().string(); }
  std::string origin() const override { return in_.files.front().string(); }

 private:
  RawGridInput in_;
  uint64_t count_ = 0;
};
}  // namespace

std::unique_ptr<AmrSource> open_raw_grid(const RawGridInput& input) { return std::make_unique<RawGridSource>(input); }

}  // namespace vs
