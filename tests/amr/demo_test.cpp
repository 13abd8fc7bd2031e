// The procedural demos: size, determinism, octree validity and the character of the fields.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unordered_set>

#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"

namespace vs {
namespace {

constexpr uint64_t kSmall = 100'000;
constexpr int kSteps = 3;

struct Demo {
  std::unique_ptr<AmrSource> source;
  std::vector<Cell> cells;
};

Demo make(const std::string& name, uint64_t target, int steps = kSteps) {
  Demo d;
  d.source = make_demo({name, target, steps});
  d.cells = d.source->take_cells();
  return d;
}

std::vector<float> values(AmrSource& s, int field, int step) {
  std::vector<float> v(s.cell_count());
  s.read_values(field, step, v.data());
  return v;
}

int field_index(const AmrSource& s, const std::string& name) {
  const auto names = s.field_names();
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}

bool same_cells(const std::vector<Cell>& a, const std::vector<Cell>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Cell)) == 0;
}
bool same_values(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(DemoOptions, RejectsBadOptions) {
  EXPECT_EQ(demo_names(), (std::vector<std::string>{"jet", "cosmo"}));
  EXPECT_THROW(make_demo({"nope", kSmall, 2}), UsageError);
  EXPECT_THROW(make_demo({"jet", 9'999, 2}), UsageError);
  EXPECT_THROW(make_demo({"cosmo", 2'000'000'001, 2}), UsageError);
  EXPECT_THROW(make_demo({"jet", kSmall, 0}), UsageError);
}

class DemoSmall : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { demo_ = make(GetParam(), kSmall); }
  Demo demo_;
};

TEST_P(DemoSmall, CountNearTarget) {
  const double n = double(demo_.source->cell_count());
  EXPECT_EQ(demo_.cells.size(), demo_.source->cell_count());
  EXPECT_NEAR(n / double(kSmall), 1.0, 0.25) << n << " cells";
  EXPECT_NE(demo_.source->description().find("demo " + GetParam()), std::string::npos);
  EXPECT_EQ(demo_.source->step_count(), kSteps);
  for (int s = 1; s < kSteps; ++s) EXPECT_GT(demo_.source->step_time(s), demo_.source->step_time(s - 1));
}

TEST_P(DemoSmall, Deterministic) {
  Demo again = make(GetParam(), kSmall);
  EXPECT_TRUE(same_cells(demo_.cells, again.cells));
  for (int f = 0; f < int(demo_.source->field_names().size()); ++f)
    for (int step : {0, 1}) EXPECT_TRUE(same_values(values(*demo_.source, f, step), values(*again.source, f, step)));
  // take_cells may be called again and gives the same cells.
  EXPECT_TRUE(same_cells(demo_.cells, again.source->take_cells()));
}

TEST_P(DemoSmall, SameOnOneThread) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  Demo serial = make(GetParam(), kSmall);
  EXPECT_TRUE(same_cells(demo_.cells, serial.cells));
  for (int f = 0; f < int(demo_.source->field_names().size()); ++f)
    EXPECT_TRUE(same_values(values(*demo_.source, f, 1), values(*serial.source, f, 1)));
}

TEST_P(DemoSmall, LevelsAndAlignment) {
  std::vector<uint64_t> per_level(kMaxLevel + 1, 0);
  for (const Cell& c : demo_.cells) {
    ASSERT_GE(c.level, 0);
    ASSERT_LE(c.level, kMaxLevel);
    const int32_t mask = level_width(c.level) - 1;
    ASSERT_TRUE((c.lower.x & mask) == 0 && (c.lower.y & mask) == 0 && (c.lower.z & mask) == 0)
        << c.lower.x << "," << c.lower.y << "," << c.lower.z << " level " << c.level;
    ++per_level[size_t(c.level)];
  }
  const auto levels = std::count_if(per_level.begin(), per_level.end(), [](uint64_t n) { return n > 0; });
  EXPECT_GE(levels, 5);
  EXPECT_GT(per_level[0], 0u);
}

// Cells aligned to their widths overlap only when one contains the other, that is when a coarser
// cell sits at an ancestor position of a finer one. No duplicates, no such ancestor, and a total
// volume equal to the bounding box's volume: the cells tile the box exactly.
TEST_P(DemoSmall, CellsTileTheDomain) {
  vec3i lo(INT32_MAX), hi(INT32_MIN);
  uint64_t volume = 0;
  int max_level = 0;
  for (const Cell& c : demo_.cells) {
    const int32_t w = level_width(c.level);
    lo = vmin(lo, c.lower);
    hi = vmax(hi, c.lower + vec3i(w));
    volume += uint64_t(w) * uint64_t(w) * uint64_t(w);
    max_level = std::max(max_level, int(c.level));
  }
  EXPECT_EQ(lo, vec3i(0));
  EXPECT_EQ(volume, uint64_t(hi.x) * uint64_t(hi.y) * uint64_t(hi.z));
  ASSERT_LT(reduce_max(hi), 1 << 19);
  auto key = [](vec3i p, int level) {
    return uint64_t(p.x) | uint64_t(p.y) << 19 | uint64_t(p.z) << 38 | uint64_t(level) << 57;
  };
  std::unordered_set<uint64_t> present;
  for (const Cell& c : demo_.cells) present.insert(key(c.lower, c.level));
  EXPECT_EQ(present.size(), demo_.cells.size());
  uint64_t overlaps = 0;
  for (const Cell& c : demo_.cells)
    for (int level = c.level + 1; level <= max_level; ++level) {
      const int32_t mask = ~(level_width(level) - 1);
      overlaps += present.count(key(vec3i(c.lower.x & mask, c.lower.y & mask, c.lower.z & mask), level));
    }
  EXPECT_EQ(overlaps, 0u);
}

TEST_P(DemoSmall, ValuesFiniteAndChanging) {
  const size_t n = demo_.cells.size();
  for (int f = 0; f < int(demo_.source->field_names().size()); ++f) {
    const auto name = demo_.source->field_names()[size_t(f)];
    const auto a = values(*demo_.source, f, 0), b = values(*demo_.source, f, 1);
    EXPECT_TRUE(std::all_of(a.begin(), a.end(), [](float v) { return std::isfinite(v); })) << name;
    EXPECT_TRUE(std::all_of(b.begin(), b.end(), [](float v) { return std::isfinite(v); })) << name;
    size_t changed = 0;
    for (size_t i = 0; i < n; ++i) changed += a[i] != b[i];
    EXPECT_GT(changed, n / 100) << name;
    const auto [lo, hi] = std::minmax_element(a.begin(), a.end());
    std::printf("  %s %s: %zu cells, step 0 range [%g, %g], %zu changed at step 1\n", GetParam().c_str(), name.c_str(),
                n, double(*lo), double(*hi), changed);
  }
}

INSTANTIATE_TEST_SUITE_P(Demos, DemoSmall, ::testing::Values("jet", "cosmo"),
                         [](const auto& param_info) { return param_info.param; });

TEST(DemoCosmo, DensityAndTemperatureRanges) {
  Demo d = make("cosmo", kSmall);
  const int density = field_index(*d.source, "density"), temperature = field_index(*d.source, "temperature");
  ASSERT_GE(density, 0);
  ASSERT_GE(temperature, 0);
  for (int step : {0, kSteps - 1}) {
    const auto rho = values(*d.source, density, step);
    const auto [rlo, rhi] = std::minmax_element(rho.begin(), rho.end());
    EXPECT_GT(*rlo, 0.f);
    EXPECT_GE(double(*rhi) / double(*rlo), 1e6) << "step " << step;
    const auto t = values(*d.source, temperature, step);
    const auto [tlo, thi] = std::minmax_element(t.begin(), t.end());
    EXPECT_GE(*tlo, 50.f);
    EXPECT_LE(*thi, 2e7f);
    EXPECT_GE(double(*thi) / double(*tlo), 1e4) << "step " << step;
  }
}

TEST(DemoJet, FinestCellsCrowdTheBody) {
  Demo d = make("jet", kSmall);
  ASSERT_GE(field_index(*d.source, "vorticity"), 0);
  ASSERT_GE(field_index(*d.source, "pressure"), 0);
  const WorldTransform xf = d.source->transform();
  uint64_t finest = 0, near_body = 0;
  for (const Cell& c : d.cells) {
    if (c.level != 0) continue;
    ++finest;
    const vec3d p = xf.to_world(vec3d(c.lower) + vec3d(0.5));
    // The body (fuselage, wing, tail) lies within x -7..7, |y| < 7.5, z -0.6..3.1 metres.
    near_body += p.x > -9 && p.x < 9 && std::abs(p.y) < 9.5 && p.z > -2.5 && p.z < 4.5;
  }
  EXPECT_GT(double(finest), 0.3 * double(d.cells.size()));
  EXPECT_EQ(near_body, finest);
}

// Prints sizes and timings; asserts only the count (timings vary too much between machines).
void check_large(const std::string& name, uint64_t target) {
  Stopwatch watch;
  auto source = make_demo({name, target, 2});
  const double make_s = watch.lap();
  const auto cells = source->take_cells();
  const double cells_s = watch.lap();
  EXPECT_NEAR(double(cells.size()) / double(target), 1.0, 0.25);
  std::vector<uint64_t> per_level(kMaxLevel + 1, 0);
  for (const Cell& c : cells) ++per_level[size_t(c.level)];
  std::printf("  %s: %zu cells (target %llu), make %.2fs, take_cells %.2fs; cells per level:", name.c_str(),
              cells.size(), (unsigned long long)target, make_s, cells_s);
  for (int l = 0; l <= kMaxLevel; ++l)
    if (per_level[size_t(l)]) std::printf(" %d:%llu", l, (unsigned long long)per_level[size_t(l)]);
  std::printf("\n");
  std::vector<float> v(cells.size());
  for (int f = 0; f < int(source->field_names().size()); ++f) {
    watch.lap();
    source->read_values(f, 1, v.data());
    const double s = watch.lap();
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    std::printf("    %s: read_values %.2fs, range [%g, %g]\n", source->field_names()[size_t(f)].c_str(), s, double(*lo),
                double(*hi));
  }
}

TEST(DemoLarge, MillionCells) {
  for (const auto& name : demo_names()) check_large(name, 1'000'000);
}

// Run by hand: --gtest_also_run_disabled_tests --gtest_filter='DemoLarge.*'
TEST(DemoLarge, DISABLED_TenMillionCells) {
  for (const auto& name : demo_names()) check_large(name, 10'000'000);
}

}  // namespace
}  // namespace vs
