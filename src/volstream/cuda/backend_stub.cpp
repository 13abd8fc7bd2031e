// Without the CUDA backend: no device, and asking for one is a clear error.
#ifndef VOLSTREAM_HAVE_CUDA
#include <stdexcept>

#include "volstream/cuda/backend.h"

namespace vs::cuda {
bool cuda_available() { return false; }
std::string device_name() { return {}; }
std::vector<float> probe_points(const AmrTopology&, const Bvh&, const float*, const std::vector<vec3f>&) {
  throw std::runtime_error("this volstream was built without CUDA");
}
RenderTimes render(const AmrTopology&, const RenderView&) { throw std::runtime_error("this volstream was built without CUDA"); }
}  // namespace vs::cuda
#endif
