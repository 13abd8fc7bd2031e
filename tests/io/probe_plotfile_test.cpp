// End to end on AMReX plotfiles with refinement ratios 2 and 4: convert to a dataset, then the
// ABR probe equals the brute-force sum over all cells at 10^4 random points, the ABR ranges
// bound every sample, the stored ABR BVH equals a fresh build, and the values round-trip exactly
// at cell centres.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_util.h"
#include "volstream/amr/abrs.h"
#include "volstream/amr/probe.h"
#include "volstream/io/dataset.h"
#include "volstream/io/plotfile.h"

namespace vs {
namespace {

double field(int comp, int level, int i, int j, int k) {
  const double s = 1.0 / (1 << (2 * level));  // rough world scale per level; exactness is not needed
  return comp * 10.0 + std::sin(0.4 * i * s + 0.1 * level) + 0.3 * std::cos(0.25 * j * s) + 0.05 * k * s + 0.01 * level;
}

PlotfileSpec spec_for_ratio(int ratio) {
  PlotfileSpec spec;
  spec.components = {"density", "energy"};
  spec.prob_lo = {-1.0, 0.0, 2.0};
  spec.prob_hi = {1.0, 1.0, 3.0};
  spec.level0_domain = {vec3i(0, 0, 0), vec3i(15, 7, 7)};
  spec.float32 = ratio == 4;
  if (ratio == 2) {
    spec.ref_ratios = {2, 2};
    spec.levels = {PlotfileLevel{{box3i{vec3i(0, 0, 0), vec3i(7, 7, 7)}, box3i{vec3i(8, 0, 0), vec3i(15, 7, 7)}}},
                   PlotfileLevel{{box3i{vec3i(4, 2, 2), vec3i(19, 9, 11)}, box3i{vec3i(20, 4, 4), vec3i(23, 7, 7)}}},
                   PlotfileLevel{{box3i{vec3i(12, 6, 6), vec3i(23, 15, 15)}}}};
  } else {
    spec.ref_ratios = {4};
    spec.levels = {
        PlotfileLevel{{box3i{vec3i(0, 0, 0), vec3i(15, 7, 7)}}},
        PlotfileLevel{{box3i{vec3i(8, 4, 4), vec3i(23, 19, 19)}, box3i{vec3i(24, 8, 8), vec3i(39, 15, 15)}}}};
  }
  return spec;
}

class PlotfileProbe : public ::testing::TestWithParam<int> {};

TEST_P(PlotfileProbe, AbrProbeEqualsBruteForce) {
  const auto dir = test::scratch_dir("plt");
  write_plotfile(dir / "plt00000", spec_for_ratio(GetParam()), field);
  auto source = open_plotfile_series({dir / "plt00000"});
  convert_to_dataset(*source, dir / "ds", ConvertOptions::silent());
  const Dataset ds(dir / "ds");
  const auto& m = ds.manifest();
  ASSERT_EQ(m.fields.size(), 2u);
  const auto cells = ds.load_cells();
  const Bvh bvh = build_abr_bvh(ds.topology());
  // The BVH stored at convert, refit at load, is the tree a build at load gives, node for node.
  ASSERT_EQ(ds.topology().abr_bvh.nodes.size(), 2 * ds.topology().abrs.size() - 1);
  AmrTopology unstored = ds.topology();
  unstored.abr_bvh.nodes.clear();
  ASSERT_EQ(test::bvh_difference(bvh.nodes, build_abr_bvh(unstored).nodes), "");
  std::mt19937 rng(GetParam());
  std::uniform_real_distribution<double> ux(-1.05, 1.05), uy(-0.05, 1.05), uz(1.95, 3.05);
  std::vector<vec3f> grid;
  for (int i = 0; i < 10000; ++i) grid.push_back(vec3f(m.transform.to_grid({ux(rng), uy(rng), uz(rng)})));
  for (int f = 0; f < 2; ++f) {
    const auto values = ds.load_values(f, 0);
    const auto ranges = ds.load_abr_ranges(f, 0);
    const auto sampled = probe_points(ds.topology(), bvh, values.data(), grid);
    int inside = 0;
    for (size_t i = 0; i < grid.size(); ++i) {
      const double ref = sample_brute_force(cells.data(), values.data(), cells.size(), vec3d(grid[i]));
      if (std::isnan(ref)) {
        ASSERT_TRUE(std::isnan(sampled[i])) << i;
        continue;
      }
      ++inside;
      ASSERT_NEAR(sampled[i], ref, 1e-5 * std::abs(ref) + 1e-6) << "point " << i;
      const int64_t abr = bvh_locate(
          bvh.nodes.data(), uint32_t(bvh.nodes.size()), [&](uint32_t k) { return ds.topology().abrs[k].box; }, grid[i]);
      ASSERT_GE(abr, 0);
      EXPECT_GE(sampled[i], ranges[size_t(abr)].lo);
      EXPECT_LE(sampled[i], ranges[size_t(abr)].hi);
    }
    EXPECT_GT(inside, 8000);
  }
}

INSTANTIATE_TEST_SUITE_P(Ratios, PlotfileProbe, ::testing::Values(2, 4));

}  // namespace
}  // namespace vs
