#include "volstream/backend/buffer.h"

#include <gtest/gtest.h>

#include "volstream/backend/backend.h"
#include "volstream/cuda/backend.h"

namespace vs {
namespace {

int64_t counted(const std::string& structure, MemorySpace space) {
  for (const MemoryEntry& e : memory_ledger().snapshot())
    if (e.structure == structure) return e.bytes[int(space)];
  return 0;
}

void round_trip(Device device, MemorySpace space) {
  const Backend backend(device);
  const std::vector<double> values = {1.5, -2.0, 3.25, 1e300};
  {
    Buffer<double> b = backend.buffer<double>("buffer test");
    b.upload(values);
    EXPECT_EQ(b.size(), values.size());
    EXPECT_EQ(counted("buffer test", space), int64_t(values.size() * sizeof(double)));
    Buffer<double> moved = std::move(b);
    EXPECT_EQ(moved.download(), values);
    EXPECT_EQ(counted("buffer test", space), int64_t(values.size() * sizeof(double)));
  }
  EXPECT_EQ(counted("buffer test", space), 0);
}

TEST(Buffer, RoundTripsAndCountsOnTheCpu) { round_trip(Device::cpu, MemorySpace::host); }

TEST(BufferCuda, RoundTripsAndCountsOnTheGpu) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  round_trip(Device::cuda, MemorySpace::device);
}

}  // namespace
}  // namespace vs
