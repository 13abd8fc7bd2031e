// The GPU side of the block integrator (block_backend.h): copies of the view's arrays and the
// same integrator as the CPU (render/integrators/integrator.h), one thread per pixel.
#include <chrono>

#include "volstream/cuda/block_backend.h"
#include "volstream/cuda/render_frame.cuh"
#include "volstream/volume/block_volume.h"

namespace vs::cuda {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Copies n elements to `buffer` and returns the device pointer; an array the view does not use
// (null) stays null, so that the kernel takes the same branches as on the CPU.
template <typename T>
T* copy_in(DeviceBuffer<T>& buffer, const T* host, size_t n) {
  if (!host) return nullptr;
  buffer.upload(host, n);
  return buffer.data();
}

}  // namespace

BlockRenderTimes render_blocks(const FrameView<BlockVolume>& h, const AmrTopology& topology, const KdBlocks& kd,
                               uint64_t vertex_count) {
  BlockRenderTimes times;
  const size_t pixels = size_t(h.width) * h.height;
  auto t0 = Clock::now();
  DeviceBuffer<KdNode> nodes;
  DeviceBuffer<Block> blocks;
  DeviceBuffer<Brick> bricks;
  DeviceBuffer<float> fields[kVolumeFields], vertex_fields[kVolumeFields], rgba;
  DeviceBuffer<uint64_t> vertex_offsets;
  DeviceBuffer<Rgba> tf, color_tf;
  DeviceBuffer<vec3f> bb;
  DeviceBuffer<uint32_t> counts;
  FrameView<BlockVolume> d = h;
  BlockVolume& v = d.volume;
  v.kd.nodes = copy_in(nodes, h.volume.kd.nodes, kd.nodes.size());
  v.kd.blocks = copy_in(blocks, h.volume.kd.blocks, kd.blocks.size());
  v.bricks = copy_in(bricks, h.volume.bricks, topology.bricks.size());
  for (int f = 0; f < kVolumeFields; ++f) {
    v.fields[f] = copy_in(fields[f], h.volume.fields[f], topology.cell_count);
    v.vertex_fields[f] = copy_in(vertex_fields[f], h.volume.vertex_fields[f], vertex_count);
  }
  v.vertex_offsets = copy_in(vertex_offsets, h.volume.vertex_offsets, kd.blocks.size());
  d.optics.tf.table = copy_in(tf, h.optics.tf.table, h.optics.tf.size);
  d.optics.bb.table = copy_in(bb, h.optics.bb.table, h.optics.bb.size);
  d.color_tf.table = copy_in(color_tf, h.color_tf.table, h.color_tf.size);
  rgba.resize(4 * pixels);
  d.rgba = rgba.data();
  if (h.sample_counts) {
    counts.resize(pixels);
    d.sample_counts = counts.data();
  }
  times.upload_seconds = seconds_since(t0);

  times.kernel_seconds = render_frame(d, cudaStream_t(0));

  t0 = Clock::now();
  VS_CUDA_CHECK(cudaMemcpy(h.rgba, d.rgba, 4 * pixels * sizeof(float), cudaMemcpyDeviceToHost));
  if (h.sample_counts)
    VS_CUDA_CHECK(cudaMemcpy(h.sample_counts, d.sample_counts, pixels * sizeof(uint32_t), cudaMemcpyDeviceToHost));
  times.download_seconds = seconds_since(t0);
  return times;
}

}  // namespace vs::cuda
