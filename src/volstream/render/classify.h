// Classification of ABRs for empty-space skipping, one function for the CPU and the GPU.
#pragma once
#include "volstream/amr/model.h"
#include "volstream/render/integrators/settings.h"
#include "volstream/render/optics/transfer_function.h"

namespace vs {

// An ABR is visible when the transfer function gives some value of its range non-zero opacity,
// or its range contains one of the iso values. Empty ranges (no finite value) are invisible.
VS_HOST_DEVICE inline bool abr_visible(const Range& r, const OpacityIndex& opacity, const IntegratorSettings& iso) {
  if (opacity.any(r.lo, r.hi)) return true;
  for (uint32_t k = 0; k < iso.iso_count && k < kMaxIso; ++k)
    if (r.lo <= iso.iso[k] && iso.iso[k] <= r.hi) return true;
  return false;
}

}  // namespace vs
