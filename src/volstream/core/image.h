// A rendered image in memory: premultiplied linear RGBA floats (files: io/image.h).
#pragma once
#include <cstdint>
#include <vector>

namespace vs {

struct Image {
  uint32_t width = 0, height = 0;
  std::vector<float> rgba;  // premultiplied linear RGBA, rows top to bottom
  Image() = default;
  Image(uint32_t w, uint32_t h) : width(w), height(h), rgba(size_t(w) * h * 4, 0.f) {}
  const float* pixel(uint32_t x, uint32_t y) const { return rgba.data() + 4 * (size_t(y) * width + x); }
};

}  // namespace vs
