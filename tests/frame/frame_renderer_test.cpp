// FrameRenderer, the frame recipe every caller drives: it draws what the lower-level renderers
// draw, redoes only the stages a change needs, counts its memory and launches, and (on a GPU)
// draws what the CPU draws with every integrator and optical model.
#include "volstream/frame/frame_renderer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.h"
#include "volstream/amr/demo.h"
#include "volstream/backend/launch_times.h"
#include "volstream/backend/memory.h"
#include "volstream/cuda/backend.h"
#include "volstream/cuda/scene_bytes.h"
#include "volstream/frame/look.h"
#include "volstream/io/image.h"

namespace vs {
namespace {

// A small cosmo demo (density and temperature), written once per test binary.
const Dataset& cosmo() {
  static const Dataset ds = [] {
    const auto dir = test::scratch_dir("frame_renderer_cosmo");
    auto source = make_demo({"cosmo", 30000, 2});
    convert_to_dataset(*source, dir, ConvertOptions::silent());
    return Dataset(dir);
  }();
  return ds;
}

FrameRequest request(const Dataset& ds) {
  FrameRequest r;
  r.width = 48;
  r.height = 40;
  r.field = ds.manifest().field_index("density");
  r.tf = make_transfer_function(ds.manifest(), r.field, {0, 1}, {});
  r.camera = default_view(ds, r.width, r.height);
  return r;
}

FrameRequest blackbody(const Dataset& ds, IntegratorKind kind) {
  FrameRequest r = request(ds);
  r.kind = kind;
  r.optics = OpticsKind::blackbody;
  r.second_field = ds.manifest().field_index("temperature");
  r.blackbody = make_blackbody_params(r.tf, DensityScale::automatic, 4, 0.25, 0);
  return r;
}

// Mean absolute difference per value.
double mean_difference(const Image& a, const Image& b) {
  EXPECT_EQ(a.rgba.size(), b.rgba.size());
  double d = 0;
  for (size_t i = 0; i < a.rgba.size() && i < b.rgba.size(); ++i) d += std::fabs(double(a.rgba[i]) - b.rgba[i]);
  return d / double(std::max<size_t>(a.rgba.size(), 1));
}

double mean_alpha(const Image& img) {
  double s = 0;
  for (size_t i = 3; i < img.rgba.size(); i += 4) s += img.rgba[i];
  return s / double(img.rgba.size() / 4);
}

TEST(FrameRenderer, DrawsWhatTheAbrRendererDraws) {
  const Dataset& ds = cosmo();
  const FrameRequest r = request(ds);
  FrameRenderer fr(ds, Device::cpu);
  const Image img = fr.render(r);

  const std::vector<float> values = ds.load_values(r.field, 0);
  AmrRenderer abr(ds.topology(), ds.manifest().transform);
  const TransferTable tf(r.tf);
  abr.classify(compute_abr_ranges(ds.topology(), values.data()), tf, r.integrator, true);
  FrameSettings fs;
  fs.width = r.width;
  fs.height = r.height;
  const Image direct = abr.render(Device::cpu, values.data(), tf, nullptr, nullptr, r.camera, fs);
  EXPECT_GT(mean_alpha(img), 0.005);  // something drawn (the demo's clumps cover a little of the view)
  EXPECT_EQ(img.rgba, direct.rgba);
  EXPECT_EQ(fr.render_srgb8(r, vec3f(0.2f)), to_rgb8(direct, vec3f(0.2f)));
}

// A camera move redoes only the render; a transfer-function change re-classifies without
// reading; a new step reads again.
TEST(FrameRenderer, RedoesOnlyTheStagesAChangeNeeds) {
  const Dataset& ds = cosmo();
  FrameRequest r = request(ds);
  FrameRenderer fr(ds, Device::cpu);
  FrameReport first, again, moved, narrower, next_step;
  fr.render(r, &first);
  EXPECT_GT(first.seconds.read, 0);
  EXPECT_GT(first.seconds.ranges, 0);
  fr.render(r, &again);
  EXPECT_EQ(again.seconds.read, 0);
  EXPECT_EQ(again.seconds.ranges, 0);
  EXPECT_EQ(again.seconds.classify + again.seconds.refit, 0);
  r.camera.position = r.camera.position * 1.1;
  fr.render(r, &moved);
  EXPECT_EQ(moved.seconds.read + moved.seconds.ranges + moved.seconds.classify + moved.seconds.refit, 0);
  EXPECT_EQ(moved.visible_regions, first.visible_regions);
  r.tf.lo = r.tf.hi * 0.01f;  // the lower densities become transparent: fewer visible ABRs
  fr.render(r, &narrower);
  EXPECT_EQ(narrower.seconds.read, 0);
  EXPECT_GT(narrower.seconds.classify + narrower.seconds.refit, 0);
  EXPECT_LT(narrower.visible_regions, first.visible_regions);
  r.step = 1;
  fr.render(r, &next_step);
  EXPECT_GT(next_step.seconds.read, 0);
}

// Blackbody light depends on density only: culling by density ranges changes no pixel.
TEST(FrameRenderer, BlackbodyOnAbrsSkipsWithoutChangingThePicture) {
  const Dataset& ds = cosmo();
  FrameRequest r = blackbody(ds, IntegratorKind::abr);
  FrameRenderer fr(ds, Device::cpu);
  FrameReport skipped, all;
  const Image a = fr.render(r, &skipped);
  r.skip = false;
  const Image b = fr.render(r, &all);
  EXPECT_GT(mean_alpha(a), 0.02);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_LE(skipped.visible_regions, all.visible_regions);
}

TEST(FrameRenderer, CountsItsMemoryAndLaunches) {
  const Dataset& ds = cosmo();
  FrameRenderer fr(ds, Device::cpu);
  fr.render(request(ds));
  int64_t field_bytes = 0, bvh_bytes = 0;
  for (const MemoryEntry& e : memory_ledger().snapshot()) {
    if (e.structure == "field values") field_bytes = e.bytes[int(MemorySpace::host)];
    if (e.structure == "BVH") bvh_bytes = e.bytes[int(MemorySpace::host)];
  }
  EXPECT_GE(field_bytes, int64_t(ds.manifest().cell_count * sizeof(float)));
  EXPECT_GT(bvh_bytes, 0);
  bool rendered = false;
  for (const LaunchTime& t : launch_times().snapshot()) rendered |= t.name == "render" && t.launches > 0;
  EXPECT_TRUE(rendered);
}

TEST(MemoryLedger, CountsWhileAlive) {
  const int64_t before = memory_ledger().total(MemorySpace::pinned);
  {
    CountedBytes a("test structure", MemorySpace::pinned, 1000);
    CountedBytes b = std::move(a);
    b.set(3000);
    EXPECT_EQ(memory_ledger().total(MemorySpace::pinned), before + 3000);
  }
  EXPECT_EQ(memory_ledger().total(MemorySpace::pinned), before);
}

// Every integrator and optical model on the GPU equals the CPU (same code, compiled twice).
TEST(FrameRendererCuda, EveryIntegratorEqualsTheCpu) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  const Dataset& ds = cosmo();
  std::vector<FrameRequest> cases;
  FrameRequest iso = request(ds);
  iso.integrator.iso_count = 1;
  iso.integrator.iso[0] = iso.tf.hi * 0.05f;
  iso.integrator.shade = 1;
  iso.second_field = ds.manifest().field_index("temperature");
  iso.color_tf = make_color_field_transfer_function(ds.manifest(), iso.second_field, {0, 1}, iso.tf, false);
  cases.push_back(request(ds));
  cases.push_back(iso);
  cases.push_back(blackbody(ds, IntegratorKind::abr));
  for (Reconstruction rec : {Reconstruction::nearest, Reconstruction::trilinear}) {
    FrameRequest b = blackbody(ds, IntegratorKind::blocks);
    b.reconstruction = rec;
    cases.push_back(b);
    FrameRequest t = request(ds);
    t.kind = IntegratorKind::blocks;
    t.reconstruction = rec;
    cases.push_back(t);
  }
  FrameRequest block_iso = iso;
  block_iso.kind = IntegratorKind::blocks;
  cases.push_back(block_iso);
  FrameRenderer cpu(ds, Device::cpu), gpu(ds, Device::cuda);
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const Image a = cpu.render(cases[i]), b = gpu.render(cases[i]);
    EXPECT_GT(mean_alpha(a), 0.01);
    // Same code, different float contraction (FMA) and math library: tiny differences, which a
    // grazing isosurface hit can amplify in a few pixels (as Render.CudaEqualsCpu).
    EXPECT_LT(mean_difference(a, b), 1e-3);
  }
}

// The device bytes `info` predicts are what the scene allocates.
TEST(FrameRendererCuda, DeviceMemoryIsWhatInfoPredicts) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  const Dataset& ds = cosmo();
  FrameRenderer gpu(ds, Device::cuda);
  const FrameRequest r = request(ds);
  gpu.render(r);
  const auto predicted = cuda::device_scene_bytes(ds.topology(), 1, r.width, r.height);  // one field
  for (const MemoryEntry& e : memory_ledger().snapshot()) {
    const auto it = predicted.find(e.structure);
    if (it == predicted.end() || e.bytes[int(MemorySpace::device)] == 0) continue;
    EXPECT_EQ(uint64_t(e.bytes[int(MemorySpace::device)]), it->second) << e.structure;
  }
}

}  // namespace
}  // namespace vs

namespace vs {
namespace {
// --layers: N Gaussian layers as yt's add_layers(N) places them, checked against the closed form
// (the same construction as bench/layers_opacity.py): centres at LO, HI and evenly between on the
// log scale, the peak at each centre, exp(-1/2) of it one sigma away, zero at 4 sigma.
TEST(Look, LayersAreYtsGaussiansOnTheTableScale) {
  TransferFunctionSpec spec;
  spec.log_scale = true;
  spec.lo = 6e-4f;
  spec.hi = 4.f;
  const int n = 6;
  const std::vector<OpacityPoint> pts = layer_opacity_points(spec, n, 0.3);
  ASSERT_EQ(pts.size(), size_t(15 * n));
  const double a = std::log10(6e-4), b = std::log10(4.0), w = 0.001 * (b - a) / n, sigma = std::sqrt(w / 2);
  for (int i = 0; i < n; ++i) {
    const double centre = a + (b - a) * i / (n - 1);
    const OpacityPoint* layer = &pts[size_t(15 * i)];
    EXPECT_NEAR(layer[7].x, float(normalised_position(spec, std::pow(10.0, centre))), 1e-6) << i;
    EXPECT_NEAR(layer[7].a, 0.3f, 1e-7f);
    EXPECT_NEAR(layer[9].a, 0.3 * std::exp(-0.5), 1e-6);  // k = 1: exp(-sigma^2 / w) = exp(-1/2)
    EXPECT_NEAR(layer[9].x - layer[7].x, sigma / (b - a), 1e-6);
    EXPECT_EQ(layer[0].a, 0.f);
    EXPECT_EQ(layer[14].a, 0.f);
  }
  for (size_t k = 1; k < pts.size(); ++k) EXPECT_LT(pts[k - 1].x, pts[k].x);
  EXPECT_THROW(layer_opacity_points(spec, 0, 0.3), UsageError);
  EXPECT_THROW(layer_opacity_points(spec, 6, 1.5), UsageError);
}
}  // namespace
}  // namespace vs
