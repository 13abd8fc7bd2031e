#include "volstream/render/integrators/block_renderer.h"

#include <numeric>
#include <stdexcept>

#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/block_backend.h"
#include "volstream/render/integrators/launch_cpu.h"

namespace vs {

BlockRenderer::BlockRenderer(const AmrTopology& topology, const WorldTransform& transform)
    : topology_(topology), transform_(transform) {
  Stopwatch watch;
  kd_ = build_kd_blocks(topology.bricks);
  build_seconds_ = watch.seconds();
  kd_bytes_ = CountedBytes("kd-tree blocks", MemorySpace::host,
                           int64_t(kd_.nodes.size() * sizeof(KdNode) + kd_.blocks.size() * sizeof(Block)));
}

Box3<double> BlockRenderer::world_bounds() const {
  if (kd_.blocks.empty()) return {vec3d(0), vec3d(1)};
  return {transform_.to_world(vec3d(kd_.bounds.lower)), transform_.to_world(vec3d(kd_.bounds.upper))};
}

const VertexField* BlockRenderer::vertex_field(int field) const {
  const VertexField& f = field == 0 ? vertex_values_ : vertex_second_;
  return f.values.empty() ? nullptr : &f;
}

void BlockRenderer::set_fields(const float* values, const float* second, bool vertex_values) {
  Stopwatch watch;
  values_ = values;
  second_ = second;
  vertex_values_ = {};
  vertex_second_ = {};
  if (vertex_values && values && !kd_.blocks.empty()) {
    vertex_values_ = build_vertex_field(kd_, topology_.bricks, values);
    if (second) vertex_second_ = build_vertex_field(kd_, topology_.bricks, second);
  }
  vertex_seconds_ = watch.seconds();
  auto bytes = [](const VertexField& f) {
    return f.offsets.size() * sizeof(uint64_t) + f.values.size() * sizeof(float);
  };
  vertex_bytes_ =
      CountedBytes("vertex values", MemorySpace::host, int64_t(bytes(vertex_values_) + bytes(vertex_second_)));
}

FrameView<BlockVolume> BlockRenderer::view(const TfView* tf, const Camera& camera, const BlockFrame& frame,
                                           const TfView* color_tf) const {
  if (!values_) throw std::logic_error("BlockRenderer: set_fields() before rendering");
  FrameView<BlockVolume> v;
  BlockVolume& vol = v.volume;
  vol.kd = make_kd_view(kd_);
  vol.bricks = topology_.bricks.data();
  vol.fields[0] = values_;
  vol.fields[1] = second_;
  vol.reconstruction = frame.settings.reconstruction;
  if (frame.settings.reconstruction == Reconstruction::trilinear && !kd_.blocks.empty()) {
    // Without vertex values the volume would fall back to per-brick interpolation (seams): a
    // different picture, so ask for them instead.
    if (vertex_values_.values.empty())
      throw std::logic_error("BlockRenderer: trilinear needs set_fields(..., vertex_values = true)");
    vol.vertex_offsets = vertex_values_.offsets.data();
    vol.vertex_fields[0] = vertex_values_.values.data();
    vol.vertex_fields[1] = second_ ? vertex_second_.values.data() : nullptr;
  }
  v.optics.kind = frame.settings.optics;
  if (tf) v.optics.tf = *tf;
  if (frame.settings.optics == Optics::blackbody) v.optics.bb = default_blackbody_table().view(frame.blackbody);
  if (frame.settings.optics == Optics::blackbody && !second_)
    throw UsageError("blackbody optics needs a temperature field");
  if (!tf && (frame.settings.optics == Optics::tf || frame.integrator.iso_count > 0))
    throw UsageError("TF optics and isosurfaces need a transfer function");
  if (color_tf && second_) {
    v.color_isosurfaces = 1;
    v.color_tf = *color_tf;
  }
  v.camera = make_camera_view(camera, frame.width, frame.height);
  v.grid = make_grid_map(transform_);
  IntegratorSettings s = frame.integrator;
  s.rate = frame.settings.rate;
  s.ref_step = frame.settings.ref_step;
  s.adaptive = 1;  // every block steps at its own level's cell width
  s.march = March::fixed_midpoint;
  v.settings = resolve_settings(s, world_bounds());
  v.width = frame.width;
  v.height = frame.height;
  return v;
}

Image BlockRenderer::render(const TfView* tf, const Camera& camera, const BlockFrame& frame, Device device,
                            BlockStats* stats, const TfView* color_tf) const {
  Image img(frame.width, frame.height);
  FrameView<BlockVolume> v = view(tf, camera, frame, color_tf);
  v.rgba = img.rgba.data();
  double upload = 0, render = 0;
  uint64_t samples = 0;
  if (kd_.blocks.empty()) {
    // nothing to draw: a transparent image
  } else if (device == Device::cuda) {
    std::vector<uint32_t> counts(size_t(frame.width) * frame.height, 0);
    v.sample_counts = counts.data();
    const cuda::BlockRenderTimes t = cuda::render_blocks(v, topology_, kd_, vertex_field(0), vertex_field(1));
    upload = t.upload_seconds + t.download_seconds;
    render = t.kernel_seconds;
    samples = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
  } else {
    Stopwatch watch;
    samples = render_frame_cpu(v);
    render = watch.seconds();
  }
  if (stats) {
    stats->build_seconds = build_seconds_;
    stats->upload_seconds = upload;
    stats->render_seconds = render;
    stats->samples = samples;
  }
  return img;
}

}  // namespace vs
