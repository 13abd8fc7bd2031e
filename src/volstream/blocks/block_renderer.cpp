#include "volstream/blocks/block_renderer.h"

#include <chrono>

#include "volstream/core/error.h"
#include "volstream/core/parallel.h"

namespace vs {

BlockRenderer::BlockRenderer(const AmrTopology& topology, const WorldTransform& transform)
    : topology_(topology), transform_(transform) {
  const auto t0 = std::chrono::steady_clock::now();
  kd_ = build_kd_blocks(topology.bricks);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Box3<double> BlockRenderer::world_bounds() const {
  if (kd_.blocks.empty()) return {vec3d(0), vec3d(1)};
  return {transform_.to_world(vec3d(kd_.bounds.lower)), transform_.to_world(vec3d(kd_.bounds.upper))};
}

BlockRenderView BlockRenderer::host_view(const float* values, const float* temperature, const TfView* tf,
                                         const Camera& camera, const BlockFrame& frame) const {
  BlockRenderView v;
  v.kd = make_kd_view(kd_);
  v.bricks = topology_.bricks.data();
  v.values = values;
  v.temperature = temperature;
  if (tf) v.tf = *tf;
  v.bb = bb_.view(frame.rho_max, frame.emission, frame.absorption, frame.log_decades);
  v.bb.emission_power = frame.emission_power;
  v.camera = make_camera_view(camera, frame.width, frame.height);
  v.grid.origin = vec3f(transform_.origin);
  v.grid.inv_cell_size = vec3f(vec3d(1.0) / transform_.cell_size);
  v.settings = frame.settings;
  if (!(v.settings.ref_step > 0.f)) v.settings.ref_step = float(reduce_max(world_bounds().size()) / 256.0);
  if (!(v.settings.rate > 0.f)) throw UsageError("sampling rate must be positive");
  if (v.settings.optics == Optics::blackbody && !temperature) throw UsageError("blackbody optics needs a temperature field");
  if (v.settings.optics == Optics::tf && !tf) throw UsageError("TF optics needs a transfer function");
  v.width = frame.width;
  v.height = frame.height;
  return v;
}

Image BlockRenderer::render(const float* values, const float* temperature, const TfView* tf, const Camera& camera,
                            const BlockFrame& frame, BlockStats* stats) const {
  Image img(frame.width, frame.height);
  std::vector<uint32_t> counts(size_t(frame.width) * frame.height, 0);
  BlockRenderView v = host_view(values, temperature, tf, camera, frame);
  v.rgba = img.rgba.data();
  v.sample_counts = counts.data();
  const auto tv = std::chrono::steady_clock::now();
  VertexField vf, vt;  // shared vertex samples for trilinear reconstruction
  if (frame.settings.reconstruction == Reconstruction::trilinear && !kd_.blocks.empty()) {
    vf = build_vertex_field(kd_, topology_.bricks, values);
    v.vertex_offsets = vf.offsets.data();
    v.vertex_values = vf.values.data();
    if (temperature) {
      vt = build_vertex_field(kd_, topology_.bricks, temperature);
      v.vertex_temperature = vt.values.data();
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (!kd_.blocks.empty()) {
    // Rows of 8x8 tiles: neighbouring rays visit the same blocks (cache locality).
    const uint32_t tx = (frame.width + 7) / 8, ty = (frame.height + 7) / 8;
    parallel_for("render_blocks", int64_t(tx) * ty, [&](int64_t tile) {
      const uint32_t x0 = uint32_t(tile % tx) * 8, y0 = uint32_t(tile / tx) * 8;
      for (uint32_t y = y0; y < y0 + 8 && y < frame.height; ++y)
        for (uint32_t x = x0; x < x0 + 8 && x < frame.width; ++x) render_block_pixel(v, x, y);
    });
  }
  if (stats) {
    stats->render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stats->build_seconds = build_seconds_;
    stats->vertex_seconds = std::chrono::duration<double>(t0 - tv).count();
    stats->samples = 0;
    for (uint32_t c : counts) stats->samples += c;
  }
  return img;
}

}  // namespace vs
