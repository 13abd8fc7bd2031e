// Without the CUDA backend: asking for the GPU mesh integrator is a clear error.
#ifndef VOLSTREAM_HAVE_CUDA
#include <stdexcept>

#include "volstream/cuda/umesh_backend.h"

namespace vs::cuda {
namespace {
[[noreturn]] void no_cuda() { throw std::runtime_error("this volstream was built without CUDA"); }
}  // namespace

struct DeviceMesh::Impl {};
DeviceMesh::DeviceMesh(const UMesh&, const ElementBvh&, std::span<const uint32_t>, const MacroCells&) { no_cuda(); }
DeviceMesh::~DeviceMesh() = default;
RenderTimes DeviceMesh::render(const FrameView<UMeshVolume>&) { no_cuda(); }
std::vector<float> DeviceMesh::probe(const float*, const std::vector<vec3f>&) { no_cuda(); }

struct DeviceCompactMesh::Impl {};
DeviceCompactMesh::DeviceCompactMesh(const CompactMesh&, const MacroCells&) { no_cuda(); }
DeviceCompactMesh::~DeviceCompactMesh() = default;
RenderTimes DeviceCompactMesh::render(const FrameView<CompactMeshVolume>&) { no_cuda(); }
std::vector<float> DeviceCompactMesh::probe(const float*, const std::vector<vec3f>&) { no_cuda(); }

}  // namespace vs::cuda
#endif
