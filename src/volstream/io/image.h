// Images: premultiplied linear RGBA floats in memory; PNG (8-bit sRGB) and PFM (float) files.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/core/image.h"
#include "volstream/core/math.h"

namespace vs {

struct ImageWriteOptions {
  bool alpha = false;               // keep transparency instead of compositing over the background
  vec3f background{0.f, 0.f, 0.f};  // sRGB-encoded colour in [0, 1]
};

// The image over the background (ignored with alpha), in linear RGB: one value per channel.
std::vector<float> composite_rgb(const Image& image, const vec3f& background_srgb);

// The 8-bit sRGB code of a linear value: round(255 * linear_to_srgb(x)) for x clamped to [0, 1],
// 0 for NaN. Found in a table of the codes' first values (built once from that definition)
// instead of a powf per channel; equal to the definition (tested).
uint8_t linear_to_srgb8(float linear);

// 8-bit sRGB RGB over the background, rows top to bottom: what PNG and ffmpeg's rgb24 take.
std::vector<uint8_t> to_rgb8(const Image& image, const vec3f& background_srgb);

// Every file is written atomically (io/atomic_file.h): it appears whole or not at all.
// 8-bit sRGB PNG: RGB composited over the background, or RGBA with straight alpha.
void write_png(const Image& image, const std::string& path, const ImageWriteOptions& options = {});
// Little-endian colour PFM ("PF"), linear RGB composited over the background. With alpha, the
// RGB stays premultiplied (no background) and the alpha goes to a grey PFM beside it
// (<path without .pfm>.alpha.pfm).
void write_pfm(const Image& image, const std::string& path, const ImageWriteOptions& options = {});
// Picks the format from the extension (.png or .pfm); UsageError for anything else.
void write_image(const Image& image, const std::string& path, const ImageWriteOptions& options = {});

// UsageError unless the path ends in .png or .pfm; InputError unless its directory is writable.
void check_image_output(const std::string& path);

// Reads a colour or grey PFM (either byte order) into an image with alpha 1. InputError on bad files.
Image read_pfm(const std::string& path);

}  // namespace vs
