// Without the CUDA backend there is no cudaHostAlloc; callers fall back to mlock().
#ifndef VOLSTREAM_HAVE_CUDA
#include "volstream/cuda/pinned.h"

namespace vs::cuda {
void* pinned_host_alloc(size_t, std::string& why) {
  why = "built without CUDA";
  return nullptr;
}
void pinned_host_free(void*) {}
}  // namespace vs::cuda
#endif
