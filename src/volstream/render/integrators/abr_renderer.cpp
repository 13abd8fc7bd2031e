#include "volstream/render/integrators/abr_renderer.h"

#include <algorithm>
#include <numeric>

#include "volstream/accel/bvh_sah.h"
#include "volstream/accel/refit.h"
#include "volstream/backend/parallel.h"
#include "volstream/backend/stopwatch.h"
#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"
#include "volstream/render/classify.h"
#include "volstream/render/integrators/launch_cpu.h"

namespace vs {

std::vector<uint8_t> classify_abrs(const std::vector<Range>& ranges, const TransferTable& tf,
                                   const IntegratorSettings& iso) {
  std::vector<uint8_t> visible(ranges.size());
  const OpacityIndex opacity = tf.opacity_index();
  parallel_for("classify", int64_t(ranges.size()),
               [&](int64_t i) { visible[size_t(i)] = abr_visible(ranges[size_t(i)], opacity, iso) ? 1 : 0; });
  return visible;
}

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

AmrRenderer::AmrRenderer(const AmrTopology& topology, const WorldTransform& transform)
    : topology_(topology), transform_(transform) {
  abr_boxes_.reserve(topology.abrs.size());
  for (const Abr& a : topology.abrs) abr_boxes_.push_back(a.box);
  template_ = build_bvh_sah(abr_boxes_);
  if (!subtrees_are_runs(template_.nodes)) throw std::logic_error("BVH node order does not allow a bottom-up refit");
  nodes_ = template_.nodes;
  bvh_bytes_ = CountedBytes(
      "BVH", MemorySpace::host,
      int64_t((template_.nodes.size() + nodes_.size()) * sizeof(BvhNode) + abr_boxes_.size() * sizeof(box3f)));
}

uint64_t AmrRenderer::classify(const std::vector<Range>& abr_ranges, const TransferTable& tf,
                               const IntegratorSettings& iso, bool skip, FrameStats* stats) {
  if (abr_ranges.size() != topology_.abrs.size()) throw std::invalid_argument("one value range per ABR expected");
  Stopwatch watch;
  std::vector<uint8_t> keep;  // empty: keep all
  uint64_t visible = topology_.abrs.size();
  if (skip) {
    keep = classify_abrs(abr_ranges, tf, iso);
    visible = uint64_t(std::count(keep.begin(), keep.end(), uint8_t(1)));
  }
  const double classify_s = watch.lap();
  refit(keep, stats);
  if (stats) stats->classify_seconds = classify_s;
  return visible;
}

uint64_t AmrRenderer::refit(const std::vector<uint8_t>& keep, FrameStats* stats) {
  Stopwatch watch;
  refit_bvh(nodes_, abr_boxes_, keep);
  const uint64_t visible = keep.empty() ? keep.size() : uint64_t(std::count(keep.begin(), keep.end(), uint8_t(1)));
  if (stats) {
    stats->refit_seconds = watch.seconds();
    stats->visible_abrs = keep.empty() ? topology_.abrs.size() : visible;
  }
  return keep.empty() ? topology_.abrs.size() : visible;
}

Box3<double> AmrRenderer::world_bounds() const { return vs::world_bounds(topology_, transform_); }

FrameView<AmrVolume> AmrRenderer::view(const FrameFields& fields, const OpticsView& optics, const TfView* color_tf,
                                       const Camera& camera, const FrameSettings& settings) const {
  if (optics.needs_second_field() && !fields.second) throw UsageError("blackbody optics needs a temperature field");
  FrameView<AmrVolume> v;
  v.volume.amr = make_view(topology_, fields.primary);
  v.volume.fields[0] = fields.primary;
  v.volume.fields[1] = fields.second;
  v.volume.nodes = nodes_.data();
  v.volume.node_count = uint32_t(nodes_.size());
  v.volume.all_nodes = template_.nodes.data();
  v.volume.all_node_count = uint32_t(template_.nodes.size());
  v.optics = optics;
  if (color_tf && fields.second) {
    v.color_isosurfaces = 1;
    v.color_tf = *color_tf;
  }
  v.camera = make_camera_view(camera, settings.width, settings.height);
  v.grid = make_grid_map(transform_);
  v.settings = resolve_settings(settings.integrator, world_bounds());
  v.width = settings.width;
  v.height = settings.height;
  return v;
}

Image AmrRenderer::render(Device device, const FrameView<AmrVolume>& host_view, FrameStats* stats) const {
  FrameView<AmrVolume> view = host_view;
  Image img(view.width, view.height);
  std::vector<uint32_t> counts(size_t(view.width) * view.height);
  view.rgba = img.rgba.data();
  view.sample_counts = counts.data();
  FrameStats local;
  local.device = device;
  if (device == Device::cuda) {
    const cuda::RenderTimes t = cuda::render(topology_, view);
    local.upload_seconds = t.upload_seconds;
    local.render_seconds = t.kernel_seconds;
  } else {
    Stopwatch watch;
    render_frame_cpu(view);
    local.render_seconds = watch.seconds();
  }
  local.samples = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
  if (stats) {
    stats->device = local.device;
    stats->upload_seconds = local.upload_seconds;
    stats->render_seconds = local.render_seconds;
    stats->samples = local.samples;
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
