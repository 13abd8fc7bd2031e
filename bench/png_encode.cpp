// PNG encoding time and size of rendered images: libpng's defaults (all five row filters, zlib
// level 6), libpng with the better of Sub and Up at level 5 on one thread (write_png until
// 2026-11-29), and io/png_encode.h's encode_png (the same filters and level, slices deflated on
// the pool's threads), each encoding to memory REPEATS times, median and range printed. The rows
// are the PNGs' own.
// usage: volstream_bench_png [--repeats N] IMAGE.png...
#include <png.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "volstream/io/png_encode.h"

namespace {

struct Rows {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> bytes;
};

Rows read_png(const char* path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path)) {
    std::fprintf(stderr, "%s: %s\n", path, image.message);
    std::exit(2);
  }
  Rows rows;
  image.format = (image.format & PNG_FORMAT_FLAG_ALPHA) ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  rows.width = int(image.width), rows.height = int(image.height);
  rows.channels = int(PNG_IMAGE_PIXEL_CHANNELS(image.format));
  rows.bytes.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rows.bytes.data(), 0, nullptr)) {
    std::fprintf(stderr, "%s: %s\n", path, image.message);
    std::exit(2);
  }
  return rows;
}

void append(png_structp png, png_bytep data, size_t size) {
  auto* out = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + size);
}

// Encodes to memory; filters < 0 and level < 0 keep libpng's defaults.
size_t encode(const Rows& rows, int filters, int level) {
  std::vector<unsigned char> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    std::fprintf(stderr, "libpng failed\n");
    std::exit(1);
  }
  png_set_write_fn(png, &out, append, nullptr);
  png_set_IHDR(png, info, png_uint_32(rows.width), png_uint_32(rows.height), 8,
               rows.channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (filters >= 0) png_set_filter(png, PNG_FILTER_TYPE_BASE, filters);
  if (level >= 0) png_set_compression_level(png, level);
  png_write_info(png, info);
  const size_t stride = size_t(rows.width) * size_t(rows.channels);
  for (int y = 0; y < rows.height; ++y) png_write_row(png, rows.bytes.data() + size_t(y) * stride);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out.size();
}

struct Timing {
  double median_ms, min_ms, max_ms;
  size_t bytes;
};

Timing time_encoding(const std::function<size_t()>& encode_once, int repeats) {
  std::vector<double> ms;
  size_t bytes = 0;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    bytes = encode_once();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], ms.front(), ms.back(), bytes};
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 9, first = 1;
  if (argc > 2 && std::strcmp(argv[1], "--repeats") == 0) repeats = std::max(1, std::atoi(argv[2])), first = 3;
  if (first >= argc) {
    std::fprintf(stderr, "usage: %s [--repeats N] IMAGE.png...\n", argv[0]);
    return 2;
  }
  std::printf(
      "| image | size | libpng defaults ms | libpng Sub+Up 5 ms | encode_png ms | encode_png faster than Sub+Up 5 | "
      "bytes default | bytes Sub+Up 5 | bytes encode_png |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (int i = first; i < argc; ++i) {
    const Rows rows = read_png(argv[i]);
    const Timing base = time_encoding([&] { return encode(rows, -1, -1); }, repeats);
    const Timing one_thread = time_encoding([&] { return encode(rows, PNG_FILTER_SUB | PNG_FILTER_UP, 5); }, repeats);
    const Timing sliced = time_encoding(
        [&] {
          return vs::encode_png({rows.bytes.data(), uint32_t(rows.width), uint32_t(rows.height), rows.channels}).size();
        },
        repeats);
    const auto cell = [](const Timing& t) {
      char text[64];
      std::snprintf(text, sizeof text, "%.1f [%.1f..%.1f]", t.median_ms, t.min_ms, t.max_ms);
      return std::string(text);
    };
    std::printf("| %s | %dx%d | %s | %s | %s | %.2fx | %zu | %zu | %zu |\n", argv[i], rows.width, rows.height,
                cell(base).c_str(), cell(one_thread).c_str(), cell(sliced).c_str(),
                one_thread.median_ms / sliced.median_ms, base.bytes, one_thread.bytes, sliced.bytes);
  }
  return 0;
}
