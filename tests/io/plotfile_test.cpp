// AMReX plotfile importer: round trips through write_plotfile, and bad input.
#include "volstream/io/plotfile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "test_util.h"
#include "volstream/core/error.h"

namespace vs {
namespace {
namespace fs = std::filesystem;
using ValueFn = std::function<double(int, int, int, int, int)>;

box3i ibox(int x0, int y0, int z0, int x1, int y1, int z1) { return {vec3i(x0, y0, z0), vec3i(x1, y1, z1)}; }

double smooth_value(int c, int l, int i, int j, int k) {
  return 1000.0 * c + 100.0 * l + 1.37 * i - 0.71 * j + 0.113 * k + 0.5;
}

// (a) 3 levels, ratio 2, several boxes per level (a level-1 box spans two level-0 boxes and a
// level-2 box spans two level-1 boxes), float64.
PlotfileSpec three_level_spec() {
  PlotfileSpec s;
  s.components = {"density", "pressure"};
  s.prob_hi = {1, 1, 0.5};
  s.level0_domain = ibox(0, 0, 0, 15, 15, 7);
  s.ref_ratios = {2, 2};
  s.levels = {
      PlotfileLevel{
          {ibox(0, 0, 0, 7, 7, 7), ibox(8, 0, 0, 15, 7, 7), ibox(0, 8, 0, 7, 15, 7), ibox(8, 8, 0, 15, 15, 7)}},
      PlotfileLevel{{ibox(4, 4, 2, 13, 11, 9), ibox(16, 16, 4, 27, 23, 11), ibox(14, 4, 2, 19, 9, 7)}},
      PlotfileLevel{{ibox(8, 8, 4, 15, 15, 11), ibox(16, 8, 4, 23, 13, 9), ibox(24, 8, 4, 31, 19, 15),
                     ibox(36, 34, 10, 47, 45, 21)}},
  };
  s.time = 1.25;
  return s;
}

// (b) 2 levels, ratio 4, float32, a domain that does not start at 0 and a world box off the origin.
PlotfileSpec ratio4_spec() {
  PlotfileSpec s;
  s.components = {"u", "v", "w"};
  s.prob_lo = {-1, 0, 2};
  s.prob_hi = {1, 3, 4};
  s.level0_domain = ibox(-4, -2, 0, 3, 3, 3);
  s.ref_ratios = {4};
  s.levels = {PlotfileLevel{{ibox(-4, -2, 0, -1, 3, 3), ibox(0, -2, 0, 3, 3, 3)}},
              PlotfileLevel{{ibox(-12, -4, 0, -5, 3, 7), ibox(-4, -4, 4, 3, 7, 15)}}};
  s.float32 = true;
  s.boxes_per_fab_file = 1;
  return s;
}

// The leaves computed the slow, obvious way: every cell of every box, dropped when its first
// child lies in a box of the next level. Keyed by (lower, level) in grid units.
struct ExpectedCell {
  int level, i, j, k;
};
using Key = std::array<int, 4>;

std::map<Key, ExpectedCell> expected_leaves(const PlotfileSpec& s) {
  const int levels = int(s.levels.size());
  std::vector<box3i> domains{s.level0_domain};
  std::vector<int> width(size_t(levels), 1);
  for (int l = 1; l < levels; ++l) {
    const int r = s.ref_ratios[size_t(l - 1)];
    domains.push_back({domains.back().lower * r, (domains.back().upper + vec3i(1)) * r - vec3i(1)});
  }
  for (int l = levels - 2; l >= 0; --l) width[size_t(l)] = width[size_t(l + 1)] * s.ref_ratios[size_t(l)];
  std::map<Key, ExpectedCell> out;
  for (int l = 0; l < levels; ++l)
    for (const box3i& b : s.levels[size_t(l)].boxes)
      for (int k = b.lower.z; k <= b.upper.z; ++k)
        for (int j = b.lower.y; j <= b.upper.y; ++j)
          for (int i = b.lower.x; i <= b.upper.x; ++i) {
            bool covered = false;
            if (l + 1 < levels) {
              const int r = s.ref_ratios[size_t(l)];
              for (const box3i& f : s.levels[size_t(l + 1)].boxes) covered |= f.contains(vec3i(i * r, j * r, k * r));
            }
            if (covered) continue;
            const vec3i g = (vec3i(i, j, k) - domains[size_t(l)].lower) * width[size_t(l)];
            out[{g.x, g.y, g.z, std::countr_zero(unsigned(width[size_t(l)]))}] = {l, i, j, k};
          }
  return out;
}

// Everything a converter would do with a source: cells and every field of every step.
void read_everything(const std::vector<fs::path>& dirs) {
  auto src = open_plotfile_series(dirs);
  src->take_cells();
  std::vector<float> values(src->cell_count());
  for (int s = 0; s < src->step_count(); ++s)
    for (int f = 0; f < int(src->field_names().size()); ++f) src->read_values(f, s, values.data());
}

// Checks cells and values of step `step` against the spec, and that the leaves tile the level-0
// boxes exactly (every finest-unit position covered once).
void check_source(AmrSource& src, const PlotfileSpec& s, const ValueFn& value, int step = 0) {
  const auto expected = expected_leaves(s);
  ASSERT_EQ(src.cell_count(), expected.size());
  EXPECT_EQ(src.field_names(), s.components);
  const std::vector<Cell> cells = src.take_cells();
  ASSERT_EQ(cells.size(), expected.size());

  std::vector<std::vector<float>> fields;
  for (int f = 0; f < int(s.components.size()); ++f) {
    fields.emplace_back(cells.size());
    src.read_values(f, step, fields.back().data());
  }
  std::set<Key> seen;
  std::set<std::array<int, 3>> finest;
  for (size_t n = 0; n < cells.size(); ++n) {
    const Cell& c = cells[n];
    const Key key{c.lower.x, c.lower.y, c.lower.z, c.level};
    ASSERT_TRUE(seen.insert(key).second) << "cell listed twice";
    const auto it = expected.find(key);
    ASSERT_NE(it, expected.end()) << "unexpected cell (covered or outside every box) at " << c.lower.x << ","
                                  << c.lower.y << "," << c.lower.z << " level " << c.level;
    const ExpectedCell& e = it->second;
    for (int f = 0; f < int(s.components.size()); ++f)
      ASSERT_EQ(fields[size_t(f)][n], float(value(f, e.level, e.i, e.j, e.k))) << "field " << f << " cell " << n;
    const int w = level_width(c.level);
    for (int z = 0; z < w; ++z)
      for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_TRUE(finest.insert({c.lower.x + x, c.lower.y + y, c.lower.z + z}).second) << "cells overlap";
  }
  // The leaves cover exactly the level-0 boxes.
  uint64_t level0 = 0;
  int w0 = 1;
  for (int r : s.ref_ratios) w0 *= r;
  for (const box3i& b : s.levels[0].boxes) level0 += uint64_t(b.size().x + 1) * (b.size().y + 1) * (b.size().z + 1);
  EXPECT_EQ(finest.size(), level0 * uint64_t(w0) * w0 * w0);
}

void check_transform(const AmrSource& src, const PlotfileSpec& s) {
  int w0 = 1;
  for (int r : s.ref_ratios) w0 *= r;
  const WorldTransform t = src.transform();
  for (int a = 0; a < 3; ++a) {
    EXPECT_DOUBLE_EQ(t.origin[a], s.prob_lo[a]);
    const double finest_cells = double(s.level0_domain.upper[a] - s.level0_domain.lower[a] + 1) * w0;
    EXPECT_DOUBLE_EQ(t.cell_size[a], (s.prob_hi[a] - s.prob_lo[a]) / finest_cells);
  }
}

std::string read_file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
void write_file_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}
// Replaces line `n` (0-based) of a text file.
void replace_line(const fs::path& p, int n, const std::string& line) {
  std::istringstream in(read_file_text(p));
  std::string out, l;
  for (int i = 0; std::getline(in, l); ++i) out += (i == n ? line : l) + "\n";
  write_file_text(p, out);
}

// ---------------------------------------------------------------------------------------------

TEST(Plotfile, ThreeLevelsRatio2Float64) {
  const auto dir = test::scratch_dir("plt") / "plt00000";
  const PlotfileSpec spec = three_level_spec();
  write_plotfile(dir, spec, smooth_value);
  ASSERT_TRUE(fs::exists(dir / "Level_2" / "Cell_D_00001"));  // several FABs per file, several files
  ASSERT_TRUE(is_plotfile(dir));
  auto src = open_plotfile_series({dir});
  EXPECT_EQ(src->step_count(), 1);
  EXPECT_DOUBLE_EQ(src->step_time(0), 1.25);
  check_transform(*src, spec);
  check_source(*src, spec, smooth_value);
}

TEST(Plotfile, TwoLevelsRatio4Float32) {
  const auto dir = test::scratch_dir("plt") / "plt00000";
  const PlotfileSpec spec = ratio4_spec();
  write_plotfile(dir, spec, smooth_value);
  auto src = open_plotfile_series({dir});
  check_transform(*src, spec);
  check_source(*src, spec, smooth_value);
}

TEST(Plotfile, CoveredCellsAreAbsent) {
  const auto dir = test::scratch_dir("plt") / "plt00000";
  PlotfileSpec spec = three_level_spec();
  write_plotfile(dir, spec, smooth_value);
  auto src = open_plotfile_series({dir});
  const auto cells = src->take_cells();
  // Level-0 cell (2,2,1) (grid (8,8,4), width 4) lies under level-1 box 0; level-1 cell (4,4,2)
  // (grid (8,8,4), width 2) lies under level-2 box 0: only level-2 cells remain there.
  int found = 0;
  for (const Cell& c : cells) {
    if (!(c.lower == vec3i(8, 8, 4))) continue;
    EXPECT_EQ(c.level, 0);
    ++found;
  }
  EXPECT_EQ(found, 1);
}

TEST(Plotfile, BigEndianGhostCellsAndNonFiniteValues) {
  const auto dir = test::scratch_dir("plt") / "plt00000";
  PlotfileSpec spec = ratio4_spec();
  spec.float32 = false;
  spec.big_endian = true;
  spec.nghost = 2;
  const ValueFn value = [](int c, int l, int i, int j, int k) {
    if (l == 1 && i == 0 && j == 0 && k == 5) return std::nan("");
    if (l == 0 && i == 3 && j == 3 && k == 3) return c == 0 ? INFINITY : 1e300;  // 1e300 -> float inf
    return smooth_value(c, l, i, j, k);
  };
  write_plotfile(dir, spec, value);
  auto src = open_plotfile_series({dir});
  const auto cells = src->take_cells();
  const auto expected = expected_leaves(spec);
  for (int f = 0; f < 2; ++f) {
    std::vector<float> v(cells.size());
    src->read_values(f, 0, v.data());
    int nan = 0, inf = 0;
    for (size_t n = 0; n < cells.size(); ++n) {
      const auto& e = expected.at({cells[n].lower.x, cells[n].lower.y, cells[n].lower.z, cells[n].level});
      const double want = value(f, e.level, e.i, e.j, e.k);
      nan += std::isnan(v[n]);
      inf += std::isinf(v[n]);
      if (std::isnan(want))
        EXPECT_TRUE(std::isnan(v[n]));
      else
        EXPECT_EQ(v[n], want > 1e39 ? INFINITY : float(want));  // beyond float range: inf, like the reader
    }
    EXPECT_EQ(nan, 1);
    EXPECT_EQ(inf, 1);
  }
}

TEST(Plotfile, SeriesOfThreeSteps) {
  const auto root = test::scratch_dir("series");
  const PlotfileSpec base = three_level_spec();
  std::vector<fs::path> dirs;
  for (int s = 0; s < 3; ++s) {
    PlotfileSpec spec = base;
    spec.time = 0.5 + s;
    dirs.push_back(root / ("plt0000" + std::to_string(s)));
    write_plotfile(dirs.back(), spec,
                   [s](int c, int l, int i, int j, int k) { return smooth_value(c, l, i, j, k) + 10000.0 * s; });
  }
  auto src = open_plotfile_series(dirs);
  ASSERT_EQ(src->step_count(), 3);
  for (int s = 0; s < 3; ++s) EXPECT_DOUBLE_EQ(src->step_time(s), 0.5 + s);
  check_transform(*src, base);
  // Out of order on purpose: every step must come from its own files.
  for (int s : {2, 0, 1}) {
    auto fresh = open_plotfile_series(dirs);
    check_source(
        *fresh, base, [s](int c, int l, int i, int j, int k) { return smooth_value(c, l, i, j, k) + 10000.0 * s; }, s);
  }
}

TEST(Plotfile, IsPlotfile) {
  const auto root = test::scratch_dir("detect");
  write_plotfile(root / "plt", ratio4_spec(), smooth_value);
  EXPECT_TRUE(is_plotfile(root / "plt"));
  EXPECT_FALSE(is_plotfile(root / "plt" / "Header"));
  EXPECT_FALSE(is_plotfile(root / "missing"));
  fs::create_directories(root / "other");
  write_file_text(root / "other" / "Header", "CheckPointVersion_1.0\n");
  EXPECT_FALSE(is_plotfile(root / "other"));
  write_file_text(root / "other" / "Header", "\x01\x02garbage\n");
  EXPECT_FALSE(is_plotfile(root / "other"));
}

// ---------------------------------------------------------------------------------------------
// Bad input: every case must end in vs::InputError, never a crash.

fs::path write_small(const std::string& name, const PlotfileSpec& spec = three_level_spec()) {
  const auto dir = test::scratch_dir(name) / "plt00000";
  write_plotfile(dir, spec, smooth_value);
  return dir;
}

TEST(PlotfileBad, TruncatedFabFile) {
  for (const double keep : {0.5, 0.95}) {
    const auto dir = write_small("trunc");
    const auto file = dir / "Level_0" / "Cell_D_00000";
    fs::resize_file(file, uint64_t(double(fs::file_size(file)) * keep));
    EXPECT_THROW(read_everything({dir}), InputError);
  }
}

TEST(PlotfileBad, MissingFabFile) {
  const auto dir = write_small("missing");
  fs::remove(dir / "Level_1" / "Cell_D_00001");
  EXPECT_THROW(read_everything({dir}), InputError);
}

TEST(PlotfileBad, GarbageHeader) {
  const auto dir = write_small("garbage");
  write_file_text(dir / "Header", "HyperCLaw-V1.1\n2\ndensity\npressure\n3\nbanana\n");
  EXPECT_THROW(read_everything({dir}), InputError);
  write_file_text(dir / "Header", std::string("\x7f"
                                              "ELF\x02\x01\x01\0\0\0",
                                              10));
  EXPECT_THROW(read_everything({dir}), InputError);
  write_file_text(dir / "Header", "");
  EXPECT_THROW(read_everything({dir}), InputError);
}

TEST(PlotfileBad, RaggedHeader) {
  // Drop the first grid-bounds line of level 1: the rest of the Header shifts by a line.
  const auto dir = write_small("ragged");
  std::istringstream in(read_file_text(dir / "Header"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  const auto level1 =
      std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("1 3 ", 0) == 0; });
  ASSERT_NE(level1, lines.end());
  lines.erase(level1 + 2);  // after "1 3 time" and the step line
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  write_file_text(dir / "Header", out);
  EXPECT_THROW(read_everything({dir}), InputError);
}

TEST(PlotfileBad, HugeComponentCount) {
  const auto dir = write_small("ncomp");
  replace_line(dir / "Header", 1, "1000000000");
  EXPECT_THROW(read_everything({dir}), InputError);
  replace_line(dir / "Header", 1, "-3");
  EXPECT_THROW(read_everything({dir}), InputError);
}

TEST(PlotfileBad, CellHeaderComponentCountMismatch) {
  const auto dir = write_small("cellh");
  replace_line(dir / "Level_1" / "Cell_H", 2, "3");
  try {
    read_everything({dir});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("Cell_H"), std::string::npos);
  }
}

TEST(PlotfileBad, BoxOutsideDomain) {
  PlotfileSpec spec = ratio4_spec();
  spec.levels[0].boxes[1] = ibox(0, -2, 0, 4, 3, 3);  // x up to 4, the domain ends at 3
  spec.levels.pop_back();
  spec.ref_ratios.clear();
  const auto dir = write_small("outside", spec);
  try {
    read_everything({dir});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("Cell_H"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("outside"), std::string::npos);
  }
}

TEST(PlotfileBad, InconsistentHierarchies) {
  {  // overlapping boxes within a level
    PlotfileSpec spec = three_level_spec();
    spec.levels[1].boxes[2] = ibox(12, 4, 2, 19, 9, 7);
    EXPECT_THROW(read_everything({write_small("overlap", spec)}), InputError);
  }
  {  // a level-2 box outside the level-1 boxes
    PlotfileSpec spec = three_level_spec();
    spec.levels[2].boxes[3] = ibox(2, 50, 2, 5, 53, 5);
    EXPECT_THROW(read_everything({write_small("nesting", spec)}), InputError);
  }
  {  // a level-1 box not aligned to the ref ratio
    PlotfileSpec spec = three_level_spec();
    spec.levels[1].boxes[1] = ibox(17, 16, 4, 27, 23, 11);
    EXPECT_THROW(read_everything({write_small("align", spec)}), InputError);
  }
  {  // ratio 3
    PlotfileSpec spec = ratio4_spec();
    spec.ref_ratios = {3};
    spec.levels[1].boxes = {ibox(-12, -6, 0, -4, 2, 5)};
    EXPECT_THROW(read_everything({write_small("ratio3", spec)}), InputError);
  }
}

TEST(PlotfileBad, FabBoxDiffersFromBoxArray) {
  const auto dir = write_small("fabbox");
  const auto file = dir / "Level_0" / "Cell_D_00000";
  std::string bytes = read_file_text(file);
  const size_t at = bytes.find(")((0,0,0)");  // the first FAB's box
  ASSERT_NE(at, std::string::npos);
  bytes[at + 3] = '1';
  write_file_text(file, bytes);
  EXPECT_THROW(read_everything({dir}), InputError);
}

TEST(PlotfileBad, FabGarbageDescriptor) {
  const auto dir = write_small("fabdesc");
  const auto file = dir / "Level_1" / "Cell_D_00000";
  std::string bytes = read_file_text(file);
  const size_t at = bytes.find("(64 11 52");
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, 9, "(16 11 52");
  write_file_text(file, bytes);
  EXPECT_THROW(read_everything({dir}), InputError);
}

TEST(PlotfileBad, SeriesWithDifferentHierarchies) {
  const auto root = test::scratch_dir("series_bad");
  const PlotfileSpec a = three_level_spec();
  write_plotfile(root / "p0", a, smooth_value);
  PlotfileSpec b = a;
  b.levels[2].boxes.pop_back();  // one box fewer
  write_plotfile(root / "p1", b, smooth_value);
  EXPECT_THROW(read_everything({root / "p0", root / "p1"}), InputError);
  PlotfileSpec c = a;
  c.levels[2].boxes[3] = ibox(38, 34, 10, 47, 45, 21);  // same count, different box
  write_plotfile(root / "p2", c, smooth_value);
  EXPECT_THROW(read_everything({root / "p0", root / "p2"}), InputError);
  PlotfileSpec d = a;
  d.components = {"density", "temperature"};
  write_plotfile(root / "p3", d, smooth_value);
  EXPECT_THROW(read_everything({root / "p0", root / "p3"}), InputError);
}

}  // namespace
}  // namespace vs
