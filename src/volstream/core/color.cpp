#include "volstream/core/color.h"

#include <algorithm>
#include <cmath>

namespace vs {

float srgb_to_linear(float c) {
  c = std::clamp(c, 0.f, 1.f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  c = std::clamp(c, 0.f, 1.f);
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
}

}  // namespace vs
