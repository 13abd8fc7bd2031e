// The compact encoding (issue 13, first slice) against the reference: the same values at random
// points (bit-identical: the same shape functions on the same corners), on every element type
// and the non-convex mesh; quantized child boxes hold their children; decoding every leaf gives
// every element once; the walk's face neighbours (cached, across sub-meshes) are the search's; the
// bytes per element, measured.
#include "volstream/umesh/compact.h"

#include <gtest/gtest.h>

#include "test_util.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iterator>
#include <random>
#include <vector>

#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/compact_store.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {

struct Encoded {
  UMesh mesh;
  WorldTransform transform;
  std::vector<float> values;
  CompactMesh compact;
};

Encoded encode(const std::string& demo, uint64_t elements) {
  Encoded e;
  const MeshData data = make_mesh_demo({demo, elements, 1}, 0);
  e.transform = mesh_transform(data);
  e.mesh = make_umesh(data, e.transform, demo);
  e.values = mesh_field_values(data, mesh_fields(data)[0]);
  e.compact = build_compact_mesh(e.mesh);
  return e;
}

class CompactTest : public ::testing::TestWithParam<std::string> {};

TEST_P(CompactTest, EqualsTheReferenceAtRandomPoints) {
  const Encoded e = encode(GetParam(), 20000);
  const UMeshRenderer reference(e.mesh, e.transform);
  const CompactMeshView compact = view_of(e.compact);
  const std::vector<float> local = e.compact.gather(e.values.data());
  const std::vector<vec3f> points = test::points_around(e.mesh.vertices, 10000, 5);
  const std::vector<float> want = reference.probe(e.values.data(), points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const float got = compact.sample(local.data(), points[i]);
    ASSERT_EQ(std::isnan(got), std::isnan(want[i])) << "point " << i;
    if (std::isnan(got)) continue;
    ++inside;
    // The same element's shape functions on the same corners: equal, but for points on a face
    // shared by two elements (either may be found; they agree to float rounding).
    EXPECT_NEAR(got, want[i], 1e-6f * std::max(1.f, std::fabs(want[i]))) << "point " << i;
  }
  EXPECT_GT(inside, 2000);
}

// for_each_element_of_leaf's pass along the corner runs gives each leaf's elements as
// CompactMeshView::element decodes them one by one (tet pairs, single tets, every other type).
TEST_P(CompactTest, ElementsOfALeafInOnePassAreTheElementsOneByOne) {
  const Encoded e = encode(GetParam(), 20000);
  const CompactMeshView view = view_of(e.compact);
  for (uint32_t l = 0; l < e.compact.leaves.size(); ++l) {
    const CompactLeaf& leaf = e.compact.leaves[l];
    const uint32_t base = e.compact.submeshes[leaf.submesh].first_vertex;
    uint32_t k = 0;
    for_each_element_of_leaf(e.compact, view, l, [&](const CompactElement& got) {
      uint8_t corner[8];
      uint16_t v[8];
      const int n = view.element(leaf, k, corner, v);
      ASSERT_EQ(got.n, n) << "leaf " << l << " element " << k;
      for (int i = 0; i < n; ++i) ASSERT_EQ(got.vertex[i], base + v[i]) << "leaf " << l << " element " << k;
      ++k;
    });
    ASSERT_EQ(k, leaf.element_count()) << "leaf " << l;
  }
}

TEST_P(CompactTest, QuantizedBoxesHoldTheirChildrenAndLeavesHoldEveryElementOnce) {
  const Encoded e = encode(GetParam(), 20000);
  const CompactMesh& c = e.compact;
  // Every leaf decoded: its elements, as sorted reference vertex lists, are the mesh's elements
  // (each once: the multi-leaf decode equals the plain element list); leaf boxes from them.
  const CompactMeshView view = view_of(c);
  std::vector<std::vector<uint32_t>> decoded, plain;
  std::vector<box3f> leaf_box(c.leaves.size(), box3f::make_empty());
  for (uint32_t l = 0; l < c.leaves.size(); ++l) {
    const CompactLeaf& leaf = c.leaves[l];
    for (uint32_t k = 0; k < leaf.element_count(); ++k) {
      uint8_t corner[8];
      uint16_t v[8];
      const int n = view.element(leaf, k, corner, v);
      std::vector<uint32_t> element;
      for (int i = 0; i < n; ++i) {
        ASSERT_LT(corner[i], leaf.table_size());
        const uint32_t local = c.submeshes[leaf.submesh].first_vertex + v[i];
        element.push_back(c.source_vertex[local]);
        leaf_box[l].extend(c.vertices[local]);
      }
      std::sort(element.begin(), element.end());
      decoded.push_back(element);
    }
  }
  for (const UElement& el : e.mesh.elements) {
    std::vector<uint32_t> element(el.v, el.v + el.vertex_count());
    std::sort(element.begin(), element.end());
    plain.push_back(element);
  }
  std::sort(decoded.begin(), decoded.end());
  std::sort(plain.begin(), plain.end());
  EXPECT_EQ(decoded, plain);
  // The exact box of a child: its leaf's elements, or the union of the exact boxes below it.
  std::function<box3f(const CompactNode&, int)> exact = [&](const CompactNode& node, int i) {
    if (node.leaf_children) return leaf_box[node.first + uint32_t(i)];
    const CompactNode& child = c.nodes[node.first + uint32_t(i)];
    box3f all = box3f::make_empty();
    for (int j = 0; j < child.count; ++j) all.extend(exact(child, j));
    return all;
  };
  for (const CompactNode& node : c.nodes)
    for (int i = 0; i < node.count; ++i) {
      const box3f q = node.child_box(i), child = exact(node, i);
      for (int a = 0; a < 3; ++a) {
        EXPECT_LE(q.lower[a], child.lower[a]);
        EXPECT_GE(q.upper[a], child.upper[a]);
      }
    }
}

// The walk over faces found by index matching (the ray's hint) gives what a search from scratch
// gives, along random lines sampled as rays are: in and out of the mesh, across leaves and
// sub-meshes (a small max sub-mesh is not needed: 20000 elements span one, so the lines also
// cross from the last leaves to the first).
TEST_P(CompactTest, WalkFromTheHintEqualsSearchAlongLines) {
  const Encoded e = encode(GetParam(), 20000);
  const CompactMeshView compact = view_of(e.compact);
  const std::vector<float> local = e.compact.gather(e.values.data());
  box3f b = box3f::make_empty();
  for (const vec3f& v : e.mesh.vertices) b.extend(v);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-0.1f, 1.1f);
  int walked = 0, holes = 0;
  for (int line = 0; line < 100; ++line) {
    const vec3f from = b.lower + b.size() * vec3f(u(rng), u(rng), u(rng));
    const vec3f to = b.lower + b.size() * vec3f(u(rng), u(rng), u(rng));
    CompactMeshView::Hint hint;
    for (int i = 0; i <= 200; ++i) {
      const vec3f p = from + (to - from) * (float(i) / 200.f);
      const int64_t before = hint.element;
      const float got = compact.sample(local.data(), p, hint), want = compact.sample(local.data(), p);
      ASSERT_EQ(std::isnan(got), std::isnan(want)) << "line " << line << " sample " << i;
      // After a sample in no element the next skips the walk; the element stays, where the
      // search starts.
      ASSERT_EQ(hint.in_hole, std::isnan(want)) << "line " << line << " sample " << i;
      if (std::isnan(want)) {
        EXPECT_EQ(hint.element, before) << "line " << line << " sample " << i;
        holes += 1;
        continue;
      }
      walked += before >= 0 ? 1 : 0;
      EXPECT_NEAR(got, want, 1e-6f * std::max(1.f, std::fabs(want))) << "line " << line << " sample " << i;
    }
  }
  EXPECT_GT(walked, 1000);
  EXPECT_GT(holes, 100);
}

// Calls f(leaf, element, corner, v, n, face) for every face of every element of `view`.
template <typename F>
void for_each_element_face(const CompactMeshView& view, F&& f) {
  for (uint32_t l = 0; l < view.leaf_count; ++l)
    for (uint32_t k = 0; k < view.leaves[l].element_count(); ++k) {
      uint8_t corner[8];
      uint16_t v[8];
      const int n = view.element(view.leaves[l], k, corner, v);
      for (int face = 0; face < shape::face_count(n); ++face) f(l, k, corner, v, n, face);
    }
}

// Every face of every element of `view`: face_neighbour (through the thread's NeighbourCache,
// asked twice: the second answer is the cache's) gives what search_face_neighbour gives; calls
// check(leaf before, leaf after) for each neighbour found.
template <typename Check>
void expect_cached_neighbours_equal_search(const CompactMeshView& view, Check&& check) {
  for_each_element_face(view, [&](uint32_t l, uint32_t k, const uint8_t* corner, const uint16_t* v, int n, int face) {
    uint32_t want_l = l, want_k = k;
    const bool want = view.search_face_neighbour(want_l, want_k, corner, v, n, face);
    for (int ask = 0; ask < 2; ++ask) {
      uint32_t got_l = l, got_k = k;
      ASSERT_EQ(view.face_neighbour(got_l, got_k, corner, v, n, face), want)
          << "leaf " << l << " element " << k << " face " << face << " ask " << ask;
      if (!want) continue;
      ASSERT_EQ(got_l, want_l) << "leaf " << l << " element " << k << " face " << face;
      ASSERT_EQ(got_k, want_k) << "leaf " << l << " element " << k << " face " << face;
    }
    if (want) check(l, want_l);
  });
}

// The neighbour cache answers what the search answers, when filled and when hit, and a thread
// that walks another mesh in between does not read that mesh's entries as this one's (the same
// leaf, element and face keys have other neighbours there).
TEST_P(CompactTest, CachedFaceNeighboursEqualTheSearch) {
  const Encoded e = encode(GetParam(), 20000), other = encode(GetParam() == "tets" ? "mixed" : "tets", 20000);
  const CompactMeshView view = view_of(e.compact), other_view = view_of(other.compact);
  ASSERT_TRUE(view.thread_caches);
  int across = 0;
  for (const CompactMeshView* v : {&view, &other_view, &view})
    expect_cached_neighbours_equal_search(*v, [&](uint32_t from, uint32_t to) { across += from != to ? 1 : 0; });
  EXPECT_GT(across, 1000);  // faces between leaves, the searches the cache saves
}

// Searches with the thread's cached element boxes (LeafBoxCache) find what searches that decode
// every element find, at points in and around the mesh, also when a view of another mesh used the
// thread's cache in between (its leaves' boxes are not this mesh's).
TEST_P(CompactTest, CachedElementBoxesGiveTheUncachedSearch) {
  const Encoded e = encode(GetParam(), 20000), other = encode(GetParam() == "tets" ? "mixed" : "tets", 20000);
  const std::vector<float> local = e.compact.gather(e.values.data());
  const std::vector<float> other_local = other.compact.gather(other.values.data());
  CompactMeshView uncached = view_of(e.compact);
  uncached.thread_caches = false;
  const std::vector<vec3f> points = test::points_around(e.mesh.vertices, 4000, 17);
  const std::vector<vec3f> other_points = test::points_around(other.mesh.vertices, 500, 18);
  int inside = 0;
  for (int round = 0; round < 2; ++round) {
    const CompactMeshView cached = view_of(e.compact), other_view = view_of(other.compact);
    ASSERT_TRUE(cached.thread_caches);
    ASSERT_NE(cached.id, other_view.id);
    for (size_t i = 0; i < points.size(); ++i) {
      const float got = cached.sample(local.data(), points[i]), want = uncached.sample(local.data(), points[i]);
      ASSERT_EQ(std::isnan(got), std::isnan(want)) << "point " << i;
      if (std::isnan(want)) continue;
      ++inside;
      EXPECT_EQ(got, want) << "point " << i;
    }
    for (const vec3f& p : other_points) other_view.sample(other_local.data(), p);  // fills the cache with its leaves
  }
  EXPECT_GT(inside, 2000);
}

// A mesh of several sub-meshes: the neighbour across a face between two is found by the face's
// vertex positions (the shared vertices are replicated with their coordinates), and it is the
// element of the reference mesh across that face.
TEST(Compact, FaceNeighboursAcrossSubMeshesAreFoundByPosition) {
  const Encoded e = encode("tets", 500000);
  const CompactMesh& c = e.compact;
  ASSERT_GE(c.submeshes.size(), 2u);
  CompactMeshView view = view_of(c);
  view.thread_caches = false;
  const auto reference_corners = [&](uint32_t l, uint32_t k) {
    uint8_t corner[8];
    uint16_t v[8];
    const int n = view.element(c.leaves[l], k, corner, v);
    std::vector<uint32_t> out;
    for (int i = 0; i < n; ++i) out.push_back(c.source_vertex[c.submeshes[c.leaves[l].submesh].first_vertex + v[i]]);
    std::sort(out.begin(), out.end());
    return out;
  };
  int across = 0;
  for_each_element_face(view, [&](uint32_t l, uint32_t k, const uint8_t* corner, const uint16_t* v, int n, int face) {
    uint32_t to_l = l, to_k = k;
    if (!view.face_neighbour(to_l, to_k, corner, v, n, face) || c.leaves[to_l].submesh == c.leaves[l].submesh) return;
    ++across;
    // The two tets share exactly the face's three reference vertices.
    const std::vector<uint32_t> a = reference_corners(l, k), b = reference_corners(to_l, to_k);
    std::vector<uint32_t> shared;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(shared));
    ASSERT_EQ(shared.size(), 3u) << "leaf " << l << " element " << k << " face " << face;
  });
  EXPECT_GT(across, 100);
}

// The quantized containment test keeps every child whose decoded box holds the point, at
// points on and near the boxes' corners (where rounding decides).
TEST_P(CompactTest, ChildrenHoldingNeverDropsAChildThatHoldsThePoint) {
  const Encoded e = encode(GetParam(), 20000);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int held = 0;
  for (const CompactNode& node : e.compact.nodes)
    for (int i = 0; i < node.count; ++i) {
      const box3f box = node.child_box(i);
      for (int k = 0; k < 8; ++k) {
        vec3f p = box.lower + box.size() * vec3f(u(rng), u(rng), u(rng));
        if (k < 4) p[k % 3] = k % 2 ? box.upper[k % 3] : box.lower[k % 3];  // on a face
        if (!box.contains(p)) continue;
        ++held;
        EXPECT_TRUE(children_holding(node, p) >> i & 1u) << "child " << i;
      }
    }
  EXPECT_GT(held, 1000);
}

INSTANTIATE_TEST_SUITE_P(Demos, CompactTest, ::testing::Values("tets", "mixed", "holes"));

// A multi-leaf holds two runs of the cluster order where they hold tets alone (64 per leaf but
// the last), else one: other elements (here hexes of 8 vertices each, 64 x 8 > 256) 32 at most.
TEST(Compact, LeavesOfTetsHoldTwoRunsOthersOne) {
  const Encoded e = encode("tets", 20000);
  size_t full = 0;
  for (const CompactLeaf& leaf : e.compact.leaves) full += leaf.element_count() == kMultiLeafSize;
  EXPECT_EQ(full, e.mesh.elements.size() / kMultiLeafSize);

  UMesh hexes;  // 1000 unit cubes apart from each other, 8 vertices of their own each
  for (uint32_t h = 0; h < 1000; ++h) {
    UElement el;
    const vec3f at(float(h % 10) * 2.f, float(h / 10 % 10) * 2.f, float(h / 100) * 2.f);
    for (uint32_t i = 0; i < 8; ++i) {
      el.v[i] = uint32_t(hexes.vertices.size());
      const uint32_t x = (i == 1 || i == 2 || i == 5 || i == 6), y = (i == 2 || i == 3 || i == 6 || i == 7);
      hexes.vertices.push_back(at + vec3f(float(x), float(y), float(i >= 4)));
    }
    hexes.elements.push_back(el);
  }
  hexes.count_by_type[3] = hexes.elements.size();
  const CompactMesh c = build_compact_mesh(hexes);
  uint64_t elements = 0;
  for (const CompactLeaf& leaf : c.leaves) {
    EXPECT_LE(leaf.element_count(), kMultiLeafSize / 2);
    EXPECT_EQ(leaf.table_size(), 8u * leaf.element_count());
    elements += leaf.element_count();
  }
  EXPECT_EQ(elements, hexes.elements.size());
}

TEST(Compact, BytesPerElementOfOneMillionTetsAreMeasured) {
  const Encoded e = encode("tets", 1000000);
  const CompactBytes b = e.compact.bytes_by_part();
  const double n = double(e.mesh.elements.size());
  std::printf(
      "compact, %.0f tets: vertices %.2f, vertex tables %.2f, corners %.2f, leaves %.2f, nodes %.2f, sub-meshes "
      "%.3f, field %.2f = %.2f B/element (%llu sub-meshes, %.1f%% vertices replicated, %.1f%% tets paired)\n",
      n, b.vertices / n, b.tables / n, b.corners / n, b.leaves / n, b.nodes / n, b.submeshes / n, b.field / n,
      b.total() / n, (unsigned long long)e.compact.submeshes.size(),
      100.0 * double(e.compact.replicated) / double(e.mesh.vertices.size()), 100.0 * double(e.compact.paired_tets) / n);
  EXPECT_LT(b.total() / n, 12.0);
}

}  // namespace
}  // namespace vs
