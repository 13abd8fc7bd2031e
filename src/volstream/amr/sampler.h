// Tent-basis reconstruction (DESIGN.md): each cell c with centre x_c and width w_c has weight
// prod_i max(0, 1 - |p_i - x_c,i| / w_c); f(p) = sum w_c v_c / sum w_c, undefined (NaN) where the
// weights sum to zero. All positions are in grid units.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

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

// ---------------------------------------------------------------------------------------------
// The CPU's fast sampler: the same tent basis, laid out and computed for the per-sample loop.
//
// One record per brick with what a sample needs (float corner, reciprocal width), reached
// through the ABR's brick list. (Records per list entry, read in a row without the index, were
// tried first: on jet 1e6 that is 1.9 M records, 71 MiB made at load and read from memory, where
// 10k per-brick records, 0.4 MiB, stay in cache; per brick is faster there and no slower on
// few-brick datasets, bench/RESULTS.md.) Per brick the 2x2x2 cells around p are summed without
// branches: indices clamped into the brick, weights of cells outside it set to 0.
//
// - sample_abr_fast on an ABR of several bricks gives exactly sample_abr's float (the same
//   weights summed in the same order; cells of weight 0 add exactly 0, also where their value is
//   NaN, as the reference skips them).
// - An ABR of one brick (most samples: the inside of a brick) is an edge-clamped trilinear
//   interpolation: the tent weights factor per axis, and a cell's weight divided by the sum over
//   the brick is (1 - t, t) between two cells and 1 where only one cell of the brick reaches p
//   (the half-cell shell), which is what clamping p into the cell centres' box gives; so no
//   weight sum and no division, seven lerps. It differs from sample_abr by float rounding
//   only: at most 1e-6 * the largest |value| of the 8 cells read (each lerp a + t (c - a) of
//   values bounded by M is within 2 ulps of M, three levels of them, against the reference's
//   few ulps for w / sum w: well under 16 ulps = 1e-6 M); tests/amr/fast_sampler_test.cpp
//   checks it.
// NaN exactly where the reference is NaN: p beyond every cell's support, or a NaN value read
// with a non-zero weight.
struct SampleBrick {
  vec3f lower;      // grid units
  float inv_width;  // 1 / cell width
  vec3i dims;
  uint32_t reserved = 0;
  uint64_t value_offset;
};
static_assert(sizeof(SampleBrick) == 40);

// The records of a topology's bricks, in brick order.
std::vector<SampleBrick> make_sample_bricks(const AmrTopology& topology);

namespace detail {

// floor(q) as an int, for |q| < 2^31, without a libm call (floorf is one on baseline x86-64).
VS_HOST_DEVICE VS_FORCE_INLINE int32_t floor_to_int(float q) {
  const int32_t i = int32_t(q);
  return i - int32_t(float(i) > q);
}

// The brick's two cells along one axis around q (cell-centre coordinates): indices clamped into
// [0, n) and their tent weights, 0 for a cell outside the brick. The weights are computed as
// accumulate_brick computes them, so that sums over several bricks match it bit for bit.
struct AxisCells {
  int32_t i0, i1;
  float w0, w1;
};
VS_HOST_DEVICE VS_FORCE_INLINE AxisCells axis_cells(float q, int32_t n) {
  const int32_t i = floor_to_int(q);
  const float f = float(i);
  const bool in0 = i >= 0 && i < n, in1 = i >= -1 && i + 1 < n;
  const float w0 = 1.f - fabsf(q - f), w1 = 1.f - fabsf(q - (f + 1.f));
  return {in0 ? i : 0, in1 ? i + 1 : 0, in0 && w0 > 0.f ? w0 : 0.f, in1 && w1 > 0.f ? w1 : 0.f};
}

VS_HOST_DEVICE VS_FORCE_INLINE vec3f brick_cell_coords(const SampleBrick& b, const vec3f& p) {
  return (p - b.lower) * b.inv_width - vec3f(0.5f);  // as accumulate_brick: cell i's centre at i
}

// Adds the 8 cells around a point to the sums in accumulate_brick's order, given per axis the
// two cells' offsets and weights: for one point (F = float, I = int32_t) or for SIMD lanes, one
// point per lane (sampler_batch.cpp). load(offset) reads a value.
template <typename F, typename I, typename Load>
VS_HOST_DEVICE VS_FORCE_INLINE void add_cell_corners(const I (&zs)[2], const I (&ys)[2], const I (&xs)[2],
                                                     const F (&wz)[2], const F (&wy)[2], const F (&wx)[2], Load&& load,
                                                     F& weight, F& weighted_value) {
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const F w = wx[dx] * wy[dy] * wz[dz];
        const F value = load(zs[dz] + ys[dy] + xs[dx]);
        weight += w;
        weighted_value += w > 0.f ? w * value : F{};
      }
}

// sum (w v) and sum w over the brick's 8 cells around p, in accumulate_brick's order.
VS_HOST_DEVICE VS_FORCE_INLINE void accumulate_brick_fast(const SampleBrick& b, const float* values, const vec3f& p,
                                                          TentSum& sum) {
  const vec3f q = brick_cell_coords(b, p);
  const AxisCells x = axis_cells(q.x, b.dims.x), y = axis_cells(q.y, b.dims.y), z = axis_cells(q.z, b.dims.z);
  const float* v = values + b.value_offset;
  const int32_t nx = b.dims.x, nxy = b.dims.x * b.dims.y;
  const int32_t zs[2] = {z.i0 * nxy, z.i1 * nxy}, ys[2] = {y.i0 * nx, y.i1 * nx}, xs[2] = {x.i0, x.i1};
  const float wz[2] = {z.w0, z.w1}, wy[2] = {y.w0, y.w1}, wx[2] = {x.w0, x.w1};
  add_cell_corners(
      zs, ys, xs, wz, wy, wx, [v](int32_t offset) { return v[offset]; }, sum.weight, sum.weighted_value);
}

// One axis of the one-brick form: q clamped into [0, n - 1], the lower cell (at most n - 2, so
// that the upper one, i + 1, is in the brick; both 0 when n = 1) and the upper cell's weight.
struct ClampedAxis {
  int32_t i0, i1;
  float t;
};
VS_HOST_DEVICE VS_FORCE_INLINE ClampedAxis clamped_axis(float q, int32_t n) {
  const float top = float(n - 1);
  const float qc = q > 0.f ? (q < top ? q : top) : 0.f;
  const int32_t last_lower = n > 1 ? n - 2 : 0;
  const int32_t i = int32_t(qc);  // qc >= 0: truncation is floor
  const int32_t i0 = i < last_lower ? i : last_lower;
  return {i0, n > 1 ? i0 + 1 : 0, qc - float(i0)};
}

// Is q (cell-centre coordinates) where some cell of the brick has a non-zero weight? (False for
// NaN.)
VS_HOST_DEVICE VS_FORCE_INLINE bool in_brick_support(const SampleBrick& b, const vec3f& q) {
  return q.x > -1.f && q.y > -1.f && q.z > -1.f && q.x < float(b.dims.x) && q.y < float(b.dims.y) &&
         q.z < float(b.dims.z);
}

// The edge-clamped trilinear at q as nested lerps; reads only cells of the brick for any q.
VS_HOST_DEVICE VS_FORCE_INLINE float one_brick_lerps(const SampleBrick& b, const float* values, const vec3f& q) {
  const ClampedAxis x = clamped_axis(q.x, b.dims.x), y = clamped_axis(q.y, b.dims.y), z = clamped_axis(q.z, b.dims.z);
  const float* v = values + b.value_offset;
  const int32_t nx = b.dims.x, nxy = b.dims.x * b.dims.y;
  const float* z0 = v + z.i0 * nxy;
  const float* z1 = v + z.i1 * nxy;
  const int32_t y0 = y.i0 * nx, y1 = y.i1 * nx;
  auto lerp = [](float a, float c, float t) { return a + t * (c - a); };
  const float c00 = lerp(z0[y0 + x.i0], z0[y0 + x.i1], x.t), c10 = lerp(z0[y1 + x.i0], z0[y1 + x.i1], x.t);
  const float c01 = lerp(z1[y0 + x.i0], z1[y0 + x.i1], x.t), c11 = lerp(z1[y1 + x.i0], z1[y1 + x.i1], x.t);
  return lerp(lerp(c00, c10, y.t), lerp(c01, c11, y.t), z.t);
}

// The one-brick case (see above): NaN beyond the brick's support, else the lerps; a NaN value
// ("no data") among the 8 read, which the reference skips where its weight is 0 (a lerp would
// not), is rare, so then the exact sum decides.
VS_HOST_DEVICE VS_FORCE_INLINE float sample_one_brick(const SampleBrick& b, const float* values, const vec3f& p) {
  const vec3f q = brick_cell_coords(b, p);
  if (!in_brick_support(b, q)) return NAN;
  const float result = one_brick_lerps(b, values, q);
  if (result == result) return result;
  TentSum sum;
  accumulate_brick_fast(b, values, p, sum);
  return sum.value();
}

}  // namespace detail

// The fast sampler: field `values` at p (grid units) inside ABR `abr`.
VS_HOST_DEVICE VS_FORCE_INLINE float sample_abr_fast(const Abr* abrs, const uint32_t* abr_bricks,
                                                     const SampleBrick* sample_bricks, const float* values,
                                                     uint32_t abr, const vec3f& p) {
  const Abr& a = abrs[abr];
  const uint32_t* ids = abr_bricks + a.first_brick;
  if (a.brick_count == 1) return detail::sample_one_brick(sample_bricks[ids[0]], values, p);
  TentSum sum;
  for (uint32_t i = 0; i < a.brick_count; ++i) detail::accumulate_brick_fast(sample_bricks[ids[i]], values, p, sum);
  return sum.value();
}

// CPU only: the one-brick case for n <= 8 points at once, a batch of samples along a ray all in
// one ABR: out[k] at org + dir * t[k] (Ray::at), in 8 SIMD lanes. Compiled twice
// (sampler_batch.cpp), for baseline x86-64 and with AVX2, chosen by the CPU it runs on
// (core/simd.h); both give sample_abr_fast's floats bit for bit (no FMA: nothing is contracted).
// All 8 entries of out are written; those from n on repeat entry n-1.
void sample_one_brick_batch(const SampleBrick& b, const float* values, const vec3f& org, const vec3f& dir,
                            const float* t, uint32_t n, float* out);
// CPU only: the same for an ABR of several bricks, ids[0..count) into records: the tent sum
// over them, as sample_abr_fast adds it, in each lane.
void sample_bricks_batch(const SampleBrick* records, const uint32_t* ids, uint32_t count, const float* values,
                         const vec3f& org, const vec3f& dir, const float* t, uint32_t n, float* out);
// CPU only: the same for a batch whose points lie in different ABRs, point k in ABR regions[k]
// (one lane each, with its ABR's bricks; point by point on a CPU without AVX2, where the lanes'
// loads cost more): as sample_abr_fast per point. The records' value offsets must fit 32-bit
// lanes (lane_offsets_fit).
struct AbrBatch {
  const Abr* abrs;
  const uint32_t* abr_bricks;
  const SampleBrick* records;
};
void sample_abrs_batch(const AbrBatch& a, const float* values, const uint32_t* regions, const vec3f& org,
                       const vec3f& dir, const float* t, uint32_t n, float* out);
bool lane_offsets_fit(const std::vector<SampleBrick>& records);  // every value offset below 2^31
// (core/simd.h says which build runs and forces the baseline.)

}  // namespace vs
