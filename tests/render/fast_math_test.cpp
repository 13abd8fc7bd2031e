// core/fast_math.h and the opacity correction built on it, against double-precision libm and the
// powf definition, with the error bounds the header states.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "volstream/core/fast_math.h"
#include "volstream/core/simd.h"
#include "volstream/render/optics/optics.h"

namespace vs {
namespace {

bool same_float(float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

TEST(FastMath, Log2WithinItsBoundOverEveryBinade) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> mantissa(1.f, 2.f);
  double worst = 0;
  for (int e = -126; e <= 127; ++e) {
    for (int i = 0; i < 2000; ++i) {
      // Random mantissas plus the edges of the [sqrt(1/2), sqrt(2)) cut and of the binade.
      float m = i == 0   ? 1.f
                : i == 1 ? std::nextafter(2.f, 0.f)
                : i == 2 ? 1.41421354f
                : i == 3 ? 1.41421366f
                         : mantissa(rng);
      const float x = std::ldexp(m, e);
      if (!std::isfinite(x)) continue;
      const double exact = std::log2(double(x));
      const double err = std::abs(double(fast_log2(x)) - exact);
      const double bound = 2.5e-7 + 6e-8 * std::abs(exact);
      ASSERT_LE(err, bound) << "x = " << x;
      worst = std::max(worst, err - 6e-8 * std::abs(exact));
      // log10 = log2 * log10(2) in float: the absolute part scaled, and a few ulps of the
      // result (log2's rounding, the product's, the constant's): 2e-7 relative.
      ASSERT_NEAR(double(fast_log10(x)), std::log10(double(x)),
                  0.30103 * 2.5e-7 + 2e-7 * std::abs(std::log10(double(x))))
          << "x = " << x;
    }
  }
  std::printf("fast_log2: worst error beyond the result's own rounding %.3g\n", worst);
}

TEST(FastMath, Log2NearOneIsRelativelyAccurate) {
  // alpha' = 1 - (1 - alpha)^L needs log2(1 - alpha) for tiny alpha: no absolute floor there.
  for (float a = 1e-7f; a < 0.3f; a *= 1.37f) {
    const float x = 1.f - a;
    const double exact = std::log2(double(x));
    ASSERT_NEAR(fast_log2(x), exact, 4e-7 * std::abs(exact)) << "x = 1 - " << a;
  }
}

TEST(FastMath, Log2SpecialValuesAsLibm) {
  const float inf = std::numeric_limits<float>::infinity();
  for (float x :
       {0.f, -0.f, -1.f, -inf, inf, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min(),
        1e-40f, std::numeric_limits<float>::max(), std::numeric_limits<float>::min()}) {
    if (x == std::numeric_limits<float>::max() || x == std::numeric_limits<float>::min())
      EXPECT_NEAR(fast_log2(x), log2f(x), 1e-5) << x;
    else
      EXPECT_TRUE(same_float(fast_log2(x), log2f(x))) << x << ": " << fast_log2(x) << " vs " << log2f(x);
  }
  EXPECT_EQ(fast_log2(1.f), 0.f);
  EXPECT_EQ(fast_log2(1024.f), 10.f);
}

TEST(FastMath, Exp2WithinItsBound) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (int n = 0; n > -127; --n) {
    for (int i = 0; i < 2000; ++i) {
      const float y = i == 0 ? float(n) : i == 1 ? float(n) - 0.5f : float(n) - unit(rng);
      if (y < -126.f) continue;
      const double exact = std::exp2(double(y));
      ASSERT_LE(std::abs(double(fast_exp2_nonpositive(y)) - exact), 3e-7 * exact) << "y = " << y;
    }
  }
  EXPECT_EQ(fast_exp2_nonpositive(0.f), 1.f);
  EXPECT_EQ(fast_exp2_nonpositive(-0.f), 1.f);
  EXPECT_EQ(fast_exp2_nonpositive(-127.f), 0.f);
  EXPECT_EQ(fast_exp2_nonpositive(-std::numeric_limits<float>::infinity()), 0.f);
  EXPECT_TRUE(std::isnan(fast_exp2_nonpositive(std::numeric_limits<float>::quiet_NaN())));
}

TEST(FastMath, CorrectedAlphaWithinTwoMillionthsOfThePowfDefinition) {
  double worst = 0;
  for (int i = 0; i <= 4000; ++i) {
    // Dense over [0, 1], plus opacities within a few ulps of 0 and 1.
    const float a = i < 3990 ? float(i) / 3989.f : i < 3995 ? 1e-7f * float(i - 3989) : 1.f - 6e-8f * float(i - 3994);
    for (float len = 1.f / 64.f; len <= 64.f; len *= 1.21f) {
      const double exact = 1.0 - std::pow(1.0 - double(a), double(len));
      const double err = std::abs(double(corrected_alpha(a, len)) - exact);
      ASSERT_LE(err, 2e-6) << "alpha " << a << " len " << len;
      // The libm form it replaces is no closer than the bound either way.
      ASSERT_LE(std::abs(double(1.f - powf(1.f - a, len)) - exact), 2e-6);
      worst = std::max(worst, err);
    }
  }
  std::printf("corrected_alpha: worst error %.3g\n", worst);
  EXPECT_EQ(corrected_alpha(0.f, 3.f), 0.f);
  EXPECT_EQ(corrected_alpha(1.f, 0.5f), 1.f);
}

// The batch form the CPU's march uses (optics.h, tf_lookup_batch) gives TfView::lookup's colour
// and corrected_alpha's opacity bit for bit on both builds, on a linear and a log scale, for
// values of every kind (zero, negative, subnormal, infinite, NaN, beyond the range).
TEST(FastMath, TransferBatchEqualsTheScalarFunctionsOnEveryBuild) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const float inf = std::numeric_limits<float>::infinity();
  for (bool log_scale : {false, true}) {
    TransferFunctionSpec spec;
    spec.colors = builtin_color_map("viridis");
    spec.opacity = {{0.f, 0.f}, {0.3f, 0.9f}, {0.5f, 0.f}, {0.7f, 1.f}, {1.f, 0.4f}};
    spec.lo = log_scale ? 1e-4f : -2.f;
    spec.hi = log_scale ? 10.f : 3.f;
    spec.log_scale = log_scale;
    const TransferTable table(spec);
    const TfView tf = table.view();
    for (bool baseline : {true, false}) {
      simd::force_baseline(baseline);
      for (int batch = 0; batch < 400; ++batch) {
        float f[8], len[8];
        TfBatch out;
        const uint32_t n = 1 + uint32_t(batch) % 8;
        for (uint32_t k = 0; k < n; ++k) {
          const float u = unit(rng);
          f[k] = batch < 8 && k == 0 ? std::array<float, 8>{0.f, -1.f, 1e-40f, inf, NAN, 1e9f, 1e-30f, -inf}[batch]
                 : log_scale         ? std::pow(10.f, -5.f + 7.f * u)
                                     : -3.f + 7.f * u;
          len[k] = 0.05f + 4.f * unit(rng);
        }
        tf_lookup_batch(tf, f, len, n, out);
        for (uint32_t k = 0; k < 8; ++k) {  // entries from n on repeat entry n - 1
          const uint32_t from = std::min(k, n - 1);
          const Rgba c = tf.lookup(f[from]);
          const float a = c.a > 0.f ? corrected_alpha(c.a, len[from]) : 0.f;
          ASSERT_TRUE(same_float(out.a[k], c.a)) << simd::isa() << " f " << f[from];
          if (c.a > 0.f) {  // the colour of a transparent sample is not needed
            ASSERT_TRUE(same_float(out.r[k], c.r) && same_float(out.g[k], c.g) && same_float(out.b[k], c.b))
                << simd::isa() << " f " << f[from];
          }
          ASSERT_TRUE(same_float(out.alpha[k], a))
              << simd::isa() << " f " << f[from] << ": " << out.alpha[k] << " vs " << a;
        }
      }
    }
  }
  simd::force_baseline(false);
}

}  // namespace
}  // namespace vs
