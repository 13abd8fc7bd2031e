// Device memory and copies as plain host functions (no CUDA headers), so that backend/buffer.h
// can own device memory from code compiled without nvcc. Without CUDA every call throws.
#pragma once
#include <cstddef>

namespace vs::cuda {

void* device_malloc(size_t bytes);
void device_free(void* p);
// Synchronous copies: they return when the data has arrived.
void copy_to_device(void* device, const void* host, size_t bytes);
void copy_to_host(void* host, const void* device, size_t bytes);

}  // namespace vs::cuda
