// The CUDA side of parallel_for: the same (name, n, f) signature as backend/parallel.h, one
// thread per index, timed with a pair of CUDA events per launch (launch_times.h). f must be a
// __device__-callable lambda (compiled with --extended-lambda).
#pragma once
#include <cstdint>

#include "volstream/cuda/cuda_check.h"

namespace vs::cuda {

template <typename F>
__global__ void parallel_for_kernel(int64_t n, F f) {
  const int64_t i = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

// Events around one launch: record_start() before it, record_stop() after it. The times reach
// launch_times() when collect_launch_times() finds the stop event done (after a stream sync).
class TimedLaunch {
 public:
  TimedLaunch(const char* name, cudaStream_t stream);
  void stop();

 private:
  const char* name_;
  cudaStream_t stream_;
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
};
// Adds the times of every finished launch to launch_times(); launches still running stay pending.
void collect_launch_times();

template <typename F>
void parallel_for(const char* name, int64_t n, F f, cudaStream_t stream = 0) {
  if (n <= 0) return;
  constexpr int kBlock = 128;
  const int64_t blocks = (n + kBlock - 1) / kBlock;
  TimedLaunch timed(name, stream);
  parallel_for_kernel<<<unsigned(blocks), kBlock, 0, stream>>>(n, f);
  check(cudaGetLastError(), name, __FILE__, __LINE__);
  timed.stop();
}

}  // namespace vs::cuda
