// Without the CUDA backend: device memory is a clear error (cuda_available() is false).
#ifndef VOLSTREAM_HAVE_CUDA
#include <stdexcept>

#include "volstream/cuda/memory.h"

namespace vs::cuda {
namespace {
[[noreturn]] void no_cuda() { throw std::runtime_error("this volstream was built without CUDA"); }
}  // namespace
void* device_malloc(size_t) { no_cuda(); }
void device_free(void*) {}
void copy_to_device(void*, const void*, size_t) { no_cuda(); }
void copy_to_host(void*, const void*, size_t) { no_cuda(); }
}  // namespace vs::cuda
#endif
