#include "volstream/blocks/block_renderer.h"

#include <chrono>
#include <stdexcept>

#include "volstream/core/error.h"
#include "volstream/core/parallel.h"
#include "volstream/cuda/block_backend.h"

namespace vs {
namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

BlockRenderer::BlockRenderer(const AmrTopology& topology, const WorldTransform& transform)
    : topology_(topology), transform_(transform) {
  const auto t0 = Clock::now();
  kd_ = build_kd_blocks(topology.bricks);
  build_seconds_ = seconds_since(t0);
}

Box3<double> BlockRenderer::world_bounds() const {
  if (kd_.blocks.empty()) return {vec3d(0), vec3d(1)};
  return {transform_.to_world(vec3d(kd_.bounds.lower)), transform_.to_world(vec3d(kd_.bounds.upper))};
}

void BlockRenderer::set_fields(const float* values, const float* temperature, bool vertex_values) {
  const auto t0 = Clock::now();
  values_ = values;
  temperature_ = temperature;
  vertex_values_ = {};
  vertex_temperature_ = {};
  if (vertex_values && values && !kd_.blocks.empty()) {
    vertex_values_ = build_vertex_field(kd_, topology_.bricks, values);
    if (temperature) vertex_temperature_ = build_vertex_field(kd_, topology_.bricks, temperature);
  }
  vertex_seconds_ = seconds_since(t0);
}

BlockRenderView BlockRenderer::host_view(const TfView* tf, const Camera& camera, const BlockFrame& frame) const {
  if (!values_) throw std::logic_error("BlockRenderer: set_fields() before rendering");
  BlockRenderView v;
  v.kd = make_kd_view(kd_);
  v.bricks = topology_.bricks.data();
  v.brick_count = uint32_t(topology_.bricks.size());
  v.values = values_;
  v.temperature = temperature_;
  v.value_count = topology_.cell_count;
  if (frame.settings.reconstruction == Reconstruction::trilinear && !kd_.blocks.empty()) {
    // Without vertex values the integrator would fall back to per-brick interpolation (seams):
    // a different picture, so ask for them instead.
    if (vertex_values_.values.empty()) throw std::logic_error("BlockRenderer: trilinear needs set_fields(..., vertex_values = true)");
    v.vertex_offsets = vertex_values_.offsets.data();
    v.vertex_values = vertex_values_.values.data();
    v.vertex_temperature = temperature_ ? vertex_temperature_.values.data() : nullptr;
    v.vertex_count = vertex_values_.values.size();
  }
  if (tf) v.tf = *tf;
  v.bb = bb_.view(frame.rho_max, frame.emission, frame.absorption, frame.log_decades);
  v.bb.emission_power = frame.emission_power;
  v.camera = make_camera_view(camera, frame.width, frame.height);
  v.grid.origin = vec3f(transform_.origin);
  v.grid.inv_cell_size = vec3f(vec3d(1.0) / transform_.cell_size);
  v.settings = frame.settings;
  if (!(v.settings.ref_step > 0.f)) v.settings.ref_step = float(reduce_max(world_bounds().size()) / 256.0);
  if (!(v.settings.rate > 0.f)) throw UsageError("sampling rate must be positive");
  if (v.settings.optics == Optics::blackbody && !temperature_) throw UsageError("blackbody optics needs a temperature field");
  if (v.settings.optics == Optics::tf && !tf) throw UsageError("TF optics needs a transfer function");
  v.width = frame.width;
  v.height = frame.height;
  return v;
}

Image BlockRenderer::render(const TfView* tf, const Camera& camera, const BlockFrame& frame, Device device,
                            BlockStats* stats) const {
  Image img(frame.width, frame.height);
  std::vector<uint32_t> counts(size_t(frame.width) * frame.height, 0);
  BlockRenderView v = host_view(tf, camera, frame);
  v.rgba = img.rgba.data();
  v.sample_counts = counts.data();
  double upload = 0, render = 0;
  if (kd_.blocks.empty()) {
    // nothing to draw: a transparent image
  } else if (device == Device::cuda) {
    const cuda::BlockRenderTimes t = cuda::render_blocks(v);
    upload = t.upload_seconds + t.download_seconds;
    render = t.kernel_seconds;
  } else {
    const auto t0 = Clock::now();
    // Rows of 8x8 tiles: neighbouring rays visit the same blocks (cache locality).
    const uint32_t tx = (frame.width + 7) / 8, ty = (frame.height + 7) / 8;
    parallel_for("render_blocks", int64_t(tx) * ty, [&](int64_t tile) {
      const uint32_t x0 = uint32_t(tile % tx) * 8, y0 = uint32_t(tile / tx) * 8;
      for (uint32_t y = y0; y < y0 + 8 && y < frame.height; ++y)
        for (uint32_t x = x0; x < x0 + 8 && x < frame.width; ++x) render_block_pixel(v, x, y);
    });
    render = seconds_since(t0);
  }
  if (stats) {
    stats->build_seconds = build_seconds_;
    stats->upload_seconds = upload;
    stats->render_seconds = render;
    stats->samples = 0;
    for (uint32_t c : counts) stats->samples += c;
  }
  return img;
}

}  // namespace vs
