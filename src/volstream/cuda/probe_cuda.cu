// CUDA device queries, and one-off point probes through a DeviceScene (DeviceScene::probe).
#include "volstream/cuda/backend.h"
#include "volstream/cuda/cuda_check.h"

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
  DeviceScene scene(topology);
  scene.set_bvh(bvh.nodes);
  DeviceValueBuffers device_values(1, topology.cell_count);
  device_values.upload(0, values, topology.cell_count);
  return scene.probe(device_values.data(0), grid_points);
}

}  // namespace vs::cuda
