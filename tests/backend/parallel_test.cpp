#include "volstream/backend/parallel.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
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
  for (const int64_t n : {0, 1, 5, 255, 256, 257, 4096, 4097, 100000}) {
    for (const int failures : {0, 1, 2, 3, 50}) {
      std::vector<uint8_t> ok(size_t(n), 1);
      for (int f = 0; f < failures && n > 0; ++f) ok[rng() % uint64_t(n)] = 0;
      for (const int64_t grain : {int64_t(1), int64_t(4096)}) {
        SCOPED_TRACE(testing::Message() << n << " items, " << failures << " failures, grain " << grain);
        EXPECT_EQ(first_failing(
                      n, [&](int64_t i) { return ok[size_t(i)] != 0; }, grain),
                  first_failing_serially(ok));
      }
    }
  }
}

// Whichever task fails sooner, the error is the serial order's first.
TEST(Parallel, InvokeInOrderThrowsTheFirstTasksErrorFirst) {
  for (int round = 0; round < 20; ++round) {
    try {
      parallel_invoke_in_order([] { throw std::runtime_error("first"); }, [] { throw std::runtime_error("second"); });
      FAIL() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "first");
    }
  }
  int ran = 0;
  EXPECT_THROW(parallel_invoke_in_order([&] { ++ran; }, [] { throw std::logic_error("second"); }), std::logic_error);
  EXPECT_EQ(ran, 1);
  std::atomic<int> both{0};
  parallel_invoke_in_order([&] { ++both; }, [&] { ++both; });
  EXPECT_EQ(both.load(), 2);
}

// Every item runs once; the error is the smallest failing item's, as the serial loop's would be.
TEST(Parallel, EachInOrderThrowsTheFirstItemsError) {
  for (int round = 0; round < 20; ++round) {
    std::vector<std::atomic<int>> runs(64);
    try {
      parallel_each_in_order(64, [&](int64_t i) {
        ++runs[size_t(i)];
        if (i % 10 == 7) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 7");
    }
    for (const std::atomic<int>& r : runs) EXPECT_EQ(r.load(), 1);
  }
  parallel_each_in_order(0, [](int64_t) { FAIL(); });
}

}  // namespace
}  // namespace vs
