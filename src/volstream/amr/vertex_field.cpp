#include "volstream/amr/vertex_field.h"

#include <algorithm>
#include <mutex>
#include <numeric>
#include <utility>

#include "volstream/backend/parallel.h"

namespace vs {
namespace {

// Blocks whose boxes overlap the open box q: down the kd-tree into the children on q's side of
// each plane (a child holds only blocks on its side of the plane, so none is missed).
void blocks_overlapping(const KdBlocks& kd, const box3i& q, std::vector<uint32_t>& out) {
  out.clear();
  uint32_t stack[kMaxKdDepth + 2];  // a walk pushes at most one more entry per level
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const KdNode& n = kd.nodes[stack[--top]];
    if (n.axis == 3) {
      if (kd.blocks[n.child].box.overlaps_open(q)) out.push_back(n.child);
      continue;
    }
    if (q.lower[n.axis] < n.split) stack[top++] = n.child;
    if (q.upper[n.axis] > n.split) stack[top++] = n.child + 1;
  }
}

// Probe k of vertex v of a block (lower corner lo, cell width w) is the point half a finest cell
// from the vertex, p = lo + v w + s (s = -1/2 or +1/2 per bit of k); in doubled coordinates,
// 2p = 2 (lo + v w) + 2s, all integers (2s = -1 or +1).
int32_t probe_offset(int k, int axis) { return (k >> axis & 1) ? 1 : -1; }

// table[8 v + k]: the block other than `self` containing probe k of vertex v, -1 for none (in
// `self` or outside the domain). Filled block by block from the candidates instead of located
// probe by probe (that point location was nearly all of the time): probe k is in block N when
// 2 N.lower <= 2p < 2 N.upper, an interval of v per axis and probe side. 2 N.lower - 2 (lo + s)
// is odd, never a multiple of 2w, so the interval ends are floor divisions by 2w (shifts).
void fill_probe_table(const KdBlocks& kd, uint32_t self, const std::vector<uint32_t>& candidates,
                      std::vector<int32_t>& table) {
  const Block& b = kd.blocks[self];
  const int32_t shift = b.level + 1;                                              // 2w = 1 << shift
  const vec3i n = (b.box.upper - b.box.lower) / level_width(b.level) + vec3i(1);  // vertices per axis
  table.assign(size_t(n.x) * n.y * n.z * 8, -1);
  for (uint32_t c : candidates) {
    if (c == self) continue;
    const box3i& nb = kd.blocks[c].box;
    int32_t v0[3][2], v1[3][2];  // inclusive vertex range per axis and probe side (-1/2, +1/2)
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        const int32_t lo = 2 * b.box.lower[a] + (side ? 1 : -1);
        v0[a][side] = std::max(((2 * nb.lower[a] - lo) >> shift) + 1, 0);
        v1[a][side] = std::min((2 * nb.upper[a] - lo) >> shift, n[a] - 1);
      }
    for (int k = 0; k < 8; ++k) {
      const int sx = k & 1, sy = k >> 1 & 1, sz = k >> 2 & 1;
      for (int32_t z = v0[2][sz]; z <= v1[2][sz]; ++z)
        for (int32_t y = v0[1][sy]; y <= v1[1][sy]; ++y)
          for (int32_t x = v0[0][sx]; x <= v1[0][sx]; ++x)
            table[((size_t(z) * n.y + y) * n.x + x) * 8 + size_t(k)] = int32_t(c);
    }
  }
}

// Value of the cell of `block` containing probe k of vertex g (grid units): the cell index
// floor((p - lower) / width) per axis, clamped to the brick, in integers (doubled coordinates,
// the width a power of two).
float probe_value(const KdBlocks& kd, const std::vector<Brick>& bricks, const float* cells, uint32_t block,
                  const vec3i& g, int k) {
  const Brick& br = bricks[kd.blocks[block].brick];
  int32_t c[3];
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp((2 * (g[a] - br.lower[a]) + probe_offset(k, a)) >> (br.level + 1), 0, br.dims[a] - 1);
  return cells[br.value_offset + (uint64_t(c[2]) * br.dims.y + c[1]) * br.dims.x + c[0]];
}

// Value of vertex v (index in the block's vertex lattice, n per axis) of block `self`: the mean
// of the 8 cells around it, in self or in the blocks of its probe-table row. A coarser neighbour
// makes it a dangling (or coincident) node: take that block's interpolated vertex value, which is
// final because coarser levels come first.
float vertex_value(const KdBlocks& kd, const std::vector<Brick>& bricks, const float* cells, const VertexField& vf,
                   uint32_t self, const vec3i& v, const vec3i& n, const int32_t* row) {
  const Block& b = kd.blocks[self];
  const vec3i g = b.box.lower + v * level_width(b.level);
  float sum = 0.f;
  int count = 0;
  int64_t coarse = -1;
  int32_t coarse_level = b.level;
  for (int k = 0; k < 8; ++k) {
    bool inside = true;  // the probe is in self unless it leaves the box at a boundary vertex
    for (int a = 0; a < 3; ++a) inside = inside && (probe_offset(k, a) < 0 ? v[a] > 0 : v[a] + 1 < n[a]);
    const int32_t block = inside ? int32_t(self) : row[k];
    if (block < 0) continue;
    const int32_t l = kd.blocks[block].level;
    if (l > coarse_level) {
      coarse_level = l;
      coarse = block;
    }
    sum += probe_value(kd, bricks, cells, uint32_t(block), g, k);
    ++count;
  }
  if (coarse >= 0) return sample_vertices(vf.values.data(), vf.offsets[size_t(coarse)], kd.blocks[coarse], vec3f(g));
  return count > 0 ? sum / float(count) : 0.f;
}

// A vertex strictly inside a block: its 8 cells are the block's own (no probes needed); the same
// sum in the same order as vertex_value, so the same float wherever a vertex is computed.
// v is the vertex index in the brick's vertex lattice (cell c has vertices c .. c + 1).
float interior_vertex(const Brick& br, const float* cells, const vec3i& v) {
  float sum = 0.f;
  for (int k = 0; k < 8; ++k) {
    const int32_t x = v.x - 1 + (k & 1), y = v.y - 1 + (k >> 1 & 1), z = v.z - 1 + (k >> 2 & 1);
    sum += cells[br.value_offset + (uint64_t(z) * br.dims.y + y) * br.dims.x + x];
  }
  return 0.125f * sum;
}

// Scratch of one task, reused from block to block.
struct Scratch {
  std::vector<uint32_t> candidates;
  std::vector<int32_t> probes;
  std::vector<std::pair<uint64_t, uint64_t>> copies;  // (destination, source) in vf.values
};

// The vertex values of block i. A vertex's value depends only on its position and level, and
// most boundary vertices are shared by several blocks: the block holding the cell above the
// vertex (its probe 7, at g + 1/2) computes it when it has the same level (g is then on its
// lattice); the others record a copy, made once the whole level is done.
void block_vertices(const KdBlocks& kd, const std::vector<Brick>& bricks, const float* cells, VertexField& vf,
                    uint32_t i, Scratch& s) {
  const Block& b = kd.blocks[i];
  const int32_t w = level_width(b.level);
  const vec3i n = (b.box.upper - b.box.lower) / w + vec3i(1);
  blocks_overlapping(kd, {b.box.lower - vec3i(1), b.box.upper + vec3i(1)}, s.candidates);
  fill_probe_table(kd, i, s.candidates, s.probes);
  uint64_t out = vf.offsets[i];
  const int32_t* row = s.probes.data();
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x, row += 8, ++out) {
        if (x > 0 && y > 0 && z > 0 && x + 1 < n.x && y + 1 < n.y && z + 1 < n.z) {
          vf.values[out] = interior_vertex(bricks[b.brick], cells, b.cell_lo + vec3i(x, y, z));
          continue;
        }
        const int32_t owner = x + 1 < n.x && y + 1 < n.y && z + 1 < n.z ? int32_t(i) : row[7];
        if (owner >= 0 && owner != int32_t(i) && kd.blocks[owner].level == b.level) {
          const Block& o = kd.blocks[owner];
          const vec3i d = b.box.lower + vec3i(x, y, z) * w - o.box.lower;
          if (d.x % w == 0 && d.y % w == 0 && d.z % w == 0) {  // on o's lattice (always, for aligned levels)
            const vec3i on = (o.box.upper - o.box.lower) / w + vec3i(1), ov = d / w;
            s.copies.push_back({out, vf.offsets[owner] + (uint64_t(ov.z) * on.y + ov.y) * on.x + ov.x});
            continue;
          }
        }
        vf.values[out] = vertex_value(kd, bricks, cells, vf, i, vec3i(x, y, z), n, row);
      }
}

}  // namespace

VertexField build_vertex_field(const KdBlocks& kd, const std::vector<Brick>& bricks, const float* cell_values) {
  VertexField vf;
  vf.offsets.resize(kd.blocks.size());
  uint64_t total = 0;
  for (size_t i = 0; i < kd.blocks.size(); ++i) {
    const Block& b = kd.blocks[i];
    const vec3i n = (b.box.upper - b.box.lower) / level_width(b.level) + vec3i(1);
    vf.offsets[i] = total;
    total += uint64_t(n.x) * n.y * n.z;
  }
  vf.values.assign(total, 0.f);
  // Coarse levels first: dangling nodes read the finished values of coarser blocks.
  std::vector<uint32_t> order(kd.blocks.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return kd.blocks[a].level > kd.blocks[b].level; });
  for (size_t first = 0; first < order.size();) {
    size_t last = first;
    while (last < order.size() && kd.blocks[order[last]].level == kd.blocks[order[first]].level) ++last;
    std::vector<std::pair<uint64_t, uint64_t>> copies;
    std::mutex copies_mutex;
    parallel_for_ranges(int64_t(last - first), [&](int64_t j0, int64_t j1) {
      Scratch s;
      for (int64_t j = j0; j < j1; ++j) block_vertices(kd, bricks, cell_values, vf, order[first + size_t(j)], s);
      const std::lock_guard<std::mutex> lock(copies_mutex);
      copies.insert(copies.end(), s.copies.begin(), s.copies.end());
    });
    for (const auto& [to, from] : copies) vf.values[to] = vf.values[from];
    first = last;
  }
  return vf;
}

}  // namespace vs
