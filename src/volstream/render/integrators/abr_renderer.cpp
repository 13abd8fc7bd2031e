#include "volstream/render/integrators/abr_renderer.h"

#include <algorithm>
#include <numeric>

#include "volstream/amr/abrs.h"
#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/backend.h"
#include "volstream/render/integrators/launch_cpu.h"

namespace vs {

double default_reference_step(const Box3<double>& world_bounds) { return reduce_max(world_bounds.size()) / 256.0; }

GridMap make_grid_map(const WorldTransform& transform) {
  return {vec3f(transform.origin), vec3f(vec3d(1.0) / transform.cell_size)};
}

IntegratorSettings resolve_settings(IntegratorSettings s, const Box3<double>& world_bounds) {
  if (!(s.ref_step > 0.f)) s.ref_step = float(default_reference_step(world_bounds));
  if (!(s.rate > 0.f)) throw UsageError("sampling rate must be positive");
  return s;
}

Box3<double> world_bounds(const AmrTopology& topology, const WorldTransform& transform) {
  Box3<double> b{vec3d(INFINITY), vec3d(-INFINITY)};
  for (const Brick& br : topology.bricks) {
    const box3i c = br.cell_box();
    b.extend(transform.to_world(vec3d(c.lower)));
    b.extend(transform.to_world(vec3d(c.upper)));
  }
  if (b.empty()) b = {vec3d(0), vec3d(1)};
  return b;
}

namespace {
// The skipping structure over the ABRs: on the dataset's stored tree where there is one (no
// copy: 31 MB for jet 1e6), else on one built here.
RegionBvh abr_skipping(const AmrTopology& topology) {
  if (!topology.abr_bvh.nodes.empty()) return RegionBvh(abr_boxes(topology), &topology.abr_bvh, /*wide_walk=*/true);
  return RegionBvh(abr_boxes(topology), build_abr_bvh(topology), /*wide_walk=*/true);
}

void fill(FrameStats* stats, const SkipStats& s) {
  if (!stats) return;
  stats->classify_seconds = s.classify_seconds;
  stats->refit_seconds = s.refit_seconds;
  stats->visible_abrs = s.visible;
}
}  // namespace

AmrRenderer::AmrRenderer(const AmrTopology& topology, const WorldTransform& transform)
    : AmrRenderer(topology, transform, vs::world_bounds(topology, transform)) {}

AmrRenderer::AmrRenderer(const AmrTopology& topology, const WorldTransform& transform, const Box3<double>& world_bounds)
    : topology_(topology),
      transform_(transform),
      world_bounds_(world_bounds),
      skipping_(abr_skipping(topology)),
      sample_bricks_(make_sample_bricks(topology)),
      lane_offsets_(lane_offsets_fit(sample_bricks_)),
      sample_bricks_bytes_("ABR sample bricks", MemorySpace::host,
                           int64_t(sample_bricks_.size() * sizeof(SampleBrick))) {}

uint64_t AmrRenderer::classify(const std::vector<Range>& abr_ranges, const TransferTable& tf,
                               const IntegratorSettings& iso, bool skip, FrameStats* stats) {
  SkipStats s;
  const uint64_t visible = skipping_.classify(abr_ranges, tf, iso, skip, &s);
  fill(stats, s);
  return visible;
}

uint64_t AmrRenderer::refit(const std::vector<uint8_t>& keep, FrameStats* stats) {
  SkipStats s;
  const uint64_t visible = skipping_.refit(keep, &s);
  fill(stats, s);
  return visible;
}

FrameView<AmrVolume> AmrRenderer::view(const FrameFields& fields, const OpticsView& optics, const TfView* color_tf,
                                       const Camera& camera, const FrameSettings& settings) const {
  FrameView<AmrVolume> v;
  v.volume.amr = make_view(topology_, fields.primary);
  v.volume.fields[0] = fields.primary;
  v.volume.fields[1] = fields.second;
  v.volume.nodes = skipping_.refit_nodes().data();
  v.volume.node_count = uint32_t(skipping_.refit_nodes().size());
  v.volume.wide_nodes = skipping_.wide_nodes().nodes.data();  // the CPU's walk (null views on the GPU)
  v.volume.wide_node_count = uint32_t(skipping_.wide_nodes().nodes.size());
  v.volume.all_nodes = skipping_.template_bvh().nodes.data();
  v.volume.all_node_count = uint32_t(skipping_.template_bvh().nodes.size());
  v.volume.sample_bricks = sample_bricks_.data();  // the CPU's; the GPU's view drops it
  v.volume.lane_offsets = lane_offsets_;
  fill_frame(v, optics, color_tf, fields.second != nullptr, camera, settings, transform_, world_bounds());
  return v;
}

Image AmrRenderer::render(Device device, const FrameView<AmrVolume>& host_view, FrameStats* stats) const {
  if (device == Device::cpu) return render_view_cpu(host_view, stats);
  FrameView<AmrVolume> view = host_view;
  Image img(view.width, view.height);
  std::vector<uint32_t> counts(size_t(view.width) * view.height);
  view.rgba = img.rgba.data();
  view.sample_counts = counts.data();
  const cuda::RenderTimes t = cuda::render(topology_, view);
  if (stats) {
    stats->device = device;
    stats->upload_seconds = t.upload_seconds;
    stats->render_seconds = t.kernel_seconds;
    stats->samples = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
  }
  return img;
}

Image AmrRenderer::render(Device device, const float* values, const TransferTable& tf, const float* color_values,
                          const TransferTable* color_tf, const Camera& camera, const FrameSettings& settings,
                          FrameStats* stats) const {
  OpticsView optics;
  optics.tf = tf.view();
  const TfView color_view = color_tf ? color_tf->view() : TfView{};
  return render(
      device,
      view({values, color_tf ? color_values : nullptr}, optics, color_tf ? &color_view : nullptr, camera, settings),
      stats);
}

}  // namespace vs
