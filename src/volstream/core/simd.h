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

#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpsabi"
#elif defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace vs::simd {

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

// True where the AVX2 builds should run: the CPU has AVX2 and the baseline is not forced.
bool use_avx2();
// "avx2" or "baseline": what use_avx2() chooses now.
const char* isa();
// Run the baseline builds whatever the CPU (tests: a CPU without AVX2). The environment's
// VOLSTREAM_CPU_BASELINE=1 sets it at start-up (benchmarks).
void force_baseline(bool on);

}  // namespace vs::simd
