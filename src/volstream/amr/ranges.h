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
// Two passes, shared by CPU and GPU:
//  1. macrocells: the min/max of every 4x4x4 block of cells of every brick (one read of all values);
//  2. per ABR: the union of the macrocells that hold a cell near it, brick by brick. Reading
//     macrocells instead of cells makes this pass 10-60x less work (cells near an ABR are read by
//     every ABR they are near) at the price of up to 3 extra cells per side, still conservative.
// On the GPU pass 1 is one thread per macrocell and pass 2 one warp per ABR whose 32 lanes
// stride together over each brick's macrocells near the ABR, so every lane runs the same loop
// (no divergence between lanes, the bottleneck paper 000 names in section 7).
#pragma once
#include <cmath>
#include <vector>

#include "volstream/amr/model.h"

namespace vs {

// floor(a / 2^k) for any sign of a: C++20 (and CUDA) define >> on negative int32 as arithmetic.
// A shift, not a division: this runs for every (ABR, brick) pair of every frame, and six integer
// divisions per pair were most of the ranges stage on the CPU.
VS_HOST_DEVICE constexpr int32_t floor_div_pow2(int32_t a, int32_t k) { return a >> k; }

// The cells of brick b whose centres lie within `box` grown by one cell width, as an index box
// [lower, upper] per axis (upper < lower on some axis if none). Integer arithmetic in half-grid
// units (ABR corners are multiples of 1/2): cell i's centre is 2 lower + (2i + 1) w there. Each
// end is rounded outwards, so the set can only be a little larger than needed.
VS_HOST_DEVICE inline box3i cells_near(const Brick& b, const box3f& box) {
  const int32_t w = b.width();
  box3i r;
  for (int a = 0; a < 3; ++a) {
    const int32_t lo = int32_t(box.lower[a] * 2.f) - 2 * b.lower[a], hi = int32_t(box.upper[a] * 2.f) - 2 * b.lower[a];
    // (2i + 1) w >= lo - 2w  <=>  i >= (lo - 3w) / 2w;  (2i + 1) w <= hi + 2w  <=>  i <= (hi + w) / 2w.
    const int32_t first = floor_div_pow2(lo - 3 * w, b.level + 1), last = floor_div_pow2(hi + w, b.level + 1) + 1;
    r.lower[a] = first < 0 ? 0 : (first > b.dims[a] ? b.dims[a] : first);
    r.upper[a] = last >= b.dims[a] ? b.dims[a] - 1 : (last < 0 ? -1 : last);
  }
  return r;
}

VS_HOST_DEVICE inline void extend_range(Range& r, float v) {
  if (v != v) return;  // NaN carries no value
  r.lo = v < r.lo ? v : r.lo;
  r.hi = v > r.hi ? v : r.hi;
}

VS_HOST_DEVICE inline void extend_range(Range& r, const Range& o) {
  r.lo = o.lo < r.lo ? o.lo : r.lo;
  r.hi = o.hi > r.hi ? o.hi : r.hi;
}

inline constexpr int32_t kMacrocellLog2 = 2, kMacrocell = 1 << kMacrocellLog2;  // cells per macrocell edge

VS_HOST_DEVICE inline vec3i macrocell_dims(const Brick& b) {
  return {(b.dims.x + kMacrocell - 1) / kMacrocell, (b.dims.y + kMacrocell - 1) / kMacrocell,
          (b.dims.z + kMacrocell - 1) / kMacrocell};
}

// Where each brick's macrocells start in the macrocell array (x fastest), plus the total at the
// end: bricks + 1 entries. Depends on the topology only.
std::vector<uint64_t> macrocell_offsets(const std::vector<Brick>& bricks);

// What both passes read and write (host or device pointers).
struct RangeView {
  AmrView amr;
  const uint64_t* macro_offset = nullptr;  // macrocell_offsets()
  Range* macro = nullptr;                  // one range per macrocell (pass 1 writes it)
};

// Pass 1 for macrocell m = (mx, my, mz) of brick b: min/max over its (up to 4^3) cells.
VS_HOST_DEVICE inline Range macrocell_range(const Brick& b, const float* values, const vec3i& m) {
  Range r{INFINITY, -INFINITY};
  const vec3i lo = m * kMacrocell;
  const int32_t hx = lo.x + kMacrocell < b.dims.x ? lo.x + kMacrocell : b.dims.x;
  const int32_t hy = lo.y + kMacrocell < b.dims.y ? lo.y + kMacrocell : b.dims.y;
  const int32_t hz = lo.z + kMacrocell < b.dims.z ? lo.z + kMacrocell : b.dims.z;
  for (int32_t z = lo.z; z < hz; ++z)
    for (int32_t y = lo.y; y < hy; ++y) {
      const float* row =
          values + b.value_offset + (uint64_t(z) * uint32_t(b.dims.y) + uint32_t(y)) * uint32_t(b.dims.x);
      for (int32_t x = lo.x; x < hx; ++x) extend_range(r, row[x]);
    }
  return r;
}

// Pass 1 for global macrocell index i: finds its brick by binary search over the offsets.
VS_HOST_DEVICE inline void compute_macrocell(const RangeView& v, uint64_t i) {
  uint32_t lo = 0, hi = v.amr.brick_count;  // the brick k with offset[k] <= i < offset[k + 1]
  while (hi - lo > 1) {
    const uint32_t mid = (lo + hi) / 2;
    if (v.macro_offset[mid] <= i)
      lo = mid;
    else
      hi = mid;
  }
  const Brick& b = v.amr.bricks[lo];
  const vec3i n = macrocell_dims(b);
  const uint64_t local = i - v.macro_offset[lo];
  const vec3i m{int32_t(local % uint32_t(n.x)), int32_t(local / uint32_t(n.x) % uint32_t(n.y)),
                int32_t(local / (uint64_t(n.x) * uint32_t(n.y)))};
  v.macro[i] = macrocell_range(b, v.amr.values, m);
}

// Pass 2, one brick: extends r by the macrocells of brick `brick` holding a cell near `box`,
// visiting the flattened macrocell sub-box from `lane` in steps of `lanes` (lanes = 1: all).
VS_HOST_DEVICE inline void brick_range_near(const RangeView& v, uint32_t brick, const box3f& box, uint32_t lane,
                                            uint32_t lanes, Range& r) {
  const Brick& b = v.amr.bricks[brick];
  const box3i near = cells_near(b, box);
  if (near.upper.x < near.lower.x || near.upper.y < near.lower.y || near.upper.z < near.lower.z) return;
  // near.lower >= 0 here, so these divisions by 4 are shifts.
  const vec3i lo{near.lower.x >> kMacrocellLog2, near.lower.y >> kMacrocellLog2, near.lower.z >> kMacrocellLog2};
  const vec3i n = macrocell_dims(b);
  const int32_t nx = (near.upper.x >> kMacrocellLog2) - lo.x + 1, ny = (near.upper.y >> kMacrocellLog2) - lo.y + 1,
                nz = (near.upper.z >> kMacrocellLog2) - lo.z + 1;
  const Range* macro = v.macro + v.macro_offset[brick];
  // Walk the sub-box in flattened order, carrying (x, y, z) along instead of dividing per step.
  int32_t x = int32_t(lane), y = 0, z = 0;
  while (x >= nx) x -= nx, ++y;
  while (y >= ny) y -= ny, ++z;
  while (z < nz) {
    extend_range(r,
                 macro[(uint64_t(lo.z + z) * uint32_t(n.y) + uint32_t(lo.y + y)) * uint32_t(n.x) + uint32_t(lo.x + x)]);
    x += int32_t(lanes);
    while (x >= nx) x -= nx, ++y;
    while (y >= ny) y -= ny, ++z;
  }
}

// Pass 2: the partial range of ABR `abr` seen by one lane of `lanes` (combine the lanes after).
VS_HOST_DEVICE inline Range abr_lane_range(const RangeView& v, uint32_t abr, uint32_t lane, uint32_t lanes) {
  const Abr& a = v.amr.abrs[abr];
  Range r{INFINITY, -INFINITY};
  for (uint32_t k = 0; k < a.brick_count; ++k)
    brick_range_near(v, v.amr.abr_bricks[a.first_brick + k], a.box, lane, lanes, r);
  return r;
}

// The sampler's float weighted average can land a few ulps outside the exact convex hull of its
// inputs: widen so that the range bounds every value it returns. Empty ranges stay empty.
// On the GPU the product and sum are written with the _rn intrinsics, which the compiler never
// contracts into one FMA (nvcc does by default): rounded twice, as on the host, the device
// ranges equal the host's bit for bit (tests/stream_test.cpp PipelineCuda.*).
VS_HOST_DEVICE inline Range widen_for_rounding(Range r) {
  if (!(r.lo <= r.hi)) return r;
  const float m = fabsf(r.lo) > fabsf(r.hi) ? fabsf(r.lo) : fabsf(r.hi);
#ifdef __CUDA_ARCH__
  const float d = __fmul_rn(1e-5f, m);
  return {__fsub_rn(r.lo, d), __fadd_rn(r.hi, d)};
#else
  const float d = 1e-5f * m;
  return {r.lo - d, r.hi + d};
#endif
}

// Both passes for all ABRs on the CPU (parallel). An ABR with no finite value near it gets lo > hi.
// `macro_offset` may be given (macrocell_offsets(topology.bricks)) to skip recomputing it.
// per_brick: the cheaper, looser ranges instead: each ABR gets the union of its bricks' whole
// ranges (pass 1, then per brick, then through the brick-to-ABR lists; no per-ABR cell boxes).
// On the CPU this is several times faster than the tight pass 2, but culls less.
enum class RangeMode { tight, per_brick };
std::vector<Range> compute_abr_ranges(const AmrTopology& topology, const float* values,
                                      const std::vector<uint64_t>* macro_offset = nullptr,
                                      RangeMode mode = RangeMode::tight);

// Min/max over all cells (NaN ignored; lo > hi when none is finite).
Range value_range(const float* values, uint64_t count);

}  // namespace vs
