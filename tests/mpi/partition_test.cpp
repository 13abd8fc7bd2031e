// The data-parallel partition (mpi/partition.h, mpi/mesh_share.h): every cell or mesh element in
// exactly one region, ranks' shares hold what the integrator reads near their region (a mesh
// part's sub-mesh samples as the whole mesh there), a visibility order per view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "test_util.h"
#include "volstream/mpi/compositing.h"
#include "volstream/mpi/mesh_share.h"
#include "volstream/mpi/partition.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"
#include "volstream/umesh/mesh_accel.h"
#include "volstream/umesh/subset.h"

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

UMesh demo_mesh(const std::string& name, uint64_t elements) {
  const MeshData data = make_mesh_demo({name, elements, 1}, 0);
  return make_umesh(data, mesh_transform(data), name);
}

// The index of either encoding (reference chunks, compact leaves) of a mesh.
MeshIndex index_of(const UMesh& mesh, bool compact) {
  if (compact) {
    const CompactMesh c = build_compact_mesh(mesh);
    return compact_mesh_index(c, build_macrocells(c));
  }
  return reference_mesh_index(reference_chunk_boxes(mesh, build_mesh_accel(mesh).bvh.items), mesh.elements.size(),
                              build_macrocells(mesh));
}

// Each item's point (a reference chunk's, a compact leaf's) lies in exactly one region, and that
// rank holds the item; the ghosts (held elements beyond the owned ones) are reported.
TEST(MeshPartition, EveryItemHeldByItsOwner) {
  const UMesh mesh = demo_mesh("holes", 3000);
  for (const bool compact : {false, true}) {
    const MeshIndex index = index_of(mesh, compact);
    const std::vector<vec3d> points = index.item_points();
    for (int ranks : {1, 2, 3, 4, 7}) {
      const Partition p = partition_points(points, ranks, index.item_elements);
      uint64_t held = 0, owned = 0;
      for (int r = 0; r < ranks; ++r) {
        const MeshShare share = mesh_share(index, points, p.regions[size_t(r)], IntegratorSettings{});
        for (uint32_t i = 0; i < points.size(); ++i) {
          if (!in_region(p.regions[size_t(r)], points[i])) continue;
          EXPECT_TRUE(std::binary_search(share.items.begin(), share.items.end(), i)) << "owned item not held";
        }
        owned += share.owned_elements;
        held += share.held_elements;
      }
      for (const vec3d& c : points) {
        int owners = 0;
        for (const Box3<double>& r : p.regions) owners += in_region(r, c);
        EXPECT_EQ(owners, 1);
      }
      EXPECT_EQ(owned, mesh.elements.size());
      EXPECT_GE(held, owned);
      std::printf("%d ranks: ghost overhead %+.1f%% (%s)\n", ranks, 100.0 * (double(held) / double(owned) - 1.0),
                  compact ? "compact" : "reference");
    }
  }
}

TEST(MeshPartition, ElementCountsBalanced) {
  const UMesh mesh = demo_mesh("tets", 6000);
  const std::vector<vec3d> centroids = element_centroids(mesh);
  for (int ranks : {2, 3, 4}) {
    const Partition p = partition_points(centroids, ranks);
    for (const Box3<double>& r : p.regions) {
      uint64_t n = 0;
      for (const vec3d& c : centroids) n += in_region(r, c);
      EXPECT_NEAR(double(n), double(centroids.size()) / ranks, 0.02 * double(centroids.size()));
    }
  }
}

// A part's macrocells on the whole mesh's grid equal the whole mesh's within the share's margin
// (boxes, step widths, value ranges), and its sub-mesh samples as the whole mesh there.
TEST(MeshPartition, PartSamplesAsTheWhole) {
  const UMesh mesh = demo_mesh("mixed", 4000);
  const MacroCells cells = build_macrocells(mesh);
  const MeshAccel accel = build_mesh_accel(mesh);
  const MeshIndex index =
      reference_mesh_index(reference_chunk_boxes(mesh, accel.bvh.items), mesh.elements.size(), cells);
  const std::vector<vec3d> points = index.item_points();
  const Partition p = partition_points(points, 3, index.item_elements);
  const Box3<double>& region = p.regions[1];
  const MeshShare share = mesh_share(index, points, region, IntegratorSettings{});
  std::vector<uint32_t> source;
  const UMesh part = mesh_subset(mesh, chunk_elements(share.items, accel.bvh.items), source);
  const MacroCells part_cells = build_macrocells(part, &cells.grid);
  std::vector<float> values(mesh.vertices.size()), part_values(source.size());
  for (size_t v = 0; v < values.size(); ++v) values[v] = mesh.vertices[v].x + 2 * mesh.vertices[v].y;
  for (size_t v = 0; v < source.size(); ++v) part_values[v] = values[source[v]];
  const std::vector<Range> ranges = macrocell_ranges(mesh, cells, values.data());
  const std::vector<Range> part_ranges = macrocell_ranges(part, part_cells, part_values.data());
  const Box3<double> near{region.lower - vec3d(share.margin), region.upper + vec3d(share.margin)};
  size_t compared = 0;
  for (size_t c = 0; c < cells.region_of_cell.size(); ++c) {
    const int32_t r = cells.region_of_cell[c], q = part_cells.region_of_cell[c];
    if (r < 0) continue;
    const box3f b = cells.box(size_t(r));
    bool reaches = true;
    for (int a = 0; a < 3; ++a) reaches &= double(b.lower[a]) <= near.upper[a] && double(b.upper[a]) >= near.lower[a];
    if (!reaches) continue;
    ASSERT_GE(q, 0);
    EXPECT_EQ(part_cells.step_width[size_t(q)], cells.step_width[size_t(r)]);
    EXPECT_EQ(part_ranges[size_t(q)].lo, ranges[size_t(r)].lo);
    EXPECT_EQ(part_ranges[size_t(q)].hi, ranges[size_t(r)].hi);
    ++compared;
  }
  EXPECT_GT(compared, 0u);
  const MeshAccel part_accel = build_mesh_accel(part);
  const UMeshView whole_view = view_of(mesh, accel), part_view = view_of(part, part_accel);
  box3f bounds = box3f::make_empty();
  for (const vec3f& v : mesh.vertices) bounds.extend(v);
  std::mt19937 rng(5);
  for (int i = 0; i < 2000; ++i) {
    vec3f q;
    for (int a = 0; a < 3; ++a)
      q[a] = float(std::uniform_real_distribution<double>(std::max(near.lower[a], double(bounds.lower[a])),
                                                          std::min(near.upper[a], double(bounds.upper[a])))(rng));
    const float f = whole_view.sample(values.data(), q), g = part_view.sample(part_values.data(), q);
    if (std::isnan(f)) {
      EXPECT_TRUE(std::isnan(g));
    } else {
      EXPECT_NEAR(f, g, 1e-4f * (1.f + std::fabs(f))) << q.x << "," << q.y << "," << q.z;
    }
  }
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
