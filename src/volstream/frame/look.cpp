#include "volstream/frame/look.h"

#include <algorithm>
#include <cmath>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/integrators/umesh_renderer.h"

namespace vs {

Look default_look(const DatasetManifest& m) {
  if (m.field_index("vorticity") >= 0)  // jet: body, wingtip vortices and the vortex street
    return {"vorticity", "inferno", 3.2f, {{0.15f, 0.f}, {0.46f, 0.01f}, {0.77f, 0.03f}, {0.93f, 0.4f}, {1.f, 0.9f}}};
  if (m.field_index("density") >= 0)  // cosmo: filaments and clumps over many decades
    return {"density", "inferno", 7.f, {{0.19f, 0.f}, {0.29f, 0.03f}, {0.43f, 0.1f}, {0.72f, 0.5f}, {1.f, 0.9f}}};
  if (m.fields.empty()) throw UsageError("the dataset has no fields");
  return {m.fields.front().name, "viridis", 0.f, {}};
}

Box3<double> world_bounds(const Dataset& ds) {
  if (ds.part()) return ds.part()->world_bounds;  // a rank's topology is only its share
  if (ds.is_mesh()) return ds.mesh_world_bounds();
  return world_bounds(ds.topology(), ds.manifest().transform);
}

Camera default_view(const Dataset& ds, uint32_t width, uint32_t height) {
  return default_camera(world_bounds(ds), double(width) / height);
}

ParaviewColorMap load_paraview_color_map(const std::string& path) {
  return parse_paraview_color_map(read_text_file(path, 64 << 20), path);
}

int field_or_throw(const DatasetManifest& m, const std::string& name, const std::string& dataset_name) {
  const int f = m.field_index(name);
  if (f < 0) throw UsageError("no field '" + name + "' in " + dataset_name);
  return f;
}

Range union_range(const FieldInfo& f, const std::vector<int>& steps) {
  Range r{INFINITY, -INFINITY};
  for (int s : steps) {
    const Range& x = f.step_ranges.at(size_t(s));
    r = {std::min(r.lo, x.lo), std::max(r.hi, x.hi)};
  }
  return r;
}

namespace {

// The request's range, else `r` (the look's decades below its maximum on a log scale). On a log
// scale the lower end must be positive: it becomes hi * 1e-6 when the data reach down to zero.
void value_range(const TransferFunctionRequest& request, Range r, float decades, TransferFunctionSpec& spec) {
  if (request.range) {
    r = *request.range;
    if (!(r.lo < r.hi)) throw UsageError("--range expects LO,HI with LO < HI");
  } else if (spec.log_scale && decades > 0 && r.hi > 0) {
    r.lo = std::max(r.lo, r.hi * std::pow(10.f, -decades));
  }
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};  // a field with no finite value
  if (spec.log_scale && !(r.hi > 0)) throw UsageError("--log: the value range has no positive values");
  if (spec.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
  spec.lo = r.lo;
  spec.hi = r.hi;
}

// A built-in map or a ParaView .json: colours (and the preset's opacity points, when it has any).
void colors_from(const std::string& name, TransferFunctionSpec& spec) {
  if (name.size() > 5 && name.substr(name.size() - 5) == ".json") {
    const ParaviewColorMap cm = load_paraview_color_map(name);
    spec.colors = cm.colors;
    if (spec.opacity.empty()) spec.opacity = cm.opacity;
    return;
  }
  spec.colors = builtin_color_map(name);
  if (spec.colors.empty()) {
    std::string names = "auto";
    for (const auto& n : builtin_color_map_names()) names += ", " + n;
    throw UsageError("unknown transfer function '" + name + "' (" + names + ", or a ParaView .json file)");
  }
}

std::vector<OpacityPoint> opacity_points(const std::vector<std::pair<double, double>>& points,
                                         const TransferFunctionSpec& spec) {
  std::vector<OpacityPoint> pts;
  for (const auto& [value, alpha] : points) {
    if (!(alpha >= 0 && alpha <= 1)) throw UsageError("--opacity: alpha must be in [0, 1]");
    const float x = normalised_position(spec, value);
    if (std::isnan(x)) throw UsageError("--opacity: value " + std::to_string(value) + " is not positive (--log)");
    pts.push_back({x, float(alpha)});
  }
  std::sort(pts.begin(), pts.end(), [](const OpacityPoint& a, const OpacityPoint& b) { return a.x < b.x; });
  return pts;
}

}  // namespace

std::vector<OpacityPoint> layer_opacity_points(const TransferFunctionSpec& spec, int n, double alpha) {
  if (n < 1 || n > 64) throw UsageError("--layers: the layer count must be in [1, 64]");
  if (!(alpha > 0 && alpha <= 1)) throw UsageError("--layers: the layer alpha must be in (0, 1]");
  auto scale = [&](double v) { return spec.log_scale ? std::log10(v) : v; };
  const double a = scale(spec.lo), span = scale(spec.hi) - a;
  if (!(span > 0)) throw UsageError("--layers: the value range is empty");
  const double w = 0.001 * span / n, sigma = std::sqrt(w / 2);
  static const double kSigmas[] = {-4, -3, -2.5, -2, -1.5, -1, -0.5, 0, 0.5, 1, 1.5, 2, 2.5, 3, 4};
  std::vector<OpacityPoint> pts;
  for (int i = 0; i < n; ++i) {
    const double c = n > 1 ? double(i) / (n - 1) : 0.5;  // normalised centre
    for (double k : kSigmas) {
      const double d = k * sigma;  // scale units from the centre
      const double layer = std::fabs(k) == 4 ? 0.0 : alpha * std::exp(-d * d / w);
      pts.push_back({float(c + d / span), float(layer)});
    }
  }
  return pts;  // sorted: the layers are far narrower than their spacing
}

TransferFunctionSpec make_transfer_function(const DatasetManifest& m, int field, const std::vector<int>& range_steps,
                                            const TransferFunctionRequest& request) {
  const Look look = default_look(m);
  const bool demo_look = m.fields.at(size_t(field)).name == look.field;
  const bool use_look = demo_look && request.color_map == "auto";
  TransferFunctionSpec spec;
  spec.log_scale = request.log || (use_look && look.log_decades > 0);
  value_range(request, union_range(m.fields[size_t(field)], range_steps), use_look ? look.log_decades : 0.f, spec);
  if (request.layers > 0 && !request.opacity.empty()) throw UsageError("--layers and --opacity exclude each other");
  if (request.layers > 0)
    spec.opacity = layer_opacity_points(spec, request.layers, request.layer_alpha);
  else if (!request.opacity.empty())
    spec.opacity = opacity_points(request.opacity, spec);
  else if (use_look)
    spec.opacity = look.opacity;
  colors_from(request.color_map == "auto" ? (demo_look ? look.color_map : "viridis") : request.color_map, spec);
  return spec;
}

TransferFunctionSpec make_color_field_transfer_function(const DatasetManifest& m, int color_field,
                                                        const std::vector<int>& range_steps,
                                                        const TransferFunctionSpec& main, bool log) {
  TransferFunctionSpec c = main;  // the same colours, over the colour field's own range
  c.log_scale = log;
  Range r = union_range(m.fields.at(size_t(color_field)), range_steps);
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};
  if (c.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
  c.lo = r.lo;
  c.hi = r.hi;
  return c;
}

DensityScale parse_density_scale(const std::string& name) {
  if (name == "auto") return DensityScale::automatic;
  if (name == "linear") return DensityScale::linear;
  if (name == "log") return DensityScale::log;
  throw UsageError("--density-scale: auto, linear or log, not '" + name + "'");
}

namespace {
// Decades of density below rho_max that the blackbody emission spans on a log scale; 0: linear.
float density_decades(const TransferFunctionSpec& spec, DensityScale scale) {
  const bool tf_log = spec.log_scale && spec.lo > 0.f && spec.hi > spec.lo;
  if (scale == DensityScale::linear || (scale == DensityScale::automatic && !tf_log)) return 0.f;
  if (tf_log) return std::log10(spec.hi / spec.lo);
  if (!(spec.hi > 0.f)) throw UsageError("--density-scale log: the density range must reach above 0");
  return 7.f;
}
}  // namespace

BlackbodyParams make_blackbody_params(const TransferFunctionSpec& density_tf, DensityScale scale, double emission,
                                      double absorption, double emission_power) {
  if (!(absorption >= 0) || !(emission >= 0)) throw UsageError("--absorption and --emission must be >= 0");
  BlackbodyParams p;
  p.rho_max = density_tf.hi;
  p.log_decades = density_decades(density_tf, scale);
  p.emission_power = emission_power > 0 ? float(emission_power) : (p.log_decades > 0.f ? 4.f : 1.f);
  p.emission = float(emission);
  p.absorption = float(absorption);
  return p;
}

IntegratorKind default_integrator(const Dataset& dataset, OpticsKind optics) {
  return optics == OpticsKind::blackbody && !dataset.is_mesh() ? IntegratorKind::blocks : IntegratorKind::abr;
}

}  // namespace vs
