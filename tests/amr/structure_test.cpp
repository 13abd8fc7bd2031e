// Independent brute-force checks of bricks, ABRs, the tent sampler and value ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <tuple>

#include "test_util.h"
#include "volstream/amr/abrs.h"
#include "volstream/amr/bricks.h"
#include "volstream/amr/probe.h"
#include "volstream/amr/ranges.h"
#include "volstream/core/error.h"

namespace vs {
namespace {

auto cell_key(const Cell& c) { return std::make_tuple(c.lower.x, c.lower.y, c.lower.z, c.level); }

struct Built {
  std::vector<Cell> input;
  BrickBuildResult bricks;
  AmrTopology topology;
};

Built build_all(std::vector<Cell> cells) {
  Built b;
  b.input = cells;
  b.bricks = build_bricks(std::move(cells), "test");
  b.topology.bricks = b.bricks.bricks;
  b.topology.cell_count = b.bricks.device_cells.size();
  build_abrs(b.topology, "test");
  return b;
}

class AmrStructure : public ::testing::TestWithParam<std::tuple<uint32_t, int, double>> {
 protected:
  void SetUp() override {
    const auto [seed, levels, refine] = GetParam();
    built_ = build_all(test::random_octree_cells(seed, vec3i(3, 2, 2), levels, refine));
  }
  Built built_;
};

TEST_P(AmrStructure, EveryCellInExactlyOneBrick) {
  const auto& r = built_.bricks;
  ASSERT_EQ(r.device_cells.size(), built_.input.size());
  // Expand each brick into its cells and compare with the input as sets.
  std::map<std::tuple<int, int, int, int>, int> seen;
  uint64_t offset = 0;
  for (const Brick& b : r.bricks) {
    EXPECT_EQ(b.value_offset, offset);
    for (int z = 0; z < b.dims.z; ++z)
      for (int y = 0; y < b.dims.y; ++y)
        for (int x = 0; x < b.dims.x; ++x) {
          const Cell c{b.lower + vec3i(x, y, z) * b.width(), b.level};
          ++seen[cell_key(c)];
          // Device order: the brick's cells x fastest.
          EXPECT_TRUE(cell_key(r.device_cells[offset]) == cell_key(c));
          ++offset;
        }
  }
  EXPECT_EQ(offset, built_.input.size());
  for (const Cell& c : built_.input) EXPECT_EQ(seen[cell_key(c)], 1);
  EXPECT_EQ(seen.size(), built_.input.size());
  for (size_t i = 0; i < r.device_cells.size(); ++i)
    ASSERT_TRUE(cell_key(r.device_cells[i]) == cell_key(built_.input[r.input_index[i]]));
}

TEST_P(AmrStructure, AbrsAreDisjointAndListExactlyTheOverlappingBricks) {
  const auto& t = built_.topology;
  ASSERT_FALSE(t.abrs.empty());
  for (size_t i = 0; i < t.abrs.size(); ++i)
    for (size_t j = i + 1; j < t.abrs.size(); ++j)
      ASSERT_FALSE(t.abrs[i].box.overlaps_open(t.abrs[j].box)) << i << " " << j;
  for (const Abr& a : t.abrs) {
    std::vector<uint32_t> listed(t.abr_bricks.begin() + a.first_brick,
                                 t.abr_bricks.begin() + a.first_brick + a.brick_count);
    std::sort(listed.begin(), listed.end());
    std::vector<uint32_t> expected;
    int32_t finest = INT32_MAX;
    for (uint32_t b = 0; b < t.bricks.size(); ++b) {
      const box3i s = t.bricks[b].support_x2();
      const box3f support{vec3f(s.lower) * 0.5f, vec3f(s.upper) * 0.5f};
      if (support.overlaps_open(a.box)) {
        expected.push_back(b);
        finest = std::min(finest, t.bricks[b].width());
        // Listed bricks cover the whole ABR (that is what makes it an ABR).
        EXPECT_TRUE(support.contains(a.box.lower) && support.contains(a.box.upper));
      }
    }
    EXPECT_EQ(listed, expected);
    EXPECT_EQ(a.finest_width, float(finest));
  }
}

// Two ABRs with the same bricks whose union is a box are one (merge_adjacent_abrs), checked pair
// by pair (these octrees need fewer than its 8 rounds).
TEST_P(AmrStructure, NoTwoAbrsWithTheSameBricksMakeABox) {
  const auto& t = built_.topology;
  auto bricks = [&](const Abr& a) {
    return std::vector<uint32_t>(t.abr_bricks.begin() + a.first_brick,
                                 t.abr_bricks.begin() + a.first_brick + a.brick_count);
  };
  for (size_t i = 0; i < t.abrs.size(); ++i)
    for (size_t j = i + 1; j < t.abrs.size(); ++j) {
      const box3f &a = t.abrs[i].box, &b = t.abrs[j].box;
      for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const bool face = a.lower[u] == b.lower[u] && a.upper[u] == b.upper[u] && a.lower[v] == b.lower[v] &&
                          a.upper[v] == b.upper[v] &&
                          (a.upper[axis] == b.lower[axis] || b.upper[axis] == a.lower[axis]);
        EXPECT_FALSE(face && bricks(t.abrs[i]) == bricks(t.abrs[j])) << "ABRs " << i << " and " << j;
      }
    }
}

TEST_P(AmrStructure, AbrsCoverTheUnionOfSupports) {
  // Rasterise supports and ABRs on the half-grid (all faces lie on it): each voxel inside some
  // support is in exactly one ABR, and no ABR reaches outside the supports.
  const auto& t = built_.topology;
  box3i bounds = box3i::make_empty();
  for (const Brick& b : t.bricks) bounds.extend(b.support_x2());
  const vec3i n = bounds.upper - bounds.lower;
  std::vector<uint8_t> in_support(size_t(n.x) * n.y * n.z, 0), in_abr(in_support.size(), 0);
  auto fill = [&](std::vector<uint8_t>& grid, box3i box, bool count) {
    for (int z = box.lower.z; z < box.upper.z; ++z)
      for (int y = box.lower.y; y < box.upper.y; ++y)
        for (int x = box.lower.x; x < box.upper.x; ++x) {
          uint8_t& v = grid[(size_t(z - bounds.lower.z) * n.y + (y - bounds.lower.y)) * n.x + (x - bounds.lower.x)];
          v = count ? uint8_t(v + 1) : uint8_t(1);
        }
  };
  for (const Brick& b : t.bricks) fill(in_support, b.support_x2(), false);
  for (const Abr& a : t.abrs) fill(in_abr, box3i{vec3i(a.box.lower * 2.f), vec3i(a.box.upper * 2.f)}, true);
  for (size_t i = 0; i < in_support.size(); ++i) ASSERT_EQ(in_abr[i], in_support[i]) << "voxel " << i;
}

TEST_P(AmrStructure, SamplerEqualsBruteForceAndRangesBoundSamples) {
  const auto& t = built_.topology;
  const auto& cells = built_.bricks.device_cells;
  std::vector<float> values(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) values[i] = test::test_value(cells[i]);
  const Bvh bvh = build_abr_bvh(t);
  const auto ranges = compute_abr_ranges(t, values.data());

  std::mt19937 rng(7);
  box3i bounds = box3i::make_empty();
  for (const Brick& b : t.bricks) bounds.extend(b.cell_box());
  std::uniform_real_distribution<float> ux(float(bounds.lower.x) - 1, float(bounds.upper.x) + 1),
      uy(float(bounds.lower.y) - 1, float(bounds.upper.y) + 1),
      uz(float(bounds.lower.z) - 1, float(bounds.upper.z) + 1);
  std::vector<vec3f> points(10000);
  for (auto& p : points) p = {ux(rng), uy(rng), uz(rng)};
  const auto sampled = probe_points(t, bvh, values.data(), points);
  const AmrView view = make_view(t, values.data());
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double ref = sample_brute_force(cells.data(), values.data(), cells.size(), vec3d(points[i]));
    if (std::isnan(ref)) {
      EXPECT_TRUE(std::isnan(sampled[i])) << i;
      continue;
    }
    ++inside;
    ASSERT_NEAR(sampled[i], ref, 1e-5 * std::abs(ref)) << "point " << i;
    const int64_t abr = bvh_locate(
        bvh.nodes.data(), uint32_t(bvh.nodes.size()), [&](uint32_t k) { return t.abrs[k].box; }, points[i]);
    ASSERT_GE(abr, 0);
    EXPECT_GE(sample_abr(view, uint32_t(abr), points[i]), ranges[size_t(abr)].lo);
    EXPECT_LE(sample_abr(view, uint32_t(abr), points[i]), ranges[size_t(abr)].hi);
  }
  EXPECT_GT(inside, 5000);
}

INSTANTIATE_TEST_SUITE_P(RandomOctrees, AmrStructure,
                         ::testing::Values(std::make_tuple(1u, 3, 0.4), std::make_tuple(2u, 4, 0.35),
                                           std::make_tuple(3u, 5, 0.3), std::make_tuple(4u, 2, 0.0),
                                           std::make_tuple(5u, 4, 0.9)));

TEST(AmrBricks, RejectsDuplicateMisalignedAndOverlappingCells) {
  EXPECT_THROW(build_bricks({{vec3i(0, 0, 0), 0}, {vec3i(0, 0, 0), 0}}, "x"), InputError);
  EXPECT_THROW(build_bricks({{vec3i(1, 0, 0), 1}}, "x"), InputError);
  EXPECT_THROW(build_bricks({{vec3i(0, 0, 0), 40}}, "x"), InputError);
  // A coarse cell and a fine cell inside it.
  Built b;
  AmrTopology t;
  t.bricks = build_bricks({{vec3i(0, 0, 0), 1}, {vec3i(1, 1, 1), 0}}, "x").bricks;
  EXPECT_THROW(build_abrs(t, "x"), InputError);
}

TEST(AmrBricks, DenseBlocksBecomeFewBricks) {
  std::vector<Cell> cells;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) cells.push_back({vec3i(x, y, z), 0});
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) cells.push_back({vec3i(16 + 2 * x, 2 * y, 2 * z), 1});
  const auto r = build_bricks(std::move(cells), "x");
  EXPECT_EQ(r.bricks.size(), 2u);
}

}  // namespace
}  // namespace vs
