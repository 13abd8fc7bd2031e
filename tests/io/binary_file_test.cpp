// Records read and mapped (io/binary_file.h) and the arrays that hold them (core/host_array.h):
// a mapped file reads as the read one, a short or long file is refused by both, and writing to
// a view copies it first, leaving the file alone; gzip streams inflate up to a cap, the first
// bytes of a long one are read alone, and a damaged one is refused.
#include <gtest/gtest.h>
#include <zlib.h>

#include <numeric>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"

namespace vs {
namespace {

std::filesystem::path file_of(const std::vector<uint32_t>& values, const char* name) {
  const auto path = test::scratch_dir("binary_file") / name;
  write_file(path, values.data(), values.size() * sizeof(uint32_t));
  return path;
}

std::vector<uint32_t> counting(size_t n) {
  std::vector<uint32_t> v(n);
  std::iota(v.begin(), v.end(), 7u);
  return v;
}

TEST(MapRecords, ReadsAsReadRecordsDoes) {
  const std::vector<uint32_t> values = counting(50000);  // several pages
  const auto path = file_of(values, "values.bin");
  const HostArray<uint32_t> mapped = map_records<uint32_t>(path, values.size());
  EXPECT_TRUE(mapped.is_view());
  EXPECT_EQ(mapped, HostArray<uint32_t>(read_records<uint32_t>(path, values.size())));
  EXPECT_EQ(mapped.at(49999), 7u + 49999u);
  EXPECT_THROW(mapped.at(50000), std::out_of_range);
}

TEST(MapRecords, RefusesAFileOfAnotherSize) {
  const auto path = file_of(counting(100), "hundred.bin");
  EXPECT_THROW(map_records<uint32_t>(path, 99), InputError);
  EXPECT_THROW(map_records<uint32_t>(path, 101), InputError);
  EXPECT_THROW(map_records<uint32_t>(path.parent_path() / "missing.bin", 1), InputError);
  EXPECT_TRUE(map_records<uint32_t>(file_of({}, "empty.bin"), 0).empty());
}

// Exact reads: a range inside the file, a range past its end refused, and zero bytes read as
// nothing (into an empty vector's data(), which may be null) anywhere in the file or past it.
TEST(ReadExact, ReadsTheRangeRefusesPastTheEndAndReadsNothingForZeroBytes) {
  const auto path = file_of(counting(10), "ten.bin");
  uint32_t two[2] = {};
  read_exact(path, 3 * sizeof(uint32_t), two, sizeof two);
  EXPECT_EQ(two[0], 10u);
  EXPECT_EQ(two[1], 11u);
  EXPECT_THROW(read_exact(path, 9 * sizeof(uint32_t), two, sizeof two), InputError);
  std::vector<uint32_t> none;
  EXPECT_NO_THROW(read_exact(path, 0, none.data(), 0));
  EXPECT_NO_THROW(read_exact(path, 1000, nullptr, 0));
  EXPECT_TRUE(read_records<uint32_t>(file_of({}, "empty_records.bin"), 0).empty());
}

std::filesystem::path gzip_of(const std::string& bytes, const char* name) {
  const auto path = test::scratch_dir("binary_file") / name;
  gzFile gz = gzopen(path.c_str(), "wb");
  EXPECT_TRUE(gz);
  EXPECT_EQ(gzwrite(gz, bytes.data(), unsigned(bytes.size())), int(bytes.size()));
  gzclose(gz);
  return path;
}

// A gzip bomb's work: 4 MiB of zeros is a 4 KiB file; refused past its cap, read below it, and
// its first bytes read alone (a long data file's settings) whatever its length.
TEST(ReadFileInflating, InflatesUpToTheCapAndRefusesPastIt) {
  const std::string zeros(4 << 20, '\0');
  const auto path = gzip_of(zeros, "zeros.dat.GZ");
  EXPECT_LT(std::filesystem::file_size(path), 64u << 10);
  EXPECT_EQ(read_file_inflating(path, UINT64_MAX, 8 << 20), zeros);
  try {
    read_file_inflating(path, UINT64_MAX, 1 << 20);
    ADD_FAILURE() << "inflated past its cap";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "the gzip stream inflates past 1 MiB, more than this reader holds at once; gunzip it first if it is "
              "meant");
  }
  EXPECT_EQ(read_file_inflating(path, 1000, 1 << 20), std::string(1000, '\0'));
  const auto plain = file_of(counting(10), "plain.dat");
  EXPECT_EQ(read_file_inflating(plain, 8).size(), 8u);
}

TEST(ReadFileInflating, RefusesADamagedStream) {
  const auto path = gzip_of(std::string(100000, 'x') + "end", "cut.gz");
  std::string bytes = read_text_file(path);
  bytes.resize(bytes.size() / 2);
  write_file(path, bytes.data(), bytes.size());
  EXPECT_THROW(read_file_inflating(path), InputError);
  EXPECT_THROW(read_file_inflating(path.parent_path() / "missing.gz"), InputError);
}

TEST(HostArray, WritingToAViewCopiesItAndLeavesTheFileAlone) {
  const auto path = file_of(counting(1000), "kept.bin");
  HostArray<uint32_t> a = map_records<uint32_t>(path, 1000);
  const HostArray<uint32_t> b = a;  // shares the mapping
  a[3] = 0;
  a.push_back(1);
  EXPECT_FALSE(a.is_view());
  EXPECT_TRUE(b.is_view());
  EXPECT_EQ(a.size(), 1001u);
  EXPECT_EQ(a[3], 0u);
  EXPECT_EQ(b[3], 10u);
  EXPECT_EQ(read_records<uint32_t>(path, 1000)[3], 10u);
}

TEST(HostArray, AViewOutlivesTheArrayItCameFrom) {
  const auto path = file_of(counting(3000), "outlives.bin");
  HostArray<uint32_t> copy;
  {
    const HostArray<uint32_t> mapped = map_records<uint32_t>(path, 3000);
    copy = mapped;
  }
  EXPECT_EQ(copy.back(), 7u + 2999u);
}

}  // namespace
}  // namespace vs
