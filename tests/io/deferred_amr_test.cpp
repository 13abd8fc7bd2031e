// AMR opened with its ABRs deferred (issue 17: a data-parallel rank reads only its part of the
// topology): at open only the bricks and the ABR chunk index are read (the index equals the one
// made from the ABRs); a rank's share read chunk by chunk equals the share made from the whole
// topology, and so do the restricted arrays and values; topology bytes read per rank fall with the
// rank count; datasets without the index are read whole; damaged files are refused with one line
// naming the file, at open or at the chunk read.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <regex>

#include "test_util.h"
#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/mpi/amr_share.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path& jet_dir() {
  static const fs::path dir = [] {
    const fs::path d = test::scratch_dir("deferred_jet");
    auto source = make_demo({"jet", 20000, 1});
    convert_to_dataset(*source, d, ConvertOptions::silent());
    return d;
  }();
  return dir;
}

uint64_t topology_file_bytes(const fs::path& dir) {  // cells.bin is for brute-force references only
  uint64_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".bin" && entry.path().filename() != "cells.bin") bytes += entry.file_size();
  return bytes;
}

template <typename T>
void expect_same_bytes(const std::vector<T>& a, const std::vector<T>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(T)), 0) << what;
}

Box3<double> region_of(const Dataset& ds, int rank, int ranks) {
  return partition_bricks(ds.topology().bricks, ranks).regions[size_t(rank)];
}

TEST(DeferredAmr, OpensWithBricksAndTheChunkIndexOnly) {
  const Dataset whole(jet_dir()), deferred(jet_dir(), TopologyLoad::deferred);
  EXPECT_FALSE(whole.topology_deferred());
  ASSERT_TRUE(deferred.topology_deferred());
  EXPECT_TRUE(deferred.topology().abrs.empty());
  expect_same_bytes(whole.topology().bricks, deferred.topology().bricks, "bricks");
  expect_same_bytes(whole.abr_chunks(), deferred.abr_chunks(), "ABR chunks");
  EXPECT_EQ(deferred.abr_chunks().size(), chunk_count(whole.topology().abrs.size()));
  EXPECT_LT(deferred.topology_bytes_read(), topology_file_bytes(jet_dir()) / 4);
}

// Rank `rank` of `ranks`: the deferred share and part equal the whole topology's; returns the
// topology bytes the deferred dataset read.
uint64_t expect_same_share(int rank, int ranks) {
  Dataset whole(jet_dir()), deferred(jet_dir(), TopologyLoad::deferred);
  const Box3<double> region = region_of(whole, rank, ranks);
  const RankShare a = rank_share(whole.topology(), region, IntegratorSettings{});
  const RankShare b = read_rank_share(deferred, region, IntegratorSettings{});
  EXPECT_EQ(a.abrs, b.abrs);
  EXPECT_EQ(a.bricks, b.bricks);
  EXPECT_EQ(a.margin, b.margin);
  for (Dataset* ds : {&whole, &deferred}) {
    DatasetPart part;
    part.abrs = a.abrs;
    part.bricks = a.bricks;
    part.owned = region;
    ds->restrict_to(part);
  }
  expect_same_bytes(whole.topology().bricks, deferred.topology().bricks, "bricks");
  expect_same_bytes(whole.topology().abrs, deferred.topology().abrs, "ABRs");
  EXPECT_EQ(whole.topology().abr_bricks, deferred.topology().abr_bricks);
  EXPECT_EQ(whole.load_values(0, 0), deferred.load_values(0, 0));
  const std::vector<Range> ra = whole.load_abr_ranges(0, 0), rb = deferred.load_abr_ranges(0, 0);
  expect_same_bytes(ra, rb, "ranges");
  return deferred.topology_bytes_read();
}

TEST(DeferredAmr, ShareReadFromTheFilesEqualsTheShareOfTheWholeAndFallsWithRanks) {
  const uint64_t files = topology_file_bytes(jet_dir());
  uint64_t previous = files;
  for (int ranks : {1, 2, 4, 8}) {
    uint64_t most = 0;
    for (int rank = 0; rank < ranks; ++rank) {
      SCOPED_TRACE("rank " + std::to_string(rank) + " of " + std::to_string(ranks));
      most = std::max(most, expect_same_share(rank, ranks));
    }
    std::printf("%d ranks: at most %llu of %llu B of topology read per rank\n", ranks, (unsigned long long)most,
                (unsigned long long)files);
    EXPECT_LT(most, previous) << ranks << " ranks";
    previous = most;
  }
}

// A dataset written before the chunk index is read whole, deferred or not, with the same share.
TEST(DeferredAmr, DatasetsWithoutTheIndexAreReadWhole) {
  const fs::path dir = test::damaged_copy(jet_dir(), "deferred_jet_old", "manifest.json", [](std::vector<char>& b) {
    const std::string text(b.begin(), b.end());
    const std::string old = std::regex_replace(text, std::regex("\"abr_chunk_count\": \\d+,?"), "");
    b.assign(old.begin(), old.end());
  });
  fs::remove(dir / "abr_chunks.bin");
  Dataset old(dir, TopologyLoad::deferred), indexed(jet_dir(), TopologyLoad::deferred);
  EXPECT_FALSE(old.topology_deferred());
  EXPECT_EQ(old.manifest().abr_chunk_count, 0u);
  const Box3<double> region = region_of(old, 1, 3);
  const RankShare a = read_rank_share(old, region, IntegratorSettings{});
  const RankShare b = read_rank_share(indexed, region, IntegratorSettings{});
  EXPECT_EQ(a.abrs, b.abrs);
  EXPECT_EQ(a.bricks, b.bricks);
}

// The line a deferred open and a read of rank 0 of 2's share give for a damaged copy ("accepted"
// if none).
std::string read_damaged(const std::string& name, const std::string& file,
                         const std::function<void(std::vector<char>&)>& damage) {
  const fs::path dir = test::damaged_copy(jet_dir(), "deferred_amr_damaged_" + name, file, damage);
  return test::input_error_line([&] {
    Dataset ds(dir, TopologyLoad::deferred);
    (void)read_rank_share(ds, region_of(ds, 0, 2), IntegratorSettings{});
  });
}

template <typename T>
void patch(std::vector<char>& bytes, size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

bool has(const std::string& line, const char* file, const char* what) {
  return line.find(file) != std::string::npos && line.find(what) != std::string::npos;
}

TEST(DeferredAmr, ReaderRefusesDamagedFilesNamingThem) {
  const char* chunks = "abr_chunks.bin";
  std::string line = read_damaged("truncated", chunks, [](auto& b) { b.resize(b.size() - 28); });
  EXPECT_TRUE(has(line, chunks, "")) << line;
  EXPECT_NE(line, "accepted");
  line = read_damaged("nan", chunks, [](auto& b) { patch<float>(b, 4, NAN); });
  EXPECT_TRUE(has(line, chunks, "chunk 0 has no finite box")) << line;
  line = read_damaged("width", chunks, [](auto& b) { patch<float>(b, 24, -1.f); });
  EXPECT_TRUE(has(line, chunks, "chunk 0 has no finite box or width")) << line;
  // Chunk 0 shrunk to a point: its ABRs (read by rank 0, whose region holds the lowest x) lie outside.
  line = read_damaged("small", chunks, [](auto& b) { std::memcpy(b.data() + 12, b.data(), 12); });
  EXPECT_TRUE(has(line, chunks, "outside its chunk's box")) << line;
  line = read_damaged("finer", chunks, [](auto& b) { patch<float>(b, 24, 0.5f); });
  EXPECT_TRUE(has(line, chunks, "outside its chunk's box or width")) << line;
  // ABR 0's list moved beyond the file, or made to overlap ABR 0's from ABR 1.
  line = read_damaged("list", "abrs.bin", [](auto& b) { patch<uint32_t>(b, offsetof(Abr, first_brick), 0x7fffffffu); });
  EXPECT_TRUE(has(line, "abrs.bin", "ABR 0's brick list")) << line;
  line = read_damaged("overlap", "abrs.bin",
                      [](auto& b) { patch<uint32_t>(b, sizeof(Abr) + offsetof(Abr, first_brick), 0); });
  EXPECT_TRUE(has(line, "abrs.bin", "ABR 1's brick list")) << line;
  line = read_damaged("brick_id", "abr_bricks.bin", [](auto& b) { patch<uint32_t>(b, 0, 0x7fffffffu); });
  EXPECT_TRUE(has(line, "bricks.bin", "out of range")) << line;
  line = read_damaged("abrs_truncated", "abrs.bin", [](auto& b) { b.resize(b.size() - 1); });
  EXPECT_TRUE(has(line, "abrs.bin", "")) << line;
  EXPECT_NE(line, "accepted");
  line = read_damaged("count", "manifest.json", [](std::vector<char>& b) {
    const std::string text(b.begin(), b.end());
    const std::string bad = std::regex_replace(text, std::regex("\"abr_chunk_count\": \\d+"), "\"abr_chunk_count\": 3");
    b.assign(bad.begin(), bad.end());
  });
  EXPECT_TRUE(has(line, "manifest.json", "abr_chunk_count")) << line;
}

}  // namespace
}  // namespace vs
