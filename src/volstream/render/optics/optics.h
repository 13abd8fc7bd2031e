// The optical models every integrator composites with, one source for CPU and CUDA: what one step
// of a ray through a homogeneous piece of the medium adds to the light carried back to the eye.
//
// - tf: a transfer function gives colour and opacity per reference step; opacity is corrected for
//   the step's true length, alpha' = 1 - (1 - alpha)^(len / ref) (paper 004, Eq. 1 for any ratio).
// - blackbody: paper 004's astrophysical model (blackbody.h): emission at the temperature (second
//   field) scaled by density (primary field), Rayleigh absorption per channel.
//
// Light is accumulated front to back as premultiplied colour and a per-channel transmittance (the
// blackbody model absorbs each channel differently; the TF model keeps the three equal).
#pragma once
#include <cmath>
#include <cstdint>

#include "volstream/core/math.h"
#include "volstream/render/optics/blackbody.h"
#include "volstream/render/optics/transfer_function.h"

namespace vs {

inline constexpr float kOpaque = 0.99f;  // early ray termination, in every channel

enum class OpticsKind : uint32_t { tf = 0, blackbody = 1 };

struct Accum {
  vec3f color{0.f, 0.f, 0.f};  // premultiplied linear RGB
  vec3f trans{1.f, 1.f, 1.f};  // transmittance per channel
  VS_HOST_DEVICE float alpha() const { return 1.f - (trans.x + trans.y + trans.z) * (1.f / 3.f); }
  // Plain comparisons, not fmaxf: its NaN rules cost instructions on the CPU (callgrind).
  VS_HOST_DEVICE bool opaque() const {
    const float t =
        trans.x > trans.y ? (trans.x > trans.z ? trans.x : trans.z) : (trans.y > trans.z ? trans.y : trans.z);
    return t <= 1.f - kOpaque;
  }
  // blend() for the transfer-function optics, whose channels keep one transmittance: one product
  // instead of three (the block march's hot loop, measured with callgrind).
  VS_HOST_DEVICE void blend_gray(float r, float g, float b, float alpha) {
    const float t = trans.x;
    const float w = t * alpha;
    color = color + vec3f(r, g, b) * w;
    trans = vec3f(t - w);
  }
  // Front-to-back "over" of a surface or step of colour (r, g, b) (straight) and opacity alpha.
  VS_HOST_DEVICE void blend(float r, float g, float b, float alpha) {
    const vec3f w = trans * alpha;
    color = color + w * vec3f(r, g, b);
    trans = trans - w;
  }
};

// alpha' = 1 - (1 - alpha)^len_ref: the table's opacity per reference step over len_ref of them.
// With core/fast_math.h's log2 and exp2 on the CPU: within 2e-6 of 1 - powf(1 - alpha, len_ref)
// for alpha in [0, 1] and len_ref in (0, 64] (tests/render/fast_math_test.cpp); whole images
// are checked against the libm definition by the golden-image tests.
VS_HOST_DEVICE inline float corrected_alpha(float alpha, float len_ref) {
  return alpha >= 1.f ? 1.f : 1.f - fast_exp2_nonpositive(len_ref * fast_log2(1.f - alpha));
}

// tf_lookup_batch's results, one array per channel, as the lanes hold them (no transposition).
struct TfBatch {
  float r[8], g[8], b[8];  // the transfer function's colour where a > 0 (else not written)
  float a[8];              // the transfer function's opacity
  float alpha[8];          // the corrected opacity
};

// CPU only: for n <= 8 samples f with step lengths len_ref (in reference steps), the transfer
// function's colour (tf.lookup) and the corrected opacity (corrected_alpha where the colour's
// alpha > 0, else 0), in SIMD lanes (tf_batch.cpp, core/simd.h): the same floats as those
// functions on either build. All 8 entries of out are written; those from n on repeat entry n-1.
void tf_lookup_batch(const TfView& tf, const float* f, const float* len_ref, uint32_t n, TfBatch& out);

// What a kernel reads of the optics: the transfer function (also used by the blackbody model's
// isosurfaces and classification) and the blackbody tables.
struct OpticsView {
  OpticsKind kind = OpticsKind::tf;
  TfView tf;
  BlackbodyView bb;

  // Does the model need the second field (the temperature) at every sample?
  VS_HOST_DEVICE bool needs_second_field() const { return kind == OpticsKind::blackbody; }
};

// Emission-absorption over a homogeneous step of len_ref reference steps, per channel:
// dI = T * E * (1 - exp(-k len)) / k, T *= exp(-k len).
VS_HOST_DEVICE inline void blackbody_step(const BlackbodyView& bb, float rho, float temperature, float len_ref,
                                          Accum& acc) {
  const float rn = bb.normalised_density(rho);
  if (!(rn > 0.f)) return;
  const float re = bb.emission_power == 1.f ? rn : powf(rn, bb.emission_power);
  const vec3f e = bb.color(temperature) * (bb.emission * re);
  for (int c = 0; c < 3; ++c) {
    const float k = bb.absorption * rn * bb.rayleigh[c];
    const float x = k * len_ref;
    const float tr = expf(-x);
    const float path = x > 1e-4f ? (1.f - tr) / k : len_ref;  // integral of exp(-k s) over the step
    acc.color[c] += acc.trans[c] * e[c] * path;
    acc.trans[c] *= tr;
  }
}

}  // namespace vs
