// The CUDA side of parallel_for: the same (name, n, f) signature as core/parallel.h, one thread
// per index. f must be a __device__-callable lambda (compiled with --extended-lambda).
#pragma once
#include <cstdint>

#include "volstream/cuda/cuda_check.h"

namespace vs::cuda {

template <typename F>
__global__ void parallel_for_kernel(int64_t n, F f) {
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

template <typename F>
void parallel_for(const char* name, int64_t n, F f, cudaStream_t stream = 0) {
  if (n <= 0) return;
  constexpr int kBlock = 128;
  const int64_t blocks = (n + kBlock - 1) / kBlock;
  parallel_for_kernel<<<unsigned(blocks), kBlock, 0, stream>>>(n, f);
  check(cudaGetLastError(), name, __FILE__, __LINE__);
}

}  // namespace vs::cuda
