#include "volstream/render/optics/blackbody.h"

#include <algorithm>
#include <cmath>

namespace vs {
namespace {

// Johnson-Cousins passbands (normalised response) from Bessell, M. S. 1990, PASP 102, 1181,
// "UBVRI passbands", Table 2 (B and V every 10 nm; R every 10 nm to 750 nm, then 50 nm).
// {wavelength nm, response}; the responses are zero outside the tabulated ranges. The same
// numbers as the SVO Filter Profile Service's Generic/Bessell.B, .V, .R and sncosmo's bessell_r.
using Sample = PassbandSample;
constexpr Sample kB[] = {{360, 0.000f}, {370, 0.030f}, {380, 0.134f}, {390, 0.567f}, {400, 0.920f}, {410, 0.978f},
                         {420, 1.000f}, {430, 0.978f}, {440, 0.935f}, {450, 0.853f}, {460, 0.740f}, {470, 0.640f},
                         {480, 0.536f}, {490, 0.424f}, {500, 0.325f}, {510, 0.235f}, {520, 0.150f}, {530, 0.095f},
                         {540, 0.043f}, {550, 0.009f}, {560, 0.000f}};
constexpr Sample kV[] = {{470, 0.000f}, {480, 0.030f}, {490, 0.163f}, {500, 0.458f}, {510, 0.780f}, {520, 0.967f},
                         {530, 1.000f}, {540, 0.973f}, {550, 0.898f}, {560, 0.792f}, {570, 0.684f}, {580, 0.574f},
                         {590, 0.461f}, {600, 0.359f}, {610, 0.270f}, {620, 0.197f}, {630, 0.135f}, {640, 0.081f},
                         {650, 0.045f}, {660, 0.025f}, {670, 0.017f}, {680, 0.013f}, {690, 0.009f}, {700, 0.000f}};
constexpr Sample kR[] = {{550, 0.00f}, {560, 0.23f}, {570, 0.74f}, {580, 0.91f}, {590, 0.98f}, {600, 1.00f},
                         {610, 0.98f}, {620, 0.96f}, {630, 0.93f}, {640, 0.90f}, {650, 0.86f}, {660, 0.81f},
                         {670, 0.78f}, {680, 0.72f}, {690, 0.67f}, {700, 0.61f}, {710, 0.56f}, {720, 0.51f},
                         {730, 0.46f}, {740, 0.40f}, {750, 0.35f}, {800, 0.14f}, {850, 0.03f}, {900, 0.00f}};

// log of Planck's B_lambda up to a constant: -5 ln(lambda) - ln(exp(hc / lambda k T) - 1).
double log_planck(double nm, double t) {
  constexpr double hc_over_k = 1.438777e7;  // nm K (second radiation constant)
  const double x = hc_over_k / (nm * t);
  const double log_denominator = x > 30 ? x : std::log(std::expm1(x));
  return -5.0 * std::log(nm) - log_denominator;
}

// log of the band mean: integral of B_lambda T(lambda) over integral of T(lambda), trapezoid rule
// on a 1 nm grid (log-sum-exp so that cold temperatures do not underflow). Dividing by the
// filter's area makes a flat spectrum white, so the broad R band does not redden every colour.
double log_band_mean(std::span<const Sample> f, double t) {
  std::vector<double> logs, weights;
  for (size_t i = 0; i + 1 < f.size(); ++i)
    for (int k = 0; k < int(f[i + 1].nm - f[i].nm); ++k) {
      const double nm = f[i].nm + k + 0.5;
      const double w = f[i].response + (f[i + 1].response - f[i].response) * (nm - f[i].nm) / (f[i + 1].nm - f[i].nm);
      if (w <= 0) continue;
      logs.push_back(log_planck(nm, t) + std::log(w));
      weights.push_back(w);
    }
  const double m = *std::max_element(logs.begin(), logs.end());
  double sum = 0, area = 0;
  for (size_t i = 0; i < logs.size(); ++i) {
    sum += std::exp(logs[i] - m);
    area += weights[i];
  }
  return m + std::log(sum) - std::log(area);
}

}  // namespace

std::span<const PassbandSample> passband(Band band) {
  switch (band) {
    case Band::B:
      return kB;
    case Band::V:
      return kV;
    case Band::R:
      return kR;
  }
  return {};
}

vec3f blackbody_rgb(double temperature_k) {
  const double r = log_band_mean(kR, temperature_k), g = log_band_mean(kV, temperature_k),
               b = log_band_mean(kB, temperature_k);
  const double m = std::max({r, g, b});  // the paper's F_i / max(F): strongest channel 1
  return {float(std::exp(r - m)), float(std::exp(g - m)), float(std::exp(b - m))};
}

vec3f rayleigh_weights() {
  auto w = [](float nm) { return std::pow(kLambdaG / nm, 4.f); };
  return {w(kLambdaR), w(kLambdaG), w(kLambdaB)};
}

BlackbodyTable::BlackbodyTable(uint32_t size) {
  entries_.resize(std::max<uint32_t>(size, 2));
  for (size_t i = 0; i < entries_.size(); ++i) {
    const double lt =
        kBlackbodyLogTMin + (kBlackbodyLogTMax - kBlackbodyLogTMin) * double(i) / double(entries_.size() - 1);
    entries_[i] = blackbody_rgb(std::pow(10.0, lt));
  }
}

BlackbodyView BlackbodyTable::view(const BlackbodyParams& p) const {
  BlackbodyView v;
  v.table = entries_.data();
  v.size = uint32_t(entries_.size());
  v.inv_rho_max = p.rho_max > 0.f ? 1.f / p.rho_max : 1.f;
  v.log_decades = p.log_decades;
  v.emission_power = p.emission_power;
  v.emission = p.emission;
  v.absorption = p.absorption;
  v.rayleigh = rayleigh_weights();
  return v;
}

vec3f rayleigh_transmittance(float absorption, float rho_over_max, float length_in_ref_steps) {
  const vec3f w = rayleigh_weights();
  const float k = absorption * rho_over_max * length_in_ref_steps;
  return {std::exp(-k * w.x), std::exp(-k * w.y), std::exp(-k * w.z)};
}

const BlackbodyTable& default_blackbody_table() {
  static const BlackbodyTable table;
  return table;
}

}  // namespace vs
