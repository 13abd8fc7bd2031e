// The sliced PNG encoder (io/png_encode.h) against libpng's reader: every image decodes to its
// own bytes, in one slice or several (1x1 to wide rows), RGB or RGBA, and the zlib stream of the
// IDAT chunks inflates whole with zlib's own checksum test; one to eight threads write the same
// file. Also the chunks libpng wrote before: the sRGB chunks and their values.
#include <gtest/gtest.h>
#include <png.h>
#include <tbb/task_arena.h>
#include <zlib.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "volstream/io/png_encode.h"

namespace vs {
namespace {

struct Chunk {
  std::string type;
  std::vector<uint8_t> data;
};

uint32_t u32_at(const uint8_t* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

// The file's chunks, each CRC checked.
std::vector<Chunk> chunks_of(const std::vector<uint8_t>& png) {
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_EQ(std::memcmp(png.data(), kSignature, 8), 0);
  std::vector<Chunk> out;
  for (size_t at = 8; at + 12 <= png.size();) {
    const uint32_t length = u32_at(&png[at]);
    Chunk c{std::string(png.begin() + int64_t(at) + 4, png.begin() + int64_t(at) + 8),
            std::vector<uint8_t>(png.begin() + int64_t(at) + 8, png.begin() + int64_t(at) + 8 + length)};
    EXPECT_EQ(u32_at(&png[at + 8 + length]), uint32_t(crc32(0L, &png[at + 4], 4 + length))) << c.type;
    out.push_back(std::move(c));
    at += 12 + length;
  }
  return out;
}

// Pixels a render might give: smooth gradients with flat stretches and some noise.
std::vector<uint8_t> test_pixels(uint32_t width, uint32_t height, int channels, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> out(size_t(width) * height * size_t(channels));
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) {
        const size_t i = (size_t(y) * width + x) * size_t(channels) + size_t(c);
        const bool flat = (x / 37 + y / 23) % 3 == 0;
        out[i] = flat ? uint8_t(20 * c) : uint8_t((x * (c + 1) + y * 3 + (rng() % 5)) & 0xff);
      }
  return out;
}

std::vector<uint8_t> decoded(const std::vector<uint8_t>& png, int channels, uint32_t& width, uint32_t& height) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  EXPECT_TRUE(png_image_begin_read_from_memory(&image, png.data(), png.size())) << image.message;
  image.format = channels == 4 ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  std::vector<uint8_t> out(PNG_IMAGE_SIZE(image));
  EXPECT_TRUE(png_image_finish_read(&image, nullptr, out.data(), 0, nullptr)) << image.message;
  width = image.width, height = image.height;
  return out;
}

// The test image encoded on `threads` threads, checked to decode to its pixels and to hold a zlib
// stream that inflates whole; the file is returned for the caller to compare.
std::vector<uint8_t> expect_round_trip(uint32_t width, uint32_t height, int channels, int threads) {
  const std::vector<uint8_t> pixels = test_pixels(width, height, channels, width * 31 + height);
  std::vector<uint8_t> png;
  tbb::task_arena(threads).execute([&] { png = encode_png({pixels.data(), width, height, channels}); });
  const std::string what = std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) +
                           ", " + std::to_string(threads) + " threads";
  uint32_t w = 0, h = 0;
  EXPECT_EQ(decoded(png, channels, w, h), pixels) << what;
  EXPECT_EQ(w, width);
  EXPECT_EQ(h, height);
  // The IDAT chunks' zlib stream inflates to one filter byte and a row per row; zlib checks the
  // Adler-32 combined from the slices'.
  std::vector<uint8_t> stream;
  for (const Chunk& c : chunks_of(png))
    if (c.type == "IDAT") stream.insert(stream.end(), c.data.begin(), c.data.end());
  std::vector<uint8_t> rows(size_t(height) * (1 + size_t(width) * size_t(channels)) + 1);
  uLongf size = uLongf(rows.size());
  EXPECT_EQ(uncompress(rows.data(), &size, stream.data(), uLong(stream.size())), Z_OK) << what;
  EXPECT_EQ(size, rows.size() - 1) << what;
  return png;
}

TEST(PngEncode, DecodesToItsPixelsTheSameFileWhateverTheThreads) {
  struct Size {
    uint32_t width, height;
    int channels;
  };
  // One slice; a render (768 KiB: 6 slices); RGBA; wide rows (15 a slice).
  for (const Size& s : {Size{1, 1, 3}, Size{7, 3, 4}, Size{512, 512, 3}, Size{300, 700, 4}, Size{3000, 90, 3}}) {
    const std::vector<uint8_t> one_thread = expect_round_trip(s.width, s.height, s.channels, 1);
    for (int threads : {2, 3, 8})
      EXPECT_EQ(expect_round_trip(s.width, s.height, s.channels, threads), one_thread)
          << s.width << "x" << s.height << ", " << threads << " threads";
  }
}

TEST(PngEncode, SlicesAre128KiBOfRows) {
  EXPECT_EQ(png_slice_rows(512, 1 + 512 * 3), 86u);  // 128 KiB of 1537-byte rows, rounded up
  EXPECT_EQ(png_slice_rows(3, 10), 3u);              // a small image: one slice
  EXPECT_EQ(png_slice_rows(1, 1), 1u);
  EXPECT_EQ(png_slice_rows(100, 1u << 20), 1u);  // rows over 128 KiB: one a slice
  EXPECT_EQ(png_slice_rows(100, 3u << 29), 1u);  // even over the 1 GiB cap
}

TEST(PngEncode, WritesTheSrgbChunksAndRefusesWhatPngCannotHold) {
  const std::vector<uint8_t> pixels = test_pixels(4, 2, 3, 1);
  const std::vector<Chunk> chunks = chunks_of(encode_png({pixels.data(), 4, 2, 3}));
  ASSERT_GE(chunks.size(), 6u);
  EXPECT_EQ(chunks.front().type, "IHDR");
  EXPECT_EQ(chunks.back().type, "IEND");
  const std::vector<uint8_t> header = {0, 0, 0, 4, 0, 0, 0, 2, 8, 2, 0, 0, 0};
  EXPECT_EQ(chunks[0].data, header);
  EXPECT_EQ(chunks[1].type, "gAMA");
  EXPECT_EQ(u32_at(chunks[1].data.data()), 45455u);
  EXPECT_EQ(chunks[2].type, "sRGB");
  EXPECT_EQ(chunks[2].data, std::vector<uint8_t>{0});
  EXPECT_EQ(chunks[3].type, "cHRM");
  EXPECT_EQ(u32_at(chunks[3].data.data()), 31270u);
  EXPECT_THROW(encode_png({pixels.data(), 0, 2, 3}), std::logic_error);
  EXPECT_THROW(encode_png({pixels.data(), 4, 2, 2}), std::logic_error);
}

}  // namespace
}  // namespace vs
