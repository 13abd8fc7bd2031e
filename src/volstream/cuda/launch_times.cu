// CUDA event timing of named launches (launch.cuh): pending event pairs, collected once done.
#include <mutex>
#include <vector>

#include "volstream/backend/launch_times.h"
#include "volstream/cuda/launch.cuh"

namespace vs::cuda {
namespace {
struct Pending {
  const char* name;
  cudaEvent_t start, stop;
};
std::mutex pending_mutex;
std::vector<Pending> pending;
}  // namespace

TimedLaunch::TimedLaunch(const char* name, cudaStream_t stream) : name_(name), stream_(stream) {
  VS_CUDA_CHECK(cudaEventCreate(&start_));
  VS_CUDA_CHECK(cudaEventCreate(&stop_));
  VS_CUDA_CHECK(cudaEventRecord(start_, stream_));
}

void TimedLaunch::stop() {
  VS_CUDA_CHECK(cudaEventRecord(stop_, stream_));
  std::lock_guard<std::mutex> lock(pending_mutex);
  pending.push_back({name_, start_, stop_});
}

void collect_launch_times() {
  std::lock_guard<std::mutex> lock(pending_mutex);
  size_t kept = 0;
  for (const Pending& p : pending) {
    if (cudaEventQuery(p.stop) != cudaSuccess) {  // still running (or not yet reached)
      pending[kept++] = p;
      continue;
    }
    float ms = 0.f;
    VS_CUDA_CHECK(cudaEventElapsedTime(&ms, p.start, p.stop));
    launch_times().add(p.name, ms * 1e-3);
    cudaEventDestroy(p.start);
    cudaEventDestroy(p.stop);
  }
  pending.resize(kept);
}

}  // namespace vs::cuda
