// The per-frame side of a mesh frame on the GPU, shared by both encodings (render_umesh_cuda.cu,
// render_compact_cuda.cu): the macrocells, their visible flags, the optics tables, the image and
// the probe points, and the launch of the shared integrator over MeshVolume<Locator>
// (render_frame.cuh). The two encodings' kernels are compiled in two files, so that their
// device code (most of the CUDA build's time) compiles in parallel.
#pragma once
#include "volstream/backend/buffer.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/launch.cuh"
#include "volstream/cuda/render_frame.cuh"
#include "volstream/cuda/umesh_backend.h"
#include "volstream/volume/umesh_volume.h"

namespace vs::cuda {

// What a frame of either encoding needs besides the mesh: the macrocells, their visible flags,
// the optics tables, the image and the probe points.
struct MeshFrameBuffers {
  Buffer<float> step_widths{Device::cuda, "mesh BVH and macrocells"};
  Buffer<int32_t> region_of_cell{Device::cuda, "mesh BVH and macrocells"};
  Buffer<uint8_t> visible{Device::cuda, "mesh BVH and macrocells"};
  Buffer<float> rgba{Device::cuda, "image"};
  Buffer<uint32_t> counts{Device::cuda, "image"};
  Buffer<vec3f> points{Device::cuda, "probe points"};
  Buffer<float> probed{Device::cuda, "probe points"};
  DeviceOpticsTables tables;

  size_t regions;

  explicit MeshFrameBuffers(const MacroCells& cells) : regions(cells.region_count()) {
    step_widths.upload(cells.step_width);
    region_of_cell.upload(cells.region_of_cell);
  }

  template <typename Locator>
  RenderTimes render(const FrameView<MeshVolume<Locator>>& h, const Locator& device_mesh) {
    const Stopwatch watch;
    visible.upload(h.volume.visible, regions);
    const size_t pixels = size_t(h.width) * h.height;
    rgba.resize(pixels * 4);
    counts.resize(pixels);
    FrameView<MeshVolume<Locator>> d = h;
    d.volume.mesh = device_mesh;
    d.volume.visible = visible.data();
    d.volume.step_widths = step_widths.data();
    d.volume.region_of_cell = region_of_cell.data();
    tables.upload(h, d, 0);  // the stream render_frame runs on below
    d.rgba = rgba.data();
    d.sample_counts = h.sample_counts ? counts.data() : nullptr;
    RenderTimes t;
    t.upload_seconds = watch.seconds();
    t.kernel_seconds = render_frame(d, 0);
    copy_to_host(h.rgba, rgba.data(), pixels * 4 * sizeof(float));
    if (h.sample_counts) copy_to_host(h.sample_counts, counts.data(), pixels * sizeof(uint32_t));
    return t;
  }

  template <typename Locator>
  std::vector<float> probe(const Locator& view, const float* device_values, const std::vector<vec3f>& grid_points) {
    points.upload(grid_points);
    probed.resize(grid_points.size());
    const vec3f* at = points.data();
    float* out = probed.data();
    parallel_for(
        "probe", int64_t(grid_points.size()), [=] __device__(int64_t i) { out[i] = view.sample(device_values, at[i]); },
        0);
    return probed.download();
  }
};

}  // namespace vs::cuda
