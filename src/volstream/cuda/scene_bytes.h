// The device memory a DeviceScene allocates for a topology, structure by structure, computed on
// the host (no GPU needed): what `info` reports before anything runs. The names are the memory
// ledger's (backend/memory.h); a CUDA test checks the ledger against this after a frame.
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "volstream/amr/model.h"

namespace vs::cuda {

// ABR integrator frames of `fields` fields (1, or 2 with a colour or temperature field) at
// width x height, sample counts included.
std::map<std::string, uint64_t> device_scene_bytes(const AmrTopology& topology, int fields, uint32_t width,
                                                   uint32_t height);

}  // namespace vs::cuda
