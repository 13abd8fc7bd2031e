// The GPU side of the block raycaster (block_backend.h): copies of the view's arrays and one
// thread per pixel running the same render_block_pixel as the CPU (blocks/block_integrator.h).
#include <chrono>

#include "volstream/blocks/block_integrator.h"
#include "volstream/cuda/block_backend.h"
#include "volstream/cuda/launch.cuh"

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

BlockRenderTimes render_blocks(const BlockRenderView& h) {
  BlockRenderTimes times;
  const size_t pixels = size_t(h.width) * h.height;
  auto t0 = Clock::now();
  // The kd traversal stack (kMaxKdDepth entries) is the kernel's whole stack frame, 768 bytes
  // (ptxas -v): within the default per-thread stack, no cudaDeviceSetLimit needed.
  DeviceBuffer<KdNode> nodes;
  DeviceBuffer<Block> blocks;
  DeviceBuffer<Brick> bricks;
  DeviceBuffer<float> values, temperature, vertex_values, vertex_temperature, rgba;
  DeviceBuffer<uint64_t> vertex_offsets;
  DeviceBuffer<Rgba> tf;
  DeviceBuffer<vec3f> bb;
  DeviceBuffer<uint32_t> counts;
  BlockRenderView d = h;
  d.kd.nodes = copy_in(nodes, h.kd.nodes, h.kd.node_count);
  d.kd.blocks = copy_in(blocks, h.kd.blocks, h.kd.block_count);
  d.bricks = copy_in(bricks, h.bricks, h.brick_count);
  d.values = copy_in(values, h.values, h.value_count);
  d.temperature = copy_in(temperature, h.temperature, h.value_count);
  d.vertex_offsets = copy_in(vertex_offsets, h.vertex_offsets, h.kd.block_count);
  d.vertex_values = copy_in(vertex_values, h.vertex_values, h.vertex_count);
  d.vertex_temperature = copy_in(vertex_temperature, h.vertex_temperature, h.vertex_count);
  d.tf.table = copy_in(tf, h.tf.table, h.tf.size);
  d.bb.table = copy_in(bb, h.bb.table, h.bb.size);
  rgba.resize(4 * pixels);
  d.rgba = rgba.data();
  if (h.sample_counts) {
    counts.resize(pixels);
    d.sample_counts = counts.data();
  }
  times.upload_seconds = seconds_since(t0);

  const Event start, stop;
  VS_CUDA_CHECK(cudaEventRecord(start.e));
  const uint32_t width = h.width;
  parallel_for("render_blocks", int64_t(pixels), [=] __device__(int64_t i) {
    render_block_pixel(d, uint32_t(i % width), uint32_t(i / width));
  });
  VS_CUDA_CHECK(cudaEventRecord(stop.e));
  VS_CUDA_CHECK(cudaEventSynchronize(stop.e));
  float ms = 0.f;
  VS_CUDA_CHECK(cudaEventElapsedTime(&ms, start.e, stop.e));
  times.kernel_seconds = ms * 1e-3;

  t0 = Clock::now();
  VS_CUDA_CHECK(cudaMemcpy(h.rgba, d.rgba, 4 * pixels * sizeof(float), cudaMemcpyDeviceToHost));
  if (h.sample_counts)
    VS_CUDA_CHECK(cudaMemcpy(h.sample_counts, d.sample_counts, pixels * sizeof(uint32_t), cudaMemcpyDeviceToHost));
  times.download_seconds = seconds_since(t0);
  return times;
}

}  // namespace vs::cuda
