// corners_box (element_box) on the host's lanes against box3f::extend, corner by corner: the
// same floats, signed zeros included, for every corner count of an element; box_contains against
// box3f::contains.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "volstream/umesh/umesh.h"

namespace vs {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(UMesh, ElementBoxIsTheBoxExtendedCornerByCorner) {
  std::mt19937 rng(5);
  const float pool[] = {0.f, -0.f, 1.f, -1.f, 1e-30f, -1e30f, 3.5f, 2.25f};
  std::uniform_int_distribution<int> pick(0, 7);
  std::uniform_real_distribution<float> any(-10.f, 10.f);
  std::vector<vec3f> vertices(64);
  for (int round = 0; round < 200; ++round) {
    // Half the coordinates from a small pool (ties and signed zeros), half at random.
    for (vec3f& v : vertices)
      for (int a = 0; a < 3; ++a) v[a] = (rng() & 1) ? pool[pick(rng)] : any(rng);
    for (const int n : {4, 5, 6, 8}) {
      UElement e;
      for (int k = 0; k < 8; ++k) e.v[k] = k < n ? uint32_t(rng() % vertices.size()) : kNoVertex;
      box3f want = box3f::make_empty();
      for (int k = 0; k < n; ++k) want.extend(vertices[e.v[k]]);
      const box3f got = element_box(vertices.data(), e);
      for (int a = 0; a < 3; ++a) {
        ASSERT_TRUE(same_bits(got.lower[a], want.lower[a])) << round << " " << n << " axis " << a;
        ASSERT_TRUE(same_bits(got.upper[a], want.upper[a])) << round << " " << n << " axis " << a;
      }
    }
  }
}

// box_contains on lanes against box3f::contains: boxes whose corners share coordinates (ties on
// every face), cross each other, or hold NaN.
TEST(UMesh, BoxContainsOnLanesIsBoxContains) {
  std::mt19937 rng(9);
  const float pool[] = {0.f, -0.f, 1.f, 2.f, 3.f, NAN};
  std::uniform_int_distribution<int> pick(0, 5);
  auto corner = [&] { return vec3f(pool[pick(rng)], pool[pick(rng)], pool[pick(rng)]); };
  for (int i = 0; i < 20000; ++i) {
    const box3f outer{corner(), corner()};
    const vec3f a = corner(), b = corner();
    const vec3f corners[2] = {a, b};
    const BoxLanes inner = corners_box_lanes(2, [&](int k) -> const vec3f& { return corners[k]; });
    box3f plain = box3f::make_empty();
    plain.extend(a), plain.extend(b);
    ASSERT_EQ(box_contains(outer, inner), outer.contains(plain)) << i;
  }
}

}  // namespace
}  // namespace vs
