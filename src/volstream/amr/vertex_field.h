// Vertex-centred values per block for trilinear reconstruction (paper 004, Sect. 4.1): each block
// gets (dims + 1)^3 vertex samples, so neighbouring blocks share their boundary samples (both
// compute the same value at a common vertex) and the interpolant is continuous across blocks.
//  - A vertex's value is the mean of the leaf cells around it (the 8 cells touching it; fewer at
//    the domain's boundary).
//  - Dangling nodes: a vertex of a fine block that touches a coarser cell (on a coarse-fine face,
//    edge or corner) takes the coarse block's interpolated value at that point, so the fine side
//    matches the coarse side exactly. Levels are processed coarse to fine for this.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/amr/kd_blocks.h"

namespace vs {

struct VertexField {
  std::vector<uint64_t> offsets;  // per block: first vertex (x fastest over dims + 1)
  std::vector<float> values;
};

VertexField build_vertex_field(const KdBlocks& kd, const std::vector<Brick>& bricks, const float* cell_values);

// Trilinear interpolation of a block's vertex values at p (grid units, inside the block).
VS_HOST_DEVICE inline float sample_vertices(const float* vertex_values, uint64_t offset, const Block& b,
                                            const vec3f& p) {
  const float inv_w = 1.f / float(level_width(b.level));
  int32_t n[3], i0[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    n[a] = (b.box.upper[a] - b.box.lower[a]) / level_width(b.level);  // cells; vertices n + 1
    float u = (p[a] - float(b.box.lower[a])) * inv_w;
    u = u > 0.f ? (u < float(n[a]) ? u : float(n[a])) : 0.f;
    i0[a] = int32_t(u) < n[a] ? int32_t(u) : n[a] - 1;
    f[a] = u - float(i0[a]);
  }
  const uint64_t sx = 1, sy = uint64_t(n[0] + 1), sz = sy * uint64_t(n[1] + 1);
  const float* v = vertex_values + offset + uint64_t(i0[0]) * sx + uint64_t(i0[1]) * sy + uint64_t(i0[2]) * sz;
  const float x00 = v[0] + (v[sx] - v[0]) * f[0];
  const float x10 = v[sy] + (v[sy + sx] - v[sy]) * f[0];
  const float x01 = v[sz] + (v[sz + sx] - v[sz]) * f[0];
  const float x11 = v[sz + sy] + (v[sz + sy + sx] - v[sz + sy]) * f[0];
  const float y0 = x00 + (x10 - x00) * f[1], y1 = x01 + (x11 - x01) * f[1];
  return y0 + (y1 - y0) * f[2];
}

}  // namespace vs
