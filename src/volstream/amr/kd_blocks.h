// Kd-tree decomposition of an AMR hierarchy into disjoint same-level blocks (paper 004, Sect. 4.1).
//
// Every brick is a dense box of same-level leaf cells; covered cells never exist (cells are leaves).
// The kd-tree splits space with axis-aligned planes; a brick crossed by a plane is cut into two
// blocks (a block is a sub-box of a brick: only its box and offset are stored, no values copied).
// Because no plane passes through a block, visiting at each node the child on the eye's side of the
// plane first gives a front-to-back order of the blocks for any viewpoint (no visibility cycles).
// Planes are placed only where they cut no cell in half: at multiples of the crossed blocks' widths.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/amr/model.h"

namespace vs {

struct Block {
  box3i box;       // grid units
  vec3i cell_lo;   // first cell of the block inside its brick (cells)
  uint32_t brick;  // index into the topology's bricks
  int32_t level;
};

// Inner node: axis 0..2, split plane at grid coordinate `split`, children at child and child + 1
// (the lower side first). Leaf: axis = 3, `child` = block index.
struct KdNode {
  int32_t axis;
  int32_t split;
  uint32_t child;
};

struct KdBlocks {
  std::vector<Block> blocks;
  std::vector<KdNode> nodes;  // nodes[0] is the root
  box3i bounds = box3i::make_empty();
};

struct KdView {
  const KdNode* nodes = nullptr;
  const Block* blocks = nullptr;
  box3f bounds;
  uint32_t node_count = 0, block_count = 0;  // not read by kernels: for copies of the arrays
};

KdBlocks build_kd_blocks(const std::vector<Brick>& bricks);
inline KdView make_kd_view(const KdBlocks& kd) {
  return {kd.nodes.data(),
          kd.blocks.data(),
          {vec3f(kd.bounds.lower), vec3f(kd.bounds.upper)},
          uint32_t(kd.nodes.size()),
          uint32_t(kd.blocks.size())};
}

// Ray [t_lo, t_hi] against a box: returns false when it misses. dir components may be zero.
VS_HOST_DEVICE inline bool clip_ray_box(const vec3f& org, const vec3f& inv_dir, const box3f& b, float& t_lo,
                                        float& t_hi) {
  for (int a = 0; a < 3; ++a) {
    float t0 = (b.lower[a] - org[a]) * inv_dir[a], t1 = (b.upper[a] - org[a]) * inv_dir[a];
    if (t0 > t1) {
      const float s = t0;
      t0 = t1;
      t1 = s;
    }
    if (t0 != t0) t0 = -INFINITY;  // 0 * inf: the ray lies in the slab's plane
    if (t1 != t1) t1 = INFINITY;
    t_lo = t0 > t_lo ? t0 : t_lo;
    t_hi = t1 < t_hi ? t1 : t_hi;
  }
  return t_lo < t_hi;
}

// Visits the blocks hit by org + t * dir (grid units) front to back: visit(block, t0, t1) with the
// block's segment; returning false stops the walk. A fixed stack: depth <= kMaxKdDepth.
inline constexpr int kMaxKdDepth = 64;
template <typename Visit>
VS_HOST_DEVICE inline void kd_traverse(const KdView& kd, const vec3f& org, const vec3f& dir, float t_min, float t_max,
                                       Visit&& visit) {
  const vec3f inv{1.f / dir.x, 1.f / dir.y, 1.f / dir.z};
  if (!clip_ray_box(org, inv, kd.bounds, t_min, t_max)) return;
  struct Entry {
    uint32_t node;
    float t0, t1;
  };
  Entry stack[kMaxKdDepth];
  int top = 0;
  Entry e{0, t_min, t_max};
  for (;;) {
    const KdNode n = kd.nodes[e.node];
    if (n.axis == 3) {
      const Block& b = kd.blocks[n.child];
      float t0 = e.t0, t1 = e.t1;
      if (clip_ray_box(org, inv, {vec3f(b.box.lower), vec3f(b.box.upper)}, t0, t1) && !visit(n.child, t0, t1)) return;
      if (top == 0) return;
      e = stack[--top];
      continue;
    }
    const float o = org[n.axis], d = dir[n.axis], c = float(n.split);
    // The near child holds the eye's side of the plane (on the plane: the side the ray goes to).
    const uint32_t near = (o < c || (o == c && d <= 0.f)) ? n.child : n.child + 1;
    const float t_split = (c - o) * inv[n.axis];
    const uint32_t far = 2 * n.child + 1 - near;
    if (d == 0.f || o == c || t_split < 0.f || t_split >= e.t1) {  // never reaches the far side here
      e.node = near;
    } else if (t_split <= e.t0) {  // already past the plane when the segment starts
      e.node = far;
    } else {
      if (top < kMaxKdDepth) stack[top++] = {far, t_split, e.t1};
      e = {near, e.t0, t_split};
    }
  }
}

// The block containing point p (grid units), or -1 outside every block. On a split plane the
// upper side wins, like the half-open cells [lower, lower + width).
VS_HOST_DEVICE inline int64_t kd_locate(const KdView& kd, const vec3f& p) {
  if (!kd.nodes || !kd.bounds.contains(p)) return -1;
  uint32_t node = 0;
  while (kd.nodes[node].axis != 3) {
    const KdNode& n = kd.nodes[node];
    node = p[n.axis] < float(n.split) ? n.child : n.child + 1;
  }
  const Block& b = kd.blocks[kd.nodes[node].child];
  const bool inside = p.x >= float(b.box.lower.x) && p.y >= float(b.box.lower.y) && p.z >= float(b.box.lower.z) &&
                      p.x < float(b.box.upper.x) && p.y < float(b.box.upper.y) && p.z < float(b.box.upper.z);
  return inside ? int64_t(kd.nodes[node].child) : -1;
}

}  // namespace vs
