// GPU rendering: the host-device render_pixel() from render/integrator.h launched one thread
// per pixel. Only memory handling differs from the CPU path: the view's host pointers are
// replaced by device copies.
#include <chrono>

#include "volstream/cuda/backend.h"
#include "volstream/cuda/launch.cuh"
#include "volstream/render/integrator.h"

namespace vs::cuda {

RenderTimes render(const AmrTopology& topology, const RenderView& host_view) {
  RenderTimes times;
  const auto t0 = std::chrono::steady_clock::now();
  const RenderView& h = host_view;
  DeviceBuffer<Brick> bricks(topology.bricks);
  DeviceBuffer<Abr> abrs(topology.abrs);
  DeviceBuffer<uint32_t> abr_bricks(topology.abr_bricks);
  DeviceBuffer<float> values, color_values;
  values.upload(h.amr.values, topology.cell_count);
  if (h.color_values) color_values.upload(h.color_values, topology.cell_count);
  DeviceBuffer<BvhNode> nodes, all_nodes;
  nodes.upload(h.nodes, h.node_count);
  all_nodes.upload(h.all_nodes, h.all_node_count);
  DeviceBuffer<Rgba> tf, color_tf;
  tf.upload(h.tf.table, h.tf.size);
  if (h.color_values) color_tf.upload(h.color_tf.table, h.color_tf.size);
  const size_t pixels = size_t(h.width) * h.height;
  DeviceBuffer<float> rgba(4 * pixels);
  DeviceBuffer<uint32_t> counts(h.sample_counts ? pixels : 0);
  VS_CUDA_CHECK(cudaDeviceSynchronize());
  times.upload_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  RenderView d = h;
  d.amr = {bricks.data(), abrs.data(), abr_bricks.data(), values.data(), uint32_t(topology.bricks.size()),
           uint32_t(topology.abrs.size())};
  d.color_values = h.color_values ? color_values.data() : nullptr;
  d.nodes = nodes.data();
  d.all_nodes = all_nodes.data();
  d.tf.table = tf.data();
  d.color_tf.table = h.color_values ? color_tf.data() : nullptr;
  d.rgba = rgba.data();
  d.sample_counts = h.sample_counts ? counts.data() : nullptr;

  // The integrator keeps its traversal stacks and segment batch in local memory (~1 KiB per
  // thread, as ptxas reports); make sure the per-thread stack allows it.
  size_t stack = 0;
  VS_CUDA_CHECK(cudaDeviceGetLimit(&stack, cudaLimitStackSize));
  if (stack < 4096) VS_CUDA_CHECK(cudaDeviceSetLimit(cudaLimitStackSize, 4096));

  cudaEvent_t start, stop;
  VS_CUDA_CHECK(cudaEventCreate(&start));
  VS_CUDA_CHECK(cudaEventCreate(&stop));
  VS_CUDA_CHECK(cudaEventRecord(start));
  const uint32_t width = h.width;
  parallel_for("render", int64_t(pixels), [=] __device__(int64_t i) {
    render_pixel(d, uint32_t(i % width), uint32_t(i / width));
  });
  VS_CUDA_CHECK(cudaEventRecord(stop));
  VS_CUDA_CHECK(cudaEventSynchronize(stop));
  float ms = 0.f;
  VS_CUDA_CHECK(cudaEventElapsedTime(&ms, start, stop));
  VS_CUDA_CHECK(cudaEventDestroy(start));
  VS_CUDA_CHECK(cudaEventDestroy(stop));
  times.kernel_seconds = ms * 1e-3;

  VS_CUDA_CHECK(cudaMemcpy(h.rgba, rgba.data(), 4 * pixels * sizeof(float), cudaMemcpyDeviceToHost));
  if (h.sample_counts)
    VS_CUDA_CHECK(cudaMemcpy(h.sample_counts, counts.data(), pixels * sizeof(uint32_t), cudaMemcpyDeviceToHost));
  return times;
}

}  // namespace vs::cuda
