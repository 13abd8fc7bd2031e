// Page-locked host memory through CUDA (cudaHostAlloc), so that host-to-device copies run at full
// PCIe speed and can overlap with kernels. Links without CUDA too: then nothing is ever returned.
#pragma once
#include <cstddef>
#include <string>

namespace vs::cuda {

// Page-aligned, page-locked memory, or nullptr (no CUDA, no device, or the allocation failed; `why`
// then says which).
void* pinned_host_alloc(size_t bytes, std::string& why);
void pinned_host_free(void* p);

}  // namespace vs::cuda
