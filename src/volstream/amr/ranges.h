// Per-ABR value ranges of one field at one step (the "ranges" stage of paper 000): for each ABR
// a [lo, hi] that bounds every value the tent-basis sampler can return inside it, so that ABRs
// the transfer function maps to zero opacity can be culled.
//
// Tight, not per brick: bricks are large and span wide value ranges, so the union of an ABR's
// brick ranges marks nearly every ABR visible for a selective transfer function (jet demo: 94% of
// ABRs), and rays then march air. A cell c (centre x_c, width w) has weight at p only if
// |p - x_c| < w on every axis, so the sampler's value anywhere in ABR box B is a convex
// combination of the cells whose centres lie in B grown by w: their range bounds it (jet demo:
// 17% of ABRs visible, 3x fewer samples).
//
// Work layout, shared by CPU and GPU: an ABR visits its bricks in turn and, in each, only the
// sub-box of cells near it. On the GPU one warp takes one ABR and its 32 lanes stride over each
// sub-box together, so every lane runs the same loop (no divergence between lanes, the
// bottleneck paper 000 names in section 7) and reads neighbouring cells (coalesced).
#pragma once
#include <cmath>
#include <vector>

#include "volstream/amr/model.h"

namespace vs {

// The cells of brick b whose centres lie within `box` grown by one cell width (inclusive, so
// rounding can only widen it), as an index box [lo, hi] per axis; hi < lo on some axis if none.
VS_HOST_DEVICE inline box3i cells_near(const Brick& b, const box3f& box) {
  const float inv_w = 1.f / float(b.width());
  box3i r;
  for (int a = 0; a < 3; ++a) {
    // Cell i's centre is lower + (i + 0.5) w; keep box.lower - w <= centre <= box.upper + w.
    const float first = floorf((box.lower[a] - float(b.lower[a])) * inv_w - 1.5f);
    const float last = ceilf((box.upper[a] - float(b.lower[a])) * inv_w + 0.5f);
    r.lower[a] = first < 0.f ? 0 : (first > float(b.dims[a]) ? b.dims[a] : int32_t(first));
    r.upper[a] = last >= float(b.dims[a]) ? b.dims[a] - 1 : (last < 0.f ? -1 : int32_t(last));
  }
  return r;
}

VS_HOST_DEVICE inline void extend_range(Range& r, float v) {
  if (v != v) return;  // NaN carries no value
  r.lo = v < r.lo ? v : r.lo;
  r.hi = v > r.hi ? v : r.hi;
}

// Extends r by the cells near `box` in brick b with flattened sub-box index lane, lane + lanes,
// ... (lanes = 1: all of them).
VS_HOST_DEVICE inline void brick_range_near(const Brick& b, const float* values, const box3f& box, uint32_t lane,
                                            uint32_t lanes, Range& r) {
  const box3i near = cells_near(b, box);
  const int32_t nx = near.upper.x - near.lower.x + 1, ny = near.upper.y - near.lower.y + 1,
                nz = near.upper.z - near.lower.z + 1;
  if (nx <= 0 || ny <= 0 || nz <= 0) return;
  // Walk the sub-box in flattened order from `lane` in steps of `lanes`, carrying (x, y, z)
  // along instead of dividing per cell.
  int32_t x = int32_t(lane), y = 0, z = 0;
  while (x >= nx) x -= nx, ++y;
  while (y >= ny) y -= ny, ++z;
  while (z < nz) {
    const uint64_t row = (uint64_t(near.lower.z + z) * uint32_t(b.dims.y) + uint32_t(near.lower.y + y)) * uint32_t(b.dims.x);
    extend_range(r, values[b.value_offset + row + uint32_t(near.lower.x + x)]);
    x += int32_t(lanes);
    while (x >= nx) x -= nx, ++y;
    while (y >= ny) y -= ny, ++z;
  }
}

// The partial range of ABR `abr` seen by one lane of `lanes` (combine the lanes' ranges after).
VS_HOST_DEVICE inline Range abr_lane_range(const AmrView& v, uint32_t abr, uint32_t lane, uint32_t lanes) {
  const Abr& a = v.abrs[abr];
  Range r{INFINITY, -INFINITY};
  for (uint32_t k = 0; k < a.brick_count; ++k)
    brick_range_near(v.bricks[v.abr_bricks[a.first_brick + k]], v.values, a.box, lane, lanes, r);
  return r;
}

// The sampler's float weighted average can land a few ulps outside the exact convex hull of its
// inputs: widen so that the range bounds every value it returns. Empty ranges stay empty.
VS_HOST_DEVICE inline Range widen_for_rounding(Range r) {
  if (!(r.lo <= r.hi)) return r;
  const float m = fabsf(r.lo) > fabsf(r.hi) ? fabsf(r.lo) : fabsf(r.hi);
  return {r.lo - 1e-5f * m, r.hi + 1e-5f * m};
}

// All ABRs on the CPU (parallel). An ABR with no finite value near it gets lo > hi.
std::vector<Range> compute_abr_ranges(const AmrTopology& topology, const float* values);

// Min/max over all cells (NaN ignored; lo > hi when none is finite).
Range value_range(const float* values, uint64_t count);

}  // namespace vs
