// GPU point probes: the host-device sample_point() from amr/probe.h launched as a CUDA grid.
#include "volstream/amr/probe.h"
#include "volstream/cuda/backend.h"
#include "volstream/cuda/launch.cuh"

namespace vs::cuda {

bool cuda_available() {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

std::string device_name() {
  if (!cuda_available()) return {};
  cudaDeviceProp prop{};
  VS_CUDA_CHECK(cudaGetDeviceProperties(&prop, 0));
  return prop.name;
}

std::vector<float> probe_points(const AmrTopology& topology, const Bvh& bvh, const float* values,
                                const std::vector<vec3f>& grid_points) {
  DeviceBuffer<Brick> bricks(topology.bricks);
  DeviceBuffer<Abr> abrs(topology.abrs);
  DeviceBuffer<uint32_t> abr_bricks(topology.abr_bricks);
  DeviceBuffer<BvhNode> nodes(bvh.nodes);
  DeviceBuffer<float> d_values;
  d_values.upload(values, topology.cell_count);
  DeviceBuffer<vec3f> points(grid_points);
  DeviceBuffer<float> out(grid_points.size());
  AmrView view{bricks.data(), abrs.data(), abr_bricks.data(), d_values.data(), uint32_t(topology.bricks.size()),
               uint32_t(topology.abrs.size())};
  const BvhNode* n = nodes.data();
  const uint32_t node_count = uint32_t(bvh.nodes.size());
  const vec3f* p = points.data();
  float* o = out.data();
  parallel_for("probe", int64_t(grid_points.size()),
               [=] __device__(int64_t i) { o[i] = sample_point(view, n, node_count, p[i]); });
  VS_CUDA_CHECK(cudaDeviceSynchronize());
  return out.download();
}

}  // namespace vs::cuda
