// Pyramids, wedges and hexahedra split into tets (umesh/split_tets.h): each element's tets fill
// it exactly (volumes of affine elements, in any vertex numbering) with its orientation; the
// split mesh is conforming (its unmatched faces are exactly the source's boundary, cut in
// triangles); it reproduces the linear field, locates points as the brute force does, and
// differs from the element's own interpolation only by what a linear fit loses.
#include "volstream/umesh/split_tets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "test_util.h"
#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/adjacency.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {

double tet_volume(const UMesh& mesh, const UElement& t) {
  const vec3d a(mesh.vertices[t.v[0]]), b(mesh.vertices[t.v[1]]), c(mesh.vertices[t.v[2]]), d(mesh.vertices[t.v[3]]);
  return dot(cross(b - a, c - a), d - a) / 6.0;
}

// One element of n corners: the reference element's corners (as split_tets.cpp places them)
// through the affine map x -> A x + o, numbered by `ids` (a permutation of 0..n).
UMesh affine_element(int n, const double (&a)[3][3], const vec3d& o, const std::vector<uint32_t>& ids) {
  const vec3d box[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const vec3d wedge[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  UMesh m;
  m.vertices.resize(size_t(n));
  UElement e;
  std::fill(std::begin(e.v), std::end(e.v), kNoVertex);
  for (int i = 0; i < n; ++i) {
    const vec3d p = n == 6 ? wedge[i] : (n == 5 && i == 4) ? vec3d(0.5, 0.5, 1.0) : box[i];
    m.vertices[ids[size_t(i)]] =
        vec3f(vec3d(a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z, a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z,
                    a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z) +
              o);
    e.v[i] = ids[size_t(i)];
  }
  m.elements.push_back(e);
  m.count_by_type[type_slot(n)] = 1;
  return m;
}

TEST(SplitTets, AffineElementsAreFilledExactlyWithTheirOrientation) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {5, 6, 8}) {
    const double reference_volume = n == 8 ? 1.0 : n == 6 ? 0.5 : 1.0 / 3.0;
    for (int trial = 0; trial < 200; ++trial) {
      double a[3][3];
      for (auto& row : a)
        for (double& x : row) x = u(rng);
      for (int i = 0; i < 3; ++i) a[i][i] += 2.0;  // well conditioned
      if (trial % 2) std::swap(a[0], a[1]);        // and mirrored: negative orientation
      const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                         a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
      std::vector<uint32_t> ids(static_cast<size_t>(n));
      std::iota(ids.begin(), ids.end(), 0u);
      std::shuffle(ids.begin(), ids.end(), rng);  // every corner may be the lowest
      const UMesh element = affine_element(n, a, {u(rng), u(rng), u(rng)}, ids);
      const UMesh tets = split_into_tets(element);
      ASSERT_EQ(tets.elements.size(), tets_per_element(n));
      EXPECT_EQ(tets.count_by_type[type_slot(4)], tets_per_element(n));
      EXPECT_EQ(tets.vertices, element.vertices);
      double sum = 0.0;
      for (const UElement& t : tets.elements) {
        ASSERT_EQ(t.vertex_count(), 4);
        const double v = tet_volume(tets, t);
        EXPECT_GT(v * det, 0.0) << "n " << n << " trial " << trial << ": a tet against its element's orientation";
        sum += v;
      }
      EXPECT_NEAR(sum, det * reference_volume, 1e-5 * std::fabs(det)) << "n " << n << " trial " << trial;
    }
  }
}

// Faces with no neighbour: a split mesh's must be the source's boundary, each quad as two triangles.
uint64_t boundary_triangles(const UMesh& mesh) {
  const std::vector<uint32_t> neighbors = build_face_neighbors(mesh);
  uint64_t count = 0;
  for (size_t e = 0; e < mesh.elements.size(); ++e) {
    const int n = mesh.elements[e].vertex_count();
    for (int f = 0; f < shape::face_count(n); ++f)
      if (neighbors[e * shape::kMaxFaces + size_t(f)] == kNoNeighbor) count += local_face(n, f).count == 4 ? 2 : 1;
  }
  return count;
}

// A demo mesh and its split.
struct Split : test::DemoMesh {
  UMesh tets;
};

Split split_demo(const std::string& name, uint64_t elements) {
  Split s{test::demo_mesh(name, elements), {}};
  s.tets = split_into_tets(s.mesh);
  return s;
}

TEST(SplitTets, TheDemoMixedMeshSplitsConformingly) {
  const Split s = split_demo("mixed", 3000);
  const uint64_t* by = s.mesh.count_by_type;
  ASSERT_GT(by[1] * by[2] * by[3], 0u) << "the demo should hold pyramids, wedges and hexahedra";
  EXPECT_EQ(s.tets.elements.size(), by[0] + 2 * by[1] + 3 * by[2] + 6 * by[3]);
  EXPECT_EQ(boundary_triangles(s.tets), boundary_triangles(s.mesh))
      << "faces inside the mesh cut differently by their two elements";
}

TEST(SplitTets, TheSplitMeshIsLocatedAsTheBruteForceDoesAndKeepsTheLinearField) {
  const Split s = split_demo("mixed", 3000);
  const std::vector<vec3f> points = test::points_around(s.mesh.vertices, 10000, 17);
  EXPECT_GT(test::expect_probe_is_brute_force(s.tets, s.transform, s.density.data(), points), 3000);
  const UMeshRenderer tets(s.tets, s.transform), elements(s.mesh, s.transform);
  const std::vector<float> linear = tets.probe(s.linear.data(), points),
                           exact = elements.probe(s.linear.data(), points);
  int both = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::isnan(linear[i]) || std::isnan(exact[i])) continue;
    ++both;
    EXPECT_NEAR(linear[i], exact[i], 2e-5 * std::max(1.f, std::fabs(exact[i]))) << "point " << i;
  }
  EXPECT_GT(both, 3000);
}

// The split changes the interpolation inside an element, not the data: on the demo's smooth
// density the mean difference from the element's own shape functions is small against the
// field's range, and the largest one is bounded (measured: 0.09% and 3.1% of the range).
TEST(SplitTets, InterpolatesCloseToTheElementsOwnShapeFunctions) {
  const Split s = split_demo("mixed", 20000);
  const UMeshRenderer tets(s.tets, s.transform), elements(s.mesh, s.transform);
  const std::vector<vec3f> points = test::points_around(s.mesh.vertices, 10000, 23);
  const std::vector<float> split = tets.probe(s.density.data(), points), own = elements.probe(s.density.data(), points);
  const auto [lo, hi] = std::minmax_element(s.density.begin(), s.density.end());
  const double range = double(*hi - *lo);
  double sum = 0.0, most = 0.0;
  int both = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::isnan(split[i]) || std::isnan(own[i])) continue;
    const double d = std::fabs(double(split[i]) - double(own[i]));
    sum += d, most = std::max(most, d), ++both;
  }
  ASSERT_GT(both, 3000);
  EXPECT_LT(sum / both, 0.01 * range);
  EXPECT_LT(most, 0.1 * range);
}

TEST(SplitTets, TetsStayAsTheyAre) {
  const Split s = split_demo("tets", 2000);
  ASSERT_EQ(s.tets.elements.size(), s.mesh.elements.size());
  for (size_t i = 0; i < s.mesh.elements.size(); ++i)
    ASSERT_TRUE(
        std::equal(std::begin(s.tets.elements[i].v), std::end(s.tets.elements[i].v), std::begin(s.mesh.elements[i].v)))
        << "tet " << i;
}

}  // namespace
}  // namespace vs
