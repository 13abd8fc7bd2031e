// CPU only (never included by CUDA code): 8 float/int lanes as GCC/Clang vector extensions, and
// the run-time choice between a function's baseline x86-64 build and its AVX2 build.
//
// A file with a SIMD kernel writes its body once as an always-inlined function over these lanes
// and two entry points calling it, one plain and one marked VS_TARGET_AVX2 (ISA flags only: no
// arch=, so the headers' inline functions keep inlining into it; no FMA, so nothing is
// contracted and both builds give the same floats), then calls
// `(simd_use_avx2() ? entry_avx2 : entry_baseline)(...)`. Lanes never cross a call (everything
// over them is inlined into the entry points), so the AVX calling-convention note (-Wpsabi)
// does not apply and is silenced here.
#pragma once
#include <cstdint>

#include "volstream/core/math.h"

#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpsabi"
#elif defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace vs::simd {

// 4 float lanes (a 3-vector's x, y, z and one unused, or a wide BVH node's 4 children): one SSE
// register on x86-64.
typedef float f4 __attribute__((vector_size(16)));
typedef int32_t i4 __attribute__((vector_size(16)));
// A 3-vector on lanes x, y, z, with 0 in the fourth.
VS_FORCE_INLINE f4 lanes_of(const vec3f& v) { return f4{v.x, v.y, v.z, 0.f}; }

inline constexpr uint32_t kLanes = 8;
typedef float f8 __attribute__((vector_size(kLanes * sizeof(float))));
typedef int32_t i8 __attribute__((vector_size(kLanes * sizeof(int32_t))));
typedef uint32_t u8 __attribute__((vector_size(kLanes * sizeof(uint32_t))));

#if defined(__x86_64__) && defined(__GNUC__)
#define VS_HAVE_AVX2_BUILD 1
#define VS_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define VS_HAVE_AVX2_BUILD 0
#define VS_TARGET_AVX2
#endif

// The instruction set a kernel body is instantiated for: a body templated on it uses AVX2's
// instructions (gathers) only in the build that runs where the CPU has them.
enum class Isa { baseline, avx2 };

// base[index[k]] for each lane: one AVX2 gather instruction, or eight loads in the baseline build
// (the same values either way). The gather is written as assembly: its intrinsic may not be
// inlined into this body, which is not itself marked for AVX2 (only the entry points are), and
// GCC checks an assembly operand's register size only where the body lands, in an AVX2 entry
// point. Clang checks it in the body, so Clang's builds (the sanitizer build) take the loads.
template <Isa kIsa>
VS_FORCE_INLINE f8 gather(const float* base, const i8& index) {
#if VS_HAVE_AVX2_BUILD && !defined(__clang__)
  if constexpr (kIsa == Isa::avx2) {
    f8 out, mask;  // mask: all lanes (the instruction clears it as it loads)
    __asm__("vpcmpeqd %[m], %[m], %[m]\n\tvgatherdps %[m], (%[b],%[i],4), %[d]"
            : [d] "=&x"(out), [m] "=&x"(mask)
            : [b] "r"(base), [i] "x"(index)
            : "memory");
    return out;
  }
#endif
  f8 out;
  for (uint32_t k = 0; k < kLanes; ++k) out[k] = base[index[k]];
  return out;
}

// p[0..n) into lanes (1 <= n <= 8); lanes n..7 repeat p[n - 1], so that they hold a value of
// the batch (valid indices and no spurious special values).
VS_FORCE_INLINE f8 load_lanes(const float* p, uint32_t n) {
  f8 out;
  if (n == kLanes) {
    __builtin_memcpy(&out, p, sizeof out);
    return out;
  }
  for (uint32_t k = 0; k < kLanes; ++k) out[k] = p[k < n ? k : n - 1];
  return out;
}
VS_FORCE_INLINE void store(float* out, const f8& lanes) { __builtin_memcpy(out, &lanes, sizeof lanes); }
// Is any lane of a comparison's mask set?
VS_FORCE_INLINE bool any(const i8& mask) {
  int32_t acc = 0;
  for (uint32_t k = 0; k < kLanes; ++k) acc |= mask[k];
  return acc != 0;
}

// Are all lanes of a and b equal?
VS_FORCE_INLINE bool all_equal(const i4& a, const i4& b) {
  const i4 same = a == b;
  return (same[0] & same[1] & same[2] & same[3]) != 0;
}

// True where the AVX2 builds should run: the CPU has AVX2 and the baseline is not forced.
bool use_avx2();
// "avx2" or "baseline": what use_avx2() chooses now.
const char* isa();
// Run the baseline builds whatever the CPU (tests: a CPU without AVX2). The environment's
// VOLSTREAM_CPU_BASELINE=1 sets it at start-up (benchmarks).
void force_baseline(bool on);

}  // namespace vs::simd
