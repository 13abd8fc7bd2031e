// DeviceMesh and DeviceCompactMesh (umesh_backend.h): a mesh's arrays in device memory and the
// shared integrator launched over MeshVolume<Locator> (render_frame.cuh); the per-frame buffers
// and the launch are one template for both encodings.
#include "volstream/backend/buffer.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/launch.cuh"
#include "volstream/cuda/render_frame.cuh"
#include "volstream/cuda/umesh_backend.h"
#include "volstream/volume/umesh_volume.h"

namespace vs::cuda {

// What a frame of either encoding needs besides the mesh: the macrocells, their visible flags,
// the optics tables, the image and the probe points.
struct MeshFrameBuffers {
  Buffer<float> step_widths{Device::cuda, "mesh BVH and macrocells"};
  Buffer<int32_t> region_of_cell{Device::cuda, "mesh BVH and macrocells"};
  Buffer<uint8_t> visible{Device::cuda, "mesh BVH and macrocells"};
  Buffer<float> rgba{Device::cuda, "image"};
  Buffer<uint32_t> counts{Device::cuda, "image"};
  Buffer<vec3f> points{Device::cuda, "probe points"};
  Buffer<float> probed{Device::cuda, "probe points"};
  DeviceOpticsTables tables;

  size_t regions;

  explicit MeshFrameBuffers(const MacroCells& cells) : regions(cells.region_count()) {
    step_widths.upload(cells.step_width);
    region_of_cell.upload(cells.region_of_cell);
  }

  template <typename Locator>
  RenderTimes render(const FrameView<MeshVolume<Locator>>& h, const Locator& device_mesh) {
    const Stopwatch watch;
    visible.upload(h.volume.visible, regions);
    const size_t pixels = size_t(h.width) * h.height;
    rgba.resize(pixels * 4);
    counts.resize(pixels);
    FrameView<MeshVolume<Locator>> d = h;
    d.volume.mesh = device_mesh;
    d.volume.visible = visible.data();
    d.volume.step_widths = step_widths.data();
    d.volume.region_of_cell = region_of_cell.data();
    tables.upload(h, d);
    d.rgba = rgba.data();
    d.sample_counts = h.sample_counts ? counts.data() : nullptr;
    RenderTimes t;
    t.upload_seconds = watch.seconds();
    t.kernel_seconds = render_frame(d, 0);
    copy_to_host(h.rgba, rgba.data(), pixels * 4 * sizeof(float));
    if (h.sample_counts) copy_to_host(h.sample_counts, counts.data(), pixels * sizeof(uint32_t));
    return t;
  }

  template <typename Locator>
  std::vector<float> probe(const Locator& view, const float* device_values, const std::vector<vec3f>& grid_points) {
    points.upload(grid_points);
    probed.resize(grid_points.size());
    const vec3f* at = points.data();
    float* out = probed.data();
    parallel_for(
        "probe", int64_t(grid_points.size()), [=] __device__(int64_t i) { out[i] = view.sample(device_values, at[i]); },
        0);
    return probed.download();
  }
};

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
