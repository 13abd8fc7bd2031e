// Face adjacency (umesh/adjacency.h) against the brute force: every face compared with every
// other by its vertex set; a face has a neighbour exactly where one other face has its vertices.
#include "volstream/umesh/adjacency.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>

#include "test_util.h"

namespace vs {
namespace {

std::array<uint32_t, 4> face_vertices(const UElement& el, int f) {
  const int n = el.vertex_count();
  const LocalFace lf = local_face(n, f);
  std::array<uint32_t, 4> v = {kNoVertex, kNoVertex, kNoVertex, kNoVertex};
  for (int i = 0; i < lf.count; ++i) v[size_t(i)] = el.v[lf.v[i]];
  std::sort(v.begin(), v.end());
  return v;
}

// neighbors[e * kMaxFaces + f] by comparing all pairs of faces.
std::vector<uint32_t> brute_force_neighbors(const UMesh& mesh) {
  std::vector<std::array<uint32_t, 4>> faces;
  std::vector<uint64_t> slots;
  for (size_t e = 0; e < mesh.elements.size(); ++e)
    for (int f = 0; f < shape::face_count(mesh.elements[e].vertex_count()); ++f) {
      faces.push_back(face_vertices(mesh.elements[e], f));
      slots.push_back(e * shape::kMaxFaces + size_t(f));
    }
  std::vector<uint32_t> neighbors(mesh.elements.size() * shape::kMaxFaces, kNoNeighbor);
  for (size_t a = 0; a < faces.size(); ++a) {
    size_t matches = 0, other = 0;
    for (size_t b = 0; b < faces.size(); ++b)
      if (b != a && faces[b] == faces[a]) ++matches, other = b;
    if (matches == 1) neighbors[slots[a]] = uint32_t(slots[other] / shape::kMaxFaces);
  }
  return neighbors;
}

void expect_brute_force(const UMesh& mesh, const std::string& what) {
  const std::vector<uint32_t> fast = build_face_neighbors(mesh), slow = brute_force_neighbors(mesh);
  ASSERT_EQ(fast.size(), slow.size()) << what;
  size_t linked = 0;
  for (size_t s = 0; s < fast.size(); ++s) {
    EXPECT_EQ(fast[s], slow[s]) << what << ": element " << s / shape::kMaxFaces << " face " << s % shape::kMaxFaces;
    linked += slow[s] != kNoNeighbor;
  }
  EXPECT_GT(linked, 0u) << what << ": a test of no shared face";
}

TEST(FaceNeighbors, DemoMeshesAreTheBruteForce) {
  for (const char* name : {"tets", "mixed", "holes"}) expect_brute_force(test::demo_mesh(name, 600).mesh, name);
}

UElement element(std::initializer_list<uint32_t> corners) {
  UElement el;
  std::fill(std::begin(el.v), std::end(el.v), kNoVertex);
  std::copy(corners.begin(), corners.end(), el.v);
  return el;
}

// Faces that do not match one to one: a hex's quad against two tets' triangles, three tets on
// one triangle and three elements on one quad (a broken mesh), and a tet naming a vertex past the
// mesh's (its faces with that vertex match nothing, and nothing is written out of bounds); the
// tets 8 and 9 do share a triangle. Adjacency does not look at the vertices' positions.
TEST(FaceNeighbors, FacesThatDoNotPairAreTheBruteForce) {
  UMesh mesh;
  mesh.vertices.resize(20);
  mesh.elements = std::vector<UElement>{
      element({0, 1, 2, 3, 4, 5, 6, 7}),  // hex: its quad 0-1-5-4 against the next two tets' triangles
      element({0, 1, 5, 8}),
      element({0, 5, 4, 8}),
      element({10, 11, 12, 13}),  // three tets on the triangle 10-11-12
      element({10, 11, 12, 14}),
      element({12, 11, 10, 15}),
      element({2, 3, 7, 6, 16}),  // pyramid and wedge on the hex's quad 2-3-7-6: three on one quad
      element({3, 2, 17, 7, 6, 18}),
      element({16, 17, 18, 19}),
      element({16, 17, 18, 1000000}),
  };
  expect_brute_force(mesh, "hand-made");
}

}  // namespace
}  // namespace vs
