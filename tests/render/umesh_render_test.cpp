// The mesh renderer against an exhaustive reference: the same integrator, but one interval per
// macrocell (the renderer merges runs of one step width: its lattice must give the same samples)
// and every sample located by testing every element (no walk, no BVH). On the non-convex demo
// (cavity, notch, a second part: rays leave and re-enter the mesh) and the mixed one, with DVR
// and an isosurface, the images agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>

#include "volstream/backend/memory.h"
#include "volstream/frame/look.h"
#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {

// UMeshVolume with point location by testing every element (the reference). Its intervals are
// the visible cells one by one, which give a DVR frame the samples of UMeshVolume's merged runs
// (the lattice march); with isosurfaces they do not: after a sample in a hole, each cell's
// interval takes an entry sample at its face, where a run takes none. Isosurface frames use the
// runs (`per_cell_intervals` false), so that both sides differ in point location alone.
struct ExhaustiveMeshVolume : UMeshVolume {
  uint32_t element_count = 0;
  bool per_cell_intervals = true;
  float sample(int field, uint32_t, const vec3f& p) const {
    ElementHit hit;
    float best = INFINITY;
    for (uint32_t e = 0; e < element_count; ++e)
      if (mesh.consider(e, p, hit, best)) break;
    if (hit.element < 0) return NAN;
    const UElement& el = mesh.elements[hit.element];
    float f = 0.f;
    for (int i = 0; i < el.vertex_count(); ++i) f += hit.w[i] * fields[field][el.v[i]];
    return f;
  }
  float sample_near(int field, uint32_t region, const vec3f& p) const { return sample(field, region, p); }
  template <typename Visit>
  void for_each_interval(const vec3f& org, const vec3f& dir, Visit&& visit) const {
    if (!per_cell_intervals) return UMeshVolume::for_each_interval(org, dir, visit);
    for_each_cell_along(grid, org, dir, [&](uint64_t cell, float t0, float t1) {
      const int32_t region = region_of_cell[cell];
      return region < 0 || !visible[region] || visit(RayInterval{uint32_t(region), t0, t1});
    });
  }
};
static_assert(Volume<ExhaustiveMeshVolume>);

struct Case {
  std::string demo;
  bool iso;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.demo << (c.iso ? " iso" : " dvr"); }

class MeshRenderTest : public ::testing::TestWithParam<Case> {};

TEST_P(MeshRenderTest, EqualsExhaustiveElementSearch) {
  const Case c = GetParam();
  const MeshData data = make_mesh_demo({c.demo, 1500, 1}, 0);
  const WorldTransform transform = mesh_transform(data);
  const UMesh mesh = make_umesh(data, transform, c.demo);
  const std::vector<float> values = mesh_field_values(data, mesh_fields(data)[c.iso ? 1 : 0]);
  UMeshRenderer renderer(mesh, transform);
  TransferTable tf([&] {
    TransferFunctionSpec s;
    s.lo = c.iso ? 0.f : 0.02f;
    s.hi = c.iso ? 7.f : 1.1f;
    s.colors = {{0.f, 0.1f, 0.2f, 0.9f}, {1.f, 1.f, 0.8f, 0.1f}};
    s.opacity = {{0.f, c.iso ? 0.f : 0.05f}, {1.f, c.iso ? 0.f : 0.6f}};
    return s;
  }());
  IntegratorSettings iso;
  if (c.iso) {
    iso.iso_count = 1;
    iso.iso[0] = 2.5f;
  }
  renderer.classify(renderer.ranges(values.data()), tf, iso, true);
  FrameSettings fs;
  fs.width = fs.height = 14;
  fs.integrator = iso;
  OpticsView optics;
  optics.tf = tf.view();
  const Camera camera = default_camera(world_bounds(mesh, transform), 1.0);
  const FrameView<UMeshVolume> view = renderer.view({values.data(), nullptr}, optics, nullptr, camera, fs);
  FrameView<ExhaustiveMeshVolume> reference;
  reference.optics = view.optics;
  reference.camera = view.camera;
  reference.grid = view.grid;
  reference.settings = view.settings;
  reference.width = view.width;
  reference.height = view.height;
  static_cast<UMeshVolume&>(reference.volume) = view.volume;
  reference.volume.element_count = uint32_t(mesh.elements.size());
  reference.volume.per_cell_intervals = !c.iso;
  const Image fast = render_view_cpu(view, nullptr), slow = render_view_cpu(reference, nullptr);
  double worst = 0, alpha = 0;
  for (size_t i = 0; i < fast.rgba.size(); ++i) worst = std::max(worst, double(std::fabs(fast.rgba[i] - slow.rgba[i])));
  for (size_t i = 3; i < fast.rgba.size(); i += 4) alpha += fast.rgba[i];
  EXPECT_GT(alpha / double(fs.width * fs.height), 0.005);  // something drawn
  EXPECT_LT(worst, 1e-5);
}

// The tets' walk records (64 B an element) are the CPU walk's: a CUDA frame's view has none, and
// asking for one builds none; a CPU frame's view has them.
TEST(MeshRender, WalkRecordsOnlyForTheCpu) {
  const MeshData data = make_mesh_demo({"tets", 1500, 1}, 0);
  const WorldTransform transform = mesh_transform(data);
  const UMesh mesh = make_umesh(data, transform, "tets");
  const UMeshRenderer renderer(mesh, transform);
  const auto walk_record_bytes = [] {
    for (const MemoryEntry& e : memory_ledger().snapshot())
      if (e.structure == "tet walk records") return e.bytes[int(MemorySpace::host)];
    return int64_t(0);
  };
  const int64_t before = walk_record_bytes();
  EXPECT_EQ(renderer.mesh_view(Device::cuda).tet_walk, nullptr);
  EXPECT_EQ(walk_record_bytes(), before);
  EXPECT_NE(renderer.mesh_view(Device::cpu).tet_walk, nullptr);
  EXPECT_EQ(walk_record_bytes(), before + int64_t(mesh.elements.size() * sizeof(TetWalkRecord)));
}

// A small frame of a mesh demo (3000 elements) through the reference encoding's renderer,
// classified with one transfer function.
struct DemoFrame {
  MeshData data;
  WorldTransform transform;
  UMesh mesh;
  std::vector<float> values;
  UMeshRenderer renderer;
  TransferTable tf;
  FrameSettings fs;
  OpticsView optics;
  Camera camera;
  DemoFrame(const std::string& demo, uint32_t size)
      : data(make_mesh_demo({demo, 3000, 1}, 0)),
        transform(mesh_transform(data)),
        mesh(make_umesh(data, transform, demo)),
        values(mesh_field_values(data, mesh_fields(data)[0])),
        renderer(mesh, transform),
        tf([] {
          TransferFunctionSpec s;
          s.lo = 0.02f, s.hi = 1.1f;
          s.colors = {{0.f, 0.1f, 0.2f, 0.9f}, {1.f, 1.f, 0.8f, 0.1f}};
          s.opacity = {{0.f, 0.05f}, {1.f, 0.6f}};
          return s;
        }()) {
    renderer.classify(renderer.ranges(values.data()), tf, IntegratorSettings{}, true);
    fs.width = fs.height = size;
    optics.tf = tf.view();
    camera = default_camera(world_bounds(mesh, transform), 1.0);
  }
  FrameView<UMeshVolume> view(Device device = Device::cpu) const {
    return renderer.view({values.data(), nullptr}, optics, nullptr, camera, fs, device);
  }
};

// A ray's first sample walks from its macrocell's start element (MeshVolume::walk_starts), not
// from the BVH's root: the same image as without starts (to float rounding), and each start
// found is the element holding its cell's centre (every element tested), or none where no
// element does. A CUDA frame's view has none.
TEST(MeshRender, WalkStartsChangeNoPixelAndHoldTheirCellsCentre) {
  for (const std::string demo : {"tets", "holes", "mixed"}) {
    SCOPED_TRACE(demo);
    const DemoFrame frame(demo, 24);
    const UMesh& mesh = frame.mesh;
    const UMeshRenderer& renderer = frame.renderer;
    const FrameSettings& fs = frame.fs;
    FrameView<UMeshVolume> view = frame.view();
    EXPECT_EQ(frame.view(Device::cuda).volume.walk_starts, nullptr);
    ASSERT_NE(view.volume.walk_starts, nullptr);
    const Image started = render_view_cpu(view, nullptr);
    const uint32_t* starts = view.volume.walk_starts;
    view.volume.walk_starts = nullptr;
    const Image from_root = render_view_cpu(view, nullptr);
    // The same elements; a tet's weights from its walk record or from a fresh solve round apart.
    double worst = 0, alpha = 0;
    for (size_t i = 0; i < started.rgba.size(); ++i)
      worst = std::max(worst, double(std::fabs(started.rgba[i] - from_root.rgba[i])));
    for (size_t i = 3; i < started.rgba.size(); i += 4) alpha += started.rgba[i];
    EXPECT_GT(alpha / double(fs.width * fs.height), 0.005);  // something drawn
    EXPECT_LT(worst, 1e-6);

    size_t found = 0;
    for (size_t r = 0; r < renderer.region_count(); ++r) {
      if (starts[r] == UMeshVolume::kWalkStartUnknown) continue;
      const vec3f centre = renderer.macrocells().box(r).center();
      float w[8], outside = INFINITY;
      if (starts[r] != UMeshVolume::kNoWalkStart) {
        ++found;
        EXPECT_TRUE(view.volume.mesh.in_element(starts[r], centre, w, &outside)) << "macrocell " << r;
        continue;
      }
      for (uint32_t e = 0; e < mesh.elements.size(); ++e)
        EXPECT_FALSE(view.volume.mesh.in_element(e, centre, w, &outside)) << "macrocell " << r << ", element " << e;
    }
    EXPECT_GT(found, 0u);
  }
}

// The same image with the view's subcell masks as without, bit for bit; something drawn.
template <typename Volume>
void expect_masks_change_no_pixel(FrameView<Volume> view) {
  ASSERT_NE(view.volume.mesh.occupancy.mask_of_region, nullptr);
  const Image masked = render_view_cpu(view, nullptr);
  view.volume.mesh.occupancy.mask_of_region = nullptr;
  const Image searched = render_view_cpu(view, nullptr);
  ASSERT_EQ(masked.rgba.size(), searched.rgba.size());
  double alpha = 0;
  for (size_t i = 3; i < masked.rgba.size(); i += 4) alpha += masked.rgba[i];
  EXPECT_GT(alpha / double(masked.rgba.size() / 4), 0.005);
  EXPECT_TRUE(std::equal(masked.rgba.begin(), masked.rgba.end(), searched.rgba.begin()));
}

// A sample in a subcell that no element's box overlaps is NaN without a search (SubcellOccupancy):
// the same image bit for bit as with every such sample searched, in both encodings, on the
// meshes that leave parts of their macrocells empty. A CUDA frame's view has no masks.
TEST(MeshRender, SubcellMasksChangeNoPixel) {
  for (const std::string demo : {"holes", "mixed"}) {
    SCOPED_TRACE(demo);
    DemoFrame frame(demo, 32);
    EXPECT_EQ(frame.view(Device::cuda).volume.mesh.occupancy.mask_of_region, nullptr);
    expect_masks_change_no_pixel(frame.view());
    std::vector<float> storage;
    const float* local = frame.renderer.compact_values(frame.values.data(), storage);
    expect_masks_change_no_pixel(
        frame.renderer.view_compact({local, nullptr}, frame.optics, nullptr, frame.camera, frame.fs));
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, MeshRenderTest,
                         ::testing::Values(Case{"holes", false}, Case{"holes", true}, Case{"mixed", false},
                                           Case{"mixed", true}),
                         [](const auto& p) { return p.param.demo + (p.param.iso ? "_iso" : "_dvr"); });

}  // namespace
}  // namespace vs
