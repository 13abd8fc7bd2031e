// Point location through the element BVH equals the brute-force test of every element (issue 12:
// relative 1e-5 at 10^4 random points) on a tet mesh, a mixed mesh of twisted hexes, wedges and
// pyramids with non-planar faces, and a non-convex mesh of two parts with a cavity and a notch;
// NaN outside; the linear field is reproduced in every element.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "io/mixed_mesh.h"
#include "test_util.h"
#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"
#include "volstream/umesh/mesh_accel.h"

namespace vs {
namespace {

using test::DemoMesh;
DemoMesh demo(const std::string& name, uint64_t elements) { return test::demo_mesh(name, elements); }

std::vector<vec3f> random_points(const DemoMesh& d, int count, uint32_t seed) {
  return test::points_around(d.mesh.vertices, count, seed);
}

class MeshProbeTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MeshProbeTest, BvhEqualsBruteForceAtRandomPoints) {
  const DemoMesh d = demo(GetParam(), 3000);
  const int inside =
      test::expect_probe_is_brute_force(d.mesh, d.transform, d.density.data(), random_points(d, 10000, 11));
  EXPECT_GT(inside, 3000);   // the padded box is mostly mesh
  EXPECT_LT(inside, 10000);  // and the padding is not
}

TEST_P(MeshProbeTest, LinearFieldIsReproducedEverywhereInside) {
  const DemoMesh d = demo(GetParam(), 3000);
  const UMeshRenderer renderer(d.mesh, d.transform);
  const std::vector<vec3f> points = random_points(d, 5000, 5);
  const std::vector<float> f = renderer.probe(d.linear.data(), points);
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::isnan(f[i])) continue;
    const vec3d w = d.transform.to_world(vec3d(points[i]));
    EXPECT_NEAR(f[i], w.x + 2 * w.y + 3 * w.z, 2e-5 * 6) << "point " << i;
  }
}

// Independent of the brute force (which shares the inside test): every element holds the mean
// of its corners, so no probe there may be NaN, and the linear field is exact there.
TEST_P(MeshProbeTest, EveryElementCentroidIsFound) {
  const DemoMesh d = demo(GetParam(), 3000);
  const UMeshRenderer renderer(d.mesh, d.transform);
  std::vector<vec3f> centroids;
  for (const UElement& e : d.mesh.elements) {
    vec3f c(0.f);
    for (int k = 0; k < e.vertex_count(); ++k) c = c + d.mesh.vertices[e.v[k]];
    centroids.push_back(c * (1.f / float(e.vertex_count())));
  }
  const std::vector<float> f = renderer.probe(d.linear.data(), centroids);
  for (size_t i = 0; i < f.size(); ++i) {
    const vec3d w = d.transform.to_world(vec3d(centroids[i]));
    ASSERT_FALSE(std::isnan(f[i])) << "element " << i << " does not hold its centroid";
    EXPECT_NEAR(f[i], w.x + 2 * w.y + 3 * w.z, 1e-4) << "element " << i;
  }
}

// The walk from the ray's hint (the previous sample's element, and a tet's kept solve) gives
// what a search from scratch gives, along random lines sampled as rays are: in and out of the
// mesh, through holes and across the parts of a non-convex one; a sample in no element sets
// in_hole, and the next one searches without walking.
TEST_P(MeshProbeTest, WalkFromTheHintEqualsSearchAlongLines) {
  const DemoMesh d = demo(GetParam(), 3000);
  const UMeshRenderer renderer(d.mesh, d.transform);
  const UMeshView mesh = renderer.mesh_view();
  const std::vector<vec3f> ends = random_points(d, 200, 5);
  int walked = 0, holes = 0;
  for (size_t line = 0; line + 1 < ends.size(); line += 2) {
    UMeshView::Hint hint;
    for (int i = 0; i <= 200; ++i) {
      const vec3f p = ends[line] + (ends[line + 1] - ends[line]) * (float(i) / 200.f);
      const bool from_hint = hint.element >= 0;
      const float got = mesh.sample(d.density.data(), p, hint), want = mesh.sample(d.density.data(), p);
      ASSERT_EQ(std::isnan(got), std::isnan(want)) << "line " << line << " sample " << i;
      // After a sample in no element the next one searches without a walk.
      ASSERT_EQ(hint.in_hole, std::isnan(want)) << "line " << line << " sample " << i;
      if (std::isnan(want)) {
        EXPECT_EQ(hint.element, -1) << "line " << line << " sample " << i;
        holes += 1;
        continue;
      }
      walked += from_hint ? 1 : 0;
      EXPECT_NEAR(got, want, 1e-6f * std::max(1.f, std::fabs(want))) << "line " << line << " sample " << i;
    }
  }
  EXPECT_GT(walked, 5000);
  EXPECT_GT(holes, 500);
}

// A tet's walk record holds its solve (the weights at any point, inside or out, are the fresh
// solve's to float rounding, and so is the most negative of them) and its neighbours as
// the adjacency has them; another type's record, and a flat tet's, say they are not a tet.
TEST_P(MeshProbeTest, TetWalkRecordsAreTheTetsSolvesAndNeighbours) {
  DemoMesh d = demo(GetParam(), 3000);
  const MeshAccel accel = build_mesh_accel(d.mesh);
  const TetWalkRecords records = tet_walk_records(d.mesh, accel.neighbors);
  const uint64_t tets = std::count_if(d.mesh.elements.begin(), d.mesh.elements.end(),
                                      [](const UElement& el) { return el.vertex_count() == 4; });
  if (tets == 0) {
    EXPECT_TRUE(records.empty());
    return;
  }
  ASSERT_EQ(records.size(), d.mesh.elements.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> weight(-0.5f, 1.f);
  int compared = 0;
  for (size_t e = 0; e < records.size(); ++e) {
    const UElement& el = d.mesh.elements[e];
    ASSERT_EQ(records[e].is_tet(), el.vertex_count() == 4) << "element " << e;
    if (!records[e].is_tet()) continue;
    vec3f x[4];
    for (int i = 0; i < 4; ++i) {
      x[i] = d.mesh.vertices[el.v[i]];
      EXPECT_EQ(records[e].neighbor[i], accel.neighbors[e * shape::kMaxFaces + size_t(i)]);
    }
    for (int k = 0; k < 4; ++k) {  // points inside and outside, from weights that sum to 1
      const float a = weight(rng), b = weight(rng), c = weight(rng);
      const vec3f p = x[0] * (1.f - a - b - c) + x[1] * a + x[2] * b + x[3] * c;
      float want[4], got[4], outside;
      int want_face = -1, got_face = -1;
      shape::locate_in_tet(x, p, want, &outside, &want_face);
      UMeshView::tet_record_weights(records[e], p, got, got_face);
      for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], 1e-5f) << "element " << e << " weight " << i;
      EXPECT_NEAR(got[got_face], want[want_face], 1e-5f) << "element " << e;  // the most negative weight
      ++compared;
    }
  }
  EXPECT_EQ(uint64_t(compared), 4 * tets);
  // A flat tet (its fourth corner in the plane of the other three) has no solve.
  d.mesh.vertices[d.mesh.elements[0].v[3]] = d.mesh.vertices[d.mesh.elements[0].v[0]];
  if (d.mesh.elements[0].vertex_count() == 4) {
    EXPECT_FALSE(tet_walk_records(d.mesh, accel.neighbors)[0].is_tet());
  }
}

// The records a convert writes block by block are those built whole, byte for byte, whatever
// the block (one element, a block that does not divide the count, one larger than the mesh).
TEST_P(MeshProbeTest, WalkRecordsInBlocksAreTheWholeRecords) {
  const DemoMesh d = demo(GetParam(), 3000);
  const MeshAccel accel = build_mesh_accel(d.mesh);
  const TetWalkRecords whole = tet_walk_records(d.mesh, accel.neighbors);
  for (const size_t block : {size_t(1), size_t(1000), size_t(1) << 20}) {
    std::vector<TetWalkRecord> blocks;
    const uint64_t count = for_each_tet_walk_block(
        d.mesh, accel.neighbors,
        [&](const TetWalkRecord* records, size_t n) { blocks.insert(blocks.end(), records, records + n); }, block);
    ASSERT_EQ(count, whole.size()) << "block " << block;
    ASSERT_EQ(blocks.size(), whole.size()) << "block " << block;
    if (whole.empty()) continue;  // no tets (the mixed demo): no records either way
    EXPECT_EQ(std::memcmp(blocks.data(), whole.data(), whole.size() * sizeof(TetWalkRecord)), 0) << "block " << block;
  }
}

// Stored records (a dataset's mesh_tet_walk.bin) pass the check when they are the mesh's own,
// also with rows off by rounding; a record that differs where the walk reads it (a neighbour, a
// row beyond rounding, a corner, a tet flag) or a count that differs is refused, naming it.
TEST_P(MeshProbeTest, StoredWalkRecordsAreCheckedAgainstTheMesh) {
  const DemoMesh d = demo(GetParam(), 3000);
  const MeshAccel accel = build_mesh_accel(d.mesh);
  const TetWalkRecords built = tet_walk_records(d.mesh, accel.neighbors);
  if (built.empty()) return;  // no tets: nothing is stored
  std::vector<TetWalkRecord> stored(built.data(), built.data() + built.size());
  const auto check = [&] { check_tet_walk_records(d.mesh, accel.neighbors, stored, "walk.bin"); };
  EXPECT_NO_THROW(check());
  const size_t e =
      size_t(std::find_if(stored.begin(), stored.end(), [](auto& r) { return r.is_tet(); }) - stored.begin());
  ASSERT_LT(e, stored.size());
  stored[e].rows[1] = stored[e].rows[1] * (1.f + 1e-6f);  // rounding
  EXPECT_NO_THROW(check());
  const std::vector<TetWalkRecord> good = stored;
  const auto refused = [&](const char* what, auto&& spoil) {
    stored = good;
    spoil(stored[e]);
    EXPECT_THROW(
        try { check(); } catch (const InputError& err) {
          EXPECT_NE(std::string(err.what()).find("walk record " + std::to_string(e)), std::string::npos) << what;
          throw;
        },
        InputError)
        << what;
  };
  refused("neighbour", [](TetWalkRecord& r) { r.neighbor[2] = r.neighbor[2] == 0 ? 1u : 0u; });
  refused("row", [](TetWalkRecord& r) { r.rows[0] = r.rows[0] * 1.01f; });
  refused("corner", [](TetWalkRecord& r) { r.origin.y += 1e-3f; });
  refused("NaN row", [](TetWalkRecord& r) { r.rows[2].z = NAN; });
  refused("no tet", [](TetWalkRecord& r) { r.rows[0].x = NAN; });
  stored = good;
  stored.pop_back();
  EXPECT_THROW(check(), InputError);
}

// A mesh of tets and other types (FUN3D's kind): the other types' records say they are not a
// tet and have no neighbours, every byte defined (a dataset stores them), so stored records of
// such a mesh pass the check.
TEST(MeshProbe, WalkRecordsOfAMixedMeshWithTets) {
  const MeshData data = test::mixed_mesh();
  const WorldTransform transform = mesh_transform(data);
  const UMesh mesh = make_umesh(data, transform, "mixed");
  const MeshAccel accel = build_mesh_accel(mesh);
  const TetWalkRecords records = tet_walk_records(mesh, accel.neighbors);
  ASSERT_EQ(records.size(), mesh.elements.size());
  int tets = 0;
  for (size_t e = 0; e < records.size(); ++e) {
    ASSERT_EQ(records[e].is_tet(), mesh.elements[e].vertex_count() == 4) << "element " << e;
    tets += records[e].is_tet();
    if (records[e].is_tet()) continue;
    for (uint32_t n : records[e].neighbor) EXPECT_EQ(n, UMeshView::kNoNeighborIndex) << "element " << e;
  }
  EXPECT_EQ(tets, 1);
  const std::vector<TetWalkRecord> stored(records.data(), records.data() + records.size());
  EXPECT_NO_THROW(check_tet_walk_records(mesh, accel.neighbors, stored, "walk.bin"));
}

INSTANTIATE_TEST_SUITE_P(Demos, MeshProbeTest, ::testing::Values("tets", "mixed", "holes"));

TEST(MeshProbe, HolesAndGapsAreNan) {
  const DemoMesh d = demo("holes", 20000);
  const UMeshRenderer renderer(d.mesh, d.transform);
  // The cavity's centre, inside the notch, between the two parts, and beyond the mesh.
  const std::vector<vec3d> world = {{0.5, 0.5, 0.5}, {0.95, 0.2, 0.5}, {1.1, 0.5, 0.5}, {2.0, 2.0, 2.0}};
  std::vector<vec3f> points;
  for (const vec3d& w : world) points.push_back(vec3f(d.transform.to_grid(w)));
  for (float v : renderer.probe(d.density.data(), points)) EXPECT_TRUE(std::isnan(v));
  // The island is there.
  EXPECT_FALSE(std::isnan(renderer.probe(d.density.data(), {vec3f(d.transform.to_grid({1.35, 0.45, 0.45}))})[0]));
}

TEST(MeshProbe, DemoMixedHasEveryNonTetType) {
  const DemoMesh d = demo("mixed", 3000);
  EXPECT_GT(d.mesh.count_by_type[type_slot(5)], 0u);
  EXPECT_GT(d.mesh.count_by_type[type_slot(6)], 0u);
  EXPECT_GT(d.mesh.count_by_type[type_slot(8)], 0u);
}

}  // namespace
}  // namespace vs
