// Transfer functions: colour map + opacity over a value range (linear or log10), baked into one
// RGBA table that kernels index (TfView). Colours in the table are linear RGB (the colour maps
// are given sRGB-encoded and converted on baking) so that compositing and shading are linear.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/core/color.h"
#include "volstream/core/fast_math.h"
#include "volstream/core/math.h"

namespace vs {

// Linear RGB + alpha. Used both straight (table entries) and premultiplied (accumulated colour).
struct Rgba {
  float r = 0, g = 0, b = 0, a = 0;
};

VS_HOST_DEVICE inline Rgba lerp(const Rgba& x, const Rgba& y, float t) {
  return {x.r + (y.r - x.r) * t, x.g + (y.g - x.g) * t, x.b + (y.b - x.b) * t, x.a + (y.a - x.a) * t};
}

// What a kernel needs: the table and the map from a value to a table position.
struct TfView {
  const Rgba* table = nullptr;
  uint32_t size = 0;
  uint32_t log_scale = 0;  // positions are computed from log10(value); values <= 0 map to the bottom
  float lo = 0.f;          // scaled (log10 when log_scale) value of table entry 0
  float inv_span = 1.f;    // 1 / (scaled hi - scaled lo)

  // fast_log10 (core/fast_math.h): within 8e-8 + 2e-7 |log10 v| of log10 (tested), a shift of
  // a table position by under 1e-3 entries for a 6-decade table at |log10 v| < 20.
  VS_HOST_DEVICE float scaled(float v) const {
    if (!log_scale) return v;
    return v > 0.f ? fast_log10(v) : -INFINITY;
  }
  // Continuous table coordinate in [0, size-1] (values outside the range clamp to the ends).
  VS_HOST_DEVICE float position(float v) const {
    float t = (scaled(v) - lo) * inv_span;
    t = t > 0.f ? (t < 1.f ? t : 1.f) : 0.f;  // also maps -inf to 0
    return t * float(size - 1);
  }
  // Linearly interpolated table entry (straight, not premultiplied colour).
  VS_HOST_DEVICE Rgba lookup(float v) const {
    const float x = position(v);
    const uint32_t i = uint32_t(x);
    if (i + 1 >= size) return table[size - 1];
    return lerp(table[i], table[i + 1], x - float(i));
  }
};

// "Can any value in [lo, hi] get non-zero opacity?" in O(1), for classifying ABRs on the host
// or the GPU: the count of opaque table entries among those a lookup of such a value reads.
// Most ranges are decided before that by comparing values with thresholds computed once per
// table (no log10f per range on a log scale): ranges wholly below or above every opaque entry
// are transparent, ranges that meet the longest run of opaque entries are visible. Both keep
// entries of margin, so they answer as the table count would; the defaults decide nothing.
struct OpacityIndex {
  TfView tf;
  const uint32_t* opaque_prefix = nullptr;  // tf.size + 1 prefix counts of entries with alpha > 0
  float transparent_below = -INFINITY, transparent_above = INFINITY;  // data values
  float opaque_lo = INFINITY, opaque_hi = -INFINITY;                  // data values; empty

  // Never false where a lookup would give alpha > 0; false for an empty range (lo > hi or NaN).
  VS_HOST_DEVICE bool any(float lo, float hi) const {
    if (!(lo <= hi)) return false;
    if (hi < transparent_below || lo > transparent_above) return false;
    if (lo <= opaque_hi && hi >= opaque_lo) return true;
    // A lookup at position x reads entries floor(x) and floor(x)+1. One more entry on each side
    // absorbs rounding differences between host and device log10f.
    const float first = floorf(tf.position(lo)) - 1.f, last = floorf(tf.position(hi)) + 2.f;
    const uint32_t begin = first > 0.f ? uint32_t(first) : 0u;
    const uint32_t end = last < float(tf.size - 1) ? uint32_t(last) + 1u : tf.size;  // exclusive
    return opaque_prefix[end] > opaque_prefix[begin < end ? begin : end];
  }
};

struct ColorPoint {
  float x, r, g, b;  // x in [0, 1] of the value range; sRGB-encoded colour
};
struct OpacityPoint {
  float x, a;  // x in [0, 1] of the (scaled) value range; alpha per reference step
};

// A transfer function before baking. Positions are normalised over [lo, hi] after scaling
// (log10 when log_scale), so one colour map fits any value range.
struct TransferFunctionSpec {
  std::vector<ColorPoint> colors;     // sorted by x
  std::vector<OpacityPoint> opacity;  // sorted by x; empty: the default ramp
  float lo = 0.f, hi = 1.f;           // value range in data units
  bool log_scale = false;
};

// Names accepted by builtin_color_map: viridis, inferno, cool-warm, grayscale, blackbody.
std::vector<std::string> builtin_color_map_names();
std::vector<ColorPoint> builtin_color_map(const std::string& name);  // empty if unknown

// ParaView colour map JSON: an array of objects (or one object) with "RGBPoints" [x,r,g,b,...]
// and optionally "Points" [x,alpha,mid,sharpness,...] for opacity. Positions are rescaled to
// [0, 1] over the RGBPoints' own x range. Throws InputError naming the file on malformed text
// (files are read by frame/look.h).
struct ParaviewColorMap {
  std::string name;
  std::vector<ColorPoint> colors;
  std::vector<OpacityPoint> opacity;  // empty when the file has none
};
ParaviewColorMap parse_paraview_color_map(const std::string& json_text, const std::string& name_for_errors);

// The default opacity: transparent in the lower 10% of the range, then a ramp to `max_alpha`.
std::vector<OpacityPoint> default_opacity_ramp(float max_alpha = 0.5f);

// Maps a data value to the normalised position used by OpacityPoint::x (honours log_scale).
// Returns NaN for values that cannot be placed (<= 0 on a log scale).
float normalised_position(const TransferFunctionSpec& spec, double value);

// The baked table plus a range-max structure for conservative classification of value ranges.
class TransferTable {
 public:
  explicit TransferTable(const TransferFunctionSpec& spec, uint32_t size = 1024);
  TfView view() const;
  const std::vector<Rgba>& entries() const { return entries_; }
  const TransferFunctionSpec& spec() const { return spec_; }
  // Colour (straight, linear RGB) of a value; for tests and the iso colour.
  Rgba lookup(float v) const { return view().lookup(v); }
  // True when some value in [lo, hi] (data units) can get non-zero opacity: the max alpha over
  // every table entry that a lookup of such a value interpolates from. Never false where a
  // lookup would give alpha > 0; false for an empty range (lo > hi, e.g. no finite value).
  bool any_opacity(float lo, float hi) const;
  OpacityIndex opacity_index() const;  // the same query for kernels (host pointers)
  const std::vector<uint32_t>& opaque_prefix() const { return opaque_prefix_; }

 private:
  TransferFunctionSpec spec_;
  std::vector<Rgba> entries_;
  std::vector<uint32_t> opaque_prefix_;  // [i]: entries before i with alpha > 0 (size + 1 counts)
  OpacityIndex shortcuts_;               // the value thresholds, found once; opacity_index() sets the pointers
  OpacityIndex find_shortcuts() const;
};

}  // namespace vs
