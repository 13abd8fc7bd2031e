// FrameRenderer on unstructured-mesh datasets: the same integrator draws DVR, isosurfaces and the
// blackbody model through the mesh; empty-space skipping over macrocells changes nothing in the
// picture; the stages are redone only when a change needs them; a time step changes only values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "test_util.h"
#include "volstream/cuda/backend.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/frame/look.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/render/integrators/umesh_renderer.h"

namespace vs {
namespace {

const Dataset& holes() {
  static const Dataset ds = [] {
    const auto dir = test::scratch_dir("mesh_frame_holes");
    auto series = make_mesh_demo_series({"holes", 20000, 2});
    convert_mesh_to_dataset(*series, dir, ConvertOptions::silent());
    return Dataset(dir);
  }();
  return ds;
}

FrameRequest request(const Dataset& ds) {
  FrameRequest r;
  r.width = 40;
  r.height = 32;
  r.field = ds.manifest().field_index("density");
  TransferFunctionRequest tf;
  tf.color_map = "viridis";
  tf.opacity = {{0.03, 0.0}, {0.3, 0.2}, {1.1, 0.6}};
  r.tf = make_transfer_function(ds.manifest(), r.field, {0, 1}, tf);
  r.camera = default_view(ds, r.width, r.height);
  return r;
}

double mean_alpha(const Image& img) {
  double sum = 0;
  for (size_t i = 3; i < img.rgba.size(); i += 4) sum += img.rgba[i];
  return sum / double(img.width * img.height);
}

double max_difference(const Image& a, const Image& b) {
  double worst = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) worst = std::max(worst, double(std::fabs(a.rgba[i] - b.rgba[i])));
  return worst;
}

TEST(MeshFrame, SkippingMacrocellsLeavesThePictureAlone) {
  FrameRenderer fr(holes(), Device::cpu);
  FrameRequest r = request(holes());
  FrameReport skipped, all;
  const Image a = fr.render(r, &skipped);
  r.skip = false;
  const Image b = fr.render(r, &all);
  EXPECT_GT(mean_alpha(a), 0.003);  // the blobs (the cavity takes much of them)
  EXPECT_LT(skipped.visible_regions, all.visible_regions);
  EXPECT_EQ(all.visible_regions, all.region_count);
  EXPECT_LT(max_difference(a, b), 1e-6);
}

// A whole load maps the reference encoding's files (core/host_array.h) and nothing on the way
// to a picture writes to them, which would copy them.
TEST(MeshFrame, DrawsFromTheMappedFilesWithoutCopyingThem) {
  FrameRenderer fr(holes(), Device::cpu);
  EXPECT_GT(mean_alpha(fr.render(request(holes()))), 0.003);
  const UMesh& mesh = holes().mesh();
  const MeshAccel& accel = holes().mesh_accel();
  EXPECT_TRUE(mesh.vertices.is_view());
  EXPECT_TRUE(mesh.elements.is_view());
  EXPECT_TRUE(accel.bvh.nodes.is_view());
  EXPECT_TRUE(accel.bvh.items.is_view());
  EXPECT_TRUE(accel.neighbors.is_view());
  ASSERT_TRUE(accel.stored_tet_walk);  // holes is made of tets: convert stores their walk records
  const TetWalkRecords walk = accel.stored_tet_walk(mesh, accel.neighbors);
  EXPECT_TRUE(walk.is_view());
  EXPECT_EQ(walk.size(), mesh.elements.size());
  // ... and a CPU frame's walk reads them (a view has no writable pointer to hand out instead).
  const UMeshRenderer renderer(mesh, accel, holes().manifest().transform);
  const TetWalkRecord* records = renderer.mesh_view(Device::cpu).tet_walk;
  ASSERT_NE(records, nullptr);
  EXPECT_EQ(std::memcmp(records, walk.data(), walk.size() * sizeof(TetWalkRecord)), 0);
}

TEST(MeshFrame, RedoesOnlyWhatAChangeNeeds) {
  FrameRenderer fr(holes(), Device::cpu);
  FrameRequest r = request(holes());
  FrameReport first, moved, next_step;
  fr.render(r, &first);
  EXPECT_GT(first.seconds.read, 0);
  EXPECT_GT(first.seconds.ranges, 0);
  r.camera.position = r.camera.position * 1.1;
  fr.render(r, &moved);
  EXPECT_EQ(moved.seconds.read + moved.seconds.ranges + moved.seconds.classify + moved.seconds.refit, 0);
  r.step = 1;
  fr.render(r, &next_step);
  EXPECT_GT(next_step.seconds.read, 0);
  EXPECT_GT(next_step.seconds.ranges, 0);
}

TEST(MeshFrame, IsosurfacesOfTheLinearFieldAndBlackbodyDraw) {
  FrameRenderer fr(holes(), Device::cpu);
  FrameRequest r = request(holes());
  r.field = holes().manifest().field_index("linear");
  r.tf =
      make_transfer_function(holes().manifest(), r.field, {0}, {"viridis", Range{0.f, 7.f}, false, {{0, 0}, {7, 0}}});
  r.integrator.iso_count = 1;
  r.integrator.iso[0] = 3.f;
  const Image iso = fr.render(r);
  EXPECT_GT(mean_alpha(iso), 0.1);  // the plane x + 2y + 3z = 3 crosses the box

  FrameRequest bb = request(holes());
  bb.optics = OpticsKind::blackbody;
  bb.second_field = holes().manifest().field_index("linear");  // any positive "temperature"
  bb.blackbody = make_blackbody_params(bb.tf, DensityScale::linear, 4, 0.25, 0);
  const Image glow = fr.render(bb);
  EXPECT_GT(mean_alpha(glow), 0.001);
}

TEST(MeshFrame, ProbeMatchesTheBruteForce) {
  FrameRenderer fr(holes(), Device::cpu);
  std::vector<vec3d> points;
  for (int i = 0; i < 200; ++i) points.push_back({0.013 * i - 0.1, 0.37 + 0.002 * i, 0.55 - 0.001 * i});
  const std::vector<float> fast = fr.probe(0, 1, points);
  const std::vector<double> reference = probe_brute_force(holes(), 0, 1, points);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(std::isnan(fast[i]), std::isnan(reference[i])) << i;
    if (!std::isnan(fast[i])) {
      EXPECT_NEAR(fast[i], reference[i], 1e-5 * std::max(1.0, std::fabs(reference[i])));
    }
  }
}

// Paper 002's compact encoding draws and probes what the reference encoding does.
TEST(MeshFrame, CompactEncodingEqualsReference) {
  FrameRenderer fr(holes(), Device::cpu);
  FrameRequest r = request(holes());
  r.integrator.iso_count = 1;
  r.integrator.iso[0] = 0.4f;
  const Image a = fr.render(r);
  r.mesh_encoding = MeshEncoding::compact;
  const Image b = fr.render(r);
  EXPECT_GT(mean_alpha(a), 0.003);
  // A paired tet's corners come in another order, so its barycentric solve rounds differently:
  // sampled values agree within 1e-6 relative (below; the encoding's stated bound is 1e-5), and a
  // pixel sums hundreds of them, so it gets the stated bound.
  EXPECT_LT(max_difference(a, b), 1e-5);
  std::vector<vec3d> points;
  for (int i = 0; i < 300; ++i) points.push_back({0.004 * i - 0.1, 0.42 + 0.001 * i, 0.5 - 0.0005 * i});
  const std::vector<float> want = fr.probe(0, 1, points), got = fr.probe(0, 1, points, MeshEncoding::compact);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(std::isnan(want[i]), std::isnan(got[i])) << i;
    if (!std::isnan(want[i])) {
      EXPECT_NEAR(got[i], want[i], 1e-6f * std::max(1.f, std::fabs(want[i])));
    }
  }
}

// The GPU renders and probes a mesh as the CPU does (the same kernel source, compiled twice).
TEST(MeshFrameCuda, EqualsTheCpu) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  const Dataset& ds = holes();
  FrameRenderer cpu(ds, Device::cpu), gpu(ds, Device::cuda);
  FrameRequest dvr = request(ds), iso = request(ds);
  iso.integrator.iso_count = 1;
  iso.integrator.iso[0] = 0.4f;
  iso.integrator.shade = 1;
  for (const FrameRequest& r : {dvr, iso}) {
    const Image a = cpu.render(r), b = gpu.render(r);
    EXPECT_GT(mean_alpha(a), 0.003);
    double sum = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i) sum += std::fabs(a.rgba[i] - b.rgba[i]);
    EXPECT_LT(sum / double(a.rgba.size()), 1e-3);
  }
  std::vector<vec3d> points;
  for (int i = 0; i < 500; ++i) points.push_back({0.0027 * i, 0.31 + 0.001 * i, 0.6 - 0.0007 * i});
  const std::vector<float> a = cpu.probe(0, 1, points), b = gpu.probe(0, 1, points);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::isnan(a[i]), std::isnan(b[i])) << i;
    if (!std::isnan(a[i])) {
      EXPECT_NEAR(a[i], b[i], 1e-5 * std::max(1.f, std::fabs(a[i])));
    }
  }
}

}  // namespace
}  // namespace vs
