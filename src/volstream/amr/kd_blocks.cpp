#include "volstream/amr/kd_blocks.h"

#include <algorithm>
#include <cstdlib>

#include "volstream/core/error.h"

namespace vs {
namespace {

box3i bounds_of(const std::vector<Block>& blocks) {
  box3i b = box3i::make_empty();
  for (const Block& k : blocks) b.extend(k.box);
  return b;
}

// A plane at c on `axis` may cut a block only between cells: c a multiple of the block's width.
bool cuts_cells(const Block& b, int axis, int32_t c) {
  return b.box.lower[axis] < c && c < b.box.upper[axis] && (c - b.box.lower[axis]) % level_width(b.level) != 0;
}

struct Plane {
  int axis = -1;
  int32_t c = 0;
  double score = 1e300;
};

// Cost of a plane: blocks it splits (each split adds a block) plus imbalance (tree depth).
// Returns a negative score for planes that would cut a cell.
double plane_score(const std::vector<Block>& blocks, int axis, int32_t c) {
  int64_t left = 0, right = 0, crossed = 0;
  for (const Block& b : blocks) {
    if (cuts_cells(b, axis, c)) return -1;
    if (b.box.upper[axis] <= c)
      ++left;
    else if (b.box.lower[axis] >= c)
      ++right;
    else
      ++crossed;
  }
  return double(crossed) + 0.25 * double(std::llabs(left - right));
}

// Candidates: block faces strictly inside the node, the 16 nearest to the middle on each axis.
// A face of a coarsest block is always valid (all widths divide it), which guarantees progress.
Plane choose_plane(const std::vector<Block>& blocks, const box3i& node) {
  Plane best;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<int32_t> faces;
    for (const Block& b : blocks)
      for (int32_t f : {b.box.lower[axis], b.box.upper[axis]})
        if (node.lower[axis] < f && f < node.upper[axis]) faces.push_back(f);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    const double mid = 0.5 * (double(node.lower[axis]) + node.upper[axis]);
    std::sort(faces.begin(), faces.end(), [&](int32_t a, int32_t b) { return std::abs(a - mid) < std::abs(b - mid); });
    if (faces.size() > 16) faces.resize(16);
    for (int32_t c : faces) {
      const double s = plane_score(blocks, axis, c);
      if (s >= 0 && s < best.score) best = {axis, c, s};
    }
  }
  if (best.axis >= 0) return best;
  int32_t coarsest = 0;  // fallback: any interior face of a coarsest block
  for (const Block& b : blocks) coarsest = std::max(coarsest, b.level);
  for (const Block& b : blocks) {
    if (b.level != coarsest) continue;
    for (int axis = 0; axis < 3; ++axis)
      for (int32_t f : {b.box.lower[axis], b.box.upper[axis]})
        if (node.lower[axis] < f && f < node.upper[axis]) return {axis, f, 0};
  }
  throw std::logic_error("kd blocks: overlapping blocks (no separating plane)");
}

// Splits blocks by the plane; a crossed block becomes two blocks of the same brick.
void partition(std::vector<Block>&& blocks, const Plane& p, std::vector<Block>& lo, std::vector<Block>& hi) {
  for (const Block& b : blocks) {
    if (b.box.upper[p.axis] <= p.c) {
      lo.push_back(b);
    } else if (b.box.lower[p.axis] >= p.c) {
      hi.push_back(b);
    } else {
      Block l = b, h = b;
      l.box.upper[p.axis] = p.c;
      h.box.lower[p.axis] = p.c;
      h.cell_lo[p.axis] += (p.c - b.box.lower[p.axis]) / level_width(b.level);
      lo.push_back(l);
      hi.push_back(h);
    }
  }
}

void build(KdBlocks& out, uint32_t node, std::vector<Block>&& blocks, int depth) {
  if (blocks.size() == 1) {
    out.nodes[node] = {3, 0, uint32_t(out.blocks.size())};
    out.blocks.push_back(blocks[0]);
    return;
  }
  if (depth >= kMaxKdDepth) throw std::runtime_error("kd blocks: tree deeper than the traversal stack");
  const Plane p = choose_plane(blocks, bounds_of(blocks));
  std::vector<Block> lo, hi;
  partition(std::move(blocks), p, lo, hi);
  const uint32_t child = uint32_t(out.nodes.size());
  out.nodes[node] = {p.axis, p.c, child};
  out.nodes.resize(out.nodes.size() + 2);
  build(out, child, std::move(lo), depth + 1);
  build(out, child + 1, std::move(hi), depth + 1);
}

}  // namespace

KdBlocks build_kd_blocks(const std::vector<Brick>& bricks) {
  KdBlocks out;
  std::vector<Block> blocks;
  for (uint32_t i = 0; i < bricks.size(); ++i) blocks.push_back({bricks[i].cell_box(), vec3i(0), i, bricks[i].level});
  if (blocks.empty()) return out;
  out.bounds = bounds_of(blocks);
  out.nodes.resize(1);
  build(out, 0, std::move(blocks), 0);
  return out;
}

}  // namespace vs
