#include "volstream/backend/parallel.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace vs {
namespace {

// The serial loop's answer: the reference first_failing must equal.
int64_t first_failing_serially(const std::vector<uint8_t>& ok) {
  for (size_t i = 0; i < ok.size(); ++i)
    if (!ok[i]) return int64_t(i);
  return -1;
}

TEST(Parallel, FirstFailingIsTheSerialLoopsAnswer) {
  std::mt19937 rng(7);
  for (const int64_t n : {0, 1, 5, 4096, 4097, 100000}) {
    for (const int failures : {0, 1, 3, 50}) {
      std::vector<uint8_t> ok(size_t(n), 1);
      for (int f = 0; f < failures && n > 0; ++f) ok[rng() % uint64_t(n)] = 0;
      for (const int64_t grain : {int64_t(1), int64_t(4096)}) {
        SCOPED_TRACE(testing::Message() << n << " items, " << failures << " failures, grain " << grain);
        EXPECT_EQ(first_failing(n, [&](int64_t i) { return ok[size_t(i)] != 0; }, grain), first_failing_serially(ok));
      }
    }
  }
}

}  // namespace
}  // namespace vs
