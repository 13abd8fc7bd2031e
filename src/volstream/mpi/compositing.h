// The pixel arithmetic of data-parallel compositing (mpi/comm.h), apart from the messages.
#pragma once
#include <cstdint>
#include <vector>

namespace vs::mpi {

// front = front over back, per premultiplied RGBA pixel, `pixels` of them.
void blend_over(float* front, const float* back, uint64_t pixels);
// front = front over back, but the result lands in back's buffer (when the front part arrived
// in a message and the back one is local).
void blend_under(const float* front, float* back, uint64_t pixels);

// Pixel range [begin, end) of piece `i` of `pieces` equal-ish pieces of `pixels`.
struct PixelRange {
  uint64_t begin, end;
  uint64_t size() const { return end - begin; }
};
PixelRange piece(uint64_t pixels, int pieces, int i);

}  // namespace vs::mpi
