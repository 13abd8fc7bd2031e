// One launch of the integrator (render/integrators/integrator.h) for any volume kind: one thread
// per pixel over a view whose pointers are all device pointers, timed with CUDA events.
#pragma once
#include "volstream/cuda/launch.cuh"
#include "volstream/render/integrators/integrator.h"

namespace vs::cuda {

// The tables a frame's optics read (transfer function, blackbody colours, isosurface colours),
// copied to the device for every volume kind's frames (DeviceScene's and the meshes'): the host
// view points at host memory, which a kernel must not read.
struct DeviceOpticsTables {
  DeviceBuffer<Rgba> tf{"transfer tables"}, color_tf{"transfer tables"};
  DeviceBuffer<vec3f> bb{"transfer tables"};  // blackbody colour table

  // Copies host view h's tables on `stream`, which the frame's kernel then runs on, and points
  // device view d at them.
  template <typename V>
  void upload(const FrameView<V>& h, FrameView<V>& d, cudaStream_t stream) {
    if (h.optics.tf.table) tf.upload_async(h.optics.tf.table, h.optics.tf.size, stream);
    if (h.color_isosurfaces) color_tf.upload_async(h.color_tf.table, h.color_tf.size, stream);
    if (h.optics.bb.table) bb.upload_async(h.optics.bb.table, h.optics.bb.size, stream);
    d.optics.tf.table = h.optics.tf.table ? tf.data() : nullptr;
    d.optics.bb.table = h.optics.bb.table ? bb.data() : nullptr;
    d.color_tf.table = h.color_isosurfaces ? color_tf.data() : nullptr;
  }
};

// The integrator keeps its traversal stacks, segment batch and isosurface hits in local memory
// (about 1 KiB per thread, as ptxas reports): make sure the per-thread stack allows it. Once per
// process: it synchronises the device.
inline void ensure_integrator_stack() {
  static const bool done = [] {
    size_t stack = 0;
    VS_CUDA_CHECK(cudaDeviceGetLimit(&stack, cudaLimitStackSize));
    if (stack < 4096) VS_CUDA_CHECK(cudaDeviceSetLimit(cudaLimitStackSize, 4096));
    return true;
  }();
  (void)done;
}

// Returns the kernel's time in seconds (waits for the stream).
template <typename V>
double render_frame(const FrameView<V>& d, cudaStream_t stream) {
  ensure_integrator_stack();
  const Event start, stop;
  VS_CUDA_CHECK(cudaEventRecord(start.e, stream));
  const uint32_t width = d.width;
  // One kernel per optical model (render_pixel's template argument), chosen once per frame.
  if (d.optics.kind == OpticsKind::blackbody)
    parallel_for(
        "render", int64_t(d.width) * d.height,
        [=] __device__(int64_t i) { render_pixel<OpticsKind::blackbody>(d, uint32_t(i % width), uint32_t(i / width)); },
        stream);
  else
    parallel_for(
        "render", int64_t(d.width) * d.height,
        [=] __device__(int64_t i) { render_pixel<OpticsKind::tf>(d, uint32_t(i % width), uint32_t(i / width)); },
        stream);
  VS_CUDA_CHECK(cudaEventRecord(stop.e, stream));
  VS_CUDA_CHECK(cudaEventSynchronize(stop.e));
  float ms = 0.f;
  VS_CUDA_CHECK(cudaEventElapsedTime(&ms, start.e, stop.e));
  return ms * 1e-3;
}

}  // namespace vs::cuda
