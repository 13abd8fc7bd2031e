#include "volstream/umesh/mesh_accel.h"

#include <algorithm>
#include <cmath>
#include <new>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/umesh/adjacency.h"

namespace vs {

std::vector<box3f> element_boxes(const UMesh& mesh) {
  std::vector<box3f> boxes(mesh.elements.size());
  parallel_for("element boxes", int64_t(boxes.size()),
               [&](int64_t e) { boxes[size_t(e)] = element_box(mesh.vertices.data(), mesh.elements[size_t(e)]); });
  return boxes;
}

Box3<double> world_bounds(std::span<const vec3f> vertices, const WorldTransform& transform) {
  Box3<double> b{vec3d(INFINITY), vec3d(-INFINITY)};
  for (const vec3f& v : vertices) b.extend(transform.to_world(vec3d(v)));
  if (b.empty()) b = {vec3d(0), vec3d(1)};
  return b;
}

TetWalkRecords::TetWalkRecords(size_t count) : count_(count) {
  auto* records = static_cast<TetWalkRecord*>(
      ::operator new[](count * sizeof(TetWalkRecord), std::align_val_t(alignof(TetWalkRecord))));
  owner_ = std::shared_ptr<const void>(records, [](const void* p) {
    ::operator delete[](const_cast<void*>(p), std::align_val_t(alignof(TetWalkRecord)));
  });
  data_ = writable_ = records;
}

TetWalkRecords TetWalkRecords::view(std::shared_ptr<const void> owner, const TetWalkRecord* data, size_t count) {
  TetWalkRecords r;
  r.owner_ = std::move(owner);
  r.data_ = data;
  r.count_ = count;
  return r;
}

namespace {
TetWalkRecord tet_walk_record(const UMesh& mesh, std::span<const uint32_t> neighbors, size_t e) {
  TetWalkRecord r;
  r.rows[0].x = NAN;  // not a tet, until shown one; nor any neighbour (stored: every byte defined)
  for (uint32_t& n : r.neighbor) n = UMeshView::kNoNeighborIndex;
  const UElement& el = mesh.elements[e];
  vec3f x[4];
  shape::TetSolve s;
  if (el.vertex_count() != 4) return r;
  for (int i = 0; i < 4; ++i) x[i] = mesh.vertices[el.v[i]];
  if (!shape::tet_solve(x, s)) return r;
  r.origin = s.origin;
  for (int i = 0; i < 3; ++i) r.rows[i] = s.rows[i] * s.inv_det;
  for (int i = 0; i < 4; ++i) r.neighbor[i] = neighbors[e * shape::kMaxFaces + size_t(i)];
  return r;
}
}  // namespace

bool has_tets(const UMesh& mesh) {
  return std::any_of(mesh.elements.begin(), mesh.elements.end(),
                     [](const UElement& el) { return el.vertex_count() == 4; });
}

namespace {
// The records of elements [first, first + count) into out[0, count), in parallel.
void fill_tet_walk_records(const UMesh& mesh, std::span<const uint32_t> neighbors, size_t first, size_t count,
                           TetWalkRecord* out) {
  parallel_for("tet walk records", int64_t(count),
               [&](int64_t i) { new (out + i) TetWalkRecord(tet_walk_record(mesh, neighbors, first + size_t(i))); });
}
}  // namespace

TetWalkRecords tet_walk_records(const UMesh& mesh, std::span<const uint32_t> neighbors) {
  if (!has_tets(mesh)) return {};
  TetWalkRecords records(mesh.elements.size());
  fill_tet_walk_records(mesh, neighbors, 0, records.size(), records.writable_data());
  return records;
}

uint64_t for_each_tet_walk_block(const UMesh& mesh, std::span<const uint32_t> neighbors,
                                 const std::function<void(const TetWalkRecord*, size_t)>& consume, size_t block) {
  if (!has_tets(mesh)) return 0;
  block = std::max<size_t>(block, 1);  // a block of none would never end
  const size_t elements = mesh.elements.size();
  TetWalkRecords records(std::min(block, elements));
  for (size_t first = 0; first < elements; first += block) {
    const size_t count = std::min(block, elements - first);
    fill_tet_walk_records(mesh, neighbors, first, count, records.writable_data());
    consume(records.data(), count);
  }
  return elements;
}

namespace {
bool rows_close(const vec3f& stored, const vec3f& built) {
  const vec3f d = stored - built;
  return dot(d, d) <= 1e-8f * dot(built, built);  // |d| <= 1e-4 |built|
}

bool same_record(const TetWalkRecord& stored, const TetWalkRecord& built) {
  if (stored.is_tet() != built.is_tet()) return false;
  for (int i = 0; i < 4; ++i)
    if (stored.neighbor[i] != built.neighbor[i]) return false;
  if (!built.is_tet()) return true;  // another type's record: the walk reads nothing else of it
  return stored.origin.x == built.origin.x && stored.origin.y == built.origin.y && stored.origin.z == built.origin.z &&
         rows_close(stored.rows[0], built.rows[0]) && rows_close(stored.rows[1], built.rows[1]) &&
         rows_close(stored.rows[2], built.rows[2]);
}
}  // namespace

void check_tet_walk_records(const UMesh& mesh, std::span<const uint32_t> neighbors,
                            std::span<const TetWalkRecord> stored, const std::string& file) {
  input_check(stored.size() == mesh.elements.size(), file, "walk records do not match the mesh");
  const int64_t bad = first_failing(int64_t(stored.size()), [&](int64_t e) {
    return same_record(stored[size_t(e)], tet_walk_record(mesh, neighbors, size_t(e)));
  });
  if (bad >= 0) input_error(file, "walk record " + std::to_string(bad) + " does not match its element");
}

MeshAccel build_mesh_accel(const UMesh& mesh) {
  MeshAccel accel;
  accel.bvh = build_element_bvh(element_boxes(mesh));
  accel.neighbors = build_face_neighbors(mesh);
  return accel;
}

namespace {

// Messages are made only on failure (a string per node would cost more than the checks).
[[noreturn]] void node_error(const std::string& file, int64_t i, const char* what) {
  input_error(file, "BVH node " + std::to_string(i) + " " + what);
}

}  // namespace

void check_mesh_accel_structure(const MeshAccel& accel, uint64_t elements, const std::string& file) {
  const ElementBvh& bvh = accel.bvh;
  const auto& nodes = bvh.nodes;
  input_check(!nodes.empty() && bvh.items.size() == elements, file, "BVH sizes do not match the mesh");
  std::vector<uint8_t> depth(nodes.size(), 0);
  std::vector<uint8_t> seen(elements, 0);
  for (size_t i = 0; i < nodes.size(); ++i) {
    const ElementBvhNode& n = nodes[i];
    if (n.count == 0) {
      // Children after their parent: every search path ends, within the search stack's depth.
      if (!(n.first > i && uint64_t(n.first) + 1 < nodes.size())) node_error(file, int64_t(i), "has bad children");
      if (depth[i] >= 60) node_error(file, int64_t(i), "is too deep");
      for (uint32_t c = n.first; c <= n.first + 1; ++c) {
        depth[c] = uint8_t(depth[i] + 1);
        if (!n.box.contains(nodes[c].box)) node_error(file, int64_t(i), "has a box that does not hold its children");
      }
      continue;
    }
    if (!(n.count <= 64 && uint64_t(n.first) + n.count <= bvh.items.size()))
      node_error(file, int64_t(i), "has bad items");
    for (uint32_t k = n.first; k < n.first + n.count; ++k) {
      const uint32_t e = bvh.items[k];
      if (!(e < seen.size() && !seen[e])) input_error(file, "BVH items are not a permutation of the elements");
      seen[e] = 1;
    }
  }
  for (uint8_t s : seen) input_check(s != 0, file, "BVH leaves do not hold every element");
  input_check(accel.neighbors.size() == elements * shape::kMaxFaces, file, "face neighbours do not match the mesh");
  const int64_t bad = first_failing(int64_t(accel.neighbors.size()), [&](int64_t i) {
    // None (kNoNeighbor + 1 wraps to 0) or an element, in one comparison: a mesh's boundary faces
    // are scattered, and a branch on each was a third of the mispredicts of a 1 M tet mesh's load.
    static_assert(kNoNeighbor == 0xffffffffu);
    return uint64_t(uint32_t(accel.neighbors[size_t(i)] + 1u)) <= elements;
  });
  input_check(bad < 0, file, "a face neighbour is out of range");
}

void check_mesh_accel_boxes(const UMesh& mesh, const MeshAccel& accel, const std::string& file) {
  const auto& nodes = accel.bvh.nodes;
  // Each element's box made where it is checked: no second array of all of them at load.
  const int64_t bad = first_failing(
      int64_t(nodes.size()),
      [&](int64_t i) {
        const ElementBvhNode& n = nodes[size_t(i)];
        for (uint32_t k = n.first; k < n.first + n.count; ++k)
          if (!box_contains(n.box, element_box_lanes(mesh.vertices.data(), mesh.elements[accel.bvh.items[k]])))
            return false;
        return true;
      },
      1024);
  if (bad >= 0) node_error(file, bad, "has a box that does not hold its elements");
}

void check_mesh_accel(const UMesh& mesh, const MeshAccel& accel, const std::string& file) {
  check_mesh_accel_structure(accel, mesh.elements.size(), file);
  check_mesh_accel_boxes(mesh, accel, file);
}

}  // namespace vs
