#include "render_options.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "parse_util.h"
#include "volstream/core/error.h"
#include "volstream/frame/look.h"

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
  cmd->add_option("--layers", o.layers,
                  "N[:ALPHA] opacity of N narrow Gaussian layers evenly over the range, ends included, each "
                  "peaking at ALPHA (default 0.3), with the width of yt's add_layers(N); instead of --opacity");
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
  cmd->add_flag("--ortho", o.ortho,
                "orthographic projection (same framing as the perspective view at the look-at point)");
  cmd->add_option("--size", o.size, "image size WxH (each at most 16384, at most 8192x8192 pixels in all)")
      ->capture_default_str();
  cmd->add_option("--spp", o.spp, "rays per pixel")->capture_default_str();
  cmd->add_option("--rate", o.rate, "samples per cell width (of each ABR's finest level)")->capture_default_str();
  cmd->add_flag("--no-skip", o.no_skip, "no empty-space skipping (march every ABR)");
  cmd->add_flag(
      "--brick-ranges", o.brick_ranges,
      "CPU: cull by per-brick value ranges (cheaper to compute per frame, culls less; the GPU always uses tight ones)");
  cmd->add_flag("--no-adaptive", o.no_adaptive, "step at the dataset's finest cell width everywhere");
  cmd->add_flag("--no-jitter", o.no_jitter, "start every ray's samples at the same offset");
  cmd->add_flag("--shade", o.shade, "gradient shading of the volume (headlight)");
  cmd->add_flag("--stored-ranges", o.stored_ranges,
                "classify with the dataset's stored per-ABR ranges instead of computing them (the same for datasets "
                "converted since 2026-11-22, per brick and looser before)" +
                    not_streamed);
  cmd->add_option("--encoding", o.encoding,
                  "meshes: stored (the dataset's), reference (the element BVH and face adjacency; datasets converted "
                  "with --encoding reference) or compact (paper 002's encoding; built at load from a reference "
                  "dataset; CPU)")
      ->check(CLI::IsMember({"stored", "reference", "compact"}))
      ->capture_default_str();
  cmd->add_option("--background", o.background, "R,G,B background in [0,1] (sRGB)")->capture_default_str();
  cmd->add_flag("--alpha", o.alpha,
                "keep transparency (PNG RGBA; PFM: premultiplied RGB + OUT.alpha.pfm)" + not_streamed);
  cmd->add_option("--device", o.device,
                  stream ? "auto | cpu | cuda (cuda: each step is uploaded; ranges, refit and render run on the GPU)"
                         : "auto | cpu | cuda")
      ->capture_default_str();
  if (!stream) add_integrator_options(cmd, o);
}

void add_integrator_options(CLI::App* cmd, RenderOptions& o) {
  cmd->add_option("--integrator", o.integrator,
                  "abr: paper 000's ABRs with the tent basis and empty-space skipping; blocks: paper 004's kd-tree "
                  "block raycaster; auto: blocks for --optics blackbody (the paper's pairing), else abr")
      ->check(CLI::IsMember({"auto", "abr", "blocks"}))
      ->capture_default_str();
  cmd->add_option("--reconstruction", o.reconstruction,
                  "blocks: nearest (the cell's value) or trilinear (vertex values shared between blocks); isosurfaces "
                  "need trilinear (nearest is piecewise constant: no surface to find between cells)")
      ->check(CLI::IsMember({"nearest", "trilinear"}))
      ->capture_default_str();
  cmd->add_option("--optics", o.optics,
                  "tf: transfer function; blackbody: emission of a blackbody at --temperature-field through Johnson "
                  "R,V,B filters scaled by density, Rayleigh absorption (paper 004; either integrator)")
      ->check(CLI::IsMember({"tf", "blackbody"}))
      ->capture_default_str();
  cmd->add_option("--temperature-field", o.temperature_field, "blackbody: temperature field (K)")
      ->capture_default_str();
  cmd->add_option("--absorption", o.absorption,
                  "blackbody: Rayleigh extinction (V band) per unit distance at max density")
      ->capture_default_str();
  cmd->add_option("--emission", o.emission, "blackbody: emission per unit distance at max density")
      ->capture_default_str();
  cmd->add_option("--density-scale", o.density_scale,
                  "blackbody: how density is normalised: linear (rho / max rho, paper 004), log (its log10 position "
                  "over the value range, 7 decades below the max unless --range/--log give one) or auto (the transfer "
                  "function's scale: log for the cosmo demo's look and --log, else linear)")
      ->check(CLI::IsMember({"auto", "linear", "log"}))
      ->capture_default_str();
  cmd->add_option(
      "--emission-power", o.emission_power,
      "blackbody: emission ~ normalised density^P (default: 1 for a linear density scale, 4 for a log one)");
}

namespace {

// --opacity V:A,... with V in data units (also with --log).
std::vector<std::pair<double, double>> parse_opacity(const std::string& text) {
  std::vector<std::pair<double, double>> pts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string::npos) throw UsageError("--opacity expects VALUE:ALPHA pairs, got '" + item + "'");
    pts.emplace_back(parse_number(item.substr(0, colon), "--opacity"),
                     parse_number(item.substr(colon + 1), "--opacity"));
  }
  return pts;
}

TransferFunctionRequest transfer_function_request(const RenderOptions& o) {
  TransferFunctionRequest t;
  t.color_map = o.tf;
  t.log = o.log;
  if (!o.range.empty()) {
    const auto v = parse_numbers(o.range, "--range");
    if (v.size() != 2) throw UsageError("--range expects LO,HI with LO < HI");
    t.range = Range{float(v[0]), float(v[1])};
  }
  if (!o.opacity.empty()) t.opacity = parse_opacity(o.opacity);
  if (!o.layers.empty()) {
    const auto v = parse_numbers(o.layers, "--layers", ':');
    if (v.empty() || v.size() > 2 || v[0] != std::floor(v[0]))
      throw UsageError("--layers expects N or N:ALPHA with N a whole number");
    t.layers = int(std::clamp(v[0], 0.0, 1000.0));
    if (t.layers == 0) throw UsageError("--layers: the layer count must be in [1, 64]");
    if (v.size() == 2) t.layer_alpha = v[1];
  }
  return t;
}

std::string dataset_name(const Dataset& ds) { return ds.dir().string(); }

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
  if (!o.field.empty()) return field_or_throw(ds.manifest(), o.field, dataset_name(ds));
  return o.field_from_look ? field_or_throw(ds.manifest(), default_look(ds.manifest()).field, dataset_name(ds)) : 0;
}

IntegratorSettings make_integrator_settings(const RenderOptions& o) {
  IntegratorSettings s;
  if (!(o.rate > 0 && o.rate <= 64)) throw UsageError("--rate must be in (0, 64]");
  if (o.spp < 1 || o.spp > 4096) throw UsageError("--spp must be in [1, 4096]");
  if (!(o.iso_alpha >= 0 && o.iso_alpha <= 1)) throw UsageError("--iso-alpha must be in [0, 1]");
  // 0 is "not given" (the renderer's default); a given length must be a positive float.
  const float unit = float(o.unit_distance);
  if (o.unit_distance != 0 && !(unit > 0 && unit < INFINITY))
    throw UsageError("--unit-distance must be a positive, finite length (in float)");
  s.rate = float(o.rate);
  s.adaptive = o.no_adaptive ? 0 : 1;
  s.jitter = o.no_jitter ? 0 : 1;
  s.shade = o.shade ? 1 : 0;
  s.spp = o.spp;
  s.ref_step = unit;  // 0: the renderer's default, 1/256 of the domain
  s.iso_alpha = float(o.iso_alpha);
  if (!o.iso.empty()) {
    const auto iso = parse_numbers(o.iso, "--iso");
    if (iso.size() > kMaxIso) throw UsageError("--iso takes at most " + std::to_string(kMaxIso) + " values");
    for (double v : iso) s.iso[s.iso_count++] = float(v);
  }
  return s;
}

Camera make_camera(const RenderOptions& o, const Dataset& ds, uint32_t width, uint32_t height) {
  Camera c = default_view(ds, width, height);
  if (!o.camera_at.empty()) c.look_at = parse_vec3(o.camera_at, "--camera-at");
  if (!o.camera_pos.empty()) c.position = parse_vec3(o.camera_pos, "--camera-pos");
  if (!o.camera_up.empty()) c.up = parse_vec3(o.camera_up, "--camera-up");
  if (!(o.fov > 0 && o.fov < 180)) throw UsageError("--fov must be in (0, 180)");
  c.fov_deg = o.fov;
  c.ortho = o.ortho;
  make_camera_view(c, width, height);  // rejects degenerate cameras now, not at the first frame
  return c;
}

namespace {

void apply_integrator_options(const RenderOptions& o, const Dataset& ds, FrameRequest& r) {
  const bool blackbody = o.optics == "blackbody";
  if (o.integrator == "auto")
    r.kind = default_integrator(ds, blackbody ? OpticsKind::blackbody : OpticsKind::tf);
  else
    r.kind = o.integrator == "blocks" ? IntegratorKind::blocks : IntegratorKind::abr;
  r.reconstruction = o.reconstruction == "nearest" ? Reconstruction::nearest : Reconstruction::trilinear;
  if (r.kind == IntegratorKind::blocks && r.reconstruction == Reconstruction::nearest && r.integrator.iso_count > 0)
    throw UsageError(
        "--iso with --integrator blocks needs --reconstruction trilinear (nearest has no surface between cells)");
  if (!blackbody) return;
  if (!o.color_field.empty())
    throw UsageError("--color-field: not with --optics blackbody (the second field is the temperature)");
  r.optics = OpticsKind::blackbody;
  r.second_field = ds.manifest().field_index(o.temperature_field);
  if (r.second_field < 0) throw UsageError("no temperature field '" + o.temperature_field + "' (--temperature-field)");
  r.blackbody =
      make_blackbody_params(r.tf, parse_density_scale(o.density_scale), o.emission, o.absorption, o.emission_power);
}

}  // namespace

RenderPlan make_render_plan(const RenderOptions& o, const Dataset& ds, const std::vector<int>& range_steps) {
  const DatasetManifest& m = ds.manifest();
  RenderPlan p;
  FrameRequest& r = p.request;
  r.field = render_field(o, ds);
  r.tf = make_transfer_function(m, r.field, range_steps, transfer_function_request(o));
  parse_size(o.size, r.width, r.height);
  r.integrator = make_integrator_settings(o);
  r.skip = !o.no_skip;
  r.range_mode = o.brick_ranges ? RangeMode::per_brick : RangeMode::tight;
  r.stored_ranges = o.stored_ranges;
  r.mesh_encoding = parse_mesh_encoding(o.encoding);
  r.camera = make_camera(o, ds, r.width, r.height);
  p.background = vec3f(parse_vec3(o.background, "--background"));
  if (!o.color_field.empty()) {
    r.second_field = field_or_throw(m, o.color_field, dataset_name(ds));
    r.color_tf = make_color_field_transfer_function(m, r.second_field, range_steps, r.tf, o.log);
  }
  apply_integrator_options(o, ds, r);
  p.device = resolve_device(o.device, ds, r.mesh_encoding);
  return p;
}

RenderPlan make_stream_render_plan(const RenderOptions& o, const Dataset& ds) {
  // The pipeline reads one field per step, computes the ABR ranges in its own stage and
  // composites every frame over the background (PNG sequence, video, benchmark hash).
  if (!o.color_field.empty())
    throw UsageError("--color-field: not available when streaming (one field per step); use render");
  if (o.stored_ranges)
    throw UsageError("--stored-ranges: not available when streaming (the ranges stage computes them)");
  if (o.alpha) throw UsageError("--alpha: not available when streaming (frames are composited over --background)");
  std::vector<int> all(size_t(ds.manifest().step_count()));
  for (size_t s = 0; s < all.size(); ++s) all[s] = int(s);
  return make_render_plan(o, ds, all);
}

stream::RenderSetup RenderPlan::setup() const {
  stream::RenderSetup s;
  s.tf = request.tf;
  s.settings.width = request.width;
  s.settings.height = request.height;
  s.settings.integrator = request.integrator;
  s.settings.skip = request.skip;
  s.settings.brick_ranges = request.range_mode == RangeMode::per_brick;
  s.camera = request.camera;
  s.device = device;
  return s;
}

}  // namespace vs::cli
