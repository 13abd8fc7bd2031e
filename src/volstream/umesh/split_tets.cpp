#include "volstream/umesh/split_tets.h"

#include <algorithm>
#include <utility>

#include "volstream/backend/parallel.h"
#include "volstream/umesh/shape.h"

namespace vs {

namespace {

// The corners' parametric points (shape.h), the pyramid's apex above its base's centre: where a
// tet's orientation is read, since the element's map keeps it (a valid element's Jacobian has
// one sign) while its corners in space may be warped.
vec3f corner_params(int n, int corner) {
  constexpr vec3f kBox[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  constexpr vec3f kWedge[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  if (n == 6) return kWedge[corner];
  if (n == 5 && corner == 4) return {0.5f, 0.5f, 1.f};
  return kBox[corner];
}

// Element-local corners a, b, c, d as a tet in VTK's order with the element's orientation: VTK's
// reference tet has a positive determinant in its own parameters, so the element's is made so.
UElement oriented_tet(const UElement& e, int n, int a, int b, int c, int d) {
  const vec3f pa = corner_params(n, a);
  if (dot(cross(corner_params(n, b) - pa, corner_params(n, c) - pa), corner_params(n, d) - pa) < 0.f) std::swap(c, d);
  UElement t;
  std::fill(std::begin(t.v), std::end(t.v), kNoVertex);
  t.v[0] = e.v[a], t.v[1] = e.v[b], t.v[2] = e.v[c], t.v[3] = e.v[d];
  return t;
}

// The local corner of the lowest vertex index among corners[0..count).
int lowest_corner(const UElement& e, const int* corners, int count) {
  int lowest = corners[0];
  for (int i = 1; i < count; ++i)
    if (e.v[corners[i]] < e.v[lowest]) lowest = corners[i];
  return lowest;
}

// Writes the tets of element e (tets_per_element of them) to out.
void split_element(const UElement& e, UElement* out) {
  const int n = e.vertex_count();
  if (n == 4) {
    *out = e;
    return;
  }
  constexpr int kAll[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  const int apex = lowest_corner(e, kAll, n);
  for (int f = 0; f < shape::face_count(n); ++f) {
    const shape::LocalFace face = shape::local_face(n, f);
    if (std::find(face.v, face.v + face.count, apex) != face.v + face.count) continue;
    if (face.count == 3) {
      *out++ = oriented_tet(e, n, apex, face.v[0], face.v[1], face.v[2]);
      continue;
    }
    // The quad's diagonal through its lowest vertex: from there round the face, k0 k1 k2 k3.
    const int first = int(std::find(face.v, face.v + 4, lowest_corner(e, face.v, 4)) - face.v);
    const int k0 = face.v[first], k1 = face.v[(first + 1) % 4], k2 = face.v[(first + 2) % 4],
              k3 = face.v[(first + 3) % 4];
    *out++ = oriented_tet(e, n, apex, k0, k1, k2);
    *out++ = oriented_tet(e, n, apex, k0, k2, k3);
  }
}

}  // namespace

UMesh split_into_tets(UMesh mesh) {
  const HostArray<UElement>& elements = mesh.elements;  // read only: a view stays a view
  const int64_t count = int64_t(elements.size());
  std::vector<uint64_t> first(size_t(count) + 1, 0);  // where each element's tets start
  for (int64_t i = 0; i < count; ++i)
    first[size_t(i) + 1] = first[size_t(i)] + tets_per_element(elements[size_t(i)].vertex_count());
  UMesh out;
  out.vertices = std::move(mesh.vertices);
  out.elements = HostArray<UElement>(first.back());
  UElement* tets = out.elements.data();
  parallel_for_ranges(count, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) split_element(elements[size_t(i)], tets + first[size_t(i)]);
  });
  out.count_by_type[type_slot(4)] = first.back();
  return out;
}

}  // namespace vs
