// DeviceMesh (umesh_backend.h): the mesh's arrays in device memory and the shared integrator
// launched over UMeshVolume (render_frame.cuh).
#include "volstream/backend/buffer.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/launch.cuh"
#include "volstream/cuda/render_frame.cuh"
#include "volstream/cuda/umesh_backend.h"
#include "volstream/volume/umesh_volume.h"

namespace vs::cuda {

struct DeviceMesh::Impl {
  Buffer<vec3f> vertices{Device::cuda, "mesh"};
  Buffer<UElement> elements{Device::cuda, "mesh"};
  Buffer<ElementBvhNode> nodes{Device::cuda, "mesh BVH and macrocells"};
  Buffer<uint32_t> items{Device::cuda, "mesh BVH and macrocells"};
  Buffer<uint32_t> neighbors{Device::cuda, "mesh BVH and macrocells"};
  Buffer<float> step_widths{Device::cuda, "mesh BVH and macrocells"};
  Buffer<int32_t> region_of_cell{Device::cuda, "mesh BVH and macrocells"};
  Buffer<BvhNode> region_nodes{Device::cuda, "BVH"};
  Buffer<float> rgba{Device::cuda, "image"};
  Buffer<uint32_t> counts{Device::cuda, "image"};
  Buffer<vec3f> points{Device::cuda, "probe points"};
  Buffer<float> probed{Device::cuda, "probe points"};

  UMeshView view() const {
    return {vertices.data(), elements.data(), nodes.data(), items.data(), uint32_t(nodes.size()), neighbors.data()};
  }
};

DeviceMesh::DeviceMesh(const UMesh& mesh, const ElementBvh& bvh, const std::vector<uint32_t>& neighbors,
                       const MacroCells& cells)
    : impl_(std::make_unique<Impl>()) {
  impl_->vertices.upload(mesh.vertices);
  impl_->elements.upload(mesh.elements);
  impl_->nodes.upload(bvh.nodes);
  impl_->items.upload(bvh.items);
  impl_->neighbors.upload(neighbors);
  impl_->step_widths.upload(cells.step_width);
  impl_->region_of_cell.upload(cells.region_of_cell);
}

DeviceMesh::~DeviceMesh() = default;

RenderTimes DeviceMesh::render(const FrameView<UMeshVolume>& h) {
  Impl& m = *impl_;
  const Stopwatch watch;
  m.region_nodes.upload(h.volume.nodes, h.volume.node_count);
  const size_t pixels = size_t(h.width) * h.height;
  m.rgba.resize(pixels * 4);
  m.counts.resize(pixels);
  FrameView<UMeshVolume> d = h;
  d.volume.mesh = m.view();
  d.volume.nodes = m.region_nodes.data();
  d.volume.step_widths = m.step_widths.data();
  d.volume.region_of_cell = m.region_of_cell.data();
  d.rgba = m.rgba.data();
  d.sample_counts = h.sample_counts ? m.counts.data() : nullptr;
  RenderTimes t;
  t.upload_seconds = watch.seconds();
  t.kernel_seconds = render_frame(d, 0);
  copy_to_host(h.rgba, m.rgba.data(), pixels * 4 * sizeof(float));
  if (h.sample_counts) copy_to_host(h.sample_counts, m.counts.data(), pixels * sizeof(uint32_t));
  return t;
}

std::vector<float> DeviceMesh::probe(const float* device_values, const std::vector<vec3f>& grid_points) {
  Impl& m = *impl_;
  m.points.upload(grid_points);
  m.probed.resize(grid_points.size());
  const UMeshView view = m.view();
  const vec3f* points = m.points.data();
  float* out = m.probed.data();
  parallel_for(
      "probe", int64_t(grid_points.size()),
      [=] __device__(int64_t i) { out[i] = view.sample(device_values, points[i]); }, 0);
  return m.probed.download();
}

}  // namespace vs::cuda
