// Tight per-ABR value ranges (the "ranges" stage): the min/max over only those cells that can
// have weight inside the ABR, instead of over its bricks' whole ranges.
//
// Why: bricks are large and span wide value ranges, so ranges taken per brick mark nearly every
// ABR visible for a selective transfer function (jet demo: 94% of ABRs), and rays then march
// air. A cell c (centre x_c, width w) has weight at p only if |p - x_c| < w on every axis, so the
// sampler's value anywhere in ABR box B is a convex combination of the cells whose centres lie
// in B grown by w: their range bounds it (jet demo: 17% of ABRs visible, 3x fewer samples).
#pragma once
#include <cmath>
#include <vector>

#include "volstream/amr/model.h"

namespace vs {

// Range of the cells of brick b whose centres lie within `box` grown by one cell width
// (inclusive, so rounding can only widen it). NaN values are ignored.
VS_HOST_DEVICE inline void brick_range_near(const Brick& b, const float* values, const box3f& box, Range& r) {
  const float w = float(b.width()), inv_w = 1.f / w;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    // Cell i's centre is lower + (i + 0.5) w; keep box.lower - w <= centre <= box.upper + w.
    const float first = floorf((box.lower[a] - float(b.lower[a])) * inv_w - 1.5f);
    const float last = ceilf((box.upper[a] - float(b.lower[a])) * inv_w + 0.5f);
    lo[a] = first < 0.f ? 0 : (first > float(b.dims[a]) ? b.dims[a] : int(first));
    hi[a] = last >= float(b.dims[a]) ? b.dims[a] - 1 : (last < 0.f ? -1 : int(last));
  }
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y) {
      const float* row = values + b.value_offset + (uint64_t(z) * b.dims.y + y) * b.dims.x;
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const float v = row[x];
        if (v != v) continue;  // NaN
        r.lo = v < r.lo ? v : r.lo;
        r.hi = v > r.hi ? v : r.hi;
      }
    }
}

// The range of ABR `abr` (lo > hi when no cell near it has a finite value), widened by a few
// ulps like compute_abr_ranges: the sampler's float average can land just outside its inputs.
VS_HOST_DEVICE inline Range tight_abr_range(const AmrView& v, uint32_t abr) {
  const Abr& a = v.abrs[abr];
  Range r{INFINITY, -INFINITY};
  for (uint32_t k = 0; k < a.brick_count; ++k) brick_range_near(v.bricks[v.abr_bricks[a.first_brick + k]], v.values, a.box, r);
  if (r.lo <= r.hi) {
    const float m = fabsf(r.lo) > fabsf(r.hi) ? fabsf(r.lo) : fabsf(r.hi);
    r.lo -= 1e-5f * m;
    r.hi += 1e-5f * m;
  }
  return r;
}

// All ABRs on the CPU (parallel).
std::vector<Range> compute_tight_abr_ranges(const AmrTopology& topology, const float* values);

}  // namespace vs
