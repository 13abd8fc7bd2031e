// Buffer<T>: an array owned where a backend's kernels read it (host memory for the CPU, device
// memory for CUDA), counted in the memory ledger under its structure's name. Kernels get data().
#pragma once
#include <cstddef>
#include <cstring>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "volstream/backend/device.h"
#include "volstream/backend/memory.h"
#include "volstream/cuda/memory.h"

namespace vs {

template <typename T>
class Buffer {
 public:
  Buffer(Device device, const char* structure)
      : device_(device), counted_(structure, device == Device::cuda ? MemorySpace::device : MemorySpace::host) {}
  Buffer(Buffer&& o) noexcept
      : device_(o.device_),
        ptr_(std::exchange(o.ptr_, nullptr)),
        n_(std::exchange(o.n_, 0)),
        counted_(std::move(o.counted_)) {}
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer() { release(); }

  // n elements (contents undefined after a size change).
  void resize(size_t n) {
    if (n == n_) return;
    release();
    if (n)
      ptr_ =
          static_cast<T*>(device_ == Device::cuda ? cuda::device_malloc(n * sizeof(T)) : ::operator new(n * sizeof(T)));
    n_ = n;
    counted_.set(int64_t(n * sizeof(T)));
  }
  // Copies n host elements in (resizing to n); returns when they are there.
  void upload(const T* host, size_t n) {
    resize(n);
    if (device_ == Device::cuda)
      cuda::copy_to_device(ptr_, host, n * sizeof(T));
    else if (n)
      std::memcpy(static_cast<void*>(ptr_), host, n * sizeof(T));
  }
  void upload(std::span<const T> host) { upload(host.data(), host.size()); }
  std::vector<T> download() const {
    std::vector<T> host(n_);
    if (device_ == Device::cuda)
      cuda::copy_to_host(host.data(), ptr_, n_ * sizeof(T));
    else if (n_)
      std::memcpy(static_cast<void*>(host.data()), ptr_, n_ * sizeof(T));
    return host;
  }
  T* data() { return ptr_; }
  const T* data() const { return ptr_; }
  size_t size() const { return n_; }
  Device device() const { return device_; }

 private:
  void release() {
    if (!ptr_) return;
    if (device_ == Device::cuda)
      cuda::device_free(ptr_);
    else
      ::operator delete(ptr_);
    ptr_ = nullptr;
    n_ = 0;
    counted_.set(0);
  }
  Device device_;
  T* ptr_ = nullptr;
  size_t n_ = 0;
  CountedBytes counted_;
};

}  // namespace vs
