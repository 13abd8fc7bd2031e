// The transfer function's colour and the corrected opacity for a batch of samples in 8 SIMD
// lanes, built for baseline x86-64 and for AVX2 (core/simd.h): operation for operation what
// TfView::lookup, fast_log10, corrected_alpha and fast_exp2_nonpositive do per sample, so the
// same floats; the rare values those hand to libm (subnormal or infinite values on a log scale)
// take the scalar functions.
#include "volstream/core/simd.h"
#include "volstream/render/optics/optics.h"

namespace vs {
namespace {

using simd::f8;
using simd::i8;
using simd::kLanes;
using simd::u8;

VS_FORCE_INLINE f8 bits_to_float(const u8& b) {
  f8 f;
  __builtin_memcpy(&f, &b, sizeof f);
  return f;
}
VS_FORCE_INLINE u8 float_to_bits(const f8& f) {
  u8 b;
  __builtin_memcpy(&b, &f, sizeof b);
  return b;
}
VS_FORCE_INLINE f8 splat(float x) { return f8{} + x; }

// fast_log2's normal-float path (core/fast_math.h).
VS_FORCE_INLINE f8 log2_lanes(const f8& x) {
  constexpr uint32_t kSqrtHalfBits = 0x3f3504f3u;
  const u8 shifted = float_to_bits(x) - kSqrtHalfBits;
  const i8 exponent = i8(shifted) >> 23;
  const f8 m = bits_to_float((shifted & 0x007fffffu) + kSqrtHalfBits);
  const f8 s = (m - 1.f) / (m + 1.f);
  const f8 s2 = s * s, s4 = s2 * s2;
  constexpr float c1 = 2.885390082f, c3 = 0.9617966940f, c5 = 0.5770780164f, c7 = 0.4121985831f, c9 = 0.3205988979f;
  const f8 poly = s * ((c1 + s2 * c3) + s4 * ((c5 + s2 * c7) + s4 * c9));
  return __builtin_convertvector(exponent, f8) + poly;
}

// fast_exp2_nonpositive.
VS_FORCE_INLINE f8 exp2_lanes(const f8& y) {
  constexpr float kRound = 12582912.f;
  const f8 n = (y + kRound) - kRound;
  const f8 f = y - n;
  constexpr float k1 = 0.6931471806f, k2 = 0.2402265070f, k3 = 0.05550410866f, k4 = 0.009618129108f,
                  k5 = 0.001333355815f, k6 = 1.540353039e-4f, k7 = 1.525273380e-5f;
  const f8 f2 = f * f, f4 = f2 * f2;
  const f8 p = ((1.f + f * k1) + f2 * (k2 + f * k3)) + f4 * ((k4 + f * k5) + f2 * (k6 + f * k7));
  const u8 scale_bits = (u8(__builtin_convertvector(n, i8)) + 127u) << 23;  // unsigned: no overflow
  const f8 value = p * bits_to_float(scale_bits);
  return y >= -126.f ? value : (y != y ? y : splat(0.f));
}

template <simd::Isa kIsa>
VS_FORCE_INLINE void batch_body(const TfView& tf, const float* f, const float* len_ref, uint32_t n, TfBatch& out) {
  const f8 v = simd::load_lanes(f, n), len = simd::load_lanes(len_ref, n);
  constexpr float kMinNormal = 1.17549435e-38f, kMaxFloat = 3.40282347e38f, kLog10Of2 = 0.30102999566f;
  // TfView::scaled and position.
  f8 scaled = v;
  i8 scalar_lanes = i8{};
  if (tf.log_scale) {
    scaled = v > 0.f ? log2_lanes(v) * kLog10Of2 : splat(-INFINITY);
    scalar_lanes = (v > 0.f) & ((v < kMinNormal) | (v > kMaxFloat));
  }
  f8 t = (scaled - tf.lo) * tf.inv_span;
  t = t > 0.f ? (t < 1.f ? t : splat(1.f)) : splat(0.f);
  const f8 x = t * float(tf.size - 1);
  // TfView::lookup: entries i and i + 1 (clamped; the last entry alone at the top).
  const i8 i = __builtin_convertvector(x, i8);
  const i8 last = i8{} + int32_t(tf.size - 1);
  const i8 i0 = i < last ? i : last, i1 = i + 1 < last ? i + 1 : last;
  const f8 frac = x - __builtin_convertvector(i, f8);
  const i8 at_top = i + 1 >= int32_t(tf.size);
  static_assert(sizeof(Rgba) == 4 * sizeof(float));
  const float* table = &tf.table[0].r;
  const i8 row0 = i0 * 4, row1 = i1 * 4;
  const auto entry = [&](int channel) {  // TfView::lookup's interpolation of one channel
    const f8 e0 = simd::gather<kIsa>(table, row0 + channel), e1 = simd::gather<kIsa>(table, row1 + channel);
    return at_top ? e0 : e0 + (e1 - e0) * frac;
  };
  // The opacity first: a batch wholly in the transfer function's transparent stretches (common
  // between narrow layers) needs no colour, logarithm or exponential.
  const f8 a = entry(3);
  const i8 visible = a > 0.f;
  simd::store(out.a, a);
  if (!simd::any(visible)) {
    simd::store(out.alpha, splat(0.f));
  } else {
    simd::store(out.r, entry(0));
    simd::store(out.g, entry(1));
    simd::store(out.b, entry(2));
    // corrected_alpha where the colour's alpha > 0.
    const f8 corrected = a >= 1.f ? splat(1.f) : 1.f - exp2_lanes(len * log2_lanes(1.f - a));
    simd::store(out.alpha, visible ? corrected : splat(0.f));
  }
  if (!simd::any(scalar_lanes)) return;
  for (uint32_t k = 0; k < kLanes; ++k) {
    if (!scalar_lanes[k]) continue;
    const uint32_t from = k < n ? k : n - 1;
    const Rgba color = tf.lookup(f[from]);
    out.r[k] = color.r, out.g[k] = color.g, out.b[k] = color.b, out.a[k] = color.a;
    out.alpha[k] = color.a > 0.f ? corrected_alpha(color.a, len_ref[from]) : 0.f;
  }
}

void batch_baseline(const TfView& tf, const float* f, const float* len_ref, uint32_t n, TfBatch& out) {
  batch_body<simd::Isa::baseline>(tf, f, len_ref, n, out);
}

VS_TARGET_AVX2 void batch_avx2(const TfView& tf, const float* f, const float* len_ref, uint32_t n, TfBatch& out) {
  batch_body<simd::Isa::avx2>(tf, f, len_ref, n, out);
}

}  // namespace

void tf_lookup_batch(const TfView& tf, const float* f, const float* len_ref, uint32_t n, TfBatch& out) {
  if (n == 0) return;
  (simd::use_avx2() ? batch_avx2 : batch_baseline)(tf, f, len_ref, n, out);
}

}  // namespace vs
