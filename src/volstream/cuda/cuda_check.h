// CUDA error checking and device memory owners (only included by .cu files).
#pragma once
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "volstream/backend/memory.h"

namespace vs::cuda {

inline void check(cudaError_t e, const char* what, const char* file, int line) {
  if (e != cudaSuccess)
    throw std::runtime_error(std::string("CUDA error in ") + what + " at " + file + ":" + std::to_string(line) + ": " +
                             cudaGetErrorString(e));
}
#define VS_CUDA_CHECK(call) ::vs::cuda::check((call), #call, __FILE__, __LINE__)

// An owning device array (RAII), counted in the memory ledger under its structure's name.
// Kernels get its data() pointer.
template <typename T>
class DeviceBuffer {
 public:
  explicit DeviceBuffer(const char* structure = "CUDA scratch") : counted_(structure, MemorySpace::device) {}
  DeviceBuffer(const char* structure, size_t n) : DeviceBuffer(structure) { resize(n); }
  DeviceBuffer(const char* structure, const std::vector<T>& host) : DeviceBuffer(structure) { upload(host); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept : ptr_(o.ptr_), n_(o.n_), counted_(std::move(o.counted_)) {
    o.ptr_ = nullptr, o.n_ = 0;
  }
  ~DeviceBuffer() { cudaFree(ptr_); }
  void resize(size_t n) {
    if (n == n_) return;
    cudaFree(ptr_);
    ptr_ = nullptr;
    n_ = 0;
    counted_.set(0);
    if (n) VS_CUDA_CHECK(cudaMalloc(&ptr_, n * sizeof(T)));
    n_ = n;
    counted_.set(int64_t(n * sizeof(T)));
  }
  // Returns when the data is on the device. cudaMemcpy from pageable memory returns once the
  // data is staged, before its DMA has landed, and it runs on the default stream, which kernels
  // on a non-blocking stream (DeviceScene's) do not wait for: hence the explicit synchronise.
  void upload(const T* host, size_t n) {
    resize(n);
    if (!n) return;
    VS_CUDA_CHECK(cudaMemcpy(ptr_, host, n * sizeof(T), cudaMemcpyHostToDevice));
    VS_CUDA_CHECK(cudaStreamSynchronize(0));
  }
  void upload(const std::vector<T>& host) { upload(host.data(), host.size()); }
  // Grows (never shrinks) to at least n elements, so that a frame loop stops allocating after
  // its first frame (cudaFree synchronises the whole device).
  void ensure(size_t n) {
    if (n > n_) resize(n);
  }
  // Copies n elements in on `stream` (ensure() first); the caller synchronises the stream.
  void upload_async(const T* host, size_t n, cudaStream_t stream) {
    ensure(n);
    if (n) VS_CUDA_CHECK(cudaMemcpyAsync(ptr_, host, n * sizeof(T), cudaMemcpyHostToDevice, stream));
  }
  std::vector<T> download() const {
    std::vector<T> host(n_);
    if (n_) VS_CUDA_CHECK(cudaMemcpy(host.data(), ptr_, n_ * sizeof(T), cudaMemcpyDeviceToHost));
    return host;
  }
  T* data() const { return ptr_; }
  size_t size() const { return n_; }

 private:
  T* ptr_ = nullptr;
  size_t n_ = 0;
  CountedBytes counted_;
};

// A CUDA event (RAII), for kernel timings.
struct Event {
  cudaEvent_t e = nullptr;
  Event() { VS_CUDA_CHECK(cudaEventCreate(&e)); }
  ~Event() { cudaEventDestroy(e); }
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;
};

}  // namespace vs::cuda
