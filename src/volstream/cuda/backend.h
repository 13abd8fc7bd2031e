// What the host code may ask of the CUDA backend. Everything here also links without CUDA:
// cuda_available() is then false and the other calls throw.
#pragma once
#include <string>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/amr/model.h"

namespace vs {
struct RenderView;
}

namespace vs::cuda {

bool cuda_available();        // compiled with CUDA and a device is present
std::string device_name();    // e.g. "NVIDIA H100 80GB HBM3"; empty without a device

// The same computation as vs::probe_points, on the GPU.
std::vector<float> probe_points(const AmrTopology& topology, const Bvh& bvh, const float* values,
                                const std::vector<vec3f>& grid_points);

// Renders `host_view` (host pointers, as from AmrRenderer::host_view) on the GPU: uploads the
// topology, values, BVHs and tables, runs render_pixel per pixel, and copies the image (and the
// per-pixel sample counts when host_view.sample_counts is set) back to host_view.rgba.
struct RenderTimes {
  double upload_seconds = 0, kernel_seconds = 0;
};
RenderTimes render(const AmrTopology& topology, const RenderView& host_view);

}  // namespace vs::cuda
