// The backend a FrameRenderer (or any caller) runs on: where buffers live, how kernels are
// launched and what they cost. The CPU backend launches through parallel_for (parallel.h, oneTBB);
// the CUDA backend through cuda/launch.cuh, with kernels instantiated in .cu files from the same
// VS_HOST_DEVICE sources, on the streams of a cuda::DeviceScene. Both time every named launch
// (launch_times.h) and count every buffer (memory.h).
#pragma once
#include <string>

#include "volstream/backend/buffer.h"
#include "volstream/backend/device.h"
#include "volstream/backend/launch_times.h"
#include "volstream/backend/memory.h"

namespace vs {

class Backend {
 public:
  explicit Backend(Device device) : device_(device) {}
  Device device() const { return device_; }
  // An empty buffer in this backend's memory, counted as `structure`.
  template <typename T>
  Buffer<T> buffer(const char* structure) const {
    return Buffer<T>(device_, structure);
  }
  // "cpu" or "cuda (<GPU name>)".
  std::string name() const { return describe(device_); }
  // Every counted structure, and every named launch so far (process-wide).
  std::string memory_report() const { return format_memory(memory_ledger().snapshot()); }
  std::string launch_report() const { return format_launch_times(launch_times().snapshot()); }

 private:
  Device device_;
};

}  // namespace vs
