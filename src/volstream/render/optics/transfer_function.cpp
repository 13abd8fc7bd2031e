#include "volstream/render/optics/transfer_function.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "volstream/core/error.h"

namespace vs {

std::vector<OpacityPoint> default_opacity_ramp(float max_alpha) { return {{0.f, 0.f}, {0.1f, 0.f}, {1.f, max_alpha}}; }

float normalised_position(const TransferFunctionSpec& spec, double value) {
  auto scale = [&](double v) { return spec.log_scale ? (v > 0 ? std::log10(v) : NAN) : v; };
  const double lo = scale(spec.lo), hi = scale(spec.hi), v = scale(value);
  if (!std::isfinite(v)) return NAN;
  return hi > lo ? float((v - lo) / (hi - lo)) : 0.f;
}

namespace {

// Piecewise-linear interpolation of points sorted by x, clamped at both ends.
template <typename P, typename Get>
float interpolate(const std::vector<P>& pts, float x, Get get) {
  if (x <= pts.front().x) return get(pts.front());
  if (x >= pts.back().x) return get(pts.back());
  const auto it = std::upper_bound(pts.begin(), pts.end(), x, [](float v, const P& p) { return v < p.x; });
  const P& b = *it;
  const P& a = *(it - 1);
  const float t = b.x > a.x ? (x - a.x) / (b.x - a.x) : 1.f;
  return get(a) + (get(b) - get(a)) * t;
}

std::vector<float> numbers(const nlohmann::json& j, const char* key, const std::string& file) {
  const auto& arr = j.at(key);
  input_check(arr.is_array(), file, std::string("\"") + key + "\" is not an array");
  std::vector<float> out;
  out.reserve(arr.size());
  for (const auto& v : arr) {
    input_check(v.is_number(), file, std::string("\"") + key + "\" holds a non-number");
    const double d = v.get<double>();
    input_check(std::isfinite(d), file, std::string("\"") + key + "\" holds a non-finite number");
    out.push_back(float(d));
  }
  return out;
}

}  // namespace

ParaviewColorMap parse_paraview_color_map(const std::string& text, const std::string& file) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    input_error(file, std::string("not valid JSON: ") + e.what());
  }
  // ParaView writes an array of presets; take the first one that has RGBPoints.
  const nlohmann::json* preset = nullptr;
  if (j.is_array()) {
    for (const auto& p : j)
      if (p.is_object() && p.contains("RGBPoints")) {
        preset = &p;
        break;
      }
  } else if (j.is_object() && j.contains("RGBPoints")) {
    preset = &j;
  }
  input_check(preset != nullptr, file, "no colour map with \"RGBPoints\"");
  ParaviewColorMap cm;
  if (preset->contains("Name") && preset->at("Name").is_string()) cm.name = preset->at("Name").get<std::string>();
  const std::vector<float> rgb = numbers(*preset, "RGBPoints", file);
  input_check(rgb.size() >= 4 && rgb.size() % 4 == 0, file, "\"RGBPoints\" must hold groups of 4 numbers x,r,g,b");
  for (size_t i = 0; i < rgb.size(); i += 4) {
    input_check(i == 0 || rgb[i] >= rgb[i - 4], file, "\"RGBPoints\" positions are not sorted");
    cm.colors.push_back(
        {rgb[i], std::clamp(rgb[i + 1], 0.f, 1.f), std::clamp(rgb[i + 2], 0.f, 1.f), std::clamp(rgb[i + 3], 0.f, 1.f)});
  }
  // Presets are stored over arbitrary ranges ([-1,1], [0,1], data units): normalise to [0, 1].
  const float x0 = cm.colors.front().x, x1 = cm.colors.back().x;
  const float span = x1 > x0 ? x1 - x0 : 1.f;
  for (ColorPoint& c : cm.colors) c.x = x1 > x0 ? (c.x - x0) / span : 0.f;
  if (preset->contains("Points")) {
    const std::vector<float> pts = numbers(*preset, "Points", file);
    input_check(pts.size() % 4 == 0, file, "\"Points\" must hold groups of 4 numbers x,alpha,midpoint,sharpness");
    for (size_t i = 0; i < pts.size(); i += 4) {
      input_check(i == 0 || pts[i] >= pts[i - 4], file, "\"Points\" positions are not sorted");
      cm.opacity.push_back({(pts[i] - x0) / span, std::clamp(pts[i + 1], 0.f, 1.f)});
    }
  }
  return cm;
}

TransferTable::TransferTable(const TransferFunctionSpec& spec, uint32_t size) : spec_(spec) {
  if (size < 2) size = 2;
  if (spec_.colors.empty()) spec_.colors = builtin_color_map("viridis");
  if (spec_.opacity.empty()) spec_.opacity = default_opacity_ramp();
  entries_.resize(size);
  for (uint32_t i = 0; i < size; ++i) {
    const float x = float(i) / float(size - 1);
    Rgba& e = entries_[i];
    e.r = srgb_to_linear(interpolate(spec_.colors, x, [](const ColorPoint& p) { return p.r; }));
    e.g = srgb_to_linear(interpolate(spec_.colors, x, [](const ColorPoint& p) { return p.g; }));
    e.b = srgb_to_linear(interpolate(spec_.colors, x, [](const ColorPoint& p) { return p.b; }));
    e.a = std::clamp(interpolate(spec_.opacity, x, [](const OpacityPoint& p) { return p.a; }), 0.f, 1.f);
  }
  // Prefix counts of entries with non-zero alpha: O(1) range queries for classification.
  opaque_prefix_.assign(size + 1, 0);
  for (uint32_t i = 0; i < size; ++i) opaque_prefix_[i + 1] = opaque_prefix_[i] + (entries_[i].a > 0.f ? 1u : 0u);
  shortcuts_ = find_shortcuts();
}

TfView TransferTable::view() const {
  TfView v;
  v.table = entries_.data();
  v.size = uint32_t(entries_.size());
  v.log_scale = spec_.log_scale ? 1u : 0u;
  const float lo = v.scaled(spec_.lo), hi = v.scaled(spec_.hi);
  v.lo = std::isfinite(lo) ? lo : 0.f;
  v.inv_span = (std::isfinite(hi) && hi > v.lo) ? 1.f / (hi - v.lo) : 0.f;  // zero span: everything at entry 0
  return v;
}

namespace {
// The data value at table position x (the inverse of TfView::position), in double.
double value_at(const TfView& v, double x) {
  const double scaled = v.lo + x / double(v.size - 1) / double(v.inv_span);
  return v.log_scale ? std::pow(10.0, scaled) : scaled;
}
}  // namespace

OpacityIndex TransferTable::opacity_index() const {
  OpacityIndex index = shortcuts_;
  index.tf = view();
  index.opaque_prefix = opaque_prefix_.data();
  return index;
}

OpacityIndex TransferTable::find_shortcuts() const {
  OpacityIndex index{view(), opaque_prefix_.data()};
  const TfView& v = index.tf;
  const int64_t size = v.size;
  if (!(v.inv_span > 0.f) || opaque_prefix_.back() == 0) return index;  // no shortcuts
  // The hull [a, b] of the opaque entries and the longest run [c, d] of opaque entries.
  int64_t a = -1, b = -1, c = 0, d = -1;
  for (int64_t i = 0, run = 0; i < size; ++i) {
    if (!(entries_[size_t(i)].a > 0.f)) {
      run = 0;
      continue;
    }
    if (a < 0) a = i;
    b = i;
    if (++run > d - c + 1) c = i - run + 1, d = i;
  }
  // The table count is false when floor(x_hi) + 2 < a or floor(x_lo) - 1 > b, and true when
  // [floor(x_lo) - 1, floor(x_hi) + 2] meets [c, d], which x_lo < d + 2 and x_hi >= c - 2 ensure.
  // Thresholds from the exact inverse, with entries of margin, are then checked against the
  // kernel's own float position, which is monotone in the value: a range beyond a threshold has
  // its position beyond the threshold's. Where float rounding is coarse (a narrow range of large
  // values) a check fails and that shortcut stays off.
  const auto to_float = [](double x) {
    return std::isinf(x) ? float(x) : (std::abs(x) < 1e38 ? float(x) : NAN);  // NaN: not representable
  };
  const float below = to_float(a - 4 >= 0 ? value_at(v, double(a - 4)) : -INFINITY);
  const float above = to_float(b + 4 <= size - 1 ? value_at(v, double(b + 4)) : INFINITY);
  const float lo = to_float(value_at(v, double(c))), hi = to_float(value_at(v, double(d)));
  if (std::isinf(below) || (!std::isnan(below) && v.position(below) < float(a - 3))) index.transparent_below = below;
  if (std::isinf(above) || (!std::isnan(above) && v.position(above) >= float(b + 3))) index.transparent_above = above;
  if (!std::isnan(lo) && !std::isnan(hi) && v.position(lo) >= float(c - 1) && v.position(hi) < float(d + 1)) {
    index.opaque_lo = lo;
    index.opaque_hi = hi;
  }
  return index;
}

bool TransferTable::any_opacity(float lo, float hi) const { return opacity_index().any(lo, hi); }

}  // namespace vs
