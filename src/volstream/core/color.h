// sRGB transfer functions (IEC 61966-2-1): colour maps are given sRGB-encoded, rendering is linear.
#pragma once

namespace vs {

float srgb_to_linear(float c);
float linear_to_srgb(float c);

}  // namespace vs
