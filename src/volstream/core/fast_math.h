// log2 and exp2 for the CPU's per-sample work (transfer-function position on a log scale, opacity
// correction): a few multiply-adds and bit operations instead of libm calls, which a profile of a
// transparent frame put at about a third of the time per sample. On the GPU (nvcc's device pass)
// they are the hardware's log2f/exp2f, which are as fast.
//
// Error bounds (tests/render/fast_math_test.cpp checks them against double precision over every
// binade, and against log2f/exp2f):
// - fast_log2(x), x a normal positive float: |error| <= 2.5e-7 + 6e-8 |log2 x| (the second term
//   is the rounding of the float result itself, which log2f has too). x = 2^e * m with
//   m in [sqrt(1/2), sqrt(2)); log2(m) = (2 / ln 2) atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716;
//   the series to s^9 leaves (2 / ln 2) |s|^11 / 11 / (1 - s^2) < 1e-9, the rest is float
//   rounding of s, of the terms and of e + log2(m). Zero, subnormals, negatives, infinities and
//   NaN go to log2f. fast_log10 = fast_log2 * log10(2): within 8e-8 + 2e-7 |log10 x|.
// - fast_exp2(y), y <= 0: relative error <= 3e-7 for y >= -126; 0 below. y = n + f with n the
//   nearest integer, |f| <= 1/2; 2^f by its Taylor series to degree 7 (remainder
//   (ln 2 / 2)^8 / 8! < 5e-9), 2^n by the exponent bits.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "volstream/core/math.h"

namespace vs {

VS_HOST_DEVICE inline float fast_log2(float x) {
#if defined(__CUDA_ARCH__)
  return log2f(x);
#else
  constexpr float kMinNormal = 1.17549435e-38f, kMaxFloat = 3.40282347e38f;
  if (!(x >= kMinNormal && x <= kMaxFloat)) return log2f(x);  // rare: keep libm's special cases
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  // Mantissa in [sqrt(1/2), sqrt(2)): subtracting the bits of sqrt(1/2) before splitting puts
  // the cut there, so that |s| stays small on both sides of 1.
  constexpr uint32_t kSqrtHalfBits = 0x3f3504f3u;
  const uint32_t shifted = bits - kSqrtHalfBits;
  const int32_t exponent = int32_t(shifted) >> 23;  // arithmetic shift: floor for x < sqrt(1/2)
  const uint32_t mantissa_bits = (shifted & 0x007fffffu) + kSqrtHalfBits;
  float m;
  std::memcpy(&m, &mantissa_bits, sizeof m);
  const float s = (m - 1.f) / (m + 1.f);
  const float s2 = s * s, s4 = s2 * s2;
  // (2 / ln 2) (s + s^3/3 + s^5/5 + s^7/7 + s^9/9), in Estrin's order (pairs, then powers of
  // s^4): a shorter chain of dependent operations than Horner's, which bounds the sample loop.
  constexpr float c1 = 2.885390082f, c3 = 0.9617966940f, c5 = 0.5770780164f, c7 = 0.4121985831f, c9 = 0.3205988979f;
  const float poly = s * ((c1 + s2 * c3) + s4 * ((c5 + s2 * c7) + s4 * c9));
  return float(exponent) + poly;
#endif
}

VS_HOST_DEVICE inline float fast_log10(float x) {
  constexpr float kLog10Of2 = 0.30102999566f;
  return fast_log2(x) * kLog10Of2;
}

// 2^y for y <= 0 (the transmittance of an opacity correction); exact 1 at 0.
VS_HOST_DEVICE inline float fast_exp2_nonpositive(float y) {
#if defined(__CUDA_ARCH__)
  return exp2f(y);
#else
  if (!(y >= -126.f)) return y != y ? y : 0.f;  // NaN stays NaN; underflow is 0 (an opaque step)
  // Round to nearest by adding and subtracting 1.5 * 2^23 (|y| < 2^22): no libm call (rintf is
  // one on baseline x86-64).
  constexpr float kRound = 12582912.f;
  const float n = (y + kRound) - kRound;
  const float f = y - n;  // exact, |f| <= 1/2
  // 2^f = e^(f ln 2): Taylor coefficients (ln 2)^k / k!.
  constexpr float k1 = 0.6931471806f, k2 = 0.2402265070f, k3 = 0.05550410866f, k4 = 0.009618129108f,
                  k5 = 0.001333355815f, k6 = 1.540353039e-4f, k7 = 1.525273380e-5f;
  const float f2 = f * f, f4 = f2 * f2;  // Estrin's order, as in fast_log2
  const float p = ((1.f + f * k1) + f2 * (k2 + f * k3)) + f4 * ((k4 + f * k5) + f2 * (k6 + f * k7));
  const uint32_t scale_bits = uint32_t(int32_t(n) + 127) << 23;  // 2^n, n in [-126, 0]
  float scale;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  return p * scale;
#endif
}

}  // namespace vs
