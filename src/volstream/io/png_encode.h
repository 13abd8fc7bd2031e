// PNG encoding of 8-bit RGB or RGBA rows, in slices on the CPU's threads.
//
// libpng deflates a render's PNG on one thread after the frame: 13-21 ms for 512x512 renders
// (volstream_bench_png), 7% of a 0.18 s command (bench/RESULTS.md). Here each slice of rows is filtered and
// deflated on its own thread as a raw deflate stream that ends on a byte boundary (a sync
// flush: an empty stored block) except the last, which ends the data. Their concatenation,
// behind the zlib header and before the Adler-32 of all rows (combined from the slices'), is one
// zlib stream, as pigz writes them. A slice starts without the previous slice's window.
#pragma once
#include <cstdint>
#include <vector>

namespace vs {

struct PngPixels {
  const uint8_t* rows = nullptr;  // height rows of width * channels bytes, top to bottom
  uint32_t width = 0, height = 0;
  int channels = 3;  // 3: RGB, 4: RGBA (straight alpha)
};

// The PNG file's bytes: sRGB chunks (sRGB, gAMA, cHRM: 8-bit values are sRGB-encoded), rows
// filtered by the better of Sub and Up (the smaller sum of absolute differences), deflated at
// level 5. std::logic_error for a size PNG cannot hold or channels other than 3 and 4.
std::vector<uint8_t> encode_png(const PngPixels& pixels);

// Rows per slice: kSliceBytes of filtered rows (at least one row, at most 1 GiB), whatever the
// number of threads, so that an image's file is the same bytes on every machine. Slices of
// 128 KiB made the renders' files 0.9-3% smaller than one slice per thread (bench/RESULTS.md)
// and give each of a few threads several slices.
inline constexpr uint64_t kSliceBytes = 128 * 1024;
uint32_t png_slice_rows(uint32_t height, uint64_t row_bytes);

}  // namespace vs
