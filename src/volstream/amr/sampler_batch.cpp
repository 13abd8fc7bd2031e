// The fast sampler over a batch of points along a ray in 8 SIMD lanes, one point per lane, built
// for baseline x86-64 (SSE2: two 4-wide halves) and for AVX2 (8 wide), chosen by the CPU
// (core/simd.h): both give sample_abr_fast's floats bit for bit (each lane does what the scalar
// form does, in its order).
#include <algorithm>
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

// A brick's record for the lanes: the same brick in every lane (float and int32_t fields: a
// batch in one ABR) or each lane its own (f8 and i8: a batch over several ABRs). Cell offsets
// count from `base`.
template <typename F, typename I>
struct BrickLanes {
  F lower_x, lower_y, lower_z, inv_width;
  I nx, ny, nz;
  I offset;  // of the brick's first value from base
  const float* base;
};
using OneBrick = BrickLanes<float, int32_t>;
using LaneBrick = BrickLanes<f8, i8>;

VS_FORCE_INLINE OneBrick same_brick(const SampleBrick& b, const float* values) {
  return {b.lower.x, b.lower.y, b.lower.z, b.inv_width, b.dims.x, b.dims.y, b.dims.z, 0, values + b.value_offset};
}

VS_FORCE_INLINE f8 as_lanes(int32_t x) { return f8{} + float(x); }
VS_FORCE_INLINE f8 as_lanes(const i8& x) { return __builtin_convertvector(x, f8); }
VS_FORCE_INLINE i8 mask_lanes(bool b) { return i8{} - int32_t(b); }  // -1 where true
VS_FORCE_INLINE i8 mask_lanes(const i8& m) { return m; }

// Lane k's brick: record ids[k] (value offsets below 2^31, see sample_abrs_batch).
VS_FORCE_INLINE LaneBrick lane_bricks(const SampleBrick* records, const uint32_t (&ids)[kLanes], const float* values) {
  LaneBrick l;
  for (uint32_t k = 0; k < kLanes; ++k) {
    const SampleBrick& b = records[ids[k]];
    l.lower_x[k] = b.lower.x, l.lower_y[k] = b.lower.y, l.lower_z[k] = b.lower.z, l.inv_width[k] = b.inv_width;
    l.nx[k] = b.dims.x, l.ny[k] = b.dims.y, l.nz[k] = b.dims.z, l.offset[k] = int32_t(b.value_offset);
  }
  l.base = values;
  return l;
}

// detail::brick_cell_coords, operation for operation.
template <typename F>
VS_FORCE_INLINE f8 cell_coord(const f8& p, const F& lower, const F& inv_width) {
  return (p - lower) * inv_width - 0.5f;
}

// detail::clamped_axis in lanes: q clamped into [0, n - 1], lower cell index and upper weight.
struct LaneAxis {
  i8 i0, i1;
  f8 t;
};
template <typename I>
VS_FORCE_INLINE LaneAxis lane_axis(const f8& q, const I& n) {
  const f8 zero = f8{}, top = as_lanes(n - 1);
  f8 qc = q > zero ? q : zero;
  qc = qc < top ? qc : top;
  const i8 several = mask_lanes(n > 1);  // -1 where the axis has two cells or more
  const i8 last_lower = several & (i8{} + (n - 2));
  const i8 i = __builtin_convertvector(qc, i8);  // qc >= 0: truncation is floor
  const i8 i0 = i < last_lower ? i : last_lower;
  return {i0, i0 - several, qc - __builtin_convertvector(i0, f8)};
}

VS_FORCE_INLINE f8 lerp(const f8& a, const f8& c, const f8& t) { return a + t * (c - a); }

// detail::sample_one_brick's trilinear form in lanes: NaN beyond the support (inside: 0 there).
template <simd::Isa kIsa, typename F, typename I>
VS_FORCE_INLINE f8 one_brick_lanes(const BrickLanes<F, I>& b, const f8& px, const f8& py, const f8& pz, i8& inside) {
  const f8 qx = cell_coord(px, b.lower_x, b.inv_width), qy = cell_coord(py, b.lower_y, b.inv_width),
           qz = cell_coord(pz, b.lower_z, b.inv_width);
  const f8 minus_one = f8{} - 1.f;
  inside = (qx > minus_one) & (qy > minus_one) & (qz > minus_one) & (qx < as_lanes(b.nx)) & (qy < as_lanes(b.ny)) &
           (qz < as_lanes(b.nz));
  const LaneAxis x = lane_axis(qx, b.nx), y = lane_axis(qy, b.ny), z = lane_axis(qz, b.nz);
  const I nxy = b.nx * b.ny;
  const i8 z0 = b.offset + z.i0 * nxy, z1 = b.offset + z.i1 * nxy, y0 = y.i0 * b.nx, y1 = y.i1 * b.nx;
  const auto at = [&](const i8& index) __attribute__((always_inline)) { return simd::gather<kIsa>(b.base, index); };
  const f8 c00 = lerp(at(z0 + y0 + x.i0), at(z0 + y0 + x.i1), x.t);
  const f8 c10 = lerp(at(z0 + y1 + x.i0), at(z0 + y1 + x.i1), x.t);
  const f8 c01 = lerp(at(z1 + y0 + x.i0), at(z1 + y0 + x.i1), x.t);
  const f8 c11 = lerp(at(z1 + y1 + x.i0), at(z1 + y1 + x.i1), x.t);
  const f8 r = lerp(lerp(c00, c10, y.t), lerp(c01, c11, y.t), z.t);
  return inside != 0 ? r : f8{} + NAN;
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
template <typename I>
VS_FORCE_INLINE LaneCells lane_cells(const f8& q, const I& n) {
  const i8 truncated = __builtin_convertvector(q, i8);
  const i8 i = truncated + (__builtin_convertvector(truncated, f8) > q);  // floor_to_int (true is -1)
  const f8 f = __builtin_convertvector(i, f8);
  const i8 in0 = (i >= 0) & (i < n), in1 = (i >= -1) & (i + 1 < n);
  const f8 w0 = 1.f - abs_lanes(q - f), w1 = 1.f - abs_lanes(q - (f + 1.f));
  const i8 zero = i8{};
  const f8 none = f8{};
  return {in0 ? i : zero, in1 ? i + 1 : zero, (in0 & (w0 > 0.f)) ? w0 : none, (in1 & (w1 > 0.f)) ? w1 : none};
}

// detail::accumulate_brick_fast for each lane's point where `active` (elsewhere it adds zeros,
// which leave the sums as they are): the 8 cells in its order.
template <simd::Isa kIsa, typename F, typename I>
VS_FORCE_INLINE void accumulate_lanes(const BrickLanes<F, I>& b, const f8& px, const f8& py, const f8& pz,
                                      const i8& active, f8& weight, f8& weighted_value) {
  const LaneCells x = lane_cells(cell_coord(px, b.lower_x, b.inv_width), b.nx);
  const LaneCells y = lane_cells(cell_coord(py, b.lower_y, b.inv_width), b.ny);
  const LaneCells z = lane_cells(cell_coord(pz, b.lower_z, b.inv_width), b.nz);
  const I nxy = b.nx * b.ny;
  const i8 zs[2] = {b.offset + z.i0 * nxy, b.offset + z.i1 * nxy}, ys[2] = {y.i0 * b.nx, y.i1 * b.nx},
           xs[2] = {x.i0, x.i1};
  const f8 wz[2] = {z.w0, z.w1}, wy[2] = {y.w0, y.w1}, wx[2] = {active ? x.w0 : f8{}, active ? x.w1 : f8{}};
  const float* v = b.base;
  detail::add_cell_corners(
      zs, ys, xs, wz, wy,
      wx, [v](const i8& offset) __attribute__((always_inline)) { return simd::gather<kIsa>(v, offset); }, weight,
      weighted_value);
}

VS_FORCE_INLINE f8 tent_value(const f8& weight, const f8& weighted_value) {  // TentSum::value
  return weight > 0.f ? weighted_value / weight : f8{} + NAN;
}

struct RayLanes {
  f8 px, py, pz;
};
// Ray::at in lanes, operation for operation.
VS_FORCE_INLINE RayLanes ray_lanes(const vec3f& org, const vec3f& dir, const float* t, uint32_t n) {
  const f8 tl = simd::load_lanes(t, n);
  return {org.x + dir.x * tl, org.y + dir.y * tl, org.z + dir.z * tl};
}

// detail::sample_one_brick at the 8 points org + dir * t[k]; lanes n..7 repeat the last point.
template <simd::Isa kIsa>
VS_FORCE_INLINE void batch_body(const SampleBrick& b, const float* values, const vec3f& org, const vec3f& dir,
                                const float* t, uint32_t n, float* out) {
  const RayLanes p = ray_lanes(org, dir, t, n);
  i8 inside;
  const f8 result = one_brick_lanes<kIsa>(same_brick(b, values), p.px, p.py, p.pz, inside);
  simd::store(out, result);
  // A NaN value read inside the support: the scalar form decides (as sample_abr_fast).
  const i8 nan_inside = (result != result) & inside;
  if (!simd::any(nan_inside)) return;
  for (uint32_t k = 0; k < kLanes; ++k)
    if (nan_inside[k]) out[k] = detail::sample_one_brick(b, values, {p.px[k], p.py[k], p.pz[k]});
}

// sample_abr_fast's sum over an ABR's bricks (ids[0..count)) at org + dir * t[k].
template <simd::Isa kIsa>
VS_FORCE_INLINE void bricks_body(const SampleBrick* records, const uint32_t* ids, uint32_t count, const float* values,
                                 const vec3f& org, const vec3f& dir, const float* t, uint32_t n, float* out) {
  const RayLanes p = ray_lanes(org, dir, t, n);
  f8 weight{}, weighted_value{};
  const i8 all = i8{} - 1;
  for (uint32_t i = 0; i < count; ++i)
    accumulate_lanes<kIsa>(same_brick(records[ids[i]], values), p.px, p.py, p.pz, all, weight, weighted_value);
  simd::store(out, tent_value(weight, weighted_value));
}

// sample_abr_fast in each lane for its own ABR regions[k]: the trilinear form for lanes whose
// ABR has one brick, the tent sum over the ABR's bricks for the others.
template <simd::Isa kIsa>
VS_FORCE_INLINE void abrs_body(const AbrBatch& a, const float* values, const uint32_t* regions, const vec3f& org,
                               const vec3f& dir, const float* t, uint32_t n, float* out) {
  const RayLanes p = ray_lanes(org, dir, t, n);
  uint32_t first[kLanes];
  i8 count;
  int32_t most = 0;
  for (uint32_t k = 0; k < kLanes; ++k) {
    const Abr& abr = a.abrs[regions[k < n ? k : n - 1]];
    first[k] = abr.first_brick;
    count[k] = int32_t(abr.brick_count);
    most = std::max(most, count[k]);
  }
  const i8 single = count == 1;
  f8 weight{}, weighted_value{}, trilinear{};
  i8 inside{};
  for (int32_t j = 0; j < most; ++j) {
    const i8 active = (count > j) & ~single;
    uint32_t ids[kLanes];
    for (uint32_t k = 0; k < kLanes; ++k) ids[k] = a.abr_bricks[first[k] + (j < count[k] ? uint32_t(j) : 0u)];
    const LaneBrick b = lane_bricks(a.records, ids, values);
    if (j == 0 && simd::any(single)) trilinear = one_brick_lanes<kIsa>(b, p.px, p.py, p.pz, inside);
    if (simd::any(active)) accumulate_lanes<kIsa>(b, p.px, p.py, p.pz, active, weight, weighted_value);
  }
  const f8 result = single ? trilinear : tent_value(weight, weighted_value);
  simd::store(out, result);
  const i8 nan_inside = (result != result) & inside & single;  // as batch_body
  if (!simd::any(nan_inside)) return;
  for (uint32_t k = 0; k < kLanes; ++k)
    if (nan_inside[k])
      out[k] = detail::sample_one_brick(a.records[a.abr_bricks[first[k]]], values, {p.px[k], p.py[k], p.pz[k]});
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

VS_TARGET_AVX2 void abrs_avx2(const AbrBatch& a, const float* values, const uint32_t* regions, const vec3f& org,
                              const vec3f& dir, const float* t, uint32_t n, float* out) {
  abrs_body<simd::Isa::avx2>(a, values, regions, org, dir, t, n, out);
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

void sample_abrs_batch(const AbrBatch& a, const float* values, const uint32_t* regions, const vec3f& org,
                       const vec3f& dir, const float* t, uint32_t n, float* out) {
  if (n == 0) return;
  if (simd::use_avx2()) return abrs_avx2(a, values, regions, org, dir, t, n, out);
  // Without AVX2's gathers, loading each lane's brick records and cells costs more than the
  // scalar form point by point (measured: jet 1e6 0.38 s against 0.33 s).
  for (uint32_t k = 0; k < kLanes; ++k) {
    const uint32_t i = k < n ? k : n - 1;
    out[k] = sample_abr_fast(a.abrs, a.abr_bricks, a.records, values, regions[i], org + dir * t[i]);
  }
}

bool lane_offsets_fit(const std::vector<SampleBrick>& records) {
  return std::all_of(records.begin(), records.end(), [](const SampleBrick& b) {
    const uint64_t cells = uint64_t(b.dims.x) * uint64_t(b.dims.y) * uint64_t(b.dims.z);
    return b.value_offset + cells <= uint64_t(INT32_MAX);
  });
}

}  // namespace vs
