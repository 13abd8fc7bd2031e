// The unstructured-mesh integrator (volume/umesh_volume.h) on the GPU: the same kernel source as
// the CPU's, for the reference encoding (DeviceMesh) and paper 002's compact one
// (DeviceCompactMesh). The mesh, its acceleration structure and the macrocells are uploaded once; per frame the refit
// region nodes (classified on the host from the macrocell ranges) are uploaded and the field
// values come as device pointers. Links without CUDA too (umesh_backend_stub.cpp: throws).
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/cuda/backend.h"
#include "volstream/umesh/element_bvh.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/umesh/umesh.h"

namespace vs {
template <typename V>
struct FrameView;
template <typename Locator>
struct MeshVolume;
struct UMeshView;
using UMeshVolume = MeshVolume<UMeshView>;
struct CompactMeshView;
using CompactMeshVolume = MeshVolume<CompactMeshView>;
struct CompactMesh;
}  // namespace vs

namespace vs::cuda {

class DeviceMesh {
 public:
  // Uploads the mesh, its BVH, face adjacency and macrocells; keeps no reference.
  DeviceMesh(const UMesh& mesh, const ElementBvh& bvh, std::span<const uint32_t> neighbors, const MacroCells& cells);
  ~DeviceMesh();
  DeviceMesh(const DeviceMesh&) = delete;
  DeviceMesh& operator=(const DeviceMesh&) = delete;

  // Renders `host_view` (camera, settings, optics and the refit region nodes from the host; its
  // field pointers must be device pointers; the mesh pointers are replaced by the device's) and
  // copies the image (and sample counts when host_view.sample_counts is set) back.
  RenderTimes render(const FrameView<UMeshVolume>& host_view);
  // Field values (device pointer) at grid points, NaN outside every element.
  std::vector<float> probe(const float* device_values, const std::vector<vec3f>& grid_points);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The compact encoding (umesh/compact.h) on the GPU; fields per local vertex
// (CompactMesh::gather order) as device pointers.
class DeviceCompactMesh {
 public:
  DeviceCompactMesh(const CompactMesh& mesh, const MacroCells& cells);
  ~DeviceCompactMesh();
  DeviceCompactMesh(const DeviceCompactMesh&) = delete;
  DeviceCompactMesh& operator=(const DeviceCompactMesh&) = delete;

  RenderTimes render(const FrameView<CompactMeshVolume>& host_view);  // as DeviceMesh::render
  std::vector<float> probe(const float* device_local_values, const std::vector<vec3f>& grid_points);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs::cuda
