// Where kernels run: the CPU (all cores, oneTBB) or a CUDA GPU.
#pragma once
#include <string>

namespace vs {

enum class Device { cpu, cuda };

// "auto" (CUDA when a GPU is present), "cpu" or "cuda"; UsageError for cuda without a GPU.
Device resolve_device(const std::string& name);
const char* to_string(Device d);
// "cpu" or "cuda (NVIDIA H100 80GB HBM3)": for reports.
std::string describe(Device d);

}  // namespace vs
