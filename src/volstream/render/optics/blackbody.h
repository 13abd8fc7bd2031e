// The astrophysical optical model of paper 004 (Sect. 5.1): gas emits a blackbody spectrum at its
// temperature seen through Johnson-Cousins R, V, B filters (Bessell 1990; as R, G, B), scaled by
// density / max density, and absorbs (Rayleigh scattering out of the line of sight) in proportion
// to density and lambda^-4.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "volstream/core/math.h"

namespace vs {

inline constexpr float kBlackbodyLogTMin = 2.f, kBlackbodyLogTMax = 8.f;  // table over 1e2 .. 1e8 K
// Effective wavelengths (nm) of R, V, B for Vega's (A0) spectrum F: lambda_eff = int lambda T F /
// int T F over the response T (the SVO Filter Profile Service gives 544.6 nm and 641.4 nm for
// these V and R curves). Not the plain response-weighted mean int lambda T / int T (441, 551 and
// 659 nm): the filters' red tails pull that up, most of all in R. For the Rayleigh weights these
// are the apt ones: the band average of lambda^-4 over a flat spectrum corresponds to 434, 546
// and 645 nm. blocks_test.cpp (Blackbody.FilterTablesMatchPublishedBands) checks all of this.
inline constexpr float kLambdaR = 641.f, kLambdaG = 545.f, kLambdaB = 438.f;

// The tabulated filter responses: {nm, response} samples, linear in between, zero outside.
struct PassbandSample {
  float nm, response;
};
enum class Band { B, V, R };
std::span<const PassbandSample> passband(Band band);

// Blackbody colour (R, G, B) at temperature T: the filter-weighted mean of B_lambda over each band,
// normalised so that the strongest channel is 1. Computed in log space: no underflow at 100 K.
vec3f blackbody_rgb(double temperature_k);

// Rayleigh cross-sections per channel relative to V: (lambda_V / lambda)^4 (B > V > R).
vec3f rayleigh_weights();

// What a kernel reads: emission colour over log10 T (linear lookup) and the absorption weights.
struct BlackbodyView {
  const vec3f* table = nullptr;
  uint32_t size = 0;
  float inv_rho_max = 1.f;  // density / rho_max: the normalised density of the paper
  // > 0: normalise on a log scale instead, over this many decades below rho_max, for data whose
  // density spans many decades (cosmology: linear rho / rho_max shows only the densest peaks).
  float log_decades = 0.f;
  // Emission uses normalised density^emission_power (1: the paper). On a log scale a power > 1
  // keeps the diffuse gas from glowing as brightly as the clumps; absorption stays linear, so
  // that thin cool gas still darkens what lies behind it.
  float emission_power = 1.f;
  float emission = 1.f;    // emission per reference step at rho = rho_max
  float absorption = 1.f;  // extinction (V band) per reference step at rho = rho_max
  vec3f rayleigh{1.f, 1.f, 1.f};

  // Density mapped to [0, 1]: rho / rho_max, or its log10 position over log_decades.
  VS_HOST_DEVICE float normalised_density(float rho) const {
    if (!(rho > 0.f)) return 0.f;
    const float r = rho * inv_rho_max;
    if (!(log_decades > 0.f)) return r < 1.f ? r : 1.f;
    const float x = 1.f + log10f(r) / log_decades;
    return x > 0.f ? (x < 1.f ? x : 1.f) : 0.f;
  }

  VS_HOST_DEVICE vec3f color(float temperature) const {
    const float lt = temperature > 0.f ? log10f(temperature) : kBlackbodyLogTMin;
    float x = (lt - kBlackbodyLogTMin) / (kBlackbodyLogTMax - kBlackbodyLogTMin) * float(size - 1);
    x = x > 0.f ? (x < float(size - 1) ? x : float(size - 1)) : 0.f;
    const uint32_t i = uint32_t(x);
    if (i + 1 >= size) return table[size - 1];
    const float f = x - float(i);
    return table[i] * (1.f - f) + table[i + 1] * f;
  }
};

// The model's parameters (BlackbodyView has their meaning).
struct BlackbodyParams {
  float rho_max = 1.f;  // density normalising emission and absorption
  float emission = 1.f, absorption = 1.f;
  float emission_power = 1.f;
  float log_decades = 0.f;  // > 0: density on a log scale
};

class BlackbodyTable {
 public:
  explicit BlackbodyTable(uint32_t size = 512);
  BlackbodyView view(const BlackbodyParams& params) const;
  const std::vector<vec3f>& entries() const { return entries_; }

 private:
  std::vector<vec3f> entries_;
};

// The default table (512 entries), made on first use (a few Planck integrals per entry, some
// 40 M instructions) and shared by every renderer: frames without blackbody optics never pay it.
const BlackbodyTable& default_blackbody_table();

// Transmittance (R, G, B) of a homogeneous slab: the reddening of white light by Rayleigh
// absorption, exp(-absorption * rho/rho_max * length * weight_c). For tests and the docs.
vec3f rayleigh_transmittance(float absorption, float rho_over_max, float length_in_ref_steps);

}  // namespace vs
