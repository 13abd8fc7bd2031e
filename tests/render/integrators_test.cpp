// The one integrator through both volume kinds and both optical models, against closed forms:
// a homogeneous blackbody slab (emission-absorption integrates exactly per step) and the
// isosurface of a linear field (a plane, lit head-on).
#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace vs
