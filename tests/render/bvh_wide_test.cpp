// The CPU's 4-wide BVH (accel/bvh_wide.h) against the binary walk it replaces: the same leaves,
// intervals and order for random rays over disjoint boxes (a refined grid, as ABRs are), after
// refits that cull regions too.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "volstream/accel/bvh_sah.h"
#include "volstream/accel/bvh_wide.h"
#include "volstream/accel/refit.h"

namespace vs {
namespace {

// Disjoint boxes tiling [0, 16)^3: a coarse grid with some cells split into eighths, recursively.
std::vector<box3f> refined_grid(std::mt19937& rng) {
  std::vector<box3f> out;
  std::uniform_real_distribution<float> u(0.f, 1.f);
  auto split = [&](auto&& self, const box3f& b, int depth) -> void {
    if (depth == 0 || u(rng) < 0.3f) {
      out.push_back(b);
      return;
    }
    const vec3f mid = (b.lower + b.upper) * 0.5f;
    for (int k = 0; k < 8; ++k) {
      box3f c;
      for (int a = 0; a < 3; ++a) {
        const bool hi = (k >> a) & 1;
        c.lower[a] = hi ? mid[a] : b.lower[a];
        c.upper[a] = hi ? b.upper[a] : mid[a];
      }
      self(self, c, depth - 1);
    }
  };
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) split(split, {vec3f(x, y, z) * 4.f, vec3f(x + 1, y + 1, z + 1) * 4.f}, 4);
  return out;
}

struct Walked {
  uint32_t item;
  float t0, t1;
};

template <typename Walk>
std::vector<Walked> walk(Walk&& each) {
  std::vector<Walked> out;
  each([&](uint32_t item, float t0, float t1) {
    out.push_back({item, t0, t1});
    return true;
  });
  return out;
}

TEST(Bvh4, WalksTheSameLeavesInTheSameOrderAsTheBinaryTree) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(-4.f, 20.f), dir(-1.f, 1.f), unit(0.f, 1.f);
  size_t max_leaves = 0;
  for (int scene = 0; scene < 4; ++scene) {
    const std::vector<box3f> boxes = refined_grid(rng);
    std::vector<BvhNode> binary = build_bvh_sah(boxes).nodes;
    Bvh4 wide = collapse_to_bvh4(binary);
    for (int refit = 0; refit < 3; ++refit) {
      if (refit > 0) {  // cull a random part of the regions, as a transfer function does
        std::vector<uint8_t> keep(boxes.size());
        for (uint8_t& k : keep) k = unit(rng) < 0.6f;
        refit_bvh(binary, boxes, keep);
        refit_bvh4(wide, binary);
      }
      for (int r = 0; r < 2000; ++r) {
        vec3f org(pos(rng), pos(rng), pos(rng)), d(dir(rng), dir(rng), dir(rng));
        if (r % 4 == 0) d[r / 4 % 3] = 0.f;  // rays in grid planes: many shared faces and edges
        if (r % 8 == 0) org = vec3f(std::floor(org.x), std::floor(org.y), 8.f);
        const auto a =
            walk([&](auto&& visit) { bvh_for_each_leaf(binary.data(), uint32_t(binary.size()), org, d, visit); });
        const auto b = walk(
            [&](auto&& visit) { bvh4_for_each_leaf(wide.nodes.data(), uint32_t(wide.nodes.size()), org, d, visit); });
        ASSERT_EQ(a.size(), b.size()) << "scene " << scene << " refit " << refit << " ray " << r;
        // No leaf twice, also where a zero-length leaf (the ray along an edge) ends a batch.
        std::vector<uint32_t> items;
        for (const Walked& w : a) items.push_back(w.item);
        std::sort(items.begin(), items.end());
        ASSERT_TRUE(std::adjacent_find(items.begin(), items.end()) == items.end()) << "ray " << r;
        max_leaves = std::max(max_leaves, a.size());
        for (size_t i = 0; i < a.size(); ++i)
          ASSERT_TRUE(a[i].item == b[i].item && a[i].t0 == b[i].t0 && a[i].t1 == b[i].t1)
              << "scene " << scene << " refit " << refit << " ray " << r << " leaf " << i;
      }
    }
  }
  EXPECT_GT(max_leaves, size_t(kLeafBatch));  // rays that take more than one batch
}

// A ray through the corners of a grid of unit cells touches two cells at each corner in a
// single point (zero-length leaves) at the entry of the next cell it crosses. Wherever such a
// tie ends a batch, the walk must go on after the longer leaf, not visit it again.
TEST(Bvh4, NoLeafTwiceAlongGridCorners) {
  std::vector<box3f> boxes;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 300; ++x) boxes.push_back({vec3f(float(x), float(y), 0.f), vec3f(x + 1.f, y + 1.f, 1.f)});
  const std::vector<BvhNode> binary = build_bvh_sah(boxes).nodes;
  const Bvh4 wide = collapse_to_bvh4(binary);
  const vec3f org(0.f, 0.f, 0.5f), dir(1.f, 1.f, 0.f);
  for (bool use_wide : {false, true}) {
    std::vector<uint32_t> items;
    float longest = 0.f;
    auto visit = [&](uint32_t item, float t0, float t1) {
      items.push_back(item);
      longest = std::max(longest, t1 - t0);
      return true;
    };
    if (use_wide)
      bvh4_for_each_leaf(wide.nodes.data(), uint32_t(wide.nodes.size()), org, dir, visit);
    else
      bvh_for_each_leaf(binary.data(), uint32_t(binary.size()), org, dir, visit);
    EXPECT_GE(items.size(), 300u) << use_wide;  // every diagonal cell
    std::sort(items.begin(), items.end());
    EXPECT_TRUE(std::adjacent_find(items.begin(), items.end()) == items.end()) << (use_wide ? "wide" : "binary");
    EXPECT_EQ(longest, 1.f);
  }
}

// Every leaf item appears in exactly one lane, whatever the tree's shape (one item, a chain).
TEST(Bvh4, CollapseKeepsEveryLeafOnce) {
  for (size_t count : {1, 2, 3, 5, 64, 1000}) {
    std::vector<box3f> boxes;
    for (size_t i = 0; i < count; ++i) boxes.push_back({vec3f(float(i), 0.f, 0.f), vec3f(float(i) + 1.f, 1.f, 1.f)});
    const Bvh4 wide = collapse_to_bvh4(build_bvh_sah(boxes).nodes);
    std::vector<int> seen(count, 0);
    for (const Bvh4Node& n : wide.nodes)
      for (uint32_t c : n.child)
        if (c != kBvh4None && (c & kBvh4Leaf)) ++seen[c & ~kBvh4Leaf];
    for (size_t i = 0; i < count; ++i) EXPECT_EQ(seen[i], 1) << count << " items, item " << i;
  }
}

}  // namespace
}  // namespace vs
