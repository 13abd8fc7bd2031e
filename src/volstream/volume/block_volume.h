// AMR through paper 004's same-level blocks (amr/kd_blocks.h): the regions are the kd-tree's
// blocks, visited front to back by its planes, and fields are reconstructed per block: nearest
// (the value of the cell containing the point) or trilinear over vertex values shared with the
// neighbouring blocks (amr/vertex_field.h, dangling nodes fixed up). Without vertex values,
// trilinear falls back to interpolating between the cell centres of the block's brick, clamped at
// the brick's faces (seams between bricks).
#pragma once
#include <cmath>
#include <cstdint>

#include "volstream/amr/kd_blocks.h"
#include "volstream/amr/model.h"
#include "volstream/amr/vertex_field.h"
#include "volstream/volume/volume.h"

namespace vs {

enum class Reconstruction : uint32_t { nearest = 0, trilinear = 1 };

namespace blocks {

VS_HOST_DEVICE inline int32_t clampi(int32_t v, int32_t lo, int32_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

VS_HOST_DEVICE inline float cell_value(const float* values, const Brick& br, int32_t x, int32_t y, int32_t z) {
  return values[br.value_offset + (uint64_t(z) * uint64_t(br.dims.y) + uint64_t(y)) * uint64_t(br.dims.x) +
                uint64_t(x)];
}

// Value of the block's cell containing p (grid units); clamped to the block against rounding.
VS_HOST_DEVICE inline float sample_nearest(const float* values, const Brick& br, const Block& b, const vec3f& p) {
  const float inv_w = 1.f / float(br.width());
  int32_t c[3];
  for (int a = 0; a < 3; ++a) {
    const int32_t hi = (b.box.upper[a] - br.lower[a]) / br.width() - 1;
    c[a] = clampi(int32_t(floorf((p[a] - float(br.lower[a])) * inv_w)), b.cell_lo[a], hi);
  }
  return cell_value(values, br, c[0], c[1], c[2]);
}

// Trilinear between the cell centres of the brick (across the kd planes that cut it), clamped
// to the outermost centres at the brick's faces.
VS_HOST_DEVICE inline float sample_trilinear(const float* values, const Brick& br, const vec3f& p) {
  const float inv_w = 1.f / float(br.width());
  int32_t i0[3], i1[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    const float n = float(br.dims[a] - 1);
    float u = (p[a] - float(br.lower[a])) * inv_w - 0.5f;
    u = u > 0.f ? (u < n ? u : n) : 0.f;
    i0[a] = clampi(int32_t(u), 0, br.dims[a] - 1);
    i1[a] = i0[a] + 1 < br.dims[a] ? i0[a] + 1 : i0[a];
    f[a] = u - float(i0[a]);
  }
  auto at = [&](int dx, int dy, int dz) {
    return cell_value(values, br, dx ? i1[0] : i0[0], dy ? i1[1] : i0[1], dz ? i1[2] : i0[2]);
  };
  const float x00 = at(0, 0, 0) + (at(1, 0, 0) - at(0, 0, 0)) * f[0];
  const float x10 = at(0, 1, 0) + (at(1, 1, 0) - at(0, 1, 0)) * f[0];
  const float x01 = at(0, 0, 1) + (at(1, 0, 1) - at(0, 0, 1)) * f[0];
  const float x11 = at(0, 1, 1) + (at(1, 1, 1) - at(0, 1, 1)) * f[0];
  const float y0 = x00 + (x10 - x00) * f[1], y1 = x01 + (x11 - x01) * f[1];
  return y0 + (y1 - y0) * f[2];
}

}  // namespace blocks

struct BlockVolume {
  KdView kd;
  const Brick* bricks = nullptr;
  const float* fields[kVolumeFields] = {};   // cell values, device order
  const uint64_t* vertex_offsets = nullptr;  // per block (vertex_field.h); null: no vertex values
  const float* vertex_fields[kVolumeFields] = {};
  Reconstruction reconstruction = Reconstruction::trilinear;

  VS_HOST_DEVICE float sample(int field, uint32_t block, const vec3f& p) const {
    const Block& b = kd.blocks[block];
    const Brick& br = bricks[b.brick];
    if (reconstruction == Reconstruction::nearest) return blocks::sample_nearest(fields[field], br, b, p);
    if (vertex_offsets && vertex_fields[field])
      return sample_vertices(vertex_fields[field], vertex_offsets[block], b, p);
    return blocks::sample_trilinear(fields[field], br, p);
  }
  VS_HOST_DEVICE int64_t locate(const vec3f& p) const { return kd_locate(kd, p); }
  VS_HOST_DEVICE float sample_near(int field, uint32_t block, const vec3f& p) const {
    const box3i& b = kd.blocks[block].box;
    if (box3f{vec3f(b.lower), vec3f(b.upper)}.contains(p)) return sample(field, block, p);
    const int64_t other = locate(p);
    return other < 0 ? NAN : sample(field, uint32_t(other), p);
  }
  VS_HOST_DEVICE float step_width(uint32_t block) const { return float(level_width(kd.blocks[block].level)); }

  template <typename Visit>
  VS_HOST_DEVICE void for_each_interval(const vec3f& org, const vec3f& dir, Visit&& visit) const {
    kd_traverse(kd, org, dir, 0.f, INFINITY, [&](uint32_t block, float t0, float t1) {
      return visit(RayInterval{block, t0, t1});
    });
  }
};
static_assert(Volume<BlockVolume>);

}  // namespace vs
