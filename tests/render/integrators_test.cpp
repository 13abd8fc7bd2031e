// The one integrator through both volume kinds and both optical models, against closed forms:
// a homogeneous blackbody slab (emission-absorption integrates exactly per step) and the
// isosurface of a linear field (a plane, lit head-on). The lattice march against its definition.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "test_util.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/integrators/block_renderer.h"

namespace vs {
namespace {

constexpr int kN = 8;  // cells per axis, level 0, world = grid units

// Orthographic camera looking down -axis at the middle of the cube, seeing only its interior.
Camera head_on(int axis) {
  Camera c;
  const double m = kN / 2.0;
  c.look_at = {m, m, m};
  c.position = c.look_at;
  c.position[axis] += 20;
  c.up = axis == 1 ? vec3d(0, 0, 1) : vec3d(0, 1, 0);
  c.ortho = true;
  c.ortho_height = 2;
  return c;
}

void expect_every_pixel(const Image& img, const vec3d& rgb, double alpha, double tol, const char* what) {
  for (uint32_t y = 0; y < img.height; ++y)
    for (uint32_t x = 0; x < img.width; ++x) {
      const float* p = img.pixel(x, y);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(p[c], rgb[c], tol) << what << " pixel " << x << "," << y << " channel " << c;
      ASSERT_NEAR(p[3], alpha, tol) << what << " pixel " << x << "," << y;
    }
}

// Constant density rho_max and temperature T along a path of L reference steps: per channel
// I = E (1 - exp(-k L)) / k with E = emission * colour(T), k = absorption * rayleigh weight.
TEST(Integrators, BlackbodySlabMatchesClosedFormOnAbrsAndBlocks) {
  const test::TestVolume vol =
      test::make_test_volume(test::uniform_cells({kN, kN, kN}), [](const vec3d&) { return 1.0; });
  const std::vector<float> temperature = test::test_values(vol, [](const vec3d&) { return 6000.0; });
  BlackbodyParams p;
  p.emission = 0.3f;
  p.absorption = 0.05f;
  const BlackbodyTable table;
  const BlackbodyView bb = table.view(p);
  auto expected = [&](double length) {
    vec3d rgb, trans;
    for (int c = 0; c < 3; ++c) {
      const double k = p.absorption * bb.rayleigh[c];
      rgb[c] = p.emission * bb.color(6000.f)[c] * (1 - std::exp(-k * length)) / k;
      trans[c] = std::exp(-k * length);
    }
    return std::pair{rgb, 1 - (trans.x + trans.y + trans.z) / 3};
  };
  // ABRs cover the cells' tent support: half a cell beyond the cells on each side.
  AmrRenderer abr(vol.topology, vol.transform);
  abr.classify(vol.abr_ranges, TransferTable(TransferFunctionSpec{}), IntegratorSettings{}, false);
  FrameSettings fs;
  fs.width = fs.height = 6;
  fs.integrator.ref_step = 1;
  OpticsView optics;
  optics.kind = OpticsKind::blackbody;
  optics.bb = bb;
  const Image a =
      abr.render(Device::cpu, abr.view({vol.values.data(), temperature.data()}, optics, nullptr, head_on(2), fs));
  const auto [rgb_abr, alpha_abr] = expected(kN + 1.0);
  expect_every_pixel(a, rgb_abr, alpha_abr, 2e-4, "abr");
  // Blocks are the cells' boxes.
  BlockRenderer blocks(vol.topology, vol.transform);
  blocks.set_fields(vol.values.data(), temperature.data());
  BlockFrame frame;
  frame.width = frame.height = 6;
  frame.settings.ref_step = 1;
  frame.settings.optics = Optics::blackbody;
  frame.blackbody = p;
  const Image b = blocks.render(nullptr, head_on(2), frame);
  const auto [rgb_blocks, alpha_blocks] = expected(double(kN));
  expect_every_pixel(b, rgb_blocks, alpha_blocks, 2e-4, "blocks");
}

// f = x: the isosurface f = iso is the plane x = iso, seen head-on along x by the headlight
// (|n . view| = 1): colour * (ambient + (1 - ambient)) + specular, opaque. The transfer
// function is transparent, so nothing else shows.
TEST(Integrators, IsosurfaceOfLinearFieldIsThePlaneOnAbrsAndBlocks) {
  const test::TestVolume vol =
      test::make_test_volume(test::uniform_cells({kN, kN, kN}), [](const vec3d& c) { return c.x; });
  TransferFunctionSpec spec;
  spec.colors = builtin_color_map("viridis");
  spec.opacity = {{0.f, 0.f}, {1.f, 0.f}};
  spec.lo = 0;
  spec.hi = kN;
  const TransferTable tf(spec);
  IntegratorSettings iso;
  iso.iso_count = 1;
  iso.iso[0] = 3.3f;
  iso.jitter = 0;
  const Rgba c = tf.lookup(3.3f);
  const vec3d lit(c.r + 0.35, c.g + 0.35, c.b + 0.35);

  AmrRenderer abr(vol.topology, vol.transform);
  EXPECT_GT(abr.classify(vol.abr_ranges, tf, iso, true), 0u);
  FrameSettings fs;
  fs.width = fs.height = 6;
  fs.integrator = iso;
  expect_every_pixel(abr.render(Device::cpu, vol.values.data(), tf, nullptr, nullptr, head_on(0), fs), lit, 1.0, 1e-3,
                     "abr");

  BlockRenderer blocks(vol.topology, vol.transform);
  blocks.set_fields(vol.values.data());
  BlockFrame frame;
  frame.width = frame.height = 6;
  frame.integrator = iso;
  const TfView view = tf.view();
  expect_every_pixel(blocks.render(&view, head_on(0), frame), lit, 1.0, 1e-3, "blocks trilinear");
}

// The lattice points an interval's steps give (March::lattice).
std::vector<float> lattice_points(float dt, float t0, float t1, float jitter) {
  IntegratorSettings st;
  st.march = March::lattice;
  st.rate = 1.f;
  detail::Ray ray{};
  ray.dir_len = 1.f;
  const detail::Steps steps = detail::make_steps(st, ray, dt, t0, t1, jitter);
  EXPECT_EQ(steps.march, March::lattice);
  std::vector<float> t(steps.n);
  float len_ref;
  for (uint32_t k = 0; k < steps.n; ++k) steps.at(k, jitter, t[k], len_ref);
  return t;
}

// An interval's samples are the points (m + jitter) dt in [t0, t1), whatever the interval: cut
// anywhere, its two parts give the same floats in the same order, so a run of macrocells samples
// as one interval would.
TEST(LatticeMarch, CutIntervalsGiveTheWholeIntervalsPoints) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int i = 0; i < 2000; ++i) {
    const float dt = 0.001f + 0.1f * u(rng), jitter = u(rng);
    const float t0 = 50.f * u(rng), t1 = t0 + 3.f * u(rng), cut = t0 + (t1 - t0) * u(rng);
    const std::vector<float> whole = lattice_points(dt, t0, t1, jitter);
    std::vector<float> parts = lattice_points(dt, t0, cut, jitter);
    const std::vector<float> second = lattice_points(dt, cut, t1, jitter);
    parts.insert(parts.end(), second.begin(), second.end());
    // A point within rounding of the cut may fall on either side of it in the parts; none did here.
    ASSERT_EQ(parts, whole) << "dt " << dt << " t0 " << t0 << " t1 " << t1 << " cut " << cut;
    for (size_t k = 0; k < whole.size(); ++k) {
      EXPECT_GE(whole[k], t0 * (1.f - 1e-6f));
      EXPECT_LT(whole[k], t1 * (1.f + 1e-6f));
      const float m = whole[k] / dt - jitter;
      EXPECT_NEAR(m, std::round(m), 1e-2f) << "on the lattice";
    }
    EXPECT_NEAR(float(whole.size()), (t1 - t0) / dt, 1.f) << "one point per step";
  }
}

TEST(LatticeMarch, ShortIntervalsMayHoldNoPointAndFarOnesFallBack) {
  EXPECT_TRUE(lattice_points(1.f, 10.6f, 10.9f, 0.5f).empty());
  EXPECT_EQ(lattice_points(1.f, 10.4f, 10.6f, 0.5f), std::vector<float>{10.5f});
  IntegratorSettings st;
  st.march = March::lattice;
  detail::Ray ray{};
  ray.dir_len = 1.f;
  // 2^24 steps from the origin floats no longer count steps: equal steps from the entry instead.
  const detail::Steps far = detail::make_steps(st, ray, 1e-3f * st.rate, 2e4f, 2e4f + 0.01f, 0.5f);
  EXPECT_EQ(far.march, March::equal_jittered);
  EXPECT_EQ(far.n, 10u);
}

}  // namespace
}  // namespace vs
