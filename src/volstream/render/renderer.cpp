#include "volstream/render/renderer.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include "volstream/accel/bvh_sah.h"
#include "volstream/accel/refit.h"
#include "volstream/core/error.h"
#include "volstream/core/parallel.h"
#include "volstream/render/classify.h"
#include "volstream/cuda/backend.h"

namespace vs {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Device resolve_device(const std::string& name) {
  if (name == "cpu") return Device::cpu;
  if (name == "cuda") {
    if (!cuda::cuda_available()) throw UsageError("--device cuda: no CUDA device (or built without CUDA)");
    return Device::cuda;
  }
  if (name == "auto") return cuda::cuda_available() ? Device::cuda : Device::cpu;
  throw UsageError("unknown device '" + name + "' (auto, cpu or cuda)");
}

const char* to_string(Device d) { return d == Device::cuda ? "cuda" : "cpu"; }

std::vector<uint8_t> classify_abrs(const std::vector<Range>& ranges, const TransferTable& tf,
                                   const IntegratorSettings& iso) {
  std::vector<uint8_t> visible(ranges.size());
  const OpacityIndex opacity = tf.opacity_index();
  parallel_for("classify", int64_t(ranges.size()),
               [&](int64_t i) { visible[size_t(i)] = abr_visible(ranges[size_t(i)], opacity, iso) ? 1 : 0; });
  return visible;
}

AmrRenderer::AmrRenderer(const AmrTopology& topology, const WorldTransform& transform)
    : topology_(topology), transform_(transform) {
  abr_boxes_.reserve(topology.abrs.size());
  for (const Abr& a : topology.abrs) abr_boxes_.push_back(a.box);
  template_ = build_bvh_sah(abr_boxes_);
  if (!subtrees_are_runs(template_.nodes)) throw std::logic_error("BVH node order does not allow a bottom-up refit");
  nodes_ = template_.nodes;
}

uint64_t AmrRenderer::classify(const std::vector<Range>& abr_ranges, const TransferTable& tf,
                               const IntegratorSettings& iso, bool skip, FrameStats* stats) {
  if (abr_ranges.size() != topology_.abrs.size()) throw std::invalid_argument("one value range per ABR expected");
  auto t0 = std::chrono::steady_clock::now();
  std::vector<uint8_t> keep;  // empty: keep all
  uint64_t visible = topology_.abrs.size();
  if (skip) {
    keep = classify_abrs(abr_ranges, tf, iso);
    visible = uint64_t(std::count(keep.begin(), keep.end(), uint8_t(1)));
  }
  const double classify_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  refit_bvh(nodes_, abr_boxes_, keep);
  if (stats) {
    stats->classify_seconds = classify_s;
    stats->refit_seconds = seconds_since(t0);
    stats->visible_abrs = visible;
  }
  return visible;
}

Box3<double> AmrRenderer::world_bounds() const {
  Box3<double> b{vec3d(INFINITY), vec3d(-INFINITY)};
  for (const Brick& br : topology_.bricks) {
    const box3i c = br.cell_box();
    b.extend(transform_.to_world(vec3d(c.lower)));
    b.extend(transform_.to_world(vec3d(c.upper)));
  }
  if (b.empty()) b = {vec3d(0), vec3d(1)};
  return b;
}

double AmrRenderer::default_reference_step() const { return reduce_max(world_bounds().size()) / 256.0; }

RenderView AmrRenderer::host_view(const float* values, const TransferTable& tf, const float* color_values,
                                  const TransferTable* color_tf, const Camera& camera,
                                  const FrameSettings& settings) const {
  RenderView v;
  v.amr = make_view(topology_, values);
  v.color_values = color_tf ? color_values : nullptr;
  v.nodes = nodes_.data();
  v.node_count = uint32_t(nodes_.size());
  v.all_nodes = template_.nodes.data();
  v.all_node_count = uint32_t(template_.nodes.size());
  v.tf = tf.view();
  if (color_tf) v.color_tf = color_tf->view();
  v.camera = make_camera_view(camera, settings.width, settings.height);
  v.grid.origin = vec3f(transform_.origin);
  v.grid.inv_cell_size = vec3f(vec3d(1.0) / transform_.cell_size);
  v.settings = settings.integrator;
  if (!(v.settings.ref_step > 0.f)) v.settings.ref_step = float(default_reference_step());
  if (!(v.settings.rate > 0.f)) throw UsageError("sampling rate must be positive");
  v.width = settings.width;
  v.height = settings.height;
  return v;
}

void render_cpu(const RenderView& view) {
  // 8x8 tiles: neighbouring rays touch the same bricks, which keeps their cells in cache.
  constexpr uint32_t kTile = 8;
  const uint32_t tiles_x = (view.width + kTile - 1) / kTile, tiles_y = (view.height + kTile - 1) / kTile;
  parallel_for("render", int64_t(tiles_x) * tiles_y, [&](int64_t tile) {
    const uint32_t x0 = uint32_t(tile % tiles_x) * kTile, y0 = uint32_t(tile / tiles_x) * kTile;
    for (uint32_t y = y0; y < std::min(y0 + kTile, view.height); ++y)
      for (uint32_t x = x0; x < std::min(x0 + kTile, view.width); ++x) render_pixel(view, x, y);
  });
}

Image AmrRenderer::render(Device device, const float* values, const TransferTable& tf, const float* color_values,
                          const TransferTable* color_tf, const Camera& camera, const FrameSettings& settings,
                          FrameStats* stats) const {
  RenderView view = host_view(values, tf, color_values, color_tf, camera, settings);
  Image img(settings.width, settings.height);
  std::vector<uint32_t> counts(size_t(settings.width) * settings.height);
  view.rgba = img.rgba.data();
  view.sample_counts = counts.data();
  FrameStats local;
  local.device = device;
  if (device == Device::cuda) {
    const cuda::RenderTimes t = cuda::render(topology_, view);
    local.upload_seconds = t.upload_seconds;
    local.render_seconds = t.kernel_seconds;
  } else {
    const auto t0 = std::chrono::steady_clock::now();
    render_cpu(view);
    local.render_seconds = seconds_since(t0);
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

}  // namespace vs
