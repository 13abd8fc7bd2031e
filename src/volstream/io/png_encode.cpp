#include "volstream/io/png_encode.h"

#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <initializer_list>
#include <stdexcept>
#include <string>

#include "volstream/backend/parallel.h"

namespace vs {
namespace {

// zlib's and a chunk's lengths are 32-bit: slices and chunks stay far below that.
constexpr size_t kMaxChunkBytes = size_t(1) << 30;

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

// A chunk: length, type, data, and the CRC-32 of type and data.
void put_chunk(std::vector<uint8_t>& out, const char (&type)[5], const uint8_t* data, size_t bytes) {
  put_u32(out, uint32_t(bytes));
  const size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + bytes);
  put_u32(out, uint32_t(crc32(0L, out.data() + type_at, uInt(out.size() - type_at))));
}
void put_chunk(std::vector<uint8_t>& out, const char (&type)[5], const std::vector<uint8_t>& data) {
  put_chunk(out, type, data.data(), data.size());
}
std::vector<uint8_t> u32s(std::initializer_list<uint32_t> values) {
  std::vector<uint8_t> out;
  for (uint32_t v : values) put_u32(out, v);
  return out;
}

// Row y filtered into out (a filter-type byte, then the row): Sub or Up, whichever sums to less
// as signed bytes (libpng's heuristic over those two filters; None is Up over the first row).
void filter_row(const PngPixels& px, uint32_t y, uint8_t* out) {
  const size_t bytes = size_t(px.width) * size_t(px.channels), bpp = size_t(px.channels);
  const uint8_t* row = px.rows + size_t(y) * bytes;
  const uint8_t* above = y > 0 ? row - bytes : nullptr;
  const auto left_of = [&](size_t i) -> uint8_t { return i >= bpp ? row[i - bpp] : 0; };  // Sub's predictor
  const auto above_of = [&](size_t i) -> uint8_t { return above ? above[i] : 0; };        // Up's
  uint64_t sub_cost = 0, up_cost = 0;
  for (size_t i = 0; i < bytes; ++i) {
    sub_cost += uint64_t(std::abs(int(int8_t(uint8_t(row[i] - left_of(i))))));
    up_cost += uint64_t(std::abs(int(int8_t(uint8_t(row[i] - above_of(i))))));
  }
  const bool use_sub = sub_cost < up_cost;
  out[0] = use_sub ? 1 : 2;  // PNG filter types: 1 Sub, 2 Up
  for (size_t i = 0; i < bytes; ++i) out[1 + i] = uint8_t(row[i] - (use_sub ? left_of(i) : above_of(i)));
}

// One slice of rows: a raw deflate stream (no header or checksum) and the Adler-32 and length of
// the filtered rows it holds.
struct DeflatedSlice {
  std::vector<uint8_t> stream;
  uLong adler = 0, bytes = 0;
};

// `last` ends the data; another slice ends with a sync flush, on a byte boundary.
DeflatedSlice deflate_slice(const PngPixels& px, uint32_t first_row, uint32_t rows, bool last) {
  const size_t row_bytes = 1 + size_t(px.width) * size_t(px.channels);
  std::vector<uint8_t> filtered(row_bytes * rows);
  for (uint32_t r = 0; r < rows; ++r) filter_row(px, first_row + r, filtered.data() + r * row_bytes);
  DeflatedSlice slice;
  slice.adler = adler32(adler32(0L, nullptr, 0), filtered.data(), uInt(filtered.size()));
  slice.bytes = uLong(filtered.size());
  z_stream z{};
  // Level 5 and the strategy for filtered rows, as write_png asked of libpng (bench/RESULTS.md).
  constexpr int kLevel = 5, kRawWindowBits = -15, kMemLevel = 8;
  if (deflateInit2(&z, kLevel, Z_DEFLATED, kRawWindowBits, kMemLevel, Z_FILTERED) != Z_OK)
    throw std::runtime_error("zlib: deflateInit2 failed");
  // Room for the worst case and the flush's empty stored block.
  std::vector<uint8_t>& out = slice.stream;
  out.resize(deflateBound(&z, uLong(filtered.size())) + 16);
  z.next_in = filtered.data();
  z.avail_in = uInt(filtered.size());
  z.next_out = out.data();
  z.avail_out = uInt(out.size());
  const int status = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
  const bool done = last ? status == Z_STREAM_END : (status == Z_OK && z.avail_in == 0 && z.avail_out > 0);
  out.resize(out.size() - z.avail_out);
  deflateEnd(&z);
  if (!done) throw std::runtime_error("zlib: deflate failed");
  return slice;
}

// The rows filtered and deflated in slices on the pool's threads, joined into one zlib stream:
// header (deflate, 32 KiB window, level 5's "default" flag; a multiple of 31 as RFC 1950 asks),
// the slices' streams, the Adler-32 of all filtered rows.
std::vector<uint8_t> zlib_stream(const PngPixels& px) {
  const uint64_t row_bytes = 1 + uint64_t(px.width) * uint64_t(px.channels);
  const uint32_t slice_rows = png_slice_rows(px.height, row_bytes);
  const uint32_t slices = (px.height + slice_rows - 1) / slice_rows;
  std::vector<DeflatedSlice> deflated(slices);
  parallel_for_ranges(int64_t(slices), [&](int64_t begin, int64_t end) {
    for (int64_t s = begin; s < end; ++s) {
      const uint32_t first = uint32_t(s) * slice_rows, rows = std::min(slice_rows, px.height - first);
      deflated[size_t(s)] = deflate_slice(px, first, rows, s + 1 == slices);
    }
  });
  std::vector<uint8_t> idat = {0x78, 0x5e};
  uLong adler = deflated[0].adler;
  for (uint32_t s = 0; s < slices; ++s) {
    idat.insert(idat.end(), deflated[s].stream.begin(), deflated[s].stream.end());
    if (s > 0) adler = adler32_combine(adler, deflated[s].adler, z_off_t(deflated[s].bytes));
  }
  put_u32(idat, uint32_t(adler));
  return idat;
}

}  // namespace

uint32_t png_slice_rows(uint32_t height, uint64_t row_bytes) {
  const uint64_t rows = (kSliceBytes + row_bytes - 1) / std::max<uint64_t>(row_bytes, 1);
  const uint64_t at_most = kMaxChunkBytes / std::max<uint64_t>(row_bytes, 1);
  return uint32_t(std::clamp<uint64_t>(std::min(rows, at_most), 1, std::max<uint32_t>(height, 1)));
}

std::vector<uint8_t> encode_png(const PngPixels& px) {
  if (px.channels != 3 && px.channels != 4) throw std::logic_error("encode_png: 3 or 4 channels");
  constexpr uint64_t kMaxDimension = 0x7fffffffu;  // PNG's limit on width and height
  if (px.width == 0 || px.height == 0 || px.width > kMaxDimension || px.height > kMaxDimension ||
      uint64_t(px.width) * uint64_t(px.channels) + 1 > 0x7fffffffu)
    throw std::logic_error("encode_png: " + std::to_string(px.width) + "x" + std::to_string(px.height) +
                           " is not a PNG size");
  const std::vector<uint8_t> idat = zlib_stream(px);
  // The file: signature, header, the sRGB chunks as libpng's png_set_sRGB_gAMA_and_cHRM writes
  // them (gamma 1/2.2 and the sRGB primaries and white point, x100000, for readers without sRGB
  // support), the data, the end.
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<uint8_t> header = u32s({px.width, px.height});
  const uint8_t color_type = px.channels == 4 ? 6 : 2;    // RGBA or RGB
  header.insert(header.end(), {8, color_type, 0, 0, 0});  // 8 bits, deflate, adaptive filters, no interlace
  put_chunk(png, "IHDR", header);
  put_chunk(png, "gAMA", u32s({45455}));
  const uint8_t perceptual = 0;
  put_chunk(png, "sRGB", &perceptual, 1);
  put_chunk(png, "cHRM", u32s({31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000}));
  for (size_t at = 0; at < idat.size(); at += kMaxChunkBytes)  // chunks of at most 1 GiB
    put_chunk(png, "IDAT", idat.data() + at, std::min(kMaxChunkBytes, idat.size() - at));
  put_chunk(png, "IEND", nullptr, 0);
  return png;
}

}  // namespace vs
