// The CPU's fast sampler (amr/sampler.h, sample_abr_fast) against the reference sample_abr, per
// sample, over random octrees of 2 to 5 levels: bit for bit on ABRs of several bricks, within
// 1e-6 of the brick's largest |value| on one-brick ABRs (the trilinear form; the header says why
// that bound holds), NaN exactly where the reference is NaN (NaN values included).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <tuple>

#include "test_util.h"
#include "volstream/amr/abrs.h"
#include "volstream/amr/bricks.h"
#include "volstream/amr/sampler.h"
#include "volstream/core/simd.h"

namespace vs {
namespace {

AmrTopology build_topology(std::vector<Cell> cells) {
  const BrickBuildResult bricks = build_bricks(std::move(cells), "test");
  AmrTopology t;
  t.bricks = bricks.bricks;
  t.cell_count = bricks.device_cells.size();
  build_abrs(t, "test");
  return t;
}

bool same_bits(float a, float b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

class FastSampler : public ::testing::TestWithParam<std::tuple<uint32_t, int, double>> {};

TEST_P(FastSampler, EqualsTheReferencePerSample) {
  const auto [seed, levels, refine] = GetParam();
  const AmrTopology t = build_topology(test::random_octree_cells(seed, vec3i(3, 2, 2), levels, refine));
  const std::vector<SampleBrick> records = make_sample_bricks(t);
  ASSERT_EQ(records.size(), t.bricks.size());

  std::mt19937 rng(seed * 31u + 1u);
  // Values of both signs over several decades, and a few NaN ("no data") cells.
  std::uniform_real_distribution<float> value(-1000.f, 1000.f), unit(0.f, 1.f);
  std::vector<float> values(t.cell_count);
  for (float& v : values) v = unit(rng) < 0.01f ? NAN : value(rng) * std::pow(10.f, -3.f * unit(rng));
  const AmrView view = make_view(t, values.data());

  uint64_t one_brick = 0, several = 0;
  double worst_relative = 0;
  for (uint32_t abr = 0; abr < t.abrs.size(); ++abr) {
    const Abr& a = t.abrs[abr];
    float max_abs = 0.f;  // over the ABR's bricks: the one-brick bound's scale
    for (uint32_t i = 0; i < a.brick_count; ++i) {
      const Brick& b = t.bricks[t.abr_bricks[a.first_brick + i]];
      for (int64_t c = 0; c < b.cell_count(); ++c)
        if (!std::isnan(values[b.value_offset + c])) max_abs = std::max(max_abs, std::abs(values[b.value_offset + c]));
    }
    const vec3f size = a.box.upper - a.box.lower;
    for (int k = 0; k < 24; ++k) {
      // Inside the box, on its faces and corners (k < 8), and at cell centres of the finest
      // level (a weight exactly 0 next to a NaN must not make the sample NaN).
      vec3f p;
      for (int axis = 0; axis < 3; ++axis) {
        const float u = k < 8 ? float((k >> axis) & 1) : unit(rng);
        p[axis] = a.box.lower[axis] + u * size[axis];
        if (k >= 16) p[axis] = std::floor(p[axis] / a.finest_width) * a.finest_width + 0.5f * a.finest_width;
        if (k >= 16 && p[axis] > a.box.upper[axis]) p[axis] = a.box.upper[axis];
      }
      const float ref = sample_abr(view, abr, p);
      const float fast = sample_abr_fast(t.abrs.data(), t.abr_bricks.data(), records.data(), values.data(), abr, p);
      ASSERT_EQ(std::isnan(ref), std::isnan(fast)) << "ABR " << abr << " bricks " << a.brick_count;
      if (a.brick_count > 1) {
        ++several;
        ASSERT_TRUE(same_bits(ref, fast)) << "ABR " << abr << ": " << ref << " vs " << fast;
      } else {
        ++one_brick;
        if (std::isnan(ref)) continue;
        const double err = std::abs(double(fast) - double(ref));
        ASSERT_LE(err, 1e-6 * max_abs) << "ABR " << abr << ": " << ref << " vs " << fast;
        worst_relative = std::max(worst_relative, err / max_abs);
      }
    }
    // Beyond the brick's support the one-brick form must give NaN as the reference does.
    if (a.brick_count == 1) {
      const Brick& b = t.bricks[t.abr_bricks[a.first_brick]];
      const vec3f far = vec3f(b.lower) - vec3f(float(b.width()) * 1.5f);
      EXPECT_TRUE(std::isnan(sample_abr(view, abr, far)));
      EXPECT_TRUE(
          std::isnan(sample_abr_fast(t.abrs.data(), t.abr_bricks.data(), records.data(), values.data(), abr, far)));
    }
  }
  EXPECT_GT(one_brick, 0u);
  EXPECT_GT(several, 0u);
  std::printf("seed %u: %llu one-brick and %llu several-brick samples, worst one-brick error %.3g of max |v|\n", seed,
              (unsigned long long)one_brick, (unsigned long long)several, worst_relative);
}

// The batch forms, on ABRs of one brick and of several: both builds (the baseline forced, as on a
// CPU without AVX2, and the AVX2 one where the CPU has it) give sample_abr_fast's floats.
TEST_P(FastSampler, BatchesEqualPointByPointOnEveryBuild) {
  const auto [seed, levels, refine] = GetParam();
  const AmrTopology t = build_topology(test::random_octree_cells(seed, vec3i(3, 2, 2), levels, refine));
  const std::vector<SampleBrick> records = make_sample_bricks(t);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(-100.f, 100.f), unit(0.f, 1.f);
  std::vector<float> values(t.cell_count);
  for (float& v : values) v = unit(rng) < 0.01f ? NAN : value(rng);
  const AmrView view = make_view(t, values.data());
  uint64_t checked = 0, one_brick = 0, several = 0;
  for (bool baseline : {true, false}) {
    simd::force_baseline(baseline);
    for (uint32_t abr = 0; abr < t.abrs.size(); ++abr) {
      const Abr& a = t.abrs[abr];
      // A ray from a point of the box grown a little (some points beyond the support), through
      // another, with n parameters along it.
      vec3f org, through;
      for (int axis = 0; axis < 3; ++axis) {
        const float lo = a.box.lower[axis], size = a.box.upper[axis] - a.box.lower[axis];
        org[axis] = lo + (1.2f * unit(rng) - 0.1f) * size;
        through[axis] = lo + (1.2f * unit(rng) - 0.1f) * size;
      }
      const vec3f dir = through - org;
      float ts[8], out[8];
      const uint32_t n = 1 + abr % 8;  // short batches too
      for (uint32_t i = 0; i < n; ++i) ts[i] = unit(rng);
      const uint32_t* ids = t.abr_bricks.data() + a.first_brick;
      if (a.brick_count == 1) {
        sample_one_brick_batch(records[ids[0]], values.data(), org, dir, ts, n, out);
        ++one_brick;
      } else {
        sample_bricks_batch(records.data(), ids, a.brick_count, values.data(), org, dir, ts, n, out);
        ++several;
      }
      for (uint32_t i = 0; i < 8; ++i) {  // entries from n on repeat entry n - 1
        const vec3f p = org + dir * ts[std::min(i, n - 1)];
        const float one = sample_abr_fast(t.abrs.data(), t.abr_bricks.data(), records.data(), values.data(), abr, p);
        const float ref = sample_abr(view, abr, p);
        ASSERT_EQ(std::isnan(out[i]), std::isnan(ref)) << simd::isa();
        ASSERT_TRUE(same_bits(out[i], one)) << simd::isa() << ": " << out[i] << " vs " << one;
        if (!std::isnan(ref)) {
          ASSERT_NEAR(out[i], ref, 1e-6 * 100.0) << simd::isa();
        }
        ++checked;
      }
    }
  }
  simd::force_baseline(false);
  EXPECT_GT(one_brick, 0u);
  EXPECT_GT(several, 0u);
}

// The batch over several ABRs (a ray's samples across short intervals, one ABR per lane): on
// both builds, each lane gives sample_abr_fast's float for its point in its ABR.
TEST_P(FastSampler, BatchesOverSeveralAbrsEqualPointByPointOnEveryBuild) {
  const auto [seed, levels, refine] = GetParam();
  const AmrTopology t = build_topology(test::random_octree_cells(seed, vec3i(3, 2, 2), levels, refine));
  const std::vector<SampleBrick> records = make_sample_bricks(t);
  ASSERT_TRUE(lane_offsets_fit(records));
  std::mt19937 rng(seed + 100);
  std::uniform_real_distribution<float> value(-100.f, 100.f), unit(0.f, 1.f);
  std::vector<float> values(t.cell_count);
  for (float& v : values) v = unit(rng) < 0.01f ? NAN : value(rng);
  box3f domain = box3f::make_empty();
  for (const Abr& a : t.abrs) domain.extend(a.box);
  const auto abr_holding = [&](const vec3f& p) {  // brute force over every ABR
    for (uint32_t a = 0; a < t.abrs.size(); ++a)
      if (t.abrs[a].box.contains(p)) return int64_t(a);
    return int64_t(-1);
  };
  uint64_t checked = 0, mixed = 0;
  for (bool baseline : {true, false}) {
    simd::force_baseline(baseline);
    for (int ray = 0; ray < 300; ++ray) {
      vec3f org, through;
      for (int axis = 0; axis < 3; ++axis) {
        org[axis] = domain.lower[axis] + unit(rng) * (domain.upper[axis] - domain.lower[axis]);
        through[axis] = domain.lower[axis] + unit(rng) * (domain.upper[axis] - domain.lower[axis]);
      }
      const vec3f dir = through - org;
      float ts[8], out[8];
      uint32_t regions[8], n = 0;
      const uint32_t want = 1 + uint32_t(ray) % 8;  // short batches too
      for (int tries = 0; tries < 64 && n < want; ++tries) {
        const float tk = unit(rng);
        const int64_t a = abr_holding(org + dir * tk);
        if (a < 0) continue;
        ts[n] = tk;
        regions[n++] = uint32_t(a);
      }
      if (n == 0) continue;
      sample_abrs_batch({t.abrs.data(), t.abr_bricks.data(), records.data()}, values.data(), regions, org, dir, ts, n,
                        out);
      mixed += std::any_of(regions, regions + n, [&](uint32_t r) { return r != regions[0]; });
      for (uint32_t i = 0; i < 8; ++i) {  // entries from n on repeat entry n - 1
        const uint32_t k = std::min(i, n - 1);
        const float one = sample_abr_fast(t.abrs.data(), t.abr_bricks.data(), records.data(), values.data(), regions[k],
                                          org + dir * ts[k]);
        ASSERT_TRUE(same_bits(out[i], one)) << simd::isa() << ": " << out[i] << " vs " << one;
        ++checked;
      }
    }
  }
  simd::force_baseline(false);
  EXPECT_GT(checked, 0u);
  EXPECT_GT(mixed, 0u);
}

INSTANTIATE_TEST_SUITE_P(RandomOctrees, FastSampler,
                         ::testing::Values(std::make_tuple(1u, 3, 0.4), std::make_tuple(2u, 4, 0.35),
                                           std::make_tuple(3u, 5, 0.3), std::make_tuple(4u, 2, 0.6),
                                           std::make_tuple(6u, 4, 0.9)));

}  // namespace
}  // namespace vs
