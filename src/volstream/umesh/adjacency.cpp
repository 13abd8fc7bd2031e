#include "volstream/umesh/adjacency.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>

#include "volstream/backend/parallel.h"

namespace vs {

namespace {

struct FaceKey {
  uint64_t hi, lo;  // the face's sorted global vertex indices packed in pairs (a triangle's fourth is kNoVertex)
  uint64_t slot;    // element * kMaxFaces + face
  bool operator<(const FaceKey& o) const { return hi != o.hi ? hi < o.hi : (lo != o.lo ? lo < o.lo : slot < o.slot); }
  bool same_face(const FaceKey& o) const { return hi == o.hi && lo == o.lo; }
};

}  // namespace

std::vector<uint32_t> build_face_neighbors(const UMesh& mesh) {
  const size_t elements = mesh.elements.size();
  std::vector<uint64_t> first(elements + 1, 0);
  for (size_t e = 0; e < elements; ++e)
    first[e + 1] = first[e] + uint64_t(shape::face_count(mesh.elements[e].vertex_count()));
  std::vector<FaceKey> keys(first[elements]);
  parallel_for("face keys", int64_t(elements), [&](int64_t e) {
    const UElement& el = mesh.elements[size_t(e)];
    const int n = el.vertex_count();
    for (int f = 0; f < shape::face_count(n); ++f) {
      const LocalFace lf = local_face(n, f);
      std::array<uint32_t, 4> v = {kNoVertex, kNoVertex, kNoVertex, kNoVertex};
      for (int i = 0; i < lf.count; ++i) v[size_t(i)] = el.v[lf.v[i]];
      std::sort(v.begin(), v.end());
      keys[first[size_t(e)] + uint64_t(f)] = {uint64_t(v[0]) << 32 | v[1], uint64_t(v[2]) << 32 | v[3],
                                              uint64_t(e) * shape::kMaxFaces + uint64_t(f)};
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  std::vector<uint32_t> neighbors(elements * shape::kMaxFaces, kNoNeighbor);
  // Runs of equal keys: exactly two elements share a conforming face (a run of three or more
  // is a broken mesh; those faces get no neighbour, and the walk falls back to the BVH there).
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j].same_face(keys[i])) ++j;
    if (j - i == 2) {
      neighbors[keys[i].slot] = uint32_t(keys[i + 1].slot / shape::kMaxFaces);
      neighbors[keys[i + 1].slot] = uint32_t(keys[i].slot / shape::kMaxFaces);
    }
    i = j;
  }
  return neighbors;
}

}  // namespace vs
