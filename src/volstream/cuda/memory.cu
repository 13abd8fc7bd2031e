#include "volstream/cuda/cuda_check.h"
#include "volstream/cuda/memory.h"

namespace vs::cuda {

void* device_malloc(size_t bytes) {
  void* p = nullptr;
  if (bytes) VS_CUDA_CHECK(cudaMalloc(&p, bytes));
  return p;
}

void device_free(void* p) { cudaFree(p); }

// cudaMemcpy from pageable memory returns once the data is staged, and kernels on non-blocking
// streams do not wait for the legacy stream: synchronise so "returned" means "arrived".
void copy_to_device(void* device, const void* host, size_t bytes) {
  if (!bytes) return;
  VS_CUDA_CHECK(cudaMemcpy(device, host, bytes, cudaMemcpyHostToDevice));
  VS_CUDA_CHECK(cudaStreamSynchronize(0));
}

void copy_to_host(void* host, const void* device, size_t bytes) {
  if (bytes) VS_CUDA_CHECK(cudaMemcpy(host, device, bytes, cudaMemcpyDeviceToHost));
}

}  // namespace vs::cuda
