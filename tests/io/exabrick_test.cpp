// ExaBrick importer: the on-disk format pinned with bytes written here, round trips through the
// writers and open_exabrick, conversion to a dataset, and bad input.
#include "volstream/io/exabrick.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/dataset.h"

namespace vs {
namespace {
namespace fs = std::filesystem;
using Key = std::array<int, 4>;  // x, y, z, level

Key key(const Cell& c) { return {c.lower.x, c.lower.y, c.lower.z, c.level}; }

// Little-endian bytes, composed by hand so that the test does not share code with the writer.
void put_u32(std::string& out, uint32_t v) {
  for (int b = 0; b < 4; ++b) out += char((v >> (8 * b)) & 0xff);
}
std::string cell_bytes(const std::vector<Cell>& cells) {
  std::string out;
  for (const Cell& c : cells)
    for (int32_t v : {c.lower.x, c.lower.y, c.lower.z, c.level}) put_u32(out, uint32_t(v));
  return out;
}
std::string float_bytes(const std::vector<float>& values) {
  std::string out;
  for (float v : values) put_u32(out, std::bit_cast<uint32_t>(v));
  return out;
}
void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}
std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A valid multi-level tiling (shuffled) and distinct exact values per (field, cell).
std::vector<Cell> sample_cells() { return test::random_octree_cells(7, vec3i(3, 2, 2), 3, 0.5); }
float value_of(int field, const Cell& c) {
  return float(1000 * field + c.lower.x) + 0.5f * float(c.lower.y) - 0.25f * float(c.lower.z) + 0.125f * float(c.level);
}
std::vector<float> field_values(int field, const std::vector<Cell>& cells) {
  std::vector<float> v;
  for (const Cell& c : cells) v.push_back(value_of(field, c));
  return v;
}

const std::vector<std::string> kFields = {"density", "temperature", "vx"};

struct Files {
  fs::path cells;
  std::vector<fs::path> scalars;
};
Files write_dataset(const fs::path& dir, const std::vector<Cell>& cells, bool library_writers) {
  Files f{dir / "cells.bin", {}};
  library_writers ? write_exabrick_cells(f.cells, cells) : write_bytes(f.cells, cell_bytes(cells));
  for (int n = 0; n < int(kFields.size()); ++n) {
    f.scalars.push_back(dir / (kFields[size_t(n)] + ".f32"));
    const auto v = field_values(n, cells);
    library_writers ? write_exabrick_scalars(f.scalars.back(), v) : write_bytes(f.scalars.back(), float_bytes(v));
  }
  return f;
}

TEST(ExaBrick, RoundTripSameCellsAndValues) {
  const std::vector<Cell> cells = sample_cells();
  ASSERT_GT(cells.size(), 50u);
  for (const bool library_writers : {true, false}) {
    SCOPED_TRACE(library_writers ? "write_exabrick_*" : "bytes written by the test");
    const Files f = write_dataset(test::scratch_dir(library_writers ? "lib" : "raw"), cells, library_writers);
    // The writers produce exactly the documented format.
    EXPECT_EQ(read_bytes(f.cells), cell_bytes(cells));
    for (int n = 0; n < int(kFields.size()); ++n)
      EXPECT_EQ(read_bytes(f.scalars[size_t(n)]), float_bytes(field_values(n, cells)));

    auto src = open_exabrick({f.cells, f.scalars});
    EXPECT_EQ(src->cell_count(), cells.size());
    EXPECT_EQ(src->field_names(), kFields);
    EXPECT_EQ(src->step_count(), 1);
    EXPECT_EQ(src->origin(), f.cells.string());
    const WorldTransform t = src->transform();
    EXPECT_EQ(t.origin, vec3d(0, 0, 0));
    EXPECT_EQ(t.cell_size, vec3d(1, 1, 1));

    const std::vector<Cell> got = src->take_cells();
    ASSERT_EQ(got.size(), cells.size());
    std::set<Key> want_set, got_set;
    for (size_t i = 0; i < cells.size(); ++i) {
      EXPECT_EQ(key(got[i]), key(cells[i])) << "input order, cell " << i;
      want_set.insert(key(cells[i]));
      got_set.insert(key(got[i]));
    }
    EXPECT_EQ(got_set, want_set);
    // Fields read in a scrambled order: each must come from its own file.
    for (int n : {2, 0, 1}) {
      std::vector<float> v(cells.size(), -1.f);
      src->read_values(n, 0, v.data());
      for (size_t i = 0; i < cells.size(); ++i)
        ASSERT_EQ(v[i], value_of(n, cells[i])) << kFields[size_t(n)] << " cell " << i;
    }
  }
}

TEST(ExaBrick, ScalarsAsTimeSeries) {
  const auto dir = test::scratch_dir("series");
  const std::vector<Cell> cells = sample_cells();
  write_bytes(dir / "cells.bin", cell_bytes(cells));
  ExaBrickInput in{dir / "cells.bin", {}, true, "rho"};
  for (int s = 0; s < 3; ++s) {
    in.scalars.push_back(dir / ("step" + std::to_string(s) + ".f32"));
    write_bytes(in.scalars.back(), float_bytes(field_values(s, cells)));
  }
  auto src = open_exabrick(in);
  EXPECT_EQ(src->field_names(), std::vector<std::string>{"rho"});
  ASSERT_EQ(src->step_count(), 3);
  std::vector<float> v(cells.size());
  for (int s : {1, 2, 0}) {
    src->read_values(0, s, v.data());
    for (size_t i = 0; i < cells.size(); ++i) ASSERT_EQ(v[i], value_of(s, cells[i])) << "step " << s << " cell " << i;
  }
}

TEST(ExaBrick, ConvertToDatasetKeepsValuesAtTheirCells) {
  const auto dir = test::scratch_dir("convert");
  const std::vector<Cell> cells = sample_cells();
  const Files f = write_dataset(dir, cells, false);
  auto src = open_exabrick({f.cells, f.scalars});
  convert_to_dataset(*src, dir / "ds", ConvertOptions::silent());

  const Dataset ds(dir / "ds");
  ASSERT_EQ(ds.manifest().cell_count, cells.size());
  ASSERT_EQ(ds.manifest().fields.size(), kFields.size());
  for (size_t n = 0; n < kFields.size(); ++n) EXPECT_EQ(ds.manifest().fields[n].name, kFields[n]);
  std::map<Key, size_t> input_index;
  for (size_t i = 0; i < cells.size(); ++i) input_index[key(cells[i])] = i;
  const std::vector<Cell> device = ds.load_cells();
  ASSERT_EQ(device.size(), cells.size());
  std::set<Key> seen;
  for (const Cell& c : device) {
    EXPECT_TRUE(input_index.count(key(c))) << "unknown cell " << c.lower.x << "," << c.lower.y << "," << c.lower.z;
    EXPECT_TRUE(seen.insert(key(c)).second) << "cell twice";
  }
  for (int n = 0; n < int(kFields.size()); ++n) {
    const std::vector<float> v = ds.load_values(n, 0);
    ASSERT_EQ(v.size(), cells.size());
    for (size_t i = 0; i < device.size(); ++i)
      ASSERT_EQ(v[i], value_of(n, cells[input_index.at(key(device[i]))])) << kFields[size_t(n)] << " device cell " << i;
  }
}

// ---------------------------------------------------------------------------------------------
// Bad input: InputError naming the offending file, at open or (for cell contents) at conversion.

struct BadCase {
  const char* name;
  // Breaks the valid files in `f`; returns the file the error must name.
  std::function<fs::path(Files& f, const std::vector<Cell>& cells)> damage;
};

fs::path rewrite_cells(Files& f, std::vector<Cell> cells, const std::function<void(std::vector<Cell>&)>& edit) {
  edit(cells);
  write_bytes(f.cells, cell_bytes(cells));
  return f.cells;
}
fs::path set_level(Files& f, const std::vector<Cell>& cells, int32_t level) {
  return rewrite_cells(f, cells, [&](auto& c) { c[c.size() / 2].level = level; });
}

const BadCase kBadCases[] = {
    {"scalars one short",
     [](Files& f, auto&) {
       fs::resize_file(f.scalars[1], fs::file_size(f.scalars[1]) - 4);
       return f.scalars[1];
     }},
    {"scalars one extra",
     [](Files& f, auto&) {
       fs::resize_file(f.scalars[2], fs::file_size(f.scalars[2]) + 4);
       return f.scalars[2];
     }},
    {"scalars not whole floats",
     [](Files& f, auto&) {
       fs::resize_file(f.scalars[0], fs::file_size(f.scalars[0]) - 1);
       return f.scalars[0];
     }},
    {"cells truncated",
     [](Files& f, auto&) {
       fs::resize_file(f.cells, fs::file_size(f.cells) - 5);
       return f.cells;
     }},
    {"cells one extra byte",
     [](Files& f, auto&) {
       fs::resize_file(f.cells, fs::file_size(f.cells) + 1);
       return f.cells;
     }},
    {"cells empty",
     [](Files& f, auto&) {
       fs::resize_file(f.cells, 0);
       return f.cells;
     }},
    {"cells missing",
     [](Files& f, auto&) {
       fs::remove(f.cells);
       return f.cells;
     }},
    {"scalar file empty",
     [](Files& f, auto&) {
       fs::resize_file(f.scalars[1], 0);
       return f.scalars[1];
     }},
    {"scalar file missing",
     [](Files& f, auto&) {
       fs::remove(f.scalars[2]);
       return f.scalars[2];
     }},
    {"no scalar files",
     [](Files& f, auto&) {
       f.scalars.clear();
       return f.cells;
     }},
    {"negative level", [](Files& f, auto& c) { return set_level(f, c, -1); }},
    {"level too large", [](Files& f, auto& c) { return set_level(f, c, kMaxLevel + 1); }},
    {"huge level", [](Files& f, auto& c) { return set_level(f, c, 1 << 30); }},
    {"duplicate cell", [](Files& f, auto& c) { return rewrite_cells(f, c, [](auto& v) { v[1] = v[0]; }); }},
    {"misaligned cell",
     [](Files& f, auto& c) {
       return rewrite_cells(f, c, [](auto& v) {
         std::find_if(v.begin(), v.end(), [](const Cell& x) { return x.level > 0; })->lower.x += 1;
       });
     }},
};

TEST(ExaBrickBad, ThrowsInputErrorNamingTheFile) {
  const std::vector<Cell> cells = sample_cells();
  for (const BadCase& bad : kBadCases) {
    SCOPED_TRACE(bad.name);
    const auto dir = test::scratch_dir("bad");
    Files f = write_dataset(dir, cells, true);
    const fs::path culprit = bad.damage(f, cells);
    try {
      auto src = open_exabrick({f.cells, f.scalars});
      convert_to_dataset(*src, dir / "ds", ConvertOptions::silent());
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), culprit.string()) << e.what();
    }
  }
}

}  // namespace
}  // namespace vs
