// The data-parallel partition (mpi/partition.h): every cell in exactly one region, ranks'
// shares hold what the integrator reads near their region, a visibility order per view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "test_util.h"
#include "volstream/mpi/compositing.h"
#include "volstream/mpi/partition.h"

namespace vs {
namespace {

test::TestVolume octree(uint32_t seed) {
  return test::make_test_volume(test::random_octree_cells(seed, {4, 3, 5}, 3, 0.4),
                                [](const vec3d& c) { return c.x + 2 * c.y - c.z; });
}

bool inside(const Box3<double>& r, const vec3d& p) {
  return p.x >= r.lower.x && p.x < r.upper.x && p.y >= r.lower.y && p.y < r.upper.y && p.z >= r.lower.z &&
         p.z < r.upper.z;
}

TEST(Partition, EveryCellInExactlyOneRegion) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const test::TestVolume v = octree(seed);
    for (int ranks : {1, 2, 3, 4, 5, 8}) {
      const Partition p = partition_bricks(v.topology.bricks, ranks);
      ASSERT_EQ(p.regions.size(), size_t(ranks));
      uint64_t counted = 0;
      for (const Brick& b : v.topology.bricks) {
        uint64_t in_regions = 0;
        for (const Box3<double>& r : p.regions) in_regions += cells_in(b, r);
        EXPECT_EQ(in_regions, uint64_t(b.cell_count())) << "seed " << seed << " ranks " << ranks;
        counted += in_regions;
        // Split on coarse cell faces: every cell's corners and centre lie in one region.
        for (int64_t i = 0; i < b.cell_count(); i += 7) {
          const vec3i idx{int32_t(i % b.dims.x), int32_t(i / b.dims.x % b.dims.y), int32_t(i / b.dims.x / b.dims.y)};
          const vec3d lo = vec3d(b.lower + idx * b.width());
          const vec3d centre = lo + vec3d(0.5 * b.width());
          const vec3d hi_inside = lo + vec3d(b.width() - 1e-6);
          int owners = 0;
          for (const Box3<double>& r : p.regions) {
            owners += inside(r, centre);
            EXPECT_EQ(inside(r, lo), inside(r, hi_inside)) << "a cell split by a region face";
          }
          EXPECT_EQ(owners, 1);
        }
      }
      EXPECT_EQ(counted, v.topology.cell_count);
    }
  }
}

TEST(Partition, CostIsBalanced) {
  const test::TestVolume v = test::make_test_volume(test::uniform_cells({32, 16, 8}), [](const vec3d&) { return 1; });
  const Partition p = partition_bricks(v.topology.bricks, 4);
  for (const Box3<double>& r : p.regions) {
    uint64_t cells = 0;
    for (const Brick& b : v.topology.bricks) cells += cells_in(b, r);
    EXPECT_EQ(cells, v.topology.cell_count / 4);
  }
}

TEST(Partition, ShareHoldsOwnedCellsBricks) {
  const test::TestVolume v = octree(4);
  const Partition p = partition_bricks(v.topology.bricks, 3);
  uint64_t held = 0;
  for (const Box3<double>& r : p.regions) {
    const RankShare share = rank_share(v.topology, r, IntegratorSettings{});
    EXPECT_TRUE(std::is_sorted(share.bricks.begin(), share.bricks.end()));
    for (uint32_t i = 0; i < v.topology.bricks.size(); ++i) {
      if (cells_in(v.topology.bricks[i], r) == 0) continue;
      EXPECT_TRUE(std::binary_search(share.bricks.begin(), share.bricks.end(), i)) << "owned brick missing";
    }
    for (uint32_t b : share.bricks) held += uint64_t(v.topology.bricks[b].cell_count());
  }
  EXPECT_GE(held, v.topology.cell_count);  // plus ghosts
}

TEST(Partition, VisibilityOrderFollowsTheEye) {
  const test::TestVolume v = test::make_test_volume(test::uniform_cells({8, 2, 2}), [](const vec3d&) { return 1; });
  const Partition p = partition_bricks(v.topology.bricks, 4);  // four slabs along x
  EXPECT_EQ(p.visibility_order({-10, 1, 1}, {1, 0, 0}, false), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(p.visibility_order({20, 1, 1}, {-1, 0, 0}, false), (std::vector<int>{3, 2, 1, 0}));
  EXPECT_EQ(p.visibility_order({5, 1, 1}, {1, 0, 0}, false).front(), 2);
  EXPECT_EQ(p.visibility_order({20, 1, 1}, {1, 0, 0}, true), (std::vector<int>{0, 1, 2, 3}));
}

TEST(Compositing, OverIsAssociative) {
  const float a[4] = {0.2f, 0.1f, 0.0f, 0.3f}, b[4] = {0.1f, 0.4f, 0.2f, 0.5f}, c[4] = {0.3f, 0.3f, 0.3f, 0.6f};
  float ab[4], bc[4], left[4], right[4];
  std::copy(a, a + 4, ab);
  mpi::blend_over(ab, b, 1);
  std::copy(ab, ab + 4, left);
  mpi::blend_over(left, c, 1);  // (a over b) over c
  std::copy(c, c + 4, bc);
  mpi::blend_under(b, bc, 1);  // b over c, in c's buffer
  std::copy(a, a + 4, right);
  mpi::blend_over(right, bc, 1);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(left[i], right[i], 1e-6f);
  uint64_t total = 0;
  for (int i = 0; i < 7; ++i) total += mpi::piece(1000, 7, i).size();
  EXPECT_EQ(total, 1000u);
}

}  // namespace
}  // namespace vs
