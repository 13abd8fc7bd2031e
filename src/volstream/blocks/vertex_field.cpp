#include "volstream/blocks/vertex_field.h"

#include <algorithm>
#include <numeric>

#include "volstream/core/parallel.h"

namespace vs {
namespace {

struct Located {
  int64_t block = -1;
  float value = 0.f;
};

// The leaf cell containing p: its block and value.
Located locate_cell(const KdView& kd, const std::vector<Brick>& bricks, const float* cells, const vec3f& p) {
  Located r;
  r.block = kd_locate(kd, p);
  if (r.block < 0) return r;
  const Brick& br = bricks[kd.blocks[r.block].brick];
  const float inv_w = 1.f / float(br.width());
  int32_t c[3];
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(int32_t(std::floor((p[a] - float(br.lower[a])) * inv_w)), 0, br.dims[a] - 1);
  r.value = cells[br.value_offset + (uint64_t(c[2]) * br.dims.y + c[1]) * br.dims.x + c[0]];
  return r;
}

// Value of vertex g (grid units) of a block of level `level`: probe the 8 cells around it, half a
// finest cell away. A coarser neighbour makes it a dangling (or coincident) node: take that
// block's interpolated vertex value, which is final because coarser levels come first.
float vertex_value(const KdView& kd, const std::vector<Brick>& bricks, const float* cells, const VertexField& vf,
                   const vec3i& g, int32_t level) {
  float sum = 0.f;
  int count = 0;
  int64_t coarse = -1;
  int32_t coarse_level = level;
  for (int k = 0; k < 8; ++k) {
    const vec3f p = vec3f(g) + vec3f(k & 1 ? 0.5f : -0.5f, k & 2 ? 0.5f : -0.5f, k & 4 ? 0.5f : -0.5f);
    const Located c = locate_cell(kd, bricks, cells, p);
    if (c.block < 0) continue;
    const int32_t l = kd.blocks[c.block].level;
    if (l > coarse_level) {
      coarse_level = l;
      coarse = c.block;
    }
    sum += c.value;
    ++count;
  }
  if (coarse >= 0) return sample_vertices(vf.values.data(), vf.offsets[size_t(coarse)], kd.blocks[coarse], vec3f(g));
  return count > 0 ? sum / float(count) : 0.f;
}

// A vertex strictly inside a block: its 8 cells are the block's own (no point location needed).
// v is the vertex index in the brick's vertex lattice (cell c has vertices c .. c + 1).
float interior_vertex(const Brick& br, const float* cells, const vec3i& v) {
  float sum = 0.f;
  for (int k = 0; k < 8; ++k) {
    const int32_t x = v.x - 1 + (k & 1), y = v.y - 1 + (k >> 1 & 1), z = v.z - 1 + (k >> 2 & 1);
    sum += cells[br.value_offset + (uint64_t(z) * br.dims.y + y) * br.dims.x + x];
  }
  return 0.125f * sum;
}

}  // namespace

VertexField build_vertex_field(const KdBlocks& kd, const std::vector<Brick>& bricks, const float* cell_values) {
  VertexField vf;
  const KdView view = make_kd_view(kd);
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
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return kd.blocks[a].level > kd.blocks[b].level; });
  for (size_t first = 0; first < order.size();) {
    size_t last = first;
    while (last < order.size() && kd.blocks[order[last]].level == kd.blocks[order[first]].level) ++last;
    parallel_for("vertex_field", int64_t(last - first), [&](int64_t j) {
      const uint32_t i = order[first + size_t(j)];
      const Block& b = kd.blocks[i];
      const int32_t w = level_width(b.level);
      const vec3i n = (b.box.upper - b.box.lower) / w + vec3i(1);
      float* out = vf.values.data() + vf.offsets[i];
      for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
          for (int x = 0; x < n.x; ++x) {
            const bool interior = x > 0 && y > 0 && z > 0 && x + 1 < n.x && y + 1 < n.y && z + 1 < n.z;
            *out++ = interior ? interior_vertex(bricks[b.brick], cell_values, b.cell_lo + vec3i(x, y, z))
                              : vertex_value(view, bricks, cell_values, vf, b.box.lower + vec3i(x, y, z) * w, b.level);
          }
    });
    first = last;
  }
  return vf;
}

}  // namespace vs
