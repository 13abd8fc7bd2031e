// DeviceMesh (umesh_backend.h): a reference-encoded mesh's arrays in device memory; frames and
// probes through MeshFrameBuffers (mesh_frame.cuh).
#include "volstream/cuda/mesh_frame.cuh"

namespace vs::cuda {

struct DeviceMesh::Impl {
  Buffer<vec3f> vertices{Device::cuda, "mesh"};
  Buffer<UElement> elements{Device::cuda, "mesh"};
  Buffer<ElementBvhNode> nodes{Device::cuda, "mesh BVH and macrocells"};
  Buffer<uint32_t> items{Device::cuda, "mesh BVH and macrocells"};
  Buffer<uint32_t> neighbors{Device::cuda, "mesh BVH and macrocells"};
  MeshFrameBuffers frame;

  explicit Impl(const MacroCells& cells) : frame(cells) {}
  UMeshView view() const {
    return {vertices.data(), elements.data(), nodes.data(), items.data(), uint32_t(nodes.size()), neighbors.data()};
  }
};

DeviceMesh::DeviceMesh(const UMesh& mesh, const ElementBvh& bvh, std::span<const uint32_t> neighbors,
                       const MacroCells& cells)
    : impl_(std::make_unique<Impl>(cells)) {
  impl_->vertices.upload(mesh.vertices);
  impl_->elements.upload(mesh.elements);
  impl_->nodes.upload(bvh.nodes);
  impl_->items.upload(bvh.items);
  impl_->neighbors.upload(neighbors);
}

DeviceMesh::~DeviceMesh() = default;

RenderTimes DeviceMesh::render(const FrameView<UMeshVolume>& h) { return impl_->frame.render(h, impl_->view()); }

std::vector<float> DeviceMesh::probe(const float* device_values, const std::vector<vec3f>& grid_points) {
  return impl_->frame.probe(impl_->view(), device_values, grid_points);
}

}  // namespace vs::cuda
