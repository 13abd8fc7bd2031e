// Raw-grid importer: every value type in both byte orders, the cell layout, the world transform,
// files as steps or fields, type names and bad input.
#include "volstream/io/raw_grid.h"

#include <gtest/gtest.h>

#include <bit>
#include <fstream>

#include "test_util.h"
#include "volstream/core/error.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const vec3i kDims(4, 3, 2);

struct TypeCase {
  RawType type;
  const char* name;
  int bytes;
  double offset, scale;  // value = scale * (x + 10y + 100z) + offset: every byte used, signs
  bool is_float;
};
const TypeCase kTypes[] = {
    {RawType::u8, "uint8", 1, 0, 1, false},          {RawType::u16, "uint16", 2, 60000, 1, false},
    {RawType::i16, "int16", 2, -1000, 1, false},     {RawType::u32, "uint32", 4, 70000, 1, false},
    {RawType::i32, "int32", 4, -100000, 1, false},   {RawType::f32, "float32", 4, -60.25, 0.5, true},
    {RawType::f64, "float64", 8, -1e-3, -2.5, true},
};

double grid_value(const TypeCase& t, int x, int y, int z, int step = 0) {
  return t.scale * (x + 10 * y + 100 * z + step) + t.offset;
}

// The bit pattern of `v` as type t, in the low t.bytes bytes, composed without the importer.
uint64_t bits(const TypeCase& t, double v) {
  if (t.is_float) return t.bytes == 4 ? std::bit_cast<uint32_t>(float(v)) : std::bit_cast<uint64_t>(v);
  return uint64_t(int64_t(v));  // two's complement; the writer keeps the low bytes
}

// x-fastest grid, each value's bytes in the requested order.
std::string grid_bytes(const TypeCase& t, bool big_endian, int step = 0) {
  std::string out;
  for (int z = 0; z < kDims.z; ++z)
    for (int y = 0; y < kDims.y; ++y)
      for (int x = 0; x < kDims.x; ++x) {
        const uint64_t b = bits(t, grid_value(t, x, y, z, step));
        for (int i = 0; i < t.bytes; ++i) out += char((b >> (8 * (big_endian ? t.bytes - 1 - i : i))) & 0xff);
      }
  return out;
}
void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

TEST(RawGrid, EveryTypeAndByteOrderDecodes) {
  const auto dir = test::scratch_dir("types");
  for (const TypeCase& t : kTypes)
    for (const bool big : {false, true}) {
      SCOPED_TRACE(std::string(t.name) + (big ? " big-endian" : " little-endian"));
      const fs::path file = dir / (std::string(t.name) + (big ? ".be" : ".le"));
      write_bytes(file, grid_bytes(t, big));
      auto src = open_raw_grid({.files = {file}, .dims = kDims, .type = t.type, .big_endian = big});
      ASSERT_EQ(src->cell_count(), 24u);
      std::vector<float> v(24, -12345.f);
      src->read_values(0, 0, v.data());
      int negative = 0;
      for (int z = 0, i = 0; z < kDims.z; ++z)
        for (int y = 0; y < kDims.y; ++y)
          for (int x = 0; x < kDims.x; ++x, ++i) {
            const double want = grid_value(t, x, y, z);
            negative += want < 0;
            EXPECT_EQ(v[size_t(i)], float(want)) << "at " << x << "," << y << "," << z;
          }
      if (t.offset < 0) {
        EXPECT_GT(negative, 0);
      }
    }
}

TEST(RawGrid, SingleLevelGridCellsAndTransform) {
  const auto dir = test::scratch_dir("cells");
  write_bytes(dir / "a.raw", grid_bytes(kTypes[0], false));
  RawGridInput in{.files = {dir / "a.raw"}, .dims = kDims, .type = RawType::u8, .field_name = "phi"};
  in.origin = vec3d(-1, 2, 0.5);
  in.spacing = vec3d(0.25, 2, 3);
  auto src = open_raw_grid(in);
  const WorldTransform t = src->transform();
  EXPECT_EQ(t.origin, in.origin);
  EXPECT_EQ(t.cell_size, in.spacing);
  EXPECT_EQ(t.to_world(vec3d(4, 3, 2)), vec3d(0, 8, 6.5));
  EXPECT_EQ(src->field_names(), std::vector<std::string>{"phi"});
  EXPECT_EQ(src->step_count(), 1);
  EXPECT_EQ(src->origin(), (dir / "a.raw").string());
  const std::vector<Cell> cells = src->take_cells();
  ASSERT_EQ(cells.size(), 24u);
  for (int z = 0, i = 0; z < kDims.z; ++z)
    for (int y = 0; y < kDims.y; ++y)
      for (int x = 0; x < kDims.x; ++x, ++i) {
        EXPECT_EQ(cells[size_t(i)].lower, vec3i(x, y, z)) << "cell " << i;
        EXPECT_EQ(cells[size_t(i)].level, 0) << "cell " << i;
      }
}

TEST(RawGrid, FilesAsStepsOrAsFields) {
  const auto dir = test::scratch_dir("multi");
  const TypeCase& t = kTypes[4];  // int32
  std::vector<fs::path> files;
  for (int s = 0; s < 3; ++s) {
    files.push_back(dir / ("f" + std::to_string(s) + ".i32"));
    write_bytes(files.back(), grid_bytes(t, false, 1000 * s));
  }
  for (const bool as_fields : {false, true}) {
    SCOPED_TRACE(as_fields ? "fields" : "steps");
    auto src = open_raw_grid({.files = files, .dims = kDims, .type = t.type, .files_are_fields = as_fields});
    EXPECT_EQ(src->step_count(), as_fields ? 1 : 3);
    const std::vector<std::string> names =
        as_fields ? std::vector<std::string>{"f0", "f1", "f2"} : std::vector<std::string>{"scalar"};
    EXPECT_EQ(src->field_names(), names);
    std::vector<float> v(24);
    for (int n : {2, 0, 1}) {
      src->read_values(as_fields ? n : 0, as_fields ? 0 : n, v.data());
      EXPECT_EQ(v[23], float(grid_value(t, 3, 2, 1, 1000 * n)));
      EXPECT_EQ(v[0], float(grid_value(t, 0, 0, 0, 1000 * n)));
    }
  }
}

TEST(RawGrid, ParseRawType) {
  for (const TypeCase& t : kTypes) {
    EXPECT_EQ(parse_raw_type(t.name), t.type) << t.name;
    EXPECT_EQ(raw_type_size(t.type), size_t(t.bytes)) << t.name;
  }
  EXPECT_EQ(parse_raw_type("float"), RawType::f32);
  EXPECT_EQ(parse_raw_type("double"), RawType::f64);
  for (const char* bad : {"", "uint64", "int8", "Float32", "f32", "float32 ", "u8"})
    EXPECT_THROW(parse_raw_type(bad), UsageError) << "'" << bad << "'";
}

TEST(RawGridBad, FileSizeMustMatchDimsAndType) {
  const auto dir = test::scratch_dir("size");
  const fs::path file = dir / "g.raw";
  struct Case {
    const char* name;
    RawType type;
    int64_t bytes;
  };
  for (const Case& c : {Case{"one short", RawType::f32, 24 * 4 - 1}, Case{"one extra", RawType::f32, 24 * 4 + 1},
                        Case{"other type size", RawType::f64, 24 * 4}, Case{"empty", RawType::u8, 0},
                        Case{"one value short", RawType::u16, 23 * 2}}) {
    SCOPED_TRACE(c.name);
    write_bytes(file, std::string(size_t(c.bytes), '\x01'));
    try {
      open_raw_grid({.files = {file}, .dims = kDims, .type = c.type});
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file.string()) << e.what();
    }
  }
  // A missing file, and a bad one behind a good one, are named too.
  write_bytes(dir / "good.raw", std::string(24, '\0'));
  write_bytes(file, std::string(23, '\0'));
  for (const fs::path& culprit : {dir / "missing.raw", file}) {
    try {
      open_raw_grid({.files = {dir / "good.raw", culprit}, .dims = kDims, .type = RawType::u8});
      ADD_FAILURE() << "no error for " << culprit;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), culprit.string()) << e.what();
    }
  }
}

TEST(RawGridBad, DimensionsAndFileListAreUsageErrors) {
  const auto dir = test::scratch_dir("usage");
  write_bytes(dir / "g.raw", std::string(24, '\0'));
  for (const vec3i d : {vec3i(0, 3, 2), vec3i(4, -1, 2), vec3i(4, 3, (1 << 16) + 1)})
    EXPECT_THROW(open_raw_grid({.files = {dir / "g.raw"}, .dims = d, .type = RawType::u8}), UsageError);
  EXPECT_THROW(open_raw_grid({.files = {}, .dims = kDims, .type = RawType::u8}), UsageError);
}

}  // namespace
}  // namespace vs
