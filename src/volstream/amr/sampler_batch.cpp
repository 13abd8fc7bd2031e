// The fast sampler over a batch of points along a ray in 8 SIMD lanes, one point per lane, built
// for baseline x86-64 (SSE2: two 4-wide halves) and for AVX2 (8 wide), chosen by the CPU
// (core/simd.h): both give sample_abr_fast's floats bit for bit (each lane does what the scalar
// form does, in its order).
#include <cmath>

// First: its silencing of the AVX calling-convention note must precede the templates of
// sampler.h that are instantiated here over lanes (add_cell_corners).
#include "volstream/core/simd.h"
// (the rest)
#include "volstream/amr/sampler.h"

namespace vs {
namespace {

using simd::f8;
using simd::i8;
using simd::kLanes;

// detail::clamped_axis in lanes: q clamped into [0, n - 1], lower cell index and upper weight.
struct LaneAxis {
  i8 i0, i1;
  f8 t;
};
VS_FORCE_INLINE LaneAxis lane_axis(const f8& q, int32_t n) {
  const f8 zero = f8{} + 0.f, top = zero + float(n - 1);
  f8 qc = q > zero ? q : zero;
  qc = qc < top ? qc : top;
  const i8 last_lower = i8{} + (n > 1 ? n - 2 : 0);
  const i8 i = __builtin_convertvector(qc, i8);  // qc >= 0: truncation is floor
  const i8 i0 = i < last_lower ? i : last_lower;
  return {i0, i0 + (n > 1 ? 1 : 0), qc - __builtin_convertvector(i0, f8)};
}

VS_FORCE_INLINE f8 lerp(const f8& a, const f8& c, const f8& t) { return a + t * (c - a); }

// detail::sample_one_brick at the 8 points org + dir * t[k]; lanes n..7 repeat the last point.
template <simd::Isa kIsa>
VS_FORCE_INLINE void batch_body(const SampleBrick& b, const float* values, const vec3f& org, const vec3f& dir,
                                const float* t, uint32_t n, float* out) {
  const f8 tl = simd::load_lanes(t, n);
  // Ray::at in lanes, operation for operation.
  const f8 px = org.x + dir.x * tl, py = org.y + dir.y * tl, pz = org.z + dir.z * tl;
  const f8 half = f8{} + 0.5f, inv_w = f8{} + b.inv_width;
  // As detail::brick_cell_coords, operation for operation.
  const f8 qx = (px - b.lower.x) * inv_w - half, qy = (py - b.lower.y) * inv_w - half,
           qz = (pz - b.lower.z) * inv_w - half;
  const f8 minus_one = f8{} - 1.f;
  const i8 inside = (qx > minus_one) & (qy > minus_one) & (qz > minus_one) & (qx < float(b.dims.x)) &
                    (qy < float(b.dims.y)) & (qz < float(b.dims.z));
  const LaneAxis x = lane_axis(qx, b.dims.x), y = lane_axis(qy, b.dims.y), z = lane_axis(qz, b.dims.z);
  const float* v = values + b.value_offset;
  const int32_t nx = b.dims.x, nxy = b.dims.x * b.dims.y;
  const i8 z0 = z.i0 * nxy, z1 = z.i1 * nxy, y0 = y.i0 * nx, y1 = y.i1 * nx;
  const f8 c00 = lerp(simd::gather<kIsa>(v, z0 + y0 + x.i0), simd::gather<kIsa>(v, z0 + y0 + x.i1), x.t);
  const f8 c10 = lerp(simd::gather<kIsa>(v, z0 + y1 + x.i0), simd::gather<kIsa>(v, z0 + y1 + x.i1), x.t);
  const f8 c01 = lerp(simd::gather<kIsa>(v, z1 + y0 + x.i0), simd::gather<kIsa>(v, z1 + y0 + x.i1), x.t);
  const f8 c11 = lerp(simd::gather<kIsa>(v, z1 + y1 + x.i0), simd::gather<kIsa>(v, z1 + y1 + x.i1), x.t);
  const f8 r = lerp(lerp(c00, c10, y.t), lerp(c01, c11, y.t), z.t);
  const f8 result = inside != 0 ? r : f8{} + NAN;
  simd::store(out, result);
  // A NaN value read inside the support: the scalar form decides (as sample_abr_fast).
  const i8 nan_inside = (result != result) & inside;
  if (!simd::any(nan_inside)) return;
  for (uint32_t k = 0; k < kLanes; ++k)
    if (nan_inside[k]) out[k] = detail::sample_one_brick(b, values, {px[k], py[k], pz[k]});
}

// detail::axis_cells in lanes.
struct LaneCells {
  i8 i0, i1;
  f8 w0, w1;
};
VS_FORCE_INLINE f8 abs_lanes(const f8& x) {
  simd::u8 bits;
  __builtin_memcpy(&bits, &x, sizeof bits);
  bits &= 0x7fffffffu;
  f8 out;
  __builtin_memcpy(&out, &bits, sizeof out);
  return out;
}
VS_FORCE_INLINE LaneCells lane_cells(const f8& q, int32_t n) {
  const i8 truncated = __builtin_convertvector(q, i8);
  const i8 i = truncated + (__builtin_convertvector(truncated, f8) > q);  // floor_to_int (true is -1)
  const f8 f = __builtin_convertvector(i, f8);
  const i8 in0 = (i >= 0) & (i < n), in1 = (i >= -1) & (i + 1 < n);
  const f8 w0 = 1.f - abs_lanes(q - f), w1 = 1.f - abs_lanes(q - (f + 1.f));
  const i8 zero = i8{};
  const f8 none = f8{};
  return {in0 ? i : zero, in1 ? i + 1 : zero, (in0 & (w0 > 0.f)) ? w0 : none, (in1 & (w1 > 0.f)) ? w1 : none};
}

// detail::accumulate_brick_fast for each lane's point: the 8 cells in its order.
template <simd::Isa kIsa>
VS_FORCE_INLINE void accumulate_lanes(const SampleBrick& b, const float* values, const f8& px, const f8& py,
                                      const f8& pz, f8& weight, f8& weighted_value) {
  const f8 half = f8{} + 0.5f, inv_w = f8{} + b.inv_width;
  const LaneCells x = lane_cells((px - b.lower.x) * inv_w - half, b.dims.x);
  const LaneCells y = lane_cells((py - b.lower.y) * inv_w - half, b.dims.y);
  const LaneCells z = lane_cells((pz - b.lower.z) * inv_w - half, b.dims.z);
  const float* v = values + b.value_offset;
  const int32_t nx = b.dims.x, nxy = b.dims.x * b.dims.y;
  const i8 zs[2] = {z.i0 * nxy, z.i1 * nxy}, ys[2] = {y.i0 * nx, y.i1 * nx}, xs[2] = {x.i0, x.i1};
  const f8 wz[2] = {z.w0, z.w1}, wy[2] = {y.w0, y.w1}, wx[2] = {x.w0, x.w1};
  detail::add_cell_corners(
      zs, ys, xs, wz, wy,
      wx, [v](const i8& offset) __attribute__((always_inline)) { return simd::gather<kIsa>(v, offset); }, weight,
      weighted_value);
}

// sample_abr_fast's sum over an ABR's bricks (ids[0..count)) at org + dir * t[k].
template <simd::Isa kIsa>
VS_FORCE_INLINE void bricks_body(const SampleBrick* records, const uint32_t* ids, uint32_t count, const float* values,
                                 const vec3f& org, const vec3f& dir, const float* t, uint32_t n, float* out) {
  const f8 tl = simd::load_lanes(t, n);
  const f8 px = org.x + dir.x * tl, py = org.y + dir.y * tl, pz = org.z + dir.z * tl;
  f8 weight{}, weighted_value{};
  for (uint32_t i = 0; i < count; ++i)
    accumulate_lanes<kIsa>(records[ids[i]], values, px, py, pz, weight, weighted_value);
  simd::store(out, weight > 0.f ? weighted_value / weight : f8{} + NAN);  // TentSum::value
}

void batch_baseline(const SampleBrick& b, const float* values, const vec3f& org, const vec3f& dir, const float* t,
                    uint32_t n, float* out) {
  batch_body<simd::Isa::baseline>(b, values, org, dir, t, n, out);
}

VS_TARGET_AVX2 void batch_avx2(const SampleBrick& b, const float* values, const vec3f& org, const vec3f& dir,
                               const float* t, uint32_t n, float* out) {
  batch_body<simd::Isa::avx2>(b, values, org, dir, t, n, out);
}

void bricks_baseline(const SampleBrick* records, const uint32_t* ids, uint32_t count, const float* values,
                     const vec3f& org, const vec3f& dir, const float* t, uint32_t n, float* out) {
  bricks_body<simd::Isa::baseline>(records, ids, count, values, org, dir, t, n, out);
}

VS_TARGET_AVX2 void bricks_avx2(const SampleBrick* records, const uint32_t* ids, uint32_t count, const float* values,
                                const vec3f& org, const vec3f& dir, const float* t, uint32_t n, float* out) {
  bricks_body<simd::Isa::avx2>(records, ids, count, values, org, dir, t, n, out);
}

}  // namespace

void sample_bricks_batch(const SampleBrick* records, const uint32_t* ids, uint32_t count, const float* values,
                         const vec3f& org, const vec3f& dir, const float* t, uint32_t n, float* out) {
  if (n == 0) return;
  (simd::use_avx2() ? bricks_avx2 : bricks_baseline)(records, ids, count, values, org, dir, t, n, out);
}

void sample_one_brick_batch(const SampleBrick& b, const float* values, const vec3f& org, const vec3f& dir,
                            const float* t, uint32_t n, float* out) {
  if (n == 0) return;
  (simd::use_avx2() ? batch_avx2 : batch_baseline)(b, values, org, dir, t, n, out);
}

}  // namespace vs
