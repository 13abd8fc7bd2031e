#include "render_options.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "parse_util.h"
#include "volstream/core/error.h"

namespace vs::cli {

RenderOptions stream_render_defaults() {
  RenderOptions o;
  o.size = "256x256";
  o.device = "cpu";
  o.tf = "viridis";
  o.field_from_look = false;
  return o;
}

void add_render_options(CLI::App* cmd, RenderOptions& o, RenderContext context) {
  const bool stream = context == RenderContext::stream;
  const std::string not_streamed = stream ? " (render only: rejected here)" : "";
  cmd->add_option("--field", o.field,
                  o.field_from_look ? "field to render (default: the first; demos: vorticity / density)"
                                    : "field to render (default: the first)");
  cmd->add_option("--tf", o.tf,
                  "colour map: auto (demos: their look; else viridis), viridis, inferno, cool-warm, grayscale, "
                  "blackbody, or a ParaView colour-map .json (RGBPoints; its opacity Points are used when --opacity "
                  "is not given)")
      ->capture_default_str();
  cmd->add_option("--range", o.range,
                  std::string("LO,HI value range of the transfer function (default: the field's range ") +
                      (stream ? "over all steps, the same for every frame)" : "at the step)"));
  cmd->add_flag("--log", o.log, "log10 value scale (a range reaching zero starts at HI*1e-6)");
  cmd->add_option("--opacity", o.opacity,
                  "opacity points VALUE:ALPHA,... with VALUE in data units (also with --log) and ALPHA the opacity "
                  "per unit distance; linear in between, constant outside (default: a ramp over the upper 90%)");
  cmd->add_option("--unit-distance", o.unit_distance,
                  "world length over which ALPHA applies (default: 1/256 of the domain's largest extent)");
  cmd->add_option("--iso", o.iso, "isosurface values V[,V...] (at most 8), coloured by the transfer function");
  cmd->add_option("--iso-alpha", o.iso_alpha, "opacity of the isosurfaces")->capture_default_str();
  cmd->add_option("--color-field", o.color_field,
                  "colour the isosurfaces by this field (its own range, same colour map)" + not_streamed);
  cmd->add_option("--camera-pos", o.camera_pos, "X,Y,Z camera position, world units (default: fitted diagonal view)");
  cmd->add_option("--camera-at", o.camera_at, "X,Y,Z point looked at (default: the domain's centre)");
  cmd->add_option("--camera-up", o.camera_up, "X,Y,Z up direction")->default_str("0,1,0");
  cmd->add_option("--fov", o.fov, "vertical field of view, degrees")->capture_default_str();
  cmd->add_flag("--ortho", o.ortho, "orthographic projection (same framing as the perspective view at the look-at point)");
  cmd->add_option("--size", o.size, "image size WxH (each at most 16384, at most 8192x8192 pixels in all)")->capture_default_str();
  cmd->add_option("--spp", o.spp, "rays per pixel")->capture_default_str();
  cmd->add_option("--rate", o.rate, "samples per cell width (of each ABR's finest level)")->capture_default_str();
  cmd->add_flag("--no-skip", o.no_skip, "no empty-space skipping (march every ABR)");
  cmd->add_flag("--brick-ranges", o.brick_ranges,
                "CPU: cull by per-brick value ranges (cheaper to compute per frame, culls less; the GPU always uses tight ones)");
  cmd->add_flag("--no-adaptive", o.no_adaptive, "step at the dataset's finest cell width everywhere");
  cmd->add_flag("--no-jitter", o.no_jitter, "start every ray's samples at the same offset");
  cmd->add_flag("--shade", o.shade, "gradient shading of the volume (headlight)");
  cmd->add_flag("--stored-ranges", o.stored_ranges,
                "classify with the dataset's stored per-ABR ranges instead of computing them (the same for datasets converted since 2026-11-22, per brick and looser before)" + not_streamed);
  cmd->add_option("--background", o.background, "R,G,B background in [0,1] (sRGB)")->capture_default_str();
  cmd->add_flag("--alpha", o.alpha, "keep transparency (PNG RGBA; PFM: premultiplied RGB + OUT.alpha.pfm)" + not_streamed);
  cmd->add_option("--device", o.device, stream ? "auto | cpu | cuda (cuda: each step is uploaded; ranges, refit and render run on the GPU)"
                                         : "auto | cpu | cuda")
      ->capture_default_str();
}

namespace {

// Built-in demos have a field and a look that show them well; other datasets: the first field.
struct Look {
  std::string field, color_map;
  float log_decades = 0;              // > 0: log scale over [hi / 10^decades, hi]
  std::vector<OpacityPoint> opacity;  // normalised positions; empty: default ramp
};
Look default_look(const DatasetManifest& m) {
  if (m.field_index("vorticity") >= 0)  // jet: body, wingtip vortices and the vortex street
    return {"vorticity", "inferno", 3.2f, {{0.15f, 0.f}, {0.46f, 0.01f}, {0.77f, 0.03f}, {0.93f, 0.4f}, {1.f, 0.9f}}};
  if (m.field_index("density") >= 0)  // cosmo: filaments and clumps over many decades
    return {"density", "inferno", 7.f, {{0.19f, 0.f}, {0.29f, 0.03f}, {0.43f, 0.1f}, {0.72f, 0.5f}, {1.f, 0.9f}}};
  return {m.fields.at(0).name, "viridis", 0.f, {}};
}

int field_or_throw(const Dataset& ds, const std::string& name) {
  const int f = ds.manifest().field_index(name);
  if (f < 0) throw UsageError("no field '" + name + "' in " + ds.dir().string());
  return f;
}

// The union of a field's ranges over the steps (callers have checked the steps).
Range union_range(const FieldInfo& f, const std::vector<int>& steps) {
  Range r{INFINITY, -INFINITY};
  for (int s : steps) {
    const Range& x = f.step_ranges.at(size_t(s));
    r = {std::min(r.lo, x.lo), std::max(r.hi, x.hi)};
  }
  return r;
}

// Value range: --range, else `r` (the look's decades below its maximum on a log scale). On a log
// scale the lower end must be positive: it becomes hi * 1e-6 when the data reach down to zero.
void value_range(const RenderOptions& o, Range r, float decades, TransferFunctionSpec& spec) {
  if (!o.range.empty()) {
    const auto v = parse_numbers(o.range, "--range");
    if (v.size() != 2 || !(v[0] < v[1])) throw UsageError("--range expects LO,HI with LO < HI");
    r = {float(v[0]), float(v[1])};
  } else if (spec.log_scale && decades > 0 && r.hi > 0) {
    r.lo = std::max(r.lo, r.hi * std::pow(10.f, -decades));
  }
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};  // a field with no finite value
  if (spec.log_scale && !(r.hi > 0)) throw UsageError("--log: the value range has no positive values");
  if (spec.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
  spec.lo = r.lo;
  spec.hi = r.hi;
}

// --tf NAME | FILE.json: colours (and a ParaView preset's opacity points, when it has any).
void colors_from(const std::string& tf, TransferFunctionSpec& spec) {
  if (tf.size() > 5 && tf.substr(tf.size() - 5) == ".json") {
    const ParaviewColorMap cm = load_paraview_color_map(tf);
    spec.colors = cm.colors;
    if (spec.opacity.empty()) spec.opacity = cm.opacity;
    return;
  }
  spec.colors = builtin_color_map(tf);
  if (spec.colors.empty()) {
    std::string names = "auto";
    for (const auto& n : builtin_color_map_names()) names += ", " + n;
    throw UsageError("unknown transfer function '" + tf + "' (" + names + ", or a ParaView .json file)");
  }
}

// --opacity V:A,... with V in data units (also with --log) and A in [0, 1].
std::vector<OpacityPoint> parse_opacity(const std::string& text, const TransferFunctionSpec& spec) {
  std::vector<OpacityPoint> pts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string::npos) throw UsageError("--opacity expects VALUE:ALPHA pairs, got '" + item + "'");
    const double v = parse_number(item.substr(0, colon), "--opacity");
    const double alpha = parse_number(item.substr(colon + 1), "--opacity");
    if (alpha < 0 || alpha > 1) throw UsageError("--opacity: alpha must be in [0, 1]");
    const float x = normalised_position(spec, v);
    if (std::isnan(x)) throw UsageError("--opacity: value " + item.substr(0, colon) + " is not positive (--log)");
    pts.push_back({x, float(alpha)});
  }
  std::sort(pts.begin(), pts.end(), [](const OpacityPoint& a, const OpacityPoint& b) { return a.x < b.x; });
  return pts;
}

// The world box of the leaf cells (what AmrRenderer::world_bounds gives, without building a BVH).
Box3<double> world_bounds(const Dataset& ds) {
  Box3<double> b{vec3d(INFINITY), vec3d(-INFINITY)};
  const WorldTransform& t = ds.manifest().transform;
  for (const Brick& br : ds.topology().bricks) {
    const box3i c = br.cell_box();
    b.extend(t.to_world(vec3d(c.lower)));
    b.extend(t.to_world(vec3d(c.upper)));
  }
  if (b.empty()) b = {vec3d(0), vec3d(1)};
  return b;
}

}  // namespace

void parse_size(const std::string& text, uint32_t& w, uint32_t& h) {
  const auto v = parse_numbers(text, "--size", 'x');
  if (v.size() != 2 || v[0] < 1 || v[1] < 1 || v[0] > 16384 || v[1] > 16384 || v[0] != std::floor(v[0]) ||
      v[1] != std::floor(v[1]) || v[0] * v[1] > kMaxPixels)
    throw UsageError("--size expects WxH with 1 <= W, H <= 16384 and W*H <= 67108864 (8192x8192)");
  w = uint32_t(v[0]);
  h = uint32_t(v[1]);
}

int render_field(const RenderOptions& o, const Dataset& ds) {
  if (!o.field.empty()) return field_or_throw(ds, o.field);
  return o.field_from_look ? field_or_throw(ds, default_look(ds.manifest()).field) : 0;
}

TransferFunctionSpec make_transfer_function(const RenderOptions& o, const Dataset& ds, int field,
                                            const std::vector<int>& range_steps) {
  const DatasetManifest& m = ds.manifest();
  const Look look = default_look(m);
  const bool demo_look = m.fields.at(size_t(field)).name == look.field;
  const bool use_look = demo_look && o.tf == "auto";
  TransferFunctionSpec spec;
  spec.log_scale = o.log || (use_look && look.log_decades > 0);
  value_range(o, union_range(m.fields[size_t(field)], range_steps), use_look ? look.log_decades : 0.f, spec);
  if (!o.opacity.empty())
    spec.opacity = parse_opacity(o.opacity, spec);
  else if (use_look)
    spec.opacity = look.opacity;
  colors_from(o.tf == "auto" ? (demo_look ? look.color_map : "viridis") : o.tf, spec);
  return spec;
}

IntegratorSettings make_integrator_settings(const RenderOptions& o) {
  IntegratorSettings s;
  if (!(o.rate > 0 && o.rate <= 64)) throw UsageError("--rate must be in (0, 64]");
  if (o.spp < 1 || o.spp > 4096) throw UsageError("--spp must be in [1, 4096]");
  if (!(o.iso_alpha >= 0 && o.iso_alpha <= 1)) throw UsageError("--iso-alpha must be in [0, 1]");
  if (!(o.unit_distance >= 0)) throw UsageError("--unit-distance must be positive");
  s.rate = float(o.rate);
  s.adaptive = o.no_adaptive ? 0 : 1;
  s.jitter = o.no_jitter ? 0 : 1;
  s.shade = o.shade ? 1 : 0;
  s.spp = o.spp;
  s.ref_step = float(o.unit_distance);  // 0: the renderer's default, 1/256 of the domain
  s.iso_alpha = float(o.iso_alpha);
  if (!o.iso.empty()) {
    const auto iso = parse_numbers(o.iso, "--iso");
    if (iso.size() > kMaxIso) throw UsageError("--iso takes at most " + std::to_string(kMaxIso) + " values");
    for (double v : iso) s.iso[s.iso_count++] = float(v);
  }
  return s;
}

FrameSettings make_frame_settings(const RenderOptions& o) {
  FrameSettings fs;
  parse_size(o.size, fs.width, fs.height);
  fs.integrator = make_integrator_settings(o);
  fs.skip = !o.no_skip;
  fs.brick_ranges = o.brick_ranges;
  return fs;
}

Camera make_camera(const RenderOptions& o, const Dataset& ds, uint32_t width, uint32_t height) {
  Camera c = default_camera(world_bounds(ds), double(width) / height);
  if (!o.camera_at.empty()) c.look_at = parse_vec3(o.camera_at, "--camera-at");
  if (!o.camera_pos.empty()) c.position = parse_vec3(o.camera_pos, "--camera-pos");
  if (!o.camera_up.empty()) c.up = parse_vec3(o.camera_up, "--camera-up");
  if (!(o.fov > 0 && o.fov < 180)) throw UsageError("--fov must be in (0, 180)");
  c.fov_deg = o.fov;
  c.ortho = o.ortho;
  make_camera_view(c, width, height);  // rejects degenerate cameras now, not at the first frame
  return c;
}

RenderPlan make_render_plan(const RenderOptions& o, const Dataset& ds, const std::vector<int>& range_steps) {
  const DatasetManifest& m = ds.manifest();
  RenderPlan p;
  p.field = render_field(o, ds);
  p.setup.tf = make_transfer_function(o, ds, p.field, range_steps);
  p.setup.settings = make_frame_settings(o);
  p.setup.camera = make_camera(o, ds, p.setup.settings.width, p.setup.settings.height);
  p.setup.device = resolve_device(o.device);
  p.background = vec3f(parse_vec3(o.background, "--background"));
  if (!o.color_field.empty()) {
    p.color_field = field_or_throw(ds, o.color_field);
    TransferFunctionSpec& c = p.color_tf;
    c = p.setup.tf;  // the same colours, over the colour field's own range
    c.log_scale = o.log;
    Range r = union_range(m.fields[size_t(p.color_field)], range_steps);
    if (!(r.lo <= r.hi)) r = {0.f, 1.f};
    if (c.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
    c.lo = r.lo;
    c.hi = r.hi;
  }
  return p;
}

RenderPlan make_stream_render_plan(const RenderOptions& o, const Dataset& ds) {
  // The pipeline reads one field per step, computes the ABR ranges in its own stage and
  // composites every frame over the background (PNG sequence, video, benchmark hash).
  if (!o.color_field.empty()) throw UsageError("--color-field: not available when streaming (one field per step); use render");
  if (o.stored_ranges) throw UsageError("--stored-ranges: not available when streaming (the ranges stage computes them)");
  if (o.alpha) throw UsageError("--alpha: not available when streaming (frames are composited over --background)");
  std::vector<int> all(size_t(ds.manifest().step_count()));
  for (size_t s = 0; s < all.size(); ++s) all[s] = int(s);
  return make_render_plan(o, ds, all);
}

}  // namespace vs::cli
