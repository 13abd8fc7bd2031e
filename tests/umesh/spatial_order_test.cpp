// The stored order of a mesh (umesh/spatial_order.h): the same elements, corners and values,
// renumbered so that face neighbours are near in memory, also for a mesh given in random order;
// point location finds the same values in either order.
#include "volstream/umesh/spatial_order.h"

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

struct Shuffled {
  UMesh mesh;
  std::vector<float> values;
  WorldTransform transform;
};

// A demo mesh with its elements and vertices in random order (a file that gives them so).
Shuffled shuffled_demo(const std::string& name, uint64_t elements) {
  const MeshData data = make_mesh_demo({name, elements, 1}, 0);
  Shuffled s;
  s.transform = mesh_transform(data);
  const UMesh mesh = make_umesh(data, s.transform, name);
  std::mt19937 rng(3);
  MeshOrder random;
  random.element_source.resize(mesh.elements.size());
  std::iota(random.element_source.begin(), random.element_source.end(), 0u);
  std::shuffle(random.element_source.begin(), random.element_source.end(), rng);
  random.vertex_target.resize(mesh.vertices.size());
  std::iota(random.vertex_target.begin(), random.vertex_target.end(), 0u);
  std::shuffle(random.vertex_target.begin(), random.vertex_target.end(), rng);
  s.mesh = reordered(mesh, random);
  s.values = reordered_values(mesh_field_values(data, mesh_fields(data)[0]), random);
  return s;
}

// Mean distance in the element array between an element and its face neighbours.
double mean_neighbour_distance(const UMesh& mesh) {
  const std::vector<uint32_t> neighbors = build_face_neighbors(mesh);
  double sum = 0.0;
  uint64_t count = 0;
  for (size_t i = 0; i < neighbors.size(); ++i) {
    if (neighbors[i] == kNoNeighbor) continue;
    sum += std::fabs(double(neighbors[i]) - double(i / shape::kMaxFaces));
    ++count;
  }
  return sum / double(count);
}

class SpatialOrderTest : public ::testing::TestWithParam<std::string> {};

TEST_P(SpatialOrderTest, KeepsEveryElementCornerAndValue) {
  const Shuffled in = shuffled_demo(GetParam(), 4000);
  const MeshOrder order = spatial_order(in.mesh);
  const UMesh out = reordered(in.mesh, order);
  const std::vector<float> values = reordered_values(in.values, order);
  ASSERT_EQ(out.elements.size(), in.mesh.elements.size());
  ASSERT_EQ(out.vertices.size(), in.mesh.vertices.size());
  std::vector<uint32_t> sources = order.element_source, targets = order.vertex_target;
  std::sort(sources.begin(), sources.end());
  std::sort(targets.begin(), targets.end());
  for (size_t i = 0; i < sources.size(); ++i) ASSERT_EQ(sources[i], i) << "not a permutation";
  for (size_t i = 0; i < targets.size(); ++i) ASSERT_EQ(targets[i], i) << "not a permutation";
  for (size_t i = 0; i < out.elements.size(); ++i) {
    const UElement &stored = out.elements[i], &input = in.mesh.elements[order.element_source[i]];
    ASSERT_EQ(stored.vertex_count(), input.vertex_count());
    for (int k = 0; k < input.vertex_count(); ++k) {
      EXPECT_EQ(out.vertices[stored.v[k]], in.mesh.vertices[input.v[k]]) << "element " << i << " corner " << k;
      EXPECT_EQ(values[stored.v[k]], in.values[input.v[k]]) << "element " << i << " corner " << k;
    }
  }
  for (int t = 0; t < 4; ++t) EXPECT_EQ(out.count_by_type[t], in.mesh.count_by_type[t]);
}

TEST_P(SpatialOrderTest, PutsFaceNeighboursNearInMemory) {
  const Shuffled in = shuffled_demo(GetParam(), 4000);
  const UMesh out = reordered(in.mesh, spatial_order(in.mesh));
  const double before = mean_neighbour_distance(in.mesh), after = mean_neighbour_distance(out);
  EXPECT_LT(after * 8.0, before) << "mean neighbour distance " << before << " -> " << after;
}

TEST_P(SpatialOrderTest, PointLocationFindsTheSameValues) {
  const Shuffled in = shuffled_demo(GetParam(), 3000);
  const MeshOrder order = spatial_order(in.mesh);
  const UMesh out = reordered(in.mesh, order);
  const std::vector<float> values = reordered_values(in.values, order);
  const std::vector<vec3f> points = test::points_around(in.mesh.vertices, 4000, 8);
  const std::vector<float> want = UMeshRenderer(in.mesh, in.transform).probe(in.values.data(), points);
  const std::vector<float> got = UMeshRenderer(out, in.transform).probe(values.data(), points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(std::isnan(got[i]), std::isnan(want[i])) << "point " << i;
    if (std::isnan(want[i])) continue;
    ++inside;
    EXPECT_NEAR(got[i], want[i], 1e-6f * std::max(1.f, std::fabs(want[i]))) << "point " << i;
  }
  EXPECT_GT(inside, 1000);
}

INSTANTIATE_TEST_SUITE_P(Demos, SpatialOrderTest, ::testing::Values("tets", "mixed", "holes"));

}  // namespace
}  // namespace vs
