#include "volstream/core/simd.h"

#include <atomic>
#include <cstdlib>

namespace vs::simd {
namespace {

bool cpu_has_avx2() {
#if VS_HAVE_AVX2_BUILD
  __builtin_cpu_init();  // may run before main (static initialisation)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

bool baseline_from_environment() {
  const char* e = std::getenv("VOLSTREAM_CPU_BASELINE");
  return e && e[0] == '1';
}

const bool g_cpu_has_avx2 = cpu_has_avx2();
std::atomic<bool> g_force_baseline{baseline_from_environment()};

}  // namespace

bool use_avx2() { return g_cpu_has_avx2 && !g_force_baseline.load(std::memory_order_relaxed); }

const char* isa() { return use_avx2() ? "avx2" : "baseline"; }

void force_baseline(bool on) { g_force_baseline.store(on, std::memory_order_relaxed); }

}  // namespace vs::simd
