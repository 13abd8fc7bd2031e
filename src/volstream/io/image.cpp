#include "volstream/io/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include "volstream/backend/parallel.h"
#include "volstream/core/color.h"
#include "volstream/core/error.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/png_encode.h"

namespace vs {
namespace {

uint8_t to_byte(float srgb) { return uint8_t(std::lround(std::clamp(srgb, 0.f, 1.f) * 255.f)); }

// linear_to_srgb8 by its definition: a powf per call.
uint8_t srgb8_by_definition(float linear) { return linear > 0.f ? to_byte(linear_to_srgb(linear)) : 0; }

float float_from_bits(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// first[k]: the smallest float whose code is k or more (bisection over the bit patterns of the
// floats in [0, 1], which are ordered as the floats are); bucket[i]: the code of i / kBuckets.
// A value's code is its bucket's, raised while the value reaches the next code's first float:
// one or two comparisons, as a bucket spans less than one code (sRGB's steepest slope is 12.92).
struct Srgb8Table {
  static constexpr int kBuckets = 4096;
  float first[257];
  uint8_t bucket[kBuckets + 1];

  Srgb8Table() {
    const uint32_t one = 0x3f800000u;  // 1.0f
    first[0] = 0.f;
    for (int k = 1; k <= 255; ++k) {
      uint32_t lo = 0, hi = one;  // the code of hi is >= k, the code of lo < k
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        (srgb8_by_definition(float_from_bits(mid)) >= k ? hi : lo) = mid;
      }
      first[k] = float_from_bits(hi);
    }
    first[256] = INFINITY;
    for (int i = 0; i <= kBuckets; ++i) bucket[i] = srgb8_by_definition(float(i) / float(kBuckets));
  }

  uint8_t code(float x) const {
    if (!(x > 0.f)) return 0;  // also NaN
    if (x >= 1.f) return 255;
    int c = bucket[int(x * float(kBuckets))];  // x * 2^12 is exact: the bucket's lower end is <= x
    while (x >= first[c + 1]) ++c;
    return uint8_t(c);
  }
};

const Srgb8Table& srgb8_table() {
  static const Srgb8Table table;
  return table;
}

// A premultiplied pixel's channels over an opaque background (given sRGB, held linear).
struct Over {
  float bg[3];
  explicit Over(const vec3f& bg_srgb)
      : bg{srgb_to_linear(bg_srgb.x), srgb_to_linear(bg_srgb.y), srgb_to_linear(bg_srgb.z)} {}
  float operator()(const float* p, int c) const { return p[c] + (1.f - p[3]) * bg[c]; }
};

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

void write_pfm_channels(const std::string& path, uint32_t w, uint32_t h, int channels, const std::vector<float>& data) {
  AtomicFile out(path);
  // Negative scale: little-endian.
  out.write(std::string(channels == 3 ? "PF" : "Pf") + "\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n");
  // PFM stores rows bottom to top.
  for (uint32_t y = h; y-- > 0;) out.write(data.data() + size_t(y) * w * channels, sizeof(float) * w * channels);
  out.commit();
}

}  // namespace

uint8_t linear_to_srgb8(float linear) { return srgb8_table().code(linear); }

std::vector<uint8_t> to_rgb8(const Image& image, const vec3f& background_srgb) {
  // composite_rgb and the encoding in one pass over the pixels.
  const Srgb8Table& table = srgb8_table();
  const Over over(background_srgb);
  std::vector<uint8_t> bytes(size_t(image.width) * image.height * 3);
  parallel_for_ranges(
      int64_t(image.width) * image.height,
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i)
          for (int c = 0; c < 3; ++c) bytes[size_t(3 * i + c)] = table.code(over(image.rgba.data() + 4 * i, c));
      },
      1 << 14);
  return bytes;
}

std::vector<float> composite_rgb(const Image& img, const vec3f& bg_srgb) {
  const Over over(bg_srgb);
  std::vector<float> rgb(size_t(img.width) * img.height * 3);
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = over(img.rgba.data() + 4 * i, c);
  return rgb;
}

void write_png(const Image& img, const std::string& path, const ImageWriteOptions& opt) {
  const int channels = opt.alpha ? 4 : 3;
  std::vector<uint8_t> bytes;
  if (opt.alpha) {
    bytes.resize(size_t(img.width) * img.height * channels);
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
      const float* p = img.rgba.data() + 4 * i;
      const float a = std::clamp(p[3], 0.f, 1.f);
      for (int c = 0; c < 3; ++c) bytes[4 * i + c] = a > 0.f ? linear_to_srgb8(p[c] / a) : 0;  // straight alpha
      bytes[4 * i + 3] = to_byte(a);
    }
  } else {
    bytes = to_rgb8(img, opt.background);
  }
  const std::vector<uint8_t> png = encode_png({bytes.data(), img.width, img.height, channels});
  write_file_atomic(path, png.data(), png.size());
}

void write_pfm(const Image& img, const std::string& path, const ImageWriteOptions& opt) {
  if (!opt.alpha) {
    write_pfm_channels(path, img.width, img.height, 3, composite_rgb(img, opt.background));
    return;
  }
  std::vector<float> rgb(size_t(img.width) * img.height * 3), alpha(size_t(img.width) * img.height);
  for (size_t i = 0; i < alpha.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = img.rgba[4 * i + c];
    alpha[i] = img.rgba[4 * i + 3];
  }
  write_pfm_channels(path, img.width, img.height, 3, rgb);
  const std::string stem = ends_with(path, ".pfm") ? path.substr(0, path.size() - 4) : path;
  write_pfm_channels(stem + ".alpha.pfm", img.width, img.height, 1, alpha);
}

void check_image_output(const std::string& path) {
  if (!ends_with(path, ".png") && !ends_with(path, ".pfm"))
    throw UsageError("output '" + path + "' must end in .png or .pfm");
  check_output_directory(path);
}

void write_image(const Image& img, const std::string& path, const ImageWriteOptions& opt) {
  if (ends_with(path, ".png")) return write_png(img, path, opt);
  if (ends_with(path, ".pfm")) return write_pfm(img, path, opt);
  throw UsageError("output '" + path + "' must end in .png or .pfm");
}

Image read_pfm(const std::string& path) {
  file_size_checked(path);  // a FIFO or directory would block or mislead
  std::ifstream in(path, std::ios::binary);
  if (!in) input_error(path, "cannot open");
  std::string magic;
  long long w = 0, h = 0;
  double scale = 0;
  in >> magic >> w >> h >> scale;
  input_check(in && (magic == "PF" || magic == "Pf"), path, "not a PFM file");
  input_check(w > 0 && h > 0 && w <= 65536 && h <= 65536, path, "bad PFM size");
  input_check(scale != 0 && std::isfinite(scale), path, "bad PFM scale");
  in.get();  // the single whitespace after the header
  const int channels = magic == "PF" ? 3 : 1;
  std::vector<float> data(size_t(w) * size_t(h) * channels);
  in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
  input_check(in.gcount() == std::streamsize(data.size() * sizeof(float)), path, "PFM file is truncated");
  const bool file_little = scale < 0;
  const uint16_t probe = 1;
  const bool host_little = *reinterpret_cast<const uint8_t*>(&probe) == 1;
  if (file_little != host_little)
    for (float& v : data) {
      uint32_t u;
      std::memcpy(&u, &v, 4);
      u = __builtin_bswap32(u);
      std::memcpy(&v, &u, 4);
    }
  Image img{uint32_t(w), uint32_t(h)};
  for (uint32_t y = 0; y < img.height; ++y)
    for (uint32_t x = 0; x < img.width; ++x) {
      const float* src = data.data() + (size_t(img.height - 1 - y) * img.width + x) * channels;
      float* dst = img.rgba.data() + 4 * (size_t(y) * img.width + x);
      for (int c = 0; c < 3; ++c) dst[c] = src[channels == 3 ? c : 0];
      dst[3] = 1.f;
    }
  return img;
}

}  // namespace vs
