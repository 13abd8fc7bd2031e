#include "volstream/mpi/compositing.h"

namespace vs::mpi {

void blend_over(float* front, const float* back, uint64_t pixels) {
  for (uint64_t p = 0; p < pixels; ++p) {
    float* f = front + 4 * p;
    const float* b = back + 4 * p;
    const float t = 1.f - f[3];
    for (int c = 0; c < 4; ++c) f[c] += t * b[c];
  }
}

void blend_under(const float* front, float* back, uint64_t pixels) {
  for (uint64_t p = 0; p < pixels; ++p) {
    const float* f = front + 4 * p;
    float* b = back + 4 * p;
    const float t = 1.f - f[3];
    for (int c = 0; c < 4; ++c) b[c] = f[c] + t * b[c];
  }
}

PixelRange piece(uint64_t pixels, int pieces, int i) {
  return {pixels * uint64_t(i) / uint64_t(pieces), pixels * uint64_t(i + 1) / uint64_t(pieces)};
}

}  // namespace vs::mpi
