// Tent-basis reconstruction (DESIGN.md): each cell c with centre x_c and width w_c has weight
// prod_i max(0, 1 - |p_i - x_c,i| / w_c); f(p) = sum w_c v_c / sum w_c, undefined (NaN) where the
// weights sum to zero. All positions are in grid units.
#pragma once
#include <cmath>
#include <cstdint>

#include "volstream/amr/model.h"

namespace vs {

// Accumulated weight and weighted value of a set of cells at one point.
struct TentSum {
  float weight = 0.f;
  float weighted_value = 0.f;
  VS_HOST_DEVICE float value() const { return weight > 0.f ? weighted_value / weight : NAN; }
};

VS_HOST_DEVICE inline float tent_weight_1d(float p, float centre, float inv_width) {
  const float t = 1.f - fabsf(p - centre) * inv_width;
  return t > 0.f ? t : 0.f;
}

// Adds the contribution of one brick's cells to `sum`: only the up to 2x2x2 cells around p.
VS_HOST_DEVICE inline void accumulate_brick(const Brick& b, const float* values, const vec3f& p, TentSum& sum) {
  const float w = float(b.width());
  const float inv_w = 1.f / w;
  // Position in cell-centre coordinates of the brick: cell i has its centre at i.
  const vec3f q = (p - vec3f(b.lower)) * inv_w - vec3f(0.5f);
  const int ix = int(floorf(q.x)), iy = int(floorf(q.y)), iz = int(floorf(q.z));
  for (int dz = 0; dz < 2; ++dz) {
    const int z = iz + dz;
    if (z < 0 || z >= b.dims.z) continue;
    const float wz = tent_weight_1d(q.z, float(z), 1.f);
    if (wz <= 0.f) continue;
    for (int dy = 0; dy < 2; ++dy) {
      const int y = iy + dy;
      if (y < 0 || y >= b.dims.y) continue;
      const float wy = tent_weight_1d(q.y, float(y), 1.f);
      if (wy <= 0.f) continue;
      for (int dx = 0; dx < 2; ++dx) {
        const int x = ix + dx;
        if (x < 0 || x >= b.dims.x) continue;
        const float wx = tent_weight_1d(q.x, float(x), 1.f);
        if (wx <= 0.f) continue;
        const float wgt = wx * wy * wz;
        const uint64_t idx = b.value_offset + (uint64_t(z) * b.dims.y + y) * b.dims.x + x;
        sum.weight += wgt;
        sum.weighted_value += wgt * values[idx];
      }
    }
  }
}

// Reconstructs the field at p (grid units) inside ABR `abr` from the ABR's bricks only.
VS_HOST_DEVICE inline float sample_abr(const AmrView& v, uint32_t abr, const vec3f& p) {
  const Abr& a = v.abrs[abr];
  TentSum sum;
  for (uint32_t i = 0; i < a.brick_count; ++i)
    accumulate_brick(v.bricks[v.abr_bricks[a.first_brick + i]], v.values, p, sum);
  return sum.value();
}

// The reference: the same sum over every cell, with no bricks or ABRs involved (double precision).
double sample_brute_force(const Cell* cells, const float* values, uint64_t n, const vec3d& p);

}  // namespace vs
