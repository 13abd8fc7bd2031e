// Page-locked host memory from the CUDA runtime (see pinned.h).
#include <cuda_runtime.h>

#include "volstream/cuda/pinned.h"

namespace vs::cuda {

void* pinned_host_alloc(size_t bytes, std::string& why) {
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    cudaGetLastError();  // clear the sticky "no device" error
    why = "no CUDA device";
    return nullptr;
  }
  void* p = nullptr;
  const cudaError_t e = cudaHostAlloc(&p, bytes, cudaHostAllocDefault);
  if (e != cudaSuccess) {
    cudaGetLastError();
    why = std::string("cudaHostAlloc: ") + cudaGetErrorString(e);
    return nullptr;
  }
  return p;
}

void pinned_host_free(void* p) {
  if (p) cudaFreeHost(p);
}

}  // namespace vs::cuda
