// The point-location structures of the reference encoding, built once at conversion and stored
// with the dataset (docs/formats.md), like the ABRs of AMR: the element BVH (element_bvh.h) and
// the face adjacency of the walk (adjacency.h). A render only reads them.
#pragma once
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "volstream/amr/source.h"
#include "volstream/umesh/element_bvh.h"
#include "volstream/umesh/umesh.h"

namespace vs {

class TetWalkRecords;
// Where the CPU walk's records come from (UMeshRenderer::mesh_view): a dataset that stores them
// maps its file and checks it against the mesh and adjacency it is given.
using TetWalkSource = std::function<TetWalkRecords(const UMesh& mesh, std::span<const uint32_t> neighbors)>;

struct MeshAccel {
  ElementBvh bvh;
  HostArray<uint32_t> neighbors;  // kMaxFaces per element
  TetWalkSource stored_tet_walk;  // empty: the records are built from the mesh (tet_walk_records)
};

std::vector<box3f> element_boxes(const UMesh& mesh);
// The world box of the mesh's vertices (in either encoding).
Box3<double> world_bounds(std::span<const vec3f> vertices, const WorldTransform& transform);
inline Box3<double> world_bounds(const UMesh& mesh, const WorldTransform& transform) {
  return world_bounds(mesh.vertices, transform);
}
MeshAccel build_mesh_accel(const UMesh& mesh);
// The walk records of a mesh's elements (element_bvh.h): 64 MB for 1 M elements. Built, the
// array is filled in parallel and never zero-filled first (on one thread) as a std::vector would,
// on ordinary pages, not huge ones: where free memory has gone back to the host, as on the
// benchmark machine, a huge page's first touch took 3-4x longer per byte (bench/RESULTS.md,
// "Topology mapped, not read"). Or a read-only view of a dataset's stored records (a mapped
// file), which costs no fresh memory at all.
class TetWalkRecords {
 public:
  TetWalkRecords() = default;
  explicit TetWalkRecords(size_t count);  // uninitialised, for tet_walk_records to fill
  // count records at `data`, which `owner` keeps valid and unchanged while any copy lives.
  static TetWalkRecords view(std::shared_ptr<const void> owner, const TetWalkRecord* data, size_t count);
  TetWalkRecord* writable_data() { return writable_; }  // null for a view
  const TetWalkRecord* data() const { return data_; }
  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  bool is_view() const { return owner_ != nullptr && writable_ == nullptr; }
  const TetWalkRecord& operator[](size_t i) const { return data_[i]; }
  operator std::span<const TetWalkRecord>() const { return {data_, count_}; }  // NOLINT: read as a span

 private:
  std::shared_ptr<const void> owner_;
  const TetWalkRecord* data_ = nullptr;
  TetWalkRecord* writable_ = nullptr;
  size_t count_ = 0;
};
bool has_tets(const UMesh& mesh);
// One walk record per element (another type's, or a degenerate tet's, with is_tet() false),
// from the mesh and its face adjacency. Empty for a mesh without tets.
TetWalkRecords tet_walk_records(const UMesh& mesh, std::span<const uint32_t> neighbors);
// The same records in order, `block` elements at a time, each block handed to `consume` (records,
// count) and then overwritten: a convert writes them as they are made, never 64 B an element at
// once. Returns how many there were (0, and no call, for a mesh without tets).
uint64_t for_each_tet_walk_block(const UMesh& mesh, std::span<const uint32_t> neighbors,
                                 const std::function<void(const TetWalkRecord*, size_t)>& consume,
                                 size_t block = size_t(1) << 16);
// InputError naming `file` unless `stored` holds exactly the records tet_walk_records would
// build: one per element, a tet's where the mesh has a sound tet (its corner 0, its neighbours
// the adjacency's) and none elsewhere. The rows may differ by rounding (a build with fused
// multiply-adds), by at most 1e-4 of their length. Rebuilt one at a time in registers: the
// check writes no memory.
void check_tet_walk_records(const UMesh& mesh, std::span<const uint32_t> neighbors,
                            std::span<const TetWalkRecord> stored, const std::string& file);

// The sampler's view of a mesh and its structures (host pointers; both must outlive it).
inline UMeshView view_of(const UMesh& mesh, const MeshAccel& accel) {
  UMeshView v;
  v.vertices = mesh.vertices.data();
  v.elements = mesh.elements.data();
  v.nodes = accel.bvh.nodes.data();
  v.items = accel.bvh.items.data();
  v.node_count = uint32_t(accel.bvh.nodes.size());
  v.neighbors = accel.neighbors.data();
  return v;
}

// InputError naming `file` unless `accel` is a sound structure over `mesh`: node links in range
// and pointing forward (so searches end), depth within the search stack, the items a
// permutation of the elements, every box holding its children or elements, every neighbour a
// valid element or none.
void check_mesh_accel(const UMesh& mesh, const MeshAccel& accel, const std::string& file);
// Its two halves: what needs only the element count (links, depth, items, neighbours; a load
// runs it while the vertices and elements are read), then the boxes against the elements (in
// parallel), which rely on the first.
void check_mesh_accel_structure(const MeshAccel& accel, uint64_t elements, const std::string& file);
void check_mesh_accel_boxes(const UMesh& mesh, const MeshAccel& accel, const std::string& file);

}  // namespace vs
