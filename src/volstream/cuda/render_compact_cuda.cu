// DeviceCompactMesh (umesh_backend.h): paper 002's compact encoding in device memory; frames and
// probes through MeshFrameBuffers (mesh_frame.cuh).
#include "volstream/cuda/mesh_frame.cuh"

namespace vs::cuda {

struct DeviceCompactMesh::Impl {
  Buffer<CompactNode> nodes{Device::cuda, "compact mesh"};
  Buffer<CompactLeaf> leaves{Device::cuda, "compact mesh"};
  Buffer<uint8_t> bytes{Device::cuda, "compact mesh"};
  Buffer<CompactSubmesh> submeshes{Device::cuda, "compact mesh"};
  Buffer<vec3f> vertices{Device::cuda, "compact mesh"};
  MeshFrameBuffers frame;
  CompactMeshView view;  // the device arrays (the tree's levels read from the host copy)

  Impl(const CompactMesh& mesh, const MacroCells& cells) : frame(cells) {
    nodes.upload(mesh.nodes);
    leaves.upload(mesh.leaves);
    bytes.upload(mesh.bytes);
    submeshes.upload(mesh.submeshes);
    vertices.upload(mesh.vertices);
    view = compact_view(mesh, nodes.data(), leaves.data(), bytes.data(), submeshes.data(), vertices.data());
  }
};

DeviceCompactMesh::DeviceCompactMesh(const CompactMesh& mesh, const MacroCells& cells)
    : impl_(std::make_unique<Impl>(mesh, cells)) {}

DeviceCompactMesh::~DeviceCompactMesh() = default;

RenderTimes DeviceCompactMesh::render(const FrameView<CompactMeshVolume>& h) {
  return impl_->frame.render(h, impl_->view);
}

std::vector<float> DeviceCompactMesh::probe(const float* device_local_values, const std::vector<vec3f>& grid_points) {
  return impl_->frame.probe(impl_->view, device_local_values, grid_points);
}

}  // namespace vs::cuda
