// The CPU's 4-wide form of a binary BVH (bvh.h), for the front-to-back walk only.
//
// On jet 1e6 (486k small ABRs) a quarter of a render is BVH traversal: about 48 box tests per
// ray, each a few data-dependent branches. Collapsing two binary levels into one node of four
// children lets one SIMD test (4 lanes) replace three node visits. The wide tree is made once
// from the binary tree's topology; after each refit (accel/refit.h) its boxes are copied from the
// refit binary nodes, so culled regions stay empty (inverted boxes) exactly as there.
//
// bvh4_next_leaves gives the same leaves with the same intervals, in the same order, as
// bvh_next_leaves on the binary tree (the same float operations per box; tests/render/
// bvh_wide_test.cpp), so images do not change. The GPU keeps the binary walk.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/accel/bvh_traverse.h"
#if !defined(__CUDACC__)
#include "volstream/core/simd.h"
#endif

namespace vs {

struct alignas(16) Bvh4Node {
  float lower[3][4], upper[3][4];  // per axis, per child lane; unused lanes hold an empty box
  uint32_t child[4];               // kBvh4Leaf | item, a wide node index, or kBvh4None
};
inline constexpr uint32_t kBvh4Leaf = 0x80000000u;
inline constexpr uint32_t kBvh4None = 0xffffffffu;

struct Bvh4 {
  std::vector<Bvh4Node> nodes;  // nodes[0] is the root (when not empty)
  // Per node and lane (4 * node + lane): the binary node whose box the lane holds, or kBvh4None.
  std::vector<uint32_t> source;
};

// The wide tree over a binary tree with the layout build_bvh_sah gives (children adjacent), with
// the binary nodes' current boxes. Each wide node takes up to four descendants of a binary
// node, opening the inner candidate with the largest box surface first.
Bvh4 collapse_to_bvh4(const std::vector<BvhNode>& binary);

// Copies the boxes of `binary` (the same topology, refit) into the wide tree's lanes.
void refit_bvh4(Bvh4& wide, const std::vector<BvhNode>& binary);

#if !defined(__CUDACC__)  // GCC vector extensions: host compilers only (CUDA files walk the binary tree)
// As bvh_next_leaves (bvh_traverse.h): the (up to) K leaves with the smallest entries among those
// the ray leaves after t_min, nearest first; returns how many.
template <int K>
inline int bvh4_next_leaves(const Bvh4Node* nodes, uint32_t node_count, const SlabRay& ray, float t_min, float t_max,
                            LeafHit (&hits)[K]) {
  using simd::f4, simd::i4;
  if (node_count == 0) return 0;
  int found = 0;
  auto bound = [&] { return found < K ? INFINITY : hits[K - 1].t0; };
  auto insert = [&](uint32_t item, float a, float b) {  // insertion sort by entry
    int k = found < K ? found++ : K - 1;
    for (; k > 0 && hits[k - 1].t0 > a; --k) hits[k] = hits[k - 1];
    hits[k] = {item, a, b};
  };
  // Per axis: which of lower/upper is the near slab (the sign of the direction, as ray_box).
  int near_is_upper[3];
  f4 org[3], inv[3];
  for (int a = 0; a < 3; ++a) {
    near_is_upper[a] = ray.inv_dir[a] < 0.f;
    org[a] = f4{} + ray.org[a];
    inv[a] = f4{} + ray.inv_dir[a];
  }
  struct Entry {
    uint32_t node;
    float t;
  };
  Entry stack[4 * 64];  // a wide level is at least one binary level (at most 60): 3 pushes each
  int top = 0;
  stack[top++] = {0, -INFINITY};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t >= bound()) continue;
    const Bvh4Node& n = nodes[e.node];
    // ray_box for four boxes: the same operations in the same order per lane.
    f4 t0 = f4{} - INFINITY, t1 = f4{} + INFINITY;
    for (int a = 0; a < 3; ++a) {
      f4 lo, hi;
      __builtin_memcpy(&lo, n.lower[a], sizeof lo);
      __builtin_memcpy(&hi, n.upper[a], sizeof hi);
      const f4 tn = ((near_is_upper[a] ? hi : lo) - org[a]) * inv[a];
      const f4 tf = ((near_is_upper[a] ? lo : hi) - org[a]) * inv[a];
      t0 = tn > t0 ? tn : t0;
      t1 = tf < t1 ? tf : t1;
    }
    const f4 a = t0 > t_min ? t0 : f4{} + t_min;
    const f4 b = t1 < t_max ? t1 : f4{} + t_max;
    const i4 hit = (a <= b) & (b > t_min);
    Entry inner[4];
    int inner_count = 0;
    for (int lane = 0; lane < 4; ++lane) {
      if (!hit[lane] || !(a[lane] < bound())) continue;
      const uint32_t c = n.child[lane];
      if (c & kBvh4Leaf)
        insert(c & ~kBvh4Leaf, a[lane], b[lane]);
      else
        inner[inner_count++] = {c, a[lane]};
    }
    // Far first, so that the nearest pops next; children the new leaves put beyond the bound
    // are dropped when popped.
    for (int i = 1; i < inner_count; ++i)
      for (int j = i; j > 0 && inner[j - 1].t < inner[j].t; --j) {
        const Entry s = inner[j];
        inner[j] = inner[j - 1];
        inner[j - 1] = s;
      }
    for (int i = 0; i < inner_count; ++i) stack[top++] = inner[i];
  }
  return found;
}

// bvh_for_each_leaf over the wide tree.
template <typename Visit>
inline void bvh4_for_each_leaf(const Bvh4Node* nodes, uint32_t node_count, const vec3f& org, const vec3f& dir,
                               Visit&& visit) {
  const SlabRay slab(org, dir);
  for_each_leaf_in_batches<kLeafBatch>(
      [&](float t, LeafHit(&hits)[kLeafBatch]) {
        return bvh4_next_leaves<kLeafBatch>(nodes, node_count, slab, t, INFINITY, hits);
      },
      visit);
}

#endif

// The front-to-back walk of a volume's regions: the wide tree on the CPU when the view has one
// (wide == nullptr on the GPU), else the binary tree.
template <typename Visit>
VS_HOST_DEVICE inline void for_each_region_leaf(const BvhNode* nodes, uint32_t node_count, const Bvh4Node* wide,
                                                uint32_t wide_count, const vec3f& org, const vec3f& dir,
                                                Visit&& visit) {
#if !defined(__CUDACC__)
  if (wide) {
    bvh4_for_each_leaf(wide, wide_count, org, dir, visit);
    return;
  }
#else
  (void)wide;
  (void)wide_count;
#endif
  bvh_for_each_leaf(nodes, node_count, org, dir, visit);
}

}  // namespace vs
