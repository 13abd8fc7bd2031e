#include "volstream/backend/device.h"

#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"

namespace vs {

Device resolve_device(const std::string& name) {
  if (name == "cpu") return Device::cpu;
  if (name == "cuda") {
    if (!cuda::cuda_available()) throw UsageError("--device cuda: no CUDA device (or built without CUDA)");
    return Device::cuda;
  }
  if (name == "auto") return cuda::cuda_available() ? Device::cuda : Device::cpu;
  throw UsageError("unknown device '" + name + "' (auto, cpu or cuda)");
}

const char* to_string(Device d) { return d == Device::cuda ? "cuda" : "cpu"; }

std::string describe(Device d) { return d == Device::cuda ? "cuda (" + cuda::device_name() + ")" : "cpu"; }

}  // namespace vs
