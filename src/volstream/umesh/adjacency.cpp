#include "volstream/umesh/adjacency.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <tuple>

#include "volstream/backend/parallel.h"

namespace vs {

namespace {

// Face f of element e by its vertices in increasing order (a triangle's fourth is kNoVertex).
std::array<uint32_t, 4> sorted_face(const UElement& el, int n, int f) {
  const LocalFace lf = local_face(n, f);
  std::array<uint32_t, 4> v = {kNoVertex, kNoVertex, kNoVertex, kNoVertex};
  for (int i = 0; i < lf.count; ++i) v[size_t(i)] = el.v[lf.v[i]];
  std::sort(v.begin(), v.end());
  return v;
}

// A face in the bucket of its smallest vertex: the other three, and its slot (element *
// kMaxFaces + face). Slot is uint32_t (16 bytes a face) while every slot and every face count
// fits in it, uint64_t beyond (24 bytes).
template <typename Slot>
struct FaceRest {
  uint32_t v1, v2, v3;
  Slot slot;
  bool operator<(const FaceRest& o) const { return std::tie(v1, v2, v3, slot) < std::tie(o.v1, o.v2, o.v3, o.slot); }
  bool same_face(const FaceRest& o) const { return v1 == o.v1 && v2 == o.v2 && v3 == o.v3; }
};

// Calls visit(slot, face's sorted vertices) for every face of every element whose vertices are
// all in range (one naming no vertex of the mesh matches nothing; the load's checks refuse it).
template <typename Visit>
void for_each_face(const UMesh& mesh, Visit&& visit) {
  const uint64_t vertices = mesh.vertices.size();
  parallel_for_ranges(
      int64_t(mesh.elements.size()),
      [&](int64_t begin, int64_t end) {
        for (int64_t e = begin; e < end; ++e) {
          const UElement& el = mesh.elements[size_t(e)];
          const int n = el.vertex_count();
          for (int f = 0; f < shape::face_count(n); ++f) {
            const std::array<uint32_t, 4> v = sorted_face(el, n, f);
            if (v[size_t(local_face(n, f).count) - 1] < vertices)
              visit(uint64_t(e) * shape::kMaxFaces + uint64_t(f), v);
          }
        }
      },
      4096);
}

// Faces are sorted into buckets by their smallest vertex (a counting sort: no 24-byte key per
// face and no sort of them all), then each bucket, a few faces, by the other three. A run of
// equal faces is two elements sharing a conforming face (three or more: a broken mesh, no
// neighbour there, and the walk falls back to the BVH). Each face is made and sorted twice, to
// count it and to place it, rather than kept from the first pass (4 more bytes a face held);
// the converts' times did not move with it (bench/RESULTS.md, "Face adjacency by buckets").
template <typename Slot>
std::vector<uint32_t> match_faces(const UMesh& mesh) {
  const size_t vertices = mesh.vertices.size();
  // ends[v]: first the count of v's faces, then, summed, where v's bucket ends; the scatter below
  // takes its slots from the back, so that ends[v] is then where v's bucket begins.
  std::vector<Slot> ends(vertices + 1, 0);
  for_each_face(mesh, [&](uint64_t, const std::array<uint32_t, 4>& v) {
    std::atomic_ref<Slot>(ends[v[0]]).fetch_add(1, std::memory_order_relaxed);
  });
  Slot sum = 0;
  for (Slot& end : ends) end = sum += end;
  std::vector<FaceRest<Slot>> rests(sum);
  for_each_face(mesh, [&](uint64_t slot, const std::array<uint32_t, 4>& v) {
    const Slot at = std::atomic_ref<Slot>(ends[v[0]]).fetch_sub(1, std::memory_order_relaxed) - 1;
    rests[at] = {v[1], v[2], v[3], Slot(slot)};
  });
  std::vector<uint32_t> neighbors(mesh.elements.size() * shape::kMaxFaces, kNoNeighbor);
  parallel_for_ranges(
      int64_t(vertices),
      [&](int64_t begin, int64_t end) {
        for (int64_t b = begin; b < end; ++b) {
          const auto first = rests.begin() + ptrdiff_t(ends[size_t(b)]),
                     last = rests.begin() + ptrdiff_t(ends[size_t(b) + 1]);
          std::sort(first, last);  // the slot last: runs come out the same whatever the threads did
          for (auto i = first; i != last;) {
            auto j = i + 1;
            while (j != last && j->same_face(*i)) ++j;
            if (j - i == 2) {
              neighbors[i->slot] = uint32_t(uint64_t(j[-1].slot) / shape::kMaxFaces);
              neighbors[j[-1].slot] = uint32_t(uint64_t(i->slot) / shape::kMaxFaces);
            }
            i = j;
          }
        }
      },
      1024);
  return neighbors;
}

}  // namespace

std::vector<uint32_t> build_face_neighbors(const UMesh& mesh) {
  // Every slot, and so every face count, below 2^32: 16 bytes a face.
  if (uint64_t(mesh.elements.size()) * shape::kMaxFaces <= UINT32_MAX) return match_faces<uint32_t>(mesh);
  return match_faces<uint64_t>(mesh);
}

}  // namespace vs
